//! The Mitsuba XML reader and converter: any bytes give a scene description or an error, never
//! a panic, and no entity is ever expanded.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // File references resolve in a folder that does not exist.
    let file = std::path::Path::new("/nonexistent-fuzz-dir/fuzz.xml");
    if let Ok(root) = spectrace::scene::mitsuba::xml::parse_scene_text(text, file) {
        let _ = spectrace::scene::mitsuba::convert::convert_tree(&root, std::path::Path::new("/nonexistent-fuzz-dir"));
    }
});
