//! PPM decoding (P3 and P6, with or without `#MAX`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = raydiance::image::ppm::parse(data);
});
