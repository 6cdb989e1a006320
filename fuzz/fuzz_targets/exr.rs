//! OpenEXR decoding, as `tonemap` reads its input.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = raydiance::image::exr::read_bytes(data);
});
