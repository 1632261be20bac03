//! [`analyze`]: the [`EffectSet`] of a scene, from the capability flags and spectra of its
//! materials and lights (the `Material` and `Light` interfaces, so plugin objects are
//! analysed exactly like built-ins).
//!
//! How each effect is found:
//! - dispersion, fluorescence, thin film, delta BSDFs: the material flags `DISPERSIVE`,
//!   `FLUORESCENT`, `THIN_FILM`, `SPECULAR`;
//! - delta lights and beam-only lights: the light flags;
//! - line emission: a light SPD with delta lines; narrowband emission: a continuous light SPD
//!   whose equivalent width is below 10 nm ([`crate::spectrum::bandwidth`]);
//! - specular chains: a delta BSDF in a scene with lights that are not beam-only (caustics);
//! - spectral flatness: a light SPD (no lines) whose value varies by less than 0.1% over
//!   380–780 nm, a material whose BSDF value (or, for delta lobes, sampled weight) at a fixed
//!   pair of directions varies by less than 0.1% over the same wavelengths (5 nm steps).

use super::effect::Effect;
use crate::light::LightFlags;
use crate::material::{Material, MaterialFlags, ShadingContext, TransportMode};
use crate::scene::Scene;
use crate::spectrum::bandwidth::{equivalent_width_nm, NARROWBAND_WIDTH_NM};
use crate::spectrum::{SampledWavelengths, Spd, LANES};
use glam::{Vec2, Vec3A};

/// Relative variation below which a spectrum counts as flat.
const FLAT_TOLERANCE: f64 = 1e-3;
/// Wavelengths probed for flatness (nm).
const PROBE_RANGE_NM: (f64, f64, f64) = (380.0, 780.0, 5.0);

/// An object or light that calls for an effect.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Caller {
    /// Scene object (index, name from the scene file).
    Object(usize, String),
    /// Light (index in the scene's light list, description).
    Light(usize, String),
}

impl std::fmt::Display for Caller {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Object(_, name) => write!(f, "object \"{name}\""),
            Self::Light(i, what) => write!(f, "light {i} ({what})"),
        }
    }
}

/// One effect found, the objects calling for it, and a detail per caller (may be empty).
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// The effect.
    pub effect: Effect,
    /// Who calls for it, with a detail (for example "line at 589 nm").
    pub callers: Vec<(Caller, String)>,
}

/// Every effect a scene calls for (see [`analyze`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EffectSet {
    findings: Vec<Finding>,
}

impl EffectSet {
    /// The findings, in [`Effect::ALL`] order.
    pub fn findings(&self) -> &[Finding] {
        &self.findings
    }

    /// True when the scene calls for `effect`.
    pub fn contains(&self, effect: Effect) -> bool {
        self.findings.iter().any(|f| f.effect == effect)
    }

    /// Who calls for `effect` (empty when absent).
    pub fn callers(&self, effect: Effect) -> Vec<&Caller> {
        self.findings
            .iter()
            .filter(|f| f.effect == effect)
            .flat_map(|f| f.callers.iter().map(|(c, _)| c))
            .collect()
    }

    /// One line for the render summary: `effects: dispersion (1), delta-lights (2), …`.
    pub fn summary_line(&self) -> String {
        let parts: Vec<String> = self
            .findings
            .iter()
            .map(|f| format!("{} ({})", f.effect.name(), f.callers.len()))
            .collect();
        format!("effects: {}", parts.join(", "))
    }

    /// The full report `spectrace explain` prints: every effect, its callers, what the render
    /// does and what it skips (warnings marked).
    pub fn report(&self) -> String {
        let mut out = String::new();
        for f in &self.findings {
            out.push_str(&format!("{}\n", f.effect.name()));
            for (c, detail) in &f.callers {
                if detail.is_empty() {
                    out.push_str(&format!("  called for by {c}\n"));
                } else {
                    out.push_str(&format!("  called for by {c}: {detail}\n"));
                }
            }
            out.push_str(&format!("  render does: {}\n", f.effect.handling()));
            if let Some(skip) = f.effect.skipped() {
                let mark = if f.effect.is_warning() {
                    "WARNING, render skips"
                } else {
                    "render skips"
                };
                out.push_str(&format!("  {mark}: {skip}\n"));
            }
        }
        out
    }
}

