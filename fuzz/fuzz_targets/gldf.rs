//! The GLDF container reader: any bytes give a container or an error, never a panic; for an
//! accepted container every variant's emitters are chosen and their photometry and spectrum
//! read (bounded by the container limits).
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = std::path::Path::new("fuzz.gldf");
    if let Ok(mut g) = spectrace::photometry::gldf::Gldf::from_bytes(data.to_vec(), path) {
        for v in g.variants.clone() {
            if let Ok((_, e)) = g.choose(Some(&v.id), None) {
                let _ = g.spectrum_of(&e);
                if let Ok(lum) = g.luminaire_of(&e) {
                    let _ = lum.flux_lm();
                }
            }
        }
    }
});
