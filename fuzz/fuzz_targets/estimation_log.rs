//! `cargo fuzz run estimation_log`: see `kairos_fuzz::estimation_log` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::estimation_log(data));
