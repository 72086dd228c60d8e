//! `cargo fuzz run scenario`: see `kairos_fuzz::scenario` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::scenario(data));