/// A light's description for reports.
fn light_label(scene: &Scene, index: usize) -> String {
    let l = &scene.lights.lights()[index];
    let f = l.flags();
    if f.contains(LightFlags::BEAMS_ONLY) {
        return "beams-only".into();
    }
    if f.contains(LightFlags::DELTA_DIRECTION) {
        return "directional".into();
    }
    if f.contains(LightFlags::DELTA_POSITION) {
        return "point-like".into();
    }
    for (o, obj) in scene.objects.objects().iter().enumerate() {
        if scene.lights.light_of_object(o as u32) == Some(index as u32) {
            return format!("area, object \"{}\"", obj.name);
        }
    }
    "area".into()
}

/// Wavelengths probed for flatness.
fn probe_wavelengths() -> Vec<f64> {
    let (lo, hi, step) = PROBE_RANGE_NM;
    let n = ((hi - lo) / step).round() as usize;
    (0..=n).map(|k| lo + k as f64 * step).collect()
}

fn is_flat(values: &[f64]) -> bool {
    let max = values.iter().cloned().fold(f64::MIN, f64::max);
    let min = values.iter().cloned().fold(f64::MAX, f64::min);
    max <= 0.0 || (max - min) <= FLAT_TOLERANCE * max
}

/// Light SPD flatness (lines make a spectrum non-flat).
fn spd_is_flat(spd: &dyn Spd) -> bool {
    if spd.is_delta() {
        return false;
    }
    let v: Vec<f64> = probe_wavelengths().iter().map(|&l| spd.value(l)).collect();
    is_flat(&v)
}

/// Material flatness: the BSDF at a fixed direction pair, or a delta lobe's sampled weight.
fn material_is_flat(m: &dyn Material) -> bool {
    let flags = m.flags();
    if flags.intersects(
        MaterialFlags::DISPERSIVE | MaterialFlags::FLUORESCENT | MaterialFlags::THIN_FILM,
    ) {
        return false;
    }
    if !flags.intersects(MaterialFlags::DIFFUSE | MaterialFlags::GLOSSY | MaterialFlags::SPECULAR) {
        return true; // emission only: judged by its light's SPD
    }
    let wo = Vec3A::new(0.0, 0.6, 0.8);
    let wi = Vec3A::new(0.0, -0.6, 0.8);
    let ctx = ShadingContext::default();
    let mut values = Vec::new();
    for chunk in probe_wavelengths().chunks(LANES) {
        let mut lambda = SampledWavelengths {
            lambda: [chunk[0] as f32; LANES],
            pdf: [1.0; LANES],
            lanes: crate::spectrum::LaneMask::ALL,
        };
        for (i, &l) in chunk.iter().enumerate() {
            lambda.lambda[i] = l as f32;
        }
        let f = if flags.has_non_specular() {
            m.eval(wo, wi, &ctx, &lambda, TransportMode::Radiance)
        } else {
            match m.sample(
                wo,
                &ctx,
                &lambda,
                0.0,
                Vec2::splat(0.5),
                TransportMode::Radiance,
            ) {
                Some(s) => s.f,
                None => continue,
            }
        };
        values.extend(f.0.iter().take(chunk.len()).map(|&v| v as f64));
    }
    is_flat(&values)
}

