//! Mitsuba's serialized mesh reader: any bytes give a valid mesh or an error, never a panic or
//! an allocation the file's counts have not been checked for.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    for index in 0..2 {
        if let Ok(m) = spectrace::scene::mitsuba::serialized::parse_serialized(data, index) {
            m.mesh.validate().expect("a mesh the reader accepts is valid");
        }
    }
});
