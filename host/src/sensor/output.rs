//! What `render --sensors-out DIR` writes for each sensor: `DIR/NAME.csv` (columns
//! `x,y,z,lux,stderr`, one row per point, row-major along edge0) and `DIR/NAME.png`, a
//! false-colour map of the illuminance over the grid (viridis) with a scale bar in lux, isolux
//! contours (marching squares between the points) at round levels also marked on the scale bar,
//! and the mean, minimum, maximum and uniformity U₀ = E_min/E_mean in the title.

use super::estimate::SensorReading;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Write the CSV (full precision, shortest round-trip decimals).
pub fn write_csv(reading: &SensorReading, path: &Path) -> Result<(), String> {
    let mut out = String::from("x,y,z,lux,stderr\n");
    for ((p, l), e) in reading.points.iter().zip(&reading.lux).zip(&reading.stderr) {
        let _ = writeln!(out, "{},{},{},{},{}", p.x, p.y, p.z, l, e);
    }
    std::fs::write(path, out).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// Write the CSV and the PNG of `reading` into `dir` (created if missing); returns the paths.
pub fn write_outputs(reading: &SensorReading, dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let csv = dir.join(format!("{}.csv", reading.name));
    write_csv(reading, &csv)?;
    let png = dir.join(format!("{}.png", reading.name));
    write_png(reading, &png)?;
    Ok(vec![csv, png])
}

/// Viridis (matplotlib's default colour map, van der Walt & Smith 2015), 8 stops sampled from
/// its published table; linear in between.
const VIRIDIS: [[u8; 3]; 8] = [
    [68, 1, 84],
    [70, 50, 127],
    [54, 92, 141],
    [39, 127, 143],
    [31, 162, 136],
    [74, 194, 110],
    [160, 219, 57],
    [254, 232, 37],
];

/// The colour of `t` ∈ [0, 1] (clamped).
pub fn viridis(t: f64) -> RGBColor {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let c = |k: usize| (VIRIDIS[i][k] as f64 * (1.0 - f) + VIRIDIS[i + 1][k] as f64 * f) as u8;
    RGBColor(c(0), c(1), c(2))
}

/// Round contour levels strictly inside (lo, hi): multiples of 1, 2 or 5 × 10ⁿ, about 6 of them.
pub fn contour_levels(lo: f64, hi: f64) -> Vec<f64> {
    if !(hi > lo) || !lo.is_finite() || !hi.is_finite() {
        return Vec::new();
    }
    let raw = (hi - lo) / 6.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let mut v = (lo / step).floor() * step + step;
    let mut out = Vec::new();
    while v < hi && out.len() < 20 {
        if v > lo {
            out.push(v);
        }
        v += step;
    }
    out
}

/// Marching squares on the point grid (values row-major, `nx × ny`, point (i, j) at grid
/// coordinates (i, j)): the segments where the bilinear field crosses `level`.
pub fn contour_segments(
    values: &[f64],
    nx: usize,
    ny: usize,
    level: f64,
) -> Vec<((f64, f64), (f64, f64))> {
    let mut segs = Vec::new();
    if nx < 2 || ny < 2 {
        return segs;
    }
    let at = |i: usize, j: usize| values[j * nx + i];
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            // Corners counter-clockwise: (i, j), (i+1, j), (i+1, j+1), (i, j+1).
            let c = [
                ((i as f64, j as f64), at(i, j)),
                (((i + 1) as f64, j as f64), at(i + 1, j)),
                (((i + 1) as f64, (j + 1) as f64), at(i + 1, j + 1)),
                ((i as f64, (j + 1) as f64), at(i, j + 1)),
            ];
            let mut cuts = Vec::with_capacity(4);
            for e in 0..4 {
                let (pa, va) = c[e];
                let (pb, vb) = c[(e + 1) % 4];
                if (va < level) != (vb < level) {
                    let t = (level - va) / (vb - va);
                    cuts.push((pa.0 + t * (pb.0 - pa.0), pa.1 + t * (pb.1 - pa.1)));
                }
            }
            match cuts.len() {
                2 => segs.push((cuts[0], cuts[1])),
                4 => {
                    // Saddle: decide by the cell's centre value.
                    let centre = (c[0].1 + c[1].1 + c[2].1 + c[3].1) / 4.0;
                    if (centre < level) == (c[0].1 < level) {
                        segs.push((cuts[0], cuts[3]));
                        segs.push((cuts[1], cuts[2]));
                    } else {
                        segs.push((cuts[0], cuts[1]));
                        segs.push((cuts[2], cuts[3]));
                    }
                }
                _ => {}
            }
        }
    }
    segs
}

/// A number of lux for a label: 3 significant digits.
fn fmt_lux(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.digits$}")
}

