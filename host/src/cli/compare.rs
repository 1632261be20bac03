//! `spectrace compare A.exr B.exr [--diff OUT.png] [--exclude-light] [--json]`: error of render
//! A against reference B (RMSE, relative MSE, CIEDE2000 mean and 99th percentile) and an
//! optional false-colour ΔE00 map.

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
}

/// Run `spectrace compare`.
pub fn run(args: &CompareArgs) -> Result<(), String> {
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
