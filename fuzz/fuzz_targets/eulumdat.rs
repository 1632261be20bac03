//! The EULUMDAT reader: any bytes give a luminaire or an error, never a panic; a luminaire it
//! accepts can be used (flux, intensities, direction sampling) and written back out.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = std::path::Path::new("/nonexistent-spectrace-fuzz/fuzz.ldt");
    if let Ok(lum) = spectrace::photometry::eulumdat::parse_eulumdat(data, path) {
        use_luminaire(&lum);
    }
});

/// Everything the renderer and the exporters do with a luminaire.
fn use_luminaire(lum: &spectrace::photometry::Luminaire) {
    let _ = lum.flux_lm();
    let _ = lum.max_cd();
    for d in [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.6, -0.48, 0.64]] {
        let _ = lum.intensity_cd(d);
    }
    if let Some(s) = spectrace::photometry::DirectionSampler::new(lum) {
        for (u1, u2) in [(0.0, 0.0), (0.5, 0.25), (0.999999, 0.999999)] {
            let (d, _) = s.sample(lum, u1, u2);
            let _ = s.pdf(lum, d);
        }
    }
    let _ = spectrace::photometry::ies_writer::write_ies_2019(lum, "fuzz");
    let _ = spectrace::photometry::eulumdat_writer::write_eulumdat(lum, "fuzz");
}
