//! The glare part of `spectrace render`: each `glare_observer` of the scene renders its
//! fisheye luminance image and prints its UGR; `--sensors-out DIR` writes `DIR/NAME.exr`,
//! `DIR/NAME.hdr` (Radiance picture for evalglare) and `DIR/NAME.json`.

use crate::integrator::RenderSettings;
use crate::scene::Scene;
use crate::sensor::glare::{measure_glare, write_outputs};
use std::path::Path;

/// Measure every glare observer of `scene` (`spp`: the default samples per pixel).
pub fn measure_glare_observers(
    scene: &Scene,
    settings: &RenderSettings,
    spp: u32,
    out: Option<&Path>,
) -> Result<(), String> {
    for obs in &scene.glare {
        let t = std::time::Instant::now();
        let samples = obs.samples.unwrap_or(spp.max(1));
        let r = measure_glare(
            scene,
            obs,
            samples,
            settings.seed,
            settings.threads,
            &settings.tracer,
        )
        .map_err(|e| format!("sensor {:?}: {e}", obs.name))?;
        let ugr = if r.ugr.is_finite() {
            format!("UGR {:.2} ± {:.2}", r.ugr, r.ugr_stderr)
        } else if r.source_pixels == 0 {
            "no glare source above the threshold (UGR undefined, below any scale)".to_string()
        } else {
            "the background is black (UGR unbounded)".to_string()
        };
        println!(
            "  {}: glare, {}×{} fisheye, {} samples per pixel: {ugr}; {} source pixels ({:.4} sr) above {:.1} cd/m², background {:.3} cd/m², vertical illuminance at the eye {:.2} lx ({:.2} s)",
            r.name,
            r.resolution,
            r.resolution,
            r.samples,
            r.source_pixels,
            r.source_solid_angle,
            r.threshold,
            r.background,
            r.e_vertical,
            t.elapsed().as_secs_f64()
        );
        if let Some(dir) = out {
            for w in write_outputs(&r, obs, dir)? {
                println!("  wrote {}", w.display());
            }
        }
    }
    Ok(())
}
