//! The OBJ reader: any text gives a valid mesh or an error, never a panic.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(mesh) = spectrace::geometry::obj::parse_obj(&text, std::path::Path::new("fuzz.obj")) {
        mesh.validate().expect("a mesh the reader accepts is valid");
    }
});
