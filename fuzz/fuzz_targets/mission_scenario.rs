//! `cargo fuzz run mission_scenario`: see `kairos_fuzz::mission_scenario` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::mission_scenario(data));
