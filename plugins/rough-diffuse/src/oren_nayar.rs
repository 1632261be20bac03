//! `oren_nayar`: rough diffuse reflection, the Oren–Nayar model (Oren & Nayar, "Generalization
//! of Lambert's reflectance model", SIGGRAPH 1994) in the form and energy-preserving
//! parameterisation of Y. Fujii, "A tiny improvement of Oren-Nayar reflectance model" (2012,
//! mimosa-pudica.net/improved-oren-nayar.html).
//!
//! | parameter     | unit | default        | meaning                                           |
//! |---------------|------|----------------|---------------------------------------------------|
//! | `reflectance` | –    | `[(555, 0.8)]` | `[(nm, r), …]`, r ∈ [0,1]; one pair = constant    |
//! | `roughness`   | –    | 0.5            | σ′ ∈ [0, 1]: weight of the rough (retro-reflective) term |
//!
//! With `wi`, `wo` in the shading frame (normal n = z): `s = wi·wo − (n·wi)(n·wo)`,
//! `t = 1` if `s ≤ 0` else `max(n·wi, n·wo)`, and `f = R(λ)·(A + B·s/t)` with
//! `A = 1/(π + (π/2 − 2/3)σ′)`, `B = σ′·A`. σ′ = 0 is exactly Lambertian.
//! Why this form rather than the widely quoted "qualitative" model (A, B from a slope angle σ):
//! that one creates energy at grazing angles (its directional albedo exceeds 1 near 90°, as
//! this plugin's tests showed while it was being written), and a renderer for people who measure
//! light must not. Fujii's normalisation makes the albedo exactly 1 at grazing for R = 1 and
//! smaller elsewhere. The surface is two-sided, like the host's `lambertian`. Directions are
//! sampled from the cosine-weighted hemisphere: the bracket is smooth and bounded, so cosine
//! sampling matches the integrand well.
//!
//! Useful check: looking straight down (wo = n), `s = 0` for every wi, so the directional albedo
//! there is exactly `π·A·R`.

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    material_flags, Flags, Host, Material, ParamDoc, PluginError, PluginResult, PluginType,
    Scatter, Surface, TransportMode, Vec3, Vec4f, Wavelengths, LANES,
};
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4};

/// A spectral reflectance in [0, 1]: `(nm, r)` pairs in increasing wavelength, interpolated
/// linearly and held constant beyond the ends (how measured reflectance tables are commonly
/// extended). One pair is a constant reflectance. (A list rather than an enum because scene
/// parameters arrive as RON values, in which enum variant names do not survive.)
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(transparent)]
pub struct Reflectance(pub Vec<(f64, f64)>);

impl Default for Reflectance {
    fn default() -> Self {
        Reflectance(vec![(555.0, 0.8)])
    }
}

impl Reflectance {
    /// The same reflectance `r` at every wavelength.
    pub fn constant(r: f64) -> Self {
        Reflectance(vec![(555.0, r)])
    }

    fn validate(&self) -> PluginResult<()> {
        let t = &self.0;
        if t.is_empty() {
            return Err(PluginError::invalid_parameter(
                "`reflectance` is empty: give at least one (nm, r) pair",
            ));
        }
        for (i, &(nm, r)) in t.iter().enumerate() {
            if !(nm.is_finite() && (0.0..=1.0).contains(&r)) {
                return Err(PluginError::invalid_parameter(format!(
                    "`reflectance`: entry {i} ({nm}, {r}) needs a finite wavelength and a value in [0, 1]"
                )));
            }
            if i > 0 && !(nm > t[i - 1].0) {
                return Err(PluginError::invalid_parameter(format!(
                    "`reflectance`: wavelengths must increase, entry {i} ({nm} nm) does not"
                )));
            }
        }
        Ok(())
    }

    /// Reflectance at `nm`.
    pub fn at(&self, nm: f64) -> f64 {
        let t = &self.0;
        let i = t.partition_point(|&(l, _)| l <= nm);
        if i == 0 {
            return t[0].1;
        }
        if i == t.len() {
            return t[t.len() - 1].1;
        }
        let ((l0, r0), (l1, r1)) = (t[i - 1], t[i]);
        r0 + (nm - l0) / (l1 - l0) * (r1 - r0)
    }
}

