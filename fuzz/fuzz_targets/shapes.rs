#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| dcol_fuzz::shapes(data));
