//! `cargo fuzz run protocol`: see `kairos_fuzz::protocol` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::protocol(data));
