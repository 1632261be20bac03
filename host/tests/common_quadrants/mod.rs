//! The quadrant check shared by the tests that compare an integrator with the path tracer on a
//! 16 × 16 image (`daylight_sky.rs`, `render_envmap_paths.rs`,
//! `integrators_bdpt_environment_mis.rs`).

/// Per 8 × 8 quadrant of two 16 × 16 images (one value per pixel): the mean of `img − pt` over
/// its standard error from the pixels' spread. Asserts the standard error is under 2% of the
/// path tracer's level (the check has power) and the mean difference within 4 of them (the
/// two estimators agree).
pub fn assert_quadrants_agree(label: &str, img: &[f64], pt: &[f64]) {
    for q in 0..4 {
        let (qx, qy) = (q % 2, q / 2);
        let idx: Vec<usize> = (0..16 * 16)
            .filter(|k| (k % 16) / 8 == qx && (k / 16) / 8 == qy)
            .collect();
        let n = idx.len() as f64;
        let d: Vec<f64> = idx.iter().map(|&k| img[k] - pt[k]).collect();
        let md = d.iter().sum::<f64>() / n;
        let var = d.iter().map(|v| (v - md).powi(2)).sum::<f64>() / (n - 1.0);
        let se = (var / n).sqrt();
        let level = idx.iter().map(|&k| pt[k]).sum::<f64>() / n;
        eprintln!(
            "{label} quadrant {q}: PT {level:.5}, {label} − PT = {md:+.5} ± {se:.5} ({:+.2}%)",
            100.0 * md / level
        );
        assert!(se < 0.02 * level, "{label} quadrant {q}: SE {se} too large");
        assert!(
            md.abs() < 4.0 * se,
            "{label} quadrant {q}: {label} − PT = {md} ± {se} (PT level {level})"
        );
    }
}
