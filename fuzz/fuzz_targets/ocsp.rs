//! `cargo fuzz run ocsp`: see `kairos_fuzz::ocsp` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::ocsp(data));
