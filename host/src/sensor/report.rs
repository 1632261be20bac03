//! The companion JSON of a sensor grid (`--sensors-out DIR` writes `DIR/NAME.json` next to the
//! CSV) and the summary lines: the grid statistics ([`super::statistics`]) in lux and, when
//! the scene's only light is its sky, the daylight factor ([`super::daylight_factor`]) in per
//! cent with the same statistics.

use super::estimate::SensorReading;
use super::statistics::{of_reading, statistics, GridStatistics};
use std::path::{Path, PathBuf};

/// What the report says about one grid.
#[derive(Clone, Debug)]
pub struct GridReport {
    /// Statistics in lx.
    pub lux: GridStatistics,
    /// The daylight factor: the outdoor reference (lx), per-point DF (%), their errors (%) and
    /// statistics (%); or why there is none.
    pub daylight: Result<(f64, Vec<f64>, Vec<f64>, GridStatistics), String>,
}

/// The report of `r`, with the outdoor reference `reference` (lx) or why there is none.
pub fn report(r: &SensorReading, reference: &Result<f64, String>) -> Result<GridReport, String> {
    let lux = of_reading(r).map_err(|e| format!("sensor {:?}: {e}", r.name))?;
    let daylight = match reference {
        Ok(e_out) => {
            let df: Vec<f64> = r.lux.iter().map(|e| 100.0 * e / e_out).collect();
            let se: Vec<f64> = r.stderr.iter().map(|e| 100.0 * e / e_out).collect();
            // The reference is a deterministic quadrature (1e-4): its error is not added.
            let st = statistics(&df, &se, 100.0 * r.mean_stderr / e_out)?;
            Ok((*e_out, df, se, st))
        }
        Err(e) => Err(e.clone()),
    };
    Ok(GridReport { lux, daylight })
}

/// Summary lines for the render output.
pub fn summary_lines(r: &SensorReading, rep: &GridReport) -> Vec<String> {
    let s = &rep.lux;
    let mut out = vec![format!(
        "    Emin {:.4} ± {:.4} lx, Ē {:.4} ± {:.4} lx, Emax {:.4} ± {:.4} lx, U0 = Emin/Ē {:.4} ± {:.4}, Emin/Emax {:.4} ± {:.4}",
        s.e_min.value, s.e_min.stderr, s.e_mean.value, s.e_mean.stderr, s.e_max.value,
        s.e_max.stderr, s.u0.value, s.u0.stderr, s.min_over_max.value, s.min_over_max.stderr
    )];
    match &rep.daylight {
        Ok((e_out, _, _, d)) => out.push(format!(
            "    daylight factor (outdoor horizontal {:.1} lx): min {:.3} ± {:.3} %, mean {:.3} ± {:.3} %, max {:.3} ± {:.3} %",
            e_out, d.e_min.value, d.e_min.stderr, d.e_mean.value, d.e_mean.stderr, d.e_max.value, d.e_max.stderr
        )),
        Err(why) => out.push(format!("    no daylight factor for {:?}: {why}", r.name)),
    }
    out
}

/// Write `DIR/NAME.json` and, with a daylight factor, `DIR/NAME_df.csv` (x,y,z,df_percent,stderr)
/// and `DIR/NAME_df.png` (false-colour map of the daylight factor, %).
pub fn write_json(r: &SensorReading, rep: &GridReport, dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut written = Vec::new();
    let df = match &rep.daylight {
        Ok((e_out, df, se, st)) => {
            let csv = dir.join(format!("{}_df.csv", r.name));
            let mut text = String::from("x,y,z,df_percent,stderr\n");
            for ((p, v), e) in r.points.iter().zip(df).zip(se) {
                text.push_str(&format!("{},{},{},{},{}\n", p.x, p.y, p.z, v, e));
            }
            std::fs::write(&csv, text)
                .map_err(|e| format!("cannot write {}: {e}", csv.display()))?;
            written.push(csv);
            let png = dir.join(format!("{}_df.png", r.name));
            let as_df = SensorReading {
                name: format!("{}_df", r.name),
                lux: df.clone(),
                stderr: se.clone(),
                ..r.clone()
            };
            super::output::write_png_of(&as_df, &png, ("daylight factor", "%"))?;
            written.push(png);
            serde_json::json!({
                "definition": "100 × E / E_outdoor, E_outdoor the unobstructed horizontal illuminance of the sky (+y up)",
                "outdoor_horizontal_lx": e_out,
                "unit": "%",
                "statistics": st,
            })
        }
        Err(why) => serde_json::json!({ "not_computed": why }),
    };
    let j = serde_json::json!({
        "name": r.name,
        "unit": "lx",
        "points": r.lux.len(),
        "resolution": [r.resolution.0, r.resolution.1],
        "samples_per_point": r.samples,
        "estimator": format!("{:?}", r.estimator),
        "non_finite_samples": r.non_finite,
        "statistics": rep.lux,
        "daylight_factor": df,
        "notes": "standard errors: Ē from the points' independent errors; Emin and Emax those of the point attaining them; ratios by first-order propagation. The minimum of noisy values is biased low by about one point error.",
    });
    let path = dir.join(format!("{}.json", r.name));
    std::fs::write(
        &path,
        serde_json::to_string_pretty(&j).unwrap_or_default() + "\n",
    )
    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    written.push(path);
    Ok(written)
}
