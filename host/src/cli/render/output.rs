//! The files a render writes (step 6 of the pipeline in [`super`]): the EXR and PNG (with a
//! rescue copy when the EXR cannot be written), the PNG exposure, the diagnostic layer and the
//! spectral EXR with its summary line.

use super::RenderArgs;
use crate::film::{write_exr_with_layers, write_png, FilmState, XyzImage};
use crate::scene::Scene;
use std::path::{Path, PathBuf};

/// The PNG's exposure multiplier and, when it was picked automatically, a line for the summary.
pub(super) fn png_exposure(
    args: &RenderArgs,
    scene: &Scene,
    image: &XyzImage,
) -> (f64, Option<String>) {
    if let Some(ev) = args.exposure {
        return (2f64.powf(ev), None);
    }
    if scene.options.png_exposure_given {
        return (scene.options.png_exposure, None);
    }
    match crate::film::exposure::auto_exposure(image) {
        Some(a) => (
            a.multiplier,
            Some(format!(
                "PNG exposure chosen automatically: {:+.1} EV (×{:.4e}), because at 0 EV the image \
                 would be {}; the EXR is unscaled; set it with --exposure EV or `png_exposure`",
                a.ev(),
                a.multiplier,
                if a.was_dark {
                    "nearly black"
                } else {
                    "mostly clipped"
                }
            )),
        ),
        None => (scene.options.png_exposure, None),
    }
}

/// Write `--spectral-exr` from the film's spectral sums, if asked for; returns the file and a
/// summary line comparing the XYZ integrated from it with the film's `image`.
pub(super) fn write_spectral(
    args: &RenderArgs,
    film: &FilmState,
    image: &XyzImage,
    scene: &Scene,
) -> Result<Option<(PathBuf, String)>, String> {
    let (Some(path), Some(spectral)) = (&args.spectral_exr, film.spectral_image()) else {
        return Ok(None);
    };
    spectral.write_exr(path)?;
    let line = spectral_summary(path, &spectral, image, scene.observer.as_ref());
    Ok(Some((path.clone(), line)))
}

/// One line: the spectral file, its nodes, and its mean XYZ by the trapezoid rule against the
/// film's (relative differences).
pub fn spectral_summary(
    path: &Path,
    spectral: &crate::film::spectral::SpectralImage,
    image: &XyzImage,
    observer: &dyn crate::color::Observer,
) -> String {
    let from_nodes = spectral.to_xyz(observer);
    let n = image.xyz.len().max(1) as f64;
    let mean = |v: &[[f64; 3]], c: usize| v.iter().map(|p| p[c]).sum::<f64>() / n;
    let rel: Vec<String> = (0..3)
        .map(|c| {
            let (a, b) = (mean(&from_nodes, c), mean(&image.xyz, c));
            if b != 0.0 {
                format!("{:+.1e}", (a - b) / b)
            } else {
                "n/a".into()
            }
        })
        .collect();
    let w = &spectral.wavelengths;
    format!(
        "  wrote {} ({} nodes {}–{} nm every {} nm); mean Y from the nodes {:.6}, film Y {:.6}; \
         relative difference X {} Y {} Z {} (rounding when the nodes are the observer's 1 nm \
         grid over its whole range, else the interpolation between nodes and the light \
         outside them)",
        path.display(),
        w.len(),
        w.first().copied().unwrap_or(0.0),
        w.last().copied().unwrap_or(0.0),
        spectral.step,
        mean(&from_nodes, 1),
        mean(&image.xyz, 1),
        rel[0],
        rel[1],
        rel[2]
    )
}

/// The optional diagnostic channels of the EXR.
pub(super) fn extra_layers(args: &RenderArgs, film: &FilmState) -> Vec<(String, Vec<f32>)> {
    diagnostic_layers(film, args.diagnostic_layer)
}

/// The diagnostic channels of the EXR when `on` (`--diagnostic-layer` of `render` and
/// `merge`): the film's rejected samples per pixel.
pub fn diagnostic_layers(film: &FilmState, on: bool) -> Vec<(String, Vec<f32>)> {
    if !on {
        return Vec::new();
    }
    let (w, h) = film.resolution();
    vec![(
        "rejected".to_string(),
        film.rejected.layer(w as usize * h as usize),
    )]
}

/// Write the EXR and PNG. If the EXR cannot be written where asked, the work is not lost: it
/// goes to a rescue file in the temp directory and the error says where.
pub(super) fn save(
    image: &XyzImage,
    outputs: &crate::cli::output_paths::OutputPaths,
    scene: &Scene,
    extra: Vec<(String, Vec<f32>)>,
    args: &RenderArgs,
) -> Result<Vec<PathBuf>, String> {
    save_image(
        image,
        outputs.exr.as_deref(),
        &outputs.png,
        &scene.options.rgb_space,
        png_exposure(args, scene, image).0,
        extra,
    )
}

/// [`save`] with the colour space and PNG exposure given (for `spectrace merge`); no EXR is
/// written when `exr` is `None` (`-o x.png`).
pub fn save_image(
    image: &XyzImage,
    exr: Option<&Path>,
    png: &Path,
    space: &crate::color::RgbColorSpace,
    png_exposure: f64,
    extra: Vec<(String, Vec<f32>)>,
) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    let mut errors = Vec::new();
    match exr.map(|exr| (exr, write_exr_with_layers(exr, image, space, extra.clone()))) {
        None => {}
        Some((exr, Ok(()))) => written.push(exr.to_path_buf()),
        Some((_, Err(e))) => {
            let rescue =
                std::env::temp_dir().join(format!("spectrace-rescue-{}.exr", std::process::id()));
            match write_exr_with_layers(&rescue, image, space, extra) {
                Ok(()) => errors.push(format!("{e}; the image was saved to {}", rescue.display())),
                Err(e2) => errors.push(format!("{e}; rescue copy failed too: {e2}")),
            }
        }
    }
    match write_png(png, image, png_exposure) {
        Ok(()) => written.push(png.to_path_buf()),
        Err(e) => errors.push(e.to_string()),
    }
    if errors.is_empty() {
        Ok(written)
    } else {
        for w in &written {
            eprintln!("spectrace: wrote {}", w.display());
        }
        Err(errors.join("; "))
    }
}
