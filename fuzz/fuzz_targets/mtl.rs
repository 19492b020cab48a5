#![no_main]
appel_fuzz::fuzz_reader!("mtl");
