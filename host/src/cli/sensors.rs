//! The sensor part of `spectrace render`: measure the scene's illuminance sensors after the
//! image (`--sensors-out DIR` writes `DIR/NAME.csv` and `DIR/NAME.png`) and write per-pixel
//! luminance (`--luminance-out F.csv`). Each sensor's line says which estimator measured it.

use crate::builtin::sensor::grid::IlluminanceGrid;
use crate::film::XyzImage;
use crate::integrator::{IntegratorKind, RenderSettings};
use crate::scene::Scene;
use crate::sensor::{measure, Estimator, MeasureSettings, SensorReading};
use std::path::Path;

/// Measure every sensor of `scene` with the estimator of `integrator`, print one summary line
/// each and write the files to `out` when given. `spp` is the render's samples per pixel, the
/// default samples per point.
pub fn measure_sensors(
    scene: &Scene,
    settings: &RenderSettings,
    integrator: IntegratorKind,
    spp: u32,
    out: Option<&Path>,
) -> Result<(), String> {
    if scene.sensors.is_empty() && scene.glare.is_empty() {
        if let Some(dir) = out {
            println!(
                "  warning: --sensors-out {}: the scene has no sensors; nothing written",
                dir.display()
            );
        }
        return Ok(());
    }
    let estimator = Estimator::for_integrator(integrator);
    println!("sensors ({integrator}: {}):", estimator.describe());
    // The daylight factor's outdoor reference (or why there is none), once for all grids.
    let df_reference = if scene.sensors.is_empty() {
        Err(String::new())
    } else {
        crate::sensor::daylight_factor::reference(scene)
    };
    for grid in &scene.sensors {
        let ms = MeasureSettings {
            estimator,
            samples: grid.samples.unwrap_or(spp.max(1)),
            seed: settings.seed,
            threads: settings.threads,
            tracer: settings.tracer,
        };
        let t = std::time::Instant::now();
        let r = measure(scene, grid, &ms).map_err(|e| format!("sensor {:?}: {e}", grid.name))?;
        print_reading(&r, grid, t.elapsed().as_secs_f64());
        let rep = crate::sensor::report::report(&r, &df_reference)?;
        for line in crate::sensor::report::summary_lines(&r, &rep) {
            println!("{line}");
        }
        if let Some(dir) = out {
            for w in crate::sensor::output::write_outputs(&r, dir)? {
                println!("  wrote {}", w.display());
            }
            for w in crate::sensor::report::write_json(&r, &rep, dir)? {
                println!("  wrote {}", w.display());
            }
        }
    }
    super::sensors_glare::measure_glare_observers(scene, settings, spp, out)?;
    Ok(())
}

/// A grid's summary line and its warnings (non-finite samples dropped, 0 lx everywhere).
fn print_reading(r: &SensorReading, grid: &IlluminanceGrid, seconds: f64) {
    let (mean, se) = r.mean();
    let (lo, hi) = r.min_max();
    let max_se = r.stderr.iter().cloned().fold(0.0, f64::max);
    println!(
        "  {}: {}×{} points, {} samples each, mean {:.4} ± {:.4} lx, min {:.4} lx, max \
         {:.4} lx, largest standard error {:.4} lx ({:.2} s)",
        r.name, r.resolution.0, r.resolution.1, r.samples, mean, se, lo, hi, max_se, seconds
    );
    if r.non_finite > 0 {
        println!(
            "  warning: sensor {:?}: {} non-finite samples dropped",
            r.name, r.non_finite
        );
    }
    if hi <= 0.0 {
        // + 0.0 prints −0 as 0.
        let n = grid.normal() + glam::DVec3::ZERO;
        println!(
            "  warning: sensor {:?} reads 0 lx everywhere: its normal edge0 × edge1 = \
             ({:.3}, {:.3}, {:.3}) may face away from the light (swap edge0 and edge1)",
            r.name, n.x, n.y, n.z
        );
    }
}

/// `--luminance-out F.csv`: per-pixel luminance of the image, cd/m².
pub fn write_luminance(scene: &Scene, image: &XyzImage, path: &Path) -> Result<(), String> {
    let mean = crate::sensor::luminance::write_luminance_csv(image, scene.observer.as_ref(), path)?;
    println!(
        "  wrote {} (luminance per pixel, mean {mean:.4} cd/m²)",
        path.display()
    );
    Ok(())
}
