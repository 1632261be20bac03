//! The built-in `plastic` and `rough_plastic` materials through the plugin conformance kit
//! (`spectrace-plugin-kit`'s `check_material`, every check: finite, chi2, sample_pdf,
//! pdf_integral, energy, reciprocity, determinism, threads, state), in-process through the
//! standard library's wrappers, which call the host's own material (the same code the renderer
//! runs) and declare RECIPROCAL for these two.
//!
//! Quantities, tolerances and why: the kit's own (see `plugin-kit/src/material.rs`): chi-square
//! at the Šidák level of 1 % over the outgoing directions, records equal to eval/pdf to 1e-3,
//! ∫pdf within 0.01 of the share of non-delta samples, white-furnace albedo − 5σ ≤ 1.001,
//! reciprocity to 1e-3, bit-identical repeated and threaded answers. The energy check uses a
//! white base (ρ = 1), the worst case for a coating that must not add light.
//! Roughnesses α from 0.1 to 0.6, GGX and Beckmann. Narrower lobes meet the kit's limit for a
//! sharp lobe on top of a diffuse floor (docs/plugins.md): its integration of `pdf` refines a
//! cell only where the density varies by a large ratio, which the diffuse floor prevents, so
//! a lobe of α = 0.01 at cos θo = 0.95 is missed by the quadrature (∫pdf 0.980 against the 1.000
//! sampled; `sample_pdf`, `energy` and `reciprocity` pass there).

use spectrace_plugin_kit::check_material;
use spectrace_standard::{Plastic, RoughPlastic};

#[test]
fn smooth_plastic_conforms() {
    for params in [
        "(diffuse_reflectance: 1)",
        "(diffuse_reflectance: 1, nonlinear: true, int_ior: 1.9)",
        "(diffuse_reflectance: (rgb: (0.8, 0.3, 0.1)), int_ior: \"N-BK7\", ext_ior: 1.000277)",
        "(diffuse_reflectance: 0.2, specular_reflectance: 0.5)",
    ] {
        let r = check_material::<Plastic>(params);
        println!("plastic {params}\n{r}");
        r.assert_pass();
    }
}

#[test]
fn rough_plastic_conforms() {
    let mut failed = Vec::new();
    for params in [
        "(diffuse_reflectance: 1, alpha: 0.1)",
        "(diffuse_reflectance: 1, alpha: 0.3, nonlinear: true, int_ior: 1.9)",
        "(diffuse_reflectance: 1, alpha: 0.6)",
        "(diffuse_reflectance: (rgb: (0.1, 0.5, 0.8)), alpha: 0.2, int_ior: \"N-SF11\")",
        "(diffuse_reflectance: 0, alpha: 0.25)",
        "(diffuse_reflectance: 1, alpha: 0.1, distribution: \"beckmann\")",
        "(diffuse_reflectance: 1, alpha: 0.5, distribution: \"beckmann\", nonlinear: true)",
    ] {
        let r = check_material::<RoughPlastic>(params);
        println!("rough_plastic {params}\n{r}");
        if !r.passed() {
            failed.push(format!("{params}: {:?}", r.failures()));
        }
    }
    assert!(failed.is_empty(), "{failed:#?}");
}
