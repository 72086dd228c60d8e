//! `cargo fuzz run schedule`: see `kairos_fuzz::schedule` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::schedule(data));
