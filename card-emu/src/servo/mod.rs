//! The servo laws the firmware runs every tick.

pub mod ffpiv;
pub mod pdplus;
