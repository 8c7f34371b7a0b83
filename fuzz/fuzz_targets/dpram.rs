//! Arbitrary DPRAM contents: the input is a script of writes over the window (mostly the
//! host's fields: configuration blocks, ring indices and entries, heartbeat, doorbell,
//! interrupt mask; sometimes anywhere), the commands that apply the blocks, any commands,
//! serves and ticks. `card_emu::testkit::fuzzing::run_dpram` checks the invariants after every step.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| card_emu::testkit::fuzzing::run_dpram(data));
