//! Where `spectrace render` writes its images, decided before anything is rendered.
//!
//! | `-o` | `--png` | EXR | PNG |
//! | --- | --- | --- | --- |
//! | `a.exr` (or no extension) | none | `a.exr` | `a.png` |
//! | `a.exr` | `b.png` | `a.exr` | `b.png` |
//! | `a.png` | none | not written | `a.png` |
//! | `a.png` | `b.png` | refused: two PNGs asked for | |
//! | a directory, or another extension | | refused, naming it | |
//!
//! Before, `-o x.png` wrote the EXR into `x.png` and then overwrote it with the PNG, and `-o /tmp`
//! wrote `/tmp.png` beside the directory.

use std::path::{Path, PathBuf};

/// The files one render writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputPaths {
    /// The OpenEXR file, if one is written.
    pub exr: Option<PathBuf>,
    /// The sRGB PNG preview.
    pub png: PathBuf,
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// Refuse a path that is a directory (or is written like one, with a trailing slash).
pub fn check_not_directory(path: &Path, option: &str) -> Result<(), String> {
    let text = path.as_os_str().to_string_lossy();
    if path.is_dir() || text.ends_with('/') || text.ends_with(std::path::MAIN_SEPARATOR) {
        return Err(format!(
            "{option} {}: is a directory; give a file name, for example {}",
            path.display(),
            path.join("render.exr").display()
        ));
    }
    Ok(())
}

/// The outputs for `-o output` and `--png png`, or why they are refused.
pub fn output_paths(output: &Path, png: Option<&Path>) -> Result<OutputPaths, String> {
    check_not_directory(output, "-o")?;
    if let Some(p) = png {
        check_not_directory(p, "--png")?;
    }
    let paths = match extension(output).as_deref() {
        None | Some("exr") => OutputPaths {
            exr: Some(output.to_path_buf()),
            png: png.map_or_else(|| output.with_extension("png"), Path::to_path_buf),
        },
        Some("png") => {
            if let Some(p) = png.filter(|p| *p != output) {
                return Err(format!(
                    "-o {} already names the PNG; --png {} would be a second one (give -o an \
                     .exr name to get both)",
                    output.display(),
                    p.display()
                ));
            }
            OutputPaths {
                exr: None,
                png: output.to_path_buf(),
            }
        }
        Some(other) => {
            return Err(format!(
                "-o {}: unknown image format `.{other}`; use .exr (OpenEXR, with a PNG preview \
                 beside it) or .png",
                output.display()
            ))
        }
    };
    if paths.exr.as_deref() == Some(paths.png.as_path()) {
        return Err(format!(
            "--png {} is the same file as the EXR output",
            paths.png.display()
        ));
    }
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    // `-o x.png` writes only a PNG, to x.png; before, the EXR went into x.png first.
    #[test]
    fn png_output_writes_only_the_png() {
        let p = output_paths(Path::new("x.png"), None).unwrap();
        assert_eq!(p.exr, None);
        assert_eq!(p.png, Path::new("x.png"));
        let p = output_paths(Path::new("x.PNG"), Some(Path::new("x.PNG"))).unwrap();
        assert_eq!(p.exr, None);
        assert!(output_paths(Path::new("x.png"), Some(Path::new("y.png"))).is_err());
    }

    // The usual forms keep their meaning.
    #[test]
    fn exr_output_gets_a_png_beside_it() {
        let p = output_paths(Path::new("out/a.exr"), None).unwrap();
        assert_eq!(p.exr.as_deref(), Some(Path::new("out/a.exr")));
        assert_eq!(p.png, Path::new("out/a.png"));
        let p = output_paths(Path::new("a.exr"), Some(Path::new("b.png"))).unwrap();
        assert_eq!(p.png, Path::new("b.png"));
        let p = output_paths(Path::new("render"), None).unwrap();
        assert_eq!(p.exr.as_deref(), Some(Path::new("render")));
        assert_eq!(p.png, Path::new("render.png"));
    }

    // A directory (existing, or written with a trailing slash) is refused by name, and so are an
    // unknown extension and a PNG on top of the EXR.
    #[test]
    fn directories_and_unknown_formats_are_refused() {
        let tmp = std::env::temp_dir();
        let e = output_paths(&tmp, None).unwrap_err();
        assert!(
            e.contains(&tmp.display().to_string()) && e.contains("is a directory"),
            "{e}"
        );
        let e = output_paths(Path::new("newdir/"), None).unwrap_err();
        assert!(e.contains("is a directory"), "{e}");
        let e = output_paths(Path::new("a.exr"), Some(&tmp)).unwrap_err();
        assert!(e.contains("--png") && e.contains("is a directory"), "{e}");
        let e = output_paths(Path::new("a.jpg"), None).unwrap_err();
        assert!(e.contains(".jpg"), "{e}");
        let e = output_paths(Path::new("a.exr"), Some(Path::new("a.exr"))).unwrap_err();
        assert!(e.contains("same file"), "{e}");
    }
}
