//! Luminance in cd/m² per pixel of a rendered image (`render --luminance-out F.csv`):
//! `L_v = 683 lm/W × ∫ L_λ V(λ) dλ`. The film stores `Y = ∫ L ȳ dλ / ∫ ȳ dλ` (the film
//! convention, W/(m²·sr) per unit ∫ȳ), so `L_v = 683 × Y × ∫ȳ dλ` when the film's observer is
//! the CIE 1931 2° one, whose ȳ is V(λ). With another observer the film's Y is not luminance
//! and the file is refused.

use crate::color::Observer;
use crate::film::XyzImage;
use std::fmt::Write as _;
use std::path::Path;

/// Per-pixel luminance (cd/m²), row-major, top row first; an error if the observer's ȳ is not
/// V(λ).
pub fn luminance_cd_m2(image: &XyzImage, observer: &dyn Observer) -> Result<Vec<f64>, String> {
    if observer.name() != crate::color::CieObserverKind::Cie1931_2.name() {
        return Err(format!(
            "luminance needs the CIE 1931 2° observer (its ȳ is the photopic V(λ)); the scene's \
             film uses `{}`",
            observer.name()
        ));
    }
    let k = super::KM_LM_PER_W * observer.integral_y();
    Ok(image.xyz.iter().map(|p| p[1] * k).collect())
}

/// Write `x,y,cd_m2` per pixel (x to the right, y down from the top row) and return the mean.
pub fn write_luminance_csv(
    image: &XyzImage,
    observer: &dyn Observer,
    path: &Path,
) -> Result<f64, String> {
    let lv = luminance_cd_m2(image, observer)?;
    let mut out = String::from("x,y,cd_m2\n");
    for (k, v) in lv.iter().enumerate() {
        let _ = writeln!(
            out,
            "{},{},{}",
            k % image.width as usize,
            k / image.width as usize,
            v
        );
    }
    std::fs::write(path, out).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(lv.iter().sum::<f64>() / lv.len().max(1) as f64)
}
