//! The `fit` target of bvol-fuzz, under libFuzzer.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| bvol_fuzz::target("fit").expect("a target").run(data));
