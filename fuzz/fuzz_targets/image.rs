//! The image readers (PNG, JPEG, Radiance HDR, OpenEXR RGB and spectral): any bytes give a
//! decoded image or an error, never a panic or an allocation beyond the budget; an accepted
//! image has `width × height` pixels of finite values ≥ 0, and a small one becomes an
//! environment map whose sampling answers are finite.
#![no_main]
use spectrace::texture::image_file::{decode, LoadedImage};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    // A 256 MiB budget: what a hostile header may ask for is refused before decoding.
    let Ok((image, _)) = decode(data, None, 256 << 20) else {
        return;
    };
    let (w, h) = image.size();
    match &image {
        LoadedImage::Rgb(i) => {
            assert_eq!(i.pixels.len(), w as usize * h as usize);
            assert!(i.pixels.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
        }
        LoadedImage::Spectral(s) => {
            assert_eq!(s.values.len(), w as usize * h as usize * s.nodes);
            assert!(s.values.iter().all(|v| v.is_finite() && *v >= 0.0));
        }
    }
    if (w as u64) * (h as u64) <= 1 << 16 {
        let id = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        if let Ok(map) = spectrace::light::EnvironmentMap::new("fuzz", image, &id, 1.0) {
            use spectrace::light::EnvironmentRadiance;
            let p = glam::Vec3A::ZERO;
            if let Some((d, pdf)) = map.sample_direction(p, glam::Vec2::new(0.3, 0.7)) {
                assert!(d.is_finite() && pdf.is_finite() && pdf >= 0.0);
            }
            assert!(map.mean_radiance().is_finite());
        }
    }
});
