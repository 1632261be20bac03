//! The scene parser and builder with the built-in types: any text gives a scene or an error,
//! never a panic. Relative file references resolve in a folder that does not exist, so the
//! target reads no files.
#![no_main]
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, ObjectFactory};
use std::path::Path;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let file = Path::new("fuzz.ron");
    if let Ok(desc) = parse_scene_str(text, file) {
        let factories: [&dyn ObjectFactory; 1] = [&BuiltinFactory];
        let _ = build_scene(
            &desc,
            Path::new("/nonexistent-spectrace-fuzz"),
            file,
            &factories,
        );
    }
});
