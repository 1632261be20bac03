//! The TM-25 ray file reader: any bytes give a ray file or an error, never a panic; a file it
//! accepts has every counted record readable, and checking its rays answers for each.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = std::path::Path::new("fuzz.TM25RAY");
    if let Ok(f) = spectrace::photometry::tm25::RayFile::from_bytes(data.to_vec(), path) {
        let _ = f.check_rays();
        let n = f.n_rays();
        for i in [0, n / 2, n.saturating_sub(1)] {
            if i < n {
                let r = f.ray(i);
                let _ = spectrace::photometry::tm25::reader::check_ray(&r, f.header.spectra.len());
            }
        }
    }
});
