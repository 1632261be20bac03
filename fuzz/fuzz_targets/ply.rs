//! The PLY reader (ascii and binary): any bytes give a valid mesh or an error, never a panic.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = spectrace::geometry::ply::parse_ply(data, std::path::Path::new("fuzz.ply")) {
        mesh.validate().expect("a mesh the reader accepts is valid");
    }
});
