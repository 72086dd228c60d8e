//! `cargo fuzz run executive`: see `kairos_fuzz::executive` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::executive(data));
