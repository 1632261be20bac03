//! `spectrace compare A.exr B.exr [--diff OUT.png] [--exclude-light] [--json]`: error of render
//! A against reference B (RMSE, relative MSE, CIEDE2000 mean and 99th percentile) and an
//! optional false-colour ΔE00 map. With `--spectral`, two spectral EXRs (`S0.<λ>nm` channels)
//! are compared channel by channel.

use crate::analysis::{
    compare_files, diff_image::DELTA_E_STOPS, write_delta_e_png, CompareOptions,
};
use std::path::PathBuf;

/// Arguments of `spectrace compare`.
#[derive(clap::Args, Debug, Clone)]
pub struct CompareArgs {
    /// The image to judge (OpenEXR with channels R, G, B in linear sRGB).
    pub test: PathBuf,
    /// The reference (same size, same channels).
    pub reference: PathBuf,
    /// Write the per-pixel CIEDE2000 as a false-colour PNG here.
    #[arg(long)]
    pub diff: Option<PathBuf>,
    /// Leave out the directly visible light (reference > 1.0, dilated by one pixel).
    #[arg(long)]
    pub exclude_light: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Compare two spectral EXRs (`S0.<λ>nm` channels, Fichet–Pacanowski–Wilkie 2021 layout)
    /// instead: RMSE over all wavelength channels, the worst channel's RMSE (W/(m²·sr·nm)) and
    /// the RMSE of the XYZ integrated from them by the trapezoid rule (CIE 1931 2°; see
    /// docs/spectral.md).
    #[arg(long, conflicts_with_all = ["diff", "exclude_light"])]
    pub spectral: bool,
}

/// `compare --spectral`: per-bin errors of spectral image A against B.
fn run_spectral(args: &CompareArgs) -> Result<(), String> {
    use crate::film::spectral::SpectralImage;
    let a = SpectralImage::read_exr(&args.test)?;
    let b = SpectralImage::read_exr(&args.reference)?;
    if (a.width, a.height) != (b.width, b.height) {
        return Err(format!(
            "{} is {}×{} but {} is {}×{}",
            args.test.display(),
            a.width,
            a.height,
            args.reference.display(),
            b.width,
            b.height
        ));
    }
    if a.wavelengths.len() != b.wavelengths.len()
        || a.wavelengths
            .iter()
            .zip(&b.wavelengths)
            .any(|(x, y)| (x - y).abs() > 1e-6)
    {
        return Err(format!(
            "{} and {} have different wavelength bins ({} and {} channels, {}–{} nm and {}–{} nm)",
            args.test.display(),
            args.reference.display(),
            a.wavelengths.len(),
            b.wavelengths.len(),
            a.wavelengths.first().unwrap_or(&0.0),
            a.wavelengths.last().unwrap_or(&0.0),
            b.wavelengths.first().unwrap_or(&0.0),
            b.wavelengths.last().unwrap_or(&0.0)
        ));
    }
    let n = a.wavelengths.len().max(1);
    let pixels = (a.width as usize * a.height as usize).max(1);
    let mut per_bin = vec![0.0f64; n];
    for (i, (x, y)) in a.values.iter().zip(&b.values).enumerate() {
        per_bin[i % n] += (x - y) * (x - y);
    }
    let total: f64 = per_bin.iter().sum();
    let rmse = (total / (pixels * n) as f64).sqrt();
    let (worst_bin, worst) = per_bin
        .iter()
        .enumerate()
        .map(|(k, s)| (k, (s / pixels as f64).sqrt()))
        .fold((0, 0.0), |m, v| if v.1 > m.1 { v } else { m });
    let obs = crate::color::CieObserverKind::Cie1931_2.get();
    let (xa, xb) = (a.to_xyz(obs), b.to_xyz(obs));
    let xyz_rmse = (xa
        .iter()
        .zip(&xb)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).powi(2)).sum::<f64>())
        .sum::<f64>()
        / (3 * pixels) as f64)
        .sqrt();
    let worst_nm = a.wavelengths.get(worst_bin).copied().unwrap_or(0.0);
    if args.json {
        println!(
            "{{\"bins\":{n},\"rmse\":{rmse},\"worst_bin_nm\":{worst_nm},\"worst_bin_rmse\":{worst},\"xyz_rmse\":{xyz_rmse}}}"
        );
        return Ok(());
    }
    println!(
        "{} vs {} ({}×{}, {} bins of {} nm)",
        args.test.display(),
        args.reference.display(),
        a.width,
        a.height,
        n,
        a.step
    );
    println!("  RMSE over all bins   {rmse:.6} W/(m²·sr·nm)");
    println!("  worst bin            {worst_nm} nm: RMSE {worst:.6}");
    println!("  XYZ from bins RMSE   {xyz_rmse:.6}");
    Ok(())
}

/// Run `spectrace compare`.
pub fn run(args: &CompareArgs) -> Result<(), String> {
    if args.spectral {
        return run_spectral(args);
    }
    let options = CompareOptions {
        exclude_light: args.exclude_light,
    };
    let (c, per_pixel, (w, h)) =
        compare_files(&args.test, &args.reference, options).map_err(|e| e.to_string())?;
    if let Some(diff) = &args.diff {
        write_delta_e_png(diff, w, h, &per_pixel).map_err(|e| e.to_string())?;
    }
    if args.json {
        println!("{}", serde_json::to_string(&c).map_err(|e| e.to_string())?);
        return Ok(());
    }
    println!(
        "{} vs {} ({}×{}, {} pixels compared, {} light pixels left out, {} non-finite)",
        args.test.display(),
        args.reference.display(),
        w,
        h,
        c.pixels,
        c.excluded_light,
        c.non_finite
    );
    println!("  RMSE              {:.6}", c.rmse);
    println!(
        "  relative MSE      {:.6}  (mean (a-b)²/(b²+ε), ε = {})",
        c.rel_mse, c.rel_mse_epsilon
    );
    println!(
        "  CIEDE2000         mean {:.4}, 99th percentile {:.4}, max {:.4}",
        c.delta_e_mean, c.delta_e_p99, c.delta_e_max
    );
    println!(
        "  mean ratio R,G,B  {:.4} {:.4} {:.4}",
        c.mean_ratio[0], c.mean_ratio[1], c.mean_ratio[2]
    );
    if let Some(diff) = &args.diff {
        let stops: Vec<String> = DELTA_E_STOPS
            .iter()
            .map(|(d, c)| format!("{d}→#{:02x}{:02x}{:02x}", c[0], c[1], c[2]))
            .collect();
        println!(
            "  wrote {} (ΔE00 colour map {}, grey = left out)",
            diff.display(),
            stops.join(" ")
        );
    }
    Ok(())
}
