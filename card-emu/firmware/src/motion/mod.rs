//! The motion algorithms: pure functions and plain data (no window, no clock, no plant), used
//! by the firmware and by the host alike.
#![deny(unsafe_code)] // (allowed only in `path::v3`: the calls into its CPU-specific build)

pub mod arc;
pub mod cam;
pub mod comp;
pub mod filters;
pub mod interp_error;
pub mod nurbs;
pub mod nurbs_interp;
pub mod otg;
pub mod path;
pub mod path_speed;
pub mod pvt;
pub mod saturation;
pub mod scurve;

/// Finite and greater than zero.
pub(crate) fn pos_finite(x: f64) -> bool {
    x.is_finite() && x > 0.0
}