/// Parameters of [`OrenNayar`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OrenNayarParams {
    /// Spectral reflectance.
    #[serde(default)]
    pub reflectance: Reflectance,
    /// σ′ ∈ [0, 1], the weight of the rough term (dimensionless).
    #[serde(default = "default_roughness")]
    pub roughness: f64,
}

fn default_roughness() -> f64 {
    0.5
}

/// The Oren–Nayar material.
pub struct OrenNayar {
    params: OrenNayarParams,
    a: f64,
    b: f64,
}

impl OrenNayar {
    /// The model's `A` and `B` (1/sr) for roughness σ′ (module docs).
    pub fn coefficients(roughness: f64) -> (f64, f64) {
        let a = 1.0 / (std::f64::consts::PI + (FRAC_PI_2 - 2.0 / 3.0) * roughness);
        (a, roughness * a)
    }

    /// `A + B·s/t` (1/sr) for a pair in one hemisphere.
    fn angular(&self, wo: Vec3, wi: Vec3) -> f64 {
        let (co, ci) = (wo.z.abs(), wi.z.abs());
        // wi·wo − (n·wi)(n·wo) is the tangent-plane part of wi·wo; with both directions on the
        // same side the product of the z's equals |wi.z|·|wo.z|.
        let s = wi.x * wo.x + wi.y * wo.y;
        let t = if s <= 0.0 { 1.0 } else { ci.max(co) };
        self.a + self.b * s / t
    }

    /// f(wo, wi) at wavelengths `nm`, 1/sr.
    fn value(&self, wo: Vec3, wi: Vec3, nm: [f64; LANES]) -> [f64; LANES] {
        if !(wo.z * wi.z > 0.0) {
            return [0.0; LANES];
        }
        let k = self.angular(wo, wi);
        nm.map(|nm| self.params.reflectance.at(nm) * k)
    }
}

impl PluginType for OrenNayar {
    const TYPE_NAME: &'static str = "oren_nayar";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str =
        "Oren–Nayar rough diffuse reflection, energy-preserving form (roughness 0 is Lambertian)";
    type Params = OrenNayarParams;

    fn params_doc() -> Vec<ParamDoc> {
        vec![
            ParamDoc::optional(
                "reflectance",
                "-",
                "[(555, 0.8)]",
                "[(nm, r), ...] with r in [0, 1], linear between entries; one pair is a constant",
            ),
            ParamDoc::optional(
                "roughness",
                "-",
                "0.5",
                "weight of the rough term in [0, 1]; 0 is Lambertian",
            ),
        ]
    }

    fn new(params: OrenNayarParams, _host: &Host<'_, '_>) -> PluginResult<Self> {
        params.reflectance.validate()?;
        if !(0.0..=1.0).contains(&params.roughness) {
            return Err(PluginError::invalid_parameter(format!(
                "`roughness` must be within [0, 1], got {}",
                params.roughness
            )));
        }
        let (a, b) = Self::coefficients(params.roughness);
        Ok(Self { params, a, b })
    }

    fn params(&self) -> &OrenNayarParams {
        &self.params
    }
}

