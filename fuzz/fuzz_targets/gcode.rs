//! The G-code reader and interpreter: any bytes as a program (lossily UTF-8), every
//! operation taken, at most 100,000 of them (a program may loop forever making motions: the
//! runner's consumer stops it, not the reader). No input may panic or hang: the reader bounds
//! loops that make no block, nesting and line length.
#![no_main]

use motioncard_sdk::gcode::{Options, Program};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    let program = Program::from_text(text, &Options::default());
    for op in program.take(100_000) {
        if op.is_err() {
            break;
        }
    }
});
