//! Command decoding: the input is a script of command entries (raw words: any opcode, axis,
//! flags and argument bits, plausible commands with broken arguments, NURBS begin/data/end
//! continuation sequences) and servo ticks, for a card with every axis enabled and groups
//! configured. `card_emu::testkit::fuzzing::run_commands` checks the invariants after every step.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| card_emu::testkit::fuzzing::run_commands(data));
