//! `cargo fuzz run plant`: see `kairos_fuzz::plant` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::plant(data));
