//! Accuracy analysis: comparing renders with a reference (RMSE, relative MSE, CIEDE2000 and a
//! false-colour difference image), long resumable reference renders, and error-versus-time
//! benchmarks of renderer configurations.

pub mod accuracy_bench;
pub mod bench_fit;
pub mod bench_scene;
pub mod ciede2000;
pub mod cielab;
pub mod diff_image;
pub mod error;
pub mod metrics;
pub mod plot;
pub mod progressive;
pub mod reference_state;
pub mod rgb_image;
pub mod specular_mask;

pub use ciede2000::delta_e_2000;
pub use cielab::{linear_srgb_to_lab, xyz_to_lab, Lab};
pub use diff_image::{delta_e_color, write_delta_e_png};
pub use error::AnalysisError;
pub use metrics::{
    compare_images, compare_images_excluding, light_mask, CompareOptions, Comparison,
    REL_MSE_EPSILON,
};
pub use progressive::{run_reference, state_path, ReferenceOutcome, ReferenceSettings};
pub use reference_state::ReferenceState;
pub use rgb_image::RgbImage;
pub use specular_mask::specular_view_mask;

/// The metrics, the per-pixel ΔE00 (`None`: left out) and the image size (width, height).
pub type FileComparison = (Comparison, Vec<Option<f64>>, (u32, u32));

/// Read two EXRs and compare `test` against `reference`; errors name the file at fault.
pub fn compare_files(
    test: &std::path::Path,
    reference: &std::path::Path,
    options: CompareOptions,
) -> Result<FileComparison, AnalysisError> {
    let a = RgbImage::read_exr(test)?;
    let b = RgbImage::read_exr(reference)?;
    if (a.width, a.height) != (b.width, b.height) {
        return Err(AnalysisError::SizeMismatch {
            a: test.to_path_buf(),
            aw: a.width,
            ah: a.height,
            b: reference.to_path_buf(),
            bw: b.width,
            bh: b.height,
        });
    }
    let (c, per_pixel) = compare_images(&a, &b, options);
    Ok((c, per_pixel, (a.width, a.height)))
}