const SIZE: (u32, u32) = (900, 700);

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    r: &SensorReading,
    (quantity, unit): (&str, &str),
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let (nx, ny) = (r.resolution.0 as usize, r.resolution.1 as usize);
    let (lo, hi) = r.min_max();
    let (mean, _) = r.mean();
    let top = if hi > lo { hi } else { lo + 1.0 };
    let norm = |v: f64| (v - lo) / (top - lo);
    let (map_area, bar_area) = root.split_horizontally(SIZE.0 - 150);
    // Lengths along the two edges, m.
    let (len0, len1) = if r.points.len() > 1 && nx * ny == r.points.len() {
        let p = |i: usize, j: usize| r.points[j * nx + i];
        let step0 = if nx > 1 {
            (p(1, 0) - p(0, 0)).length()
        } else {
            1.0
        };
        let step1 = if ny > 1 {
            (p(0, 1) - p(0, 0)).length()
        } else {
            1.0
        };
        (step0 * nx as f64, step1 * ny as f64)
    } else {
        (1.0, 1.0)
    };
    let uniformity = if mean > 0.0 { lo / mean } else { 0.0 };
    let title = format!(
        "{}: {quantity} ({unit}), mean {}, min {}, max {}, U0 {:.2}",
        r.name,
        fmt_lux(mean),
        fmt_lux(lo),
        fmt_lux(hi),
        uniformity
    );
    let mut chart = ChartBuilder::on(&map_area)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(0.0..len0, 0.0..len1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("along edge0 (m)")
        .y_desc("along edge1 (m)")
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let (c0, c1) = (len0 / nx as f64, len1 / ny as f64);
    chart
        .draw_series((0..nx * ny).map(|k| {
            let (i, j) = (k % nx, k / nx);
            Rectangle::new(
                [
                    (i as f64 * c0, j as f64 * c1),
                    ((i + 1) as f64 * c0, (j + 1) as f64 * c1),
                ],
                viridis(norm(r.lux[k])).filled(),
            )
        }))
        .map_err(err)?;
    let levels = contour_levels(lo, hi);
    for level in &levels {
        // Point (i, j) sits at the centre of its cell.
        let to_xy = |(gi, gj): (f64, f64)| ((gi + 0.5) * c0, (gj + 0.5) * c1);
        let segs = contour_segments(&r.lux, nx, ny, *level);
        chart
            .draw_series(
                segs.into_iter().map(|(a, b)| {
                    PathElement::new(vec![to_xy(a), to_xy(b)], WHITE.stroke_width(2))
                }),
            )
            .map_err(err)?;
    }
    // The scale bar: a gradient from min to max with the contour levels marked.
    let mut bar = ChartBuilder::on(&bar_area)
        .margin_top(50)
        .margin_bottom(52)
        .margin_right(12)
        .y_label_area_size(70)
        .caption(unit, ("sans-serif", 16))
        .build_cartesian_2d(0.0..1.0, lo..top)
        .map_err(err)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(8)
        .y_label_formatter(&|v| fmt_lux(*v))
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(err)?;
    let steps = 200;
    bar.draw_series((0..steps).map(|k| {
        let a = lo + (top - lo) * k as f64 / steps as f64;
        let b = lo + (top - lo) * (k + 1) as f64 / steps as f64;
        Rectangle::new([(0.0, a), (1.0, b)], viridis(norm(a)).filled())
    }))
    .map_err(err)?;
    bar.draw_series(
        levels
            .iter()
            .map(|l| PathElement::new(vec![(0.0, *l), (1.0, *l)], WHITE.stroke_width(2))),
    )
    .map_err(err)?;
    root.present().map_err(err)
}

/// Write the false-colour PNG.
pub fn write_png(reading: &SensorReading, path: &Path) -> Result<(), String> {
    write_png_of(reading, path, ("illuminance", "lx"))
}

/// [`write_png`] of another quantity per point (the values in `reading.lux`), e.g. the
/// daylight factor in %: `(quantity, unit)` label the title and the scale bar.
pub fn write_png_of(
    reading: &SensorReading,
    path: &Path,
    label: (&str, &str),
) -> Result<(), String> {
    crate::analysis::plot::register_font();
    let werr = |m: String| format!("cannot write {}: {m}", path.display());
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(
        BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area(),
        reading,
        label,
    )
    .map_err(werr)?;
    let file = std::fs::File::create(path).map_err(|e| werr(e.to_string()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), SIZE.0, SIZE.1);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(|e| werr(e.to_string()))?;
    w.write_image_data(&rgb).map_err(|e| werr(e.to_string()))?;
    w.finish().map_err(|e| werr(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Levels are round and inside the range: 0..100 gives 20, 40, 60, 80 (step 20 for a raw
    /// step of 16.7); a flat field has none.
    #[test]
    fn contour_levels_are_round() {
        assert_eq!(contour_levels(0.0, 100.0), vec![20.0, 40.0, 60.0, 80.0]);
        assert!(contour_levels(5.0, 5.0).is_empty());
    }

    /// A linear ramp v = i over a 3×3 grid crosses 0.5 in one straight line at i = 0.5: two
    /// segments (one per cell row), each from (0.5, j) to (0.5, j+1) (exact arithmetic).
    #[test]
    fn marching_squares_on_a_ramp() {
        let v: Vec<f64> = (0..9).map(|k| (k % 3) as f64).collect();
        let s = contour_segments(&v, 3, 3, 0.5);
        assert_eq!(s.len(), 2);
        for (a, b) in s {
            assert_eq!(a.0, 0.5);
            assert_eq!(b.0, 0.5);
            assert_eq!((a.1 - b.1).abs(), 1.0);
        }
    }
}