/// Cosine-weighted direction on the +z hemisphere from two uniform numbers (concentric disk
/// map, Shirley & Chiu 1997, then lifted to the hemisphere).
fn cosine_hemisphere(u0: f64, u1: f64) -> Vec3 {
    let (ox, oy) = (2.0 * u0 - 1.0, 2.0 * u1 - 1.0);
    let (r, theta) = if ox == 0.0 && oy == 0.0 {
        (0.0, 0.0)
    } else if ox.abs() > oy.abs() {
        (ox, FRAC_PI_4 * (oy / ox))
    } else {
        (oy, FRAC_PI_2 - FRAC_PI_4 * (ox / oy))
    };
    let (x, y) = (r * theta.cos(), r * theta.sin());
    Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

fn nm(lambda: &Wavelengths) -> [f64; LANES] {
    lambda.nm.map(f64::from)
}

impl Material for OrenNayar {
    fn flags(&self) -> Flags {
        material_flags::DIFFUSE | material_flags::RECIPROCAL
    }

    fn sample(
        &self,
        wo: &Vec4f,
        _surface: &Surface,
        lambda: &Wavelengths,
        u: [f32; 3],
        _mode: TransportMode,
        out: &mut Scatter,
    ) -> PluginResult<bool> {
        let wo = wo.to_f64();
        if wo.z == 0.0 {
            return Ok(false);
        }
        let mut wi = cosine_hemisphere(u[1] as f64, u[2] as f64);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = wi.z.abs() * FRAC_1_PI;
        if pdf == 0.0 {
            return Ok(false);
        }
        *out = Scatter {
            wi: Vec4f::from_f64(wi),
            value: self.value(wo, wi, nm(lambda)).map(|v| v as f32),
            pdf: pdf as f32,
            flags: material_flags::DIFFUSE,
            eta: 1.0,
        };
        Ok(true)
    }

    fn eval(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        _surface: &Surface,
        lambda: &Wavelengths,
        _mode: TransportMode,
    ) -> PluginResult<[f32; LANES]> {
        // Symmetric in (wo, wi), so radiance and importance transport are the same.
        Ok(self
            .value(wo.to_f64(), wi.to_f64(), nm(lambda))
            .map(|v| v as f32))
    }

    fn pdf(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        _surface: &Surface,
        _lambda: &Wavelengths,
        _mode: TransportMode,
    ) -> PluginResult<f32> {
        let (wo, wi) = (wo.to_f64(), wi.to_f64());
        Ok(if wo.z * wi.z > 0.0 {
            (wi.z.abs() * FRAC_1_PI) as f32
        } else {
            0.0
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spectrace_plugin_api::abi::sabi_trait::TD_Opaque;
    use spectrace_plugin_api::host::{AbiHost_TO, HostRef, NoHost};

    fn build(params: OrenNayarParams) -> PluginResult<OrenNayar> {
        let services: HostRef<'_> = AbiHost_TO::from_ptr(&NoHost, TD_Opaque);
        OrenNayar::new(params, &Host::new(&services))
    }

    fn material(roughness: f64) -> OrenNayar {
        build(OrenNayarParams {
            reflectance: Reflectance::constant(1.0),
            roughness,
        })
        .unwrap()
    }

    fn dir(theta: f64, phi: f64) -> Vec3 {
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    const L: [f64; LANES] = [450.0, 520.0, 600.0, 680.0];

    // Reciprocity f(wo, wi) = f(wi, wo) for a grid of pairs: the formula is symmetric, so any
    // difference beyond rounding (1e-12 relative) is a bug in the α/β bookkeeping.
    #[test]
    fn reciprocal() {
        let m = material(0.7);
        for i in 0..8 {
            for j in 0..8 {
                let a = dir(0.05 + 0.19 * i as f64, 0.4 * j as f64);
                let b = dir(0.1 + 0.18 * j as f64, 2.0 - 0.3 * i as f64);
                let (fab, fba) = (m.value(a, b, L)[0], m.value(b, a, L)[0]);
                assert!(
                    (fab - fba).abs() <= 1e-12 * fab.max(1e-12),
                    "{fab} vs {fba}"
                );
            }
        }
    }

    // Looking straight down, the directional albedo is exactly π·A·R (module docs). Estimated
    // with 40 000 stratified cosine samples through the interface's `sample` (single precision):
    // the integrand value·cos/pdf is the constant π·A there, so the estimate must agree to f32
    // rounding (1e-5 relative: a few ulp per sample, averaged); it tests sample, value and pdf
    // together.
    #[test]
    fn normal_incidence_albedo_is_a() {
        for sigma in [0.0, 0.2, 0.6, 1.0] {
            let m = material(sigma);
            let wo = Vec3::new(0.0, 0.0, 1.0);
            let n = 200;
            let mut sum = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let u = [
                        0.5,
                        (i as f32 + 0.5) / n as f32,
                        (j as f32 + 0.5) / n as f32,
                    ];
                    let mut s = Scatter::default();
                    let lambda = Wavelengths::at(L.map(|l| l as f32));
                    let written = m
                        .sample(
                            &Vec4f::from_f64(wo),
                            &Surface::default(),
                            &lambda,
                            u,
                            TransportMode::Radiance,
                            &mut s,
                        )
                        .unwrap();
                    assert!(written);
                    sum += f64::from(s.value[0]) * f64::from(s.wi.z) / f64::from(s.pdf);
                }
            }
            let albedo = sum / (n * n) as f64;
            let (a, _) = OrenNayar::coefficients(sigma);
            let expected = std::f64::consts::PI * a;
            assert!(
                (albedo - expected).abs() < 1e-5 * expected,
                "σ′={sigma}: {albedo} vs {expected}"
            );
        }
    }

    // Energy: at every outgoing angle the directional albedo of R = 1 stays ≤ 1 and approaches
    // 1 at grazing (the normalisation's design point). Midpoint quadrature over θi, φi with
    // 200×400 cells: its error on this smooth integrand is < 1e-3, hence the 1 + 1e-3 bound. At
    // θo = 89.4° the albedo must be within 2% of 1 (the bracket's grazing limit is reached only
    // at exactly 90°).
    /// Directional albedo of `m` (lane 0) towards `wo` by the midpoint rule on an `nt`×`np`
    /// grid in (θi, φi).
    fn directional_albedo(m: &OrenNayar, wo: Vec3, nt: usize, np: usize) -> f64 {
        let (dt, dp) = (
            FRAC_PI_2 / nt as f64,
            2.0 * std::f64::consts::PI / np as f64,
        );
        let mut albedo = 0.0;
        for i in 0..nt {
            let t = (i as f64 + 0.5) * dt;
            for j in 0..np {
                let wi = dir(t, (j as f64 + 0.5) * dp);
                albedo += m.value(wo, wi, L)[0] * wi.z * t.sin() * dt * dp;
            }
        }
        albedo
    }

    #[test]
    fn albedo_never_exceeds_one() {
        for sigma in [0.3, 0.7, 1.0] {
            let m = material(sigma);
            for k in 0..9 {
                let albedo = directional_albedo(&m, dir(0.01 + k as f64 * 0.19, 0.0), 200, 400);
                assert!(albedo <= 1.0 + 1e-3, "σ′={sigma}, θo #{k}: albedo {albedo}");
                assert!(albedo > 0.5, "σ′={sigma}, θo #{k}: albedo {albedo}");
            }
            let albedo = directional_albedo(&m, dir(1.56, 0.3), 400, 800);
            assert!(
                (albedo - 1.0).abs() < 0.02,
                "σ′={sigma} at grazing: albedo {albedo}"
            );
        }
    }

    // Bad parameters name the parameter.
    #[test]
    fn rejects_bad_parameters() {
        let bad = |p: OrenNayarParams| build(p).err().expect("must be rejected").to_string();
        let e = bad(OrenNayarParams {
            reflectance: Reflectance::constant(1.5),
            roughness: 0.1,
        });
        assert!(e.contains("reflectance"), "{e}");
        let e = bad(OrenNayarParams {
            reflectance: Reflectance(vec![(500.0, 0.2), (400.0, 0.3)]),
            roughness: 0.1,
        });
        assert!(e.contains("increase"), "{e}");
        let e = bad(OrenNayarParams {
            reflectance: Reflectance::constant(0.5),
            roughness: f64::NAN,
        });
        assert!(e.contains("roughness"), "{e}");
    }

    #[test]
    fn table_interpolates_and_holds_ends() {
        let r = Reflectance(vec![(400.0, 0.2), (500.0, 0.6)]);
        assert_eq!(r.at(350.0), 0.2);
        assert!((r.at(450.0) - 0.4).abs() < 1e-15);
        assert_eq!(r.at(900.0), 0.6);
    }
}
