//! `cargo fuzz run constraint`: see `kairos_fuzz::constraint` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::constraint(data));
