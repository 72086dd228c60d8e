//! `cargo fuzz run mission`: see `kairos_fuzz::mission` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::mission(data));