/// The effects `scene` calls for.
pub fn analyze(scene: &Scene) -> EffectSet {
    let mut found = Found::default();
    let (delta_bsdf_objects, materials_flat) = material_effects(scene, &mut found);
    let (chain_lights, lights_flat) = light_effects(scene, &mut found);
    if !delta_bsdf_objects.is_empty() {
        for (c, delta) in &chain_lights {
            let how = if *delta {
                "point-like or directional: pt cannot find its caustics"
            } else {
                "area: pt finds its caustics only by BSDF sampling onto it"
            };
            found.add(Effect::SpecularChains, c.clone(), how.into());
        }
        if !chain_lights.is_empty() {
            for c in delta_bsdf_objects {
                found.add(Effect::SpecularChains, c, String::new());
            }
        }
    }
    let mut found = found.0;
    if materials_flat && lights_flat {
        let all: Vec<(Caller, String)> = scene
            .objects
            .objects()
            .iter()
            .enumerate()
            .map(|(i, o)| (Caller::Object(i, o.name.clone()), String::new()))
            .chain(
                (0..scene.lights.lights().len())
                    .map(|i| (Caller::Light(i, light_label(scene, i)), String::new())),
            )
            .collect();
        found.insert(Effect::SpectrallyFlat, all);
    }
    EffectSet {
        findings: Effect::ALL
            .iter()
            .filter_map(|e| {
                found.remove(e).map(|callers| Finding {
                    effect: *e,
                    callers,
                })
            })
            .collect(),
    }
}

/// Each effect found with who calls for it and a detail.
#[derive(Default)]
struct Found(std::collections::BTreeMap<Effect, Vec<(Caller, String)>>);

impl Found {
    fn add(&mut self, e: Effect, c: Caller, d: String) {
        self.0.entry(e).or_default().push((c, d));
    }
}

/// The effects the objects' materials call for. Returns the objects with delta BSDFs and
/// whether every material is spectrally flat.
fn material_effects(scene: &Scene, found: &mut Found) -> (Vec<Caller>, bool) {
    let mut delta_bsdf_objects = Vec::new();
    let mut flat = true;
    for (i, obj) in scene.objects.objects().iter().enumerate() {
        let m = obj.material.as_ref();
        let flags = m.flags();
        let caller = || Caller::Object(i, obj.name.clone());
        if flags.contains(MaterialFlags::DISPERSIVE) {
            found.add(Effect::Dispersion, caller(), String::new());
        }
        if flags.contains(MaterialFlags::FLUORESCENT) {
            let detail = if m.reradiation().is_none() {
                "no re-radiation data (plugin material): reflectance only".to_string()
            } else {
                String::new()
            };
            found.add(Effect::Fluorescence, caller(), detail);
        }
        if flags.contains(MaterialFlags::THIN_FILM) {
            found.add(Effect::ThinFilm, caller(), String::new());
        }
        if flags.contains(MaterialFlags::SPECULAR) {
            found.add(Effect::DeltaBsdfs, caller(), String::new());
            delta_bsdf_objects.push(caller());
        }
        if !material_is_flat(m) {
            flat = false;
            found.add(Effect::SpectrallyVarying, caller(), "material".into());
        }
    }
    (delta_bsdf_objects, flat)
}

