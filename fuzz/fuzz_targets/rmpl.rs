//! `cargo fuzz run rmpl`: see `kairos_fuzz::rmpl` and FUZZING.md.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| kairos_fuzz::rmpl(data));
