//! Scene text through the parser, the evaluator and scene building: an error or a scene, never
//! a panic, a hang or a stack overflow.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(graph) = raydiance::lang::parse_scene(std::path::Path::new("fuzz/input.scn"), text) {
            let _ = raydiance::scene::build(&graph);
        }
    }
});