/// The effects the lights call for. Returns the lights a specular chain can start from (with
/// whether each is a delta light) and whether every probed emission spectrum is flat.
fn light_effects(scene: &Scene, found: &mut Found) -> (Vec<(Caller, bool)>, bool) {
    let mut chain_lights = Vec::new();
    let mut flat = true;
    for (i, l) in scene.lights.lights().iter().enumerate() {
        let f = l.flags();
        let caller = || Caller::Light(i, light_label(scene, i));
        if f.contains(LightFlags::BEAMS_ONLY) {
            found.add(Effect::BeamOnlyLights, caller(), String::new());
            // Its beams carry their own wavelengths; its spectrum is not probed (a plugin light
            // built against API 0.1.0 may not offer wavelength sampling at all, and every render
            // runs this analysis through the render plan).
            continue;
        }
        if f.is_delta() {
            found.add(Effect::DeltaLights, caller(), String::new());
        }
        chain_lights.push((caller(), f.is_delta()));
        let spd = l.spd();
        let lines = spd.delta_lines();
        if !lines.is_empty() {
            let nm: Vec<String> = lines.iter().map(|d| format!("{} nm", d.lambda)).collect();
            found.add(
                Effect::LineEmission,
                caller(),
                format!("line(s) at {}", nm.join(", ")),
            );
        } else {
            let w = equivalent_width_nm(spd.as_ref());
            if w < NARROWBAND_WIDTH_NM {
                found.add(
                    Effect::NarrowbandEmission,
                    caller(),
                    format!("equivalent width {w:.3} nm"),
                );
            }
        }
        if !spd_is_flat(spd.as_ref()) {
            flat = false;
            found.add(
                Effect::SpectrallyVarying,
                caller(),
                "emission spectrum".into(),
            );
        }
    }
    (chain_lights, flat)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(text: &str) -> Scene {
        let file = std::path::Path::new("t.ron");
        let desc = crate::scene::parse_scene_str(text, file).unwrap();
        crate::scene::build_scene(
            &desc,
            std::path::Path::new("."),
            file,
            &[&crate::scene::BuiltinFactory],
        )
        .unwrap()
    }

    const CAMERA: &str = r#"cameras: [(name: "c", type: "perspective",
        params: (position: (0, 0, 3), look_at: (0, 0, -1), fov: 40, resolution: (8, 8)))]"#;

    // Each effect is found with the right callers (exact: the analysis is deterministic).
    #[test]
    fn finds_effects_and_callers() {
        let s = scene(&format!(
            r#"(
            materials: [
                (name: "wall", type: "lambertian", params: (reflectance: 0.5)),
                (name: "prism", type: "dielectric", params: (ior: "N-SF11")),
                (name: "mirror", type: "mirror", params: (reflectance: 0.9)),
            ],
            objects: [
                (name: "wall", type: "quad", material: "wall",
                 params: (corner: (-2, -2, -2), edge0: (4, 0, 0), edge1: (0, 4, 0))),
                (name: "prism", type: "sphere", material: "prism", params: (center: (0, 0, 0), radius: 0.5)),
                (name: "mirror", type: "sphere", material: "mirror", params: (center: (1, 0, 0), radius: 0.3)),
            ],
            lights: [
                (name: "sodium", type: "point", params: (position: (0, 1, 1), power: 10, spd: "line:589")),
            ],
            {CAMERA},
        )"#
        ));
        let e = analyze(&s);
        assert_eq!(
            e.callers(Effect::Dispersion),
            vec![&Caller::Object(1, "prism".into())]
        );
        assert_eq!(e.callers(Effect::DeltaBsdfs).len(), 2);
        assert_eq!(e.callers(Effect::LineEmission).len(), 1);
        assert_eq!(e.callers(Effect::DeltaLights).len(), 1);
        assert_eq!(e.callers(Effect::SpecularChains).len(), 3);
        assert!(!e.contains(Effect::NarrowbandEmission));
        assert!(!e.contains(Effect::Fluorescence));
        assert!(!e.contains(Effect::SpectrallyFlat));
        assert!(e.contains(Effect::SpectrallyVarying));
        let r = e.report();
        assert!(
            // Lines render since the wavelength mixture carries their discrete probability, so a
            // line lamp alone is no longer a warning.
            r.contains("line(s) at 589 nm") && !r.contains("WARNING"),
            "{r}"
        );
        assert!(
            e.summary_line().starts_with("effects: dispersion (1)"),
            "{}",
            e.summary_line()
        );
    }

    // A grey diffuse room under an equal-energy area light is spectrally flat, with no other
    // effect than that.
    #[test]
    fn flat_scene_is_flat() {
        let s = scene(&format!(
            r#"(
            materials: [
                (name: "wall", type: "lambertian", params: (reflectance: 0.5)),
                (name: "lamp", type: "emissive", params: (radiance: "e", scale: 1)),
            ],
            objects: [
                (name: "wall", type: "quad", material: "wall",
                 params: (corner: (-2, -2, -2), edge0: (4, 0, 0), edge1: (0, 4, 0))),
                (name: "lamp", type: "quad", material: "lamp",
                 params: (corner: (-0.5, 1.5, -1), edge0: (0, 0, 1), edge1: (1, 0, 0))),
            ],
            {CAMERA},
        )"#
        ));
        let e = analyze(&s);
        let names: Vec<&str> = e.findings().iter().map(|f| f.effect.name()).collect();
        assert_eq!(names, vec!["spectrally-flat"], "{}", e.report());
    }
}
