//! `spectrace merge PARTS… -o OUT.exr [--png OUT.png] [--state OUT.state]
//! [--spectral-exr OUT.spectral.exr]`: combine the state files of the slices of one render
//! (`render --slice K/M`) into its image, and its spectral image when the slices carry spectral
//! sums (`render --spectral-exr`; written to `--spectral-exr`, by default beside the output as
//! `NAME.spectral.exr`). The parts must come
//! from the same scene, settings, seed and sample count, with every slice present exactly once;
//! the merged image is bit for bit the one `render --spp N` makes on one machine, because the
//! film's sums are exact (see `docs/distributed.md`).

use crate::color::RgbColorSpace;
use crate::film::RenderState;
use std::path::PathBuf;

/// Arguments of `spectrace merge`.
#[derive(clap::Args, Debug, Clone)]
pub struct MergeArgs {
    /// State files of the slices (any order).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// OpenEXR output (R, G, B linear + X, Y, Z).
    #[arg(short = 'o', long = "output", default_value = "render.exr")]
    pub output: PathBuf,
    /// sRGB PNG preview (default: the EXR name with .png).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Also write the merged state (a whole-render state file).
    #[arg(long)]
    pub state: Option<PathBuf>,
    /// Add the `rejected` diagnostic channel to the EXR.
    #[arg(long = "diagnostic-layer")]
    pub diagnostic_layer: bool,
    /// Where the merged spectral image goes when the slices carry spectral sums (default: the
    /// output's name with `.spectral.exr`).
    #[arg(long = "spectral-exr", value_name = "OUT.exr")]
    pub spectral_exr: Option<PathBuf>,
}

/// The default spectral output beside `output`: `NAME.spectral.exr`.
fn spectral_path(output: &std::path::Path) -> PathBuf {
    output.with_extension("spectral.exr")
}

/// Run `spectrace merge`.
pub fn run(args: &MergeArgs) -> Result<(), String> {
    let mut parts = Vec::with_capacity(args.parts.len());
    for p in &args.parts {
        let s = RenderState::load(p).map_err(|e| e.to_string())?;
        parts.push((p.clone(), s));
    }
    let merged = RenderState::merge_parts(&parts)?;
    let space = RgbColorSpace::by_name(&merged.rgb_space).ok_or_else(|| {
        format!(
            "{}: unknown RGB space {:?} in the state",
            args.parts[0].display(),
            merged.rgb_space
        )
    })?;
    let image = merged.film.image();
    let spectral = merged.film.spectral_image();
    if spectral.is_none() {
        if let Some(p) = &args.spectral_exr {
            return Err(format!(
                "--spectral-exr {}: the slices carry no spectral sums (render them with \
                 --spectral-exr)",
                p.display()
            ));
        }
    }
    let outputs = super::output_paths::output_paths(&args.output, args.png.as_deref())?;
    let (w, h) = merged.film.resolution();
    let extra = super::render::diagnostic_layers(&merged.film, args.diagnostic_layer);
    let written = super::render::save_image(
        &image,
        outputs.exr.as_deref(),
        &outputs.png,
        &space,
        merged.png_exposure,
        extra,
    )?;
    println!(
        "merged {} slices: {w}×{h}, {} spp, seed {}",
        parts.len(),
        merged.spp_total,
        merged.seed
    );
    for line in merged.film.rejected.summary() {
        println!("  {line}");
    }
    if let Some(sp) = &spectral {
        let path = args
            .spectral_exr
            .clone()
            .unwrap_or_else(|| spectral_path(&args.output));
        sp.write_exr(&path)?;
        // The scene's observer is named in the settings (`observer=NAME`); a plugin observer
        // is not available here, so the XYZ comparison is left out for it.
        let observer = merged
            .settings
            .split_whitespace()
            .find_map(|kv| kv.strip_prefix("observer="))
            .and_then(crate::color::CieObserverKind::from_name);
        match observer {
            Some(o) => println!(
                "{}",
                super::render::spectral_summary(&path, sp, &image, o.get())
            ),
            None => println!("  wrote {}", path.display()),
        }
    }
    if let Some(p) = &args.state {
        merged.save(p).map_err(|e| e.to_string())?;
        println!("  wrote {}", p.display());
    }
    for wr in written {
        println!("  wrote {}", wr.display());
    }
    Ok(())
}
