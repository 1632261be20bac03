//! Adapters: plugin objects dressed as the host's own traits, so the integrator never knows
//! where an object came from. Each per-sample call passes the host's own records by reference
//! (`super::layout`) and the plugin writes its answer into the host's record in place; the
//! answer is checked here before the integrator sees it (the seed: wrap a light whose beams are
//! in another representation, and convert in the call).
//!
//! The host traits are infallible (a hot path full of `Result`s would cost every built-in), but
//! a plugin call can fail. The adapter then returns "no contribution" and records the error in the
//! shared [`PluginFaults`]; the renderer checks it between passes and stops cleanly, keeping what
//! was rendered, with the plugin's message. A failed per-sample call answers `ERROR` or NaN and
//! keeps its error on the plugin's side of the thread; the adapter takes it through the root
//! module's `take_error` and reports it naming the plugin object and the call.

use super::checked;
use super::representation::BeamConverter;
use crate::color::Observer;
use crate::geometry::Aabb;
use crate::geometry::Ray;
use crate::light::{
    EnvironmentLight, EnvironmentRadiance, Light, LightFlags, LightLeSample, LightLiSample,
    LightSampleContext,
};
use crate::material::{
    BsdfSample, EmissionProfile, Material, MaterialFlags, ShadingContext, TransportMode as HostMode,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd, SpdSample, LANES};
use glam::{Vec2, Vec3A};
use spectrace_plugin_api::abi::std_types::{ROption, RResult};
use spectrace_plugin_api::{
    light_flags, material_flags, status, BeamRepresentation, EmittedRay, Flags, LightBox,
    LightObject, MaterialBox, MaterialObject, ObserverBox, ObserverObject, PluginError,
    RandomSample, SceneBounds, SpdBox, SpdObject, TransportMode, Vec3, Vec4f,
};
use std::fmt;
use std::sync::{Arc, OnceLock};

pub use super::faults::{Origin, PluginFaults};

fn v3(v: Vec3A) -> Vec3 {
    Vec3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// `v` as a unit vector: unchanged when it is one to f32 precision (so a direction the host
/// handed out comes back with the same bits), else normalised.
fn unit(v: Vec3A) -> Vec3A {
    if (v.length_squared() - 1.0).abs() <= 4.0 * f32::EPSILON {
        v
    } else {
        v.normalize_or_zero()
    }
}

fn mode(m: HostMode) -> TransportMode {
    match m {
        HostMode::Radiance => TransportMode::Radiance,
        HostMode::Importance => TransportMode::Importance,
    }
}

/// The root module's `take_error`: the error of the last failed per-sample call on this thread.
pub type TakeError = extern "C" fn() -> ROption<PluginError>;

/// Reports of the per-sample calls of one plugin object: a failed call's kept error taken from
/// its library and recorded with the call named, a refused answer counted with the call named.
#[derive(Clone, Debug)]
struct Calls {
    origin: Origin,
    take_error: TakeError,
}

impl Calls {
    /// The error `call` kept on this thread, taken from the library, with the call named in
    /// front of it unless it names itself (a caught panic's message starts with its call, see
    /// the API's `guard`).
    fn take(&self, call: &'static str) -> Option<PluginError> {
        let mut e = (self.take_error)().into_option()?;
        if !e.message.starts_with(call) {
            e.message = format!("{call}: {}", e.message).into();
        }
        Some(e)
    }

    /// A call that answered a status other than `WRITTEN`: nothing (`NONE`), failed (`ERROR`:
    /// its kept error taken and reported), or a status the interface does not have.
    #[cold]
    #[inline(never)]
    fn not_written<T>(&self, call: &'static str, status: u32, fallback: T) -> T {
        if status == status::NONE {
            return fallback;
        }
        let e = if status == status::ERROR {
            self.take(call).unwrap_or_else(|| {
                other_error(format!(
                    "{call} answered ERROR (status 2) without keeping an error"
                ))
            })
        } else {
            other_error(format!(
                "{call} answered status {status}, which is none of NONE (0), WRITTEN (1) and \
                 ERROR (2)"
            ))
        };
        self.origin.fail(e, fallback)
    }

    /// An answer refused for `reason`: the call's error when it kept one (a failed call answers
    /// NaN), else the answer dropped and counted; either reported with the call named.
    #[cold]
    #[inline(never)]
    fn refused<T>(&self, call: &'static str, reason: checked::Reason, fallback: T) -> T {
        match self.take(call) {
            Some(e) => self.origin.fail(e, fallback),
            None => {
                self.dropped(call, reason);
                fallback
            }
        }
    }

    /// A written answer refused for `reason` (no error to take), counted with the call named.
    #[cold]
    #[inline(never)]
    fn dropped(&self, call: &'static str, reason: checked::Reason) {
        self.origin.dropped(named_reason(call, reason));
    }
}

fn other_error(message: String) -> PluginError {
    PluginError::new(spectrace_plugin_api::ErrorKind::Other, message)
}

/// `reason` with `call` named, as dropped answers are counted (a fixed set: the counts are kept
/// by `&'static str`).
fn named_reason(call: &'static str, reason: checked::Reason) -> checked::Reason {
    macro_rules! table {
        ($($c:literal),*) => {
            match (call, reason) {
                $(
                    ($c, checked::BAD_DIRECTION) => concat!($c, ": direction not a finite unit vector"),
                    ($c, checked::BAD_DENSITY) => concat!($c, ": pdf NaN, infinite or negative"),
                    ($c, checked::BAD_VALUE) => concat!($c, ": value NaN, infinite or negative"),
                )*
                _ => reason,
            }
        };
    }
    table!(
        "sample",
        "eval",
        "pdf",
        "emitted",
        "sample_toward",
        "incident_pdf",
        "sample_emission",
        "emission_pdf",
        "radiance"
    )
}

// ----------------------------------------------------------------------------------------------
// SPD

/// A plugin SPD as a host [`Spd`].
pub struct PluginSpd {
    spd: SpdBox,
    range: (f64, f64),
    /// The spectral lines the plugin declared: a line draw is recognised by its wavelength and
    /// weighed by the line's share, exactly as the host's own line SPDs are.
    lines: Vec<crate::spectrum::DeltaLine>,
    origin: Origin,
}

impl PluginSpd {
    /// Wrap `spd` with its declarations. Lines with a wavelength or weight that is not finite
    /// and positive are dropped and counted.
    pub fn new(spd: SpdObject, origin: Origin) -> Self {
        let mut lines = Vec::with_capacity(spd.lines.len());
        for l in spd.lines.iter() {
            if l.nm.is_finite() && l.nm > 0.0 && l.weight.is_finite() && l.weight > 0.0 {
                lines.push(crate::spectrum::DeltaLine {
                    lambda: l.nm,
                    weight: l.weight,
                });
            } else {
                origin
                    .faults
                    .record_invalid(&origin.label, "spectral line not finite and positive");
            }
        }
        Self {
            range: (spd.range.min_nm, spd.range.max_nm),
            spd: spd.spd,
            lines,
            origin,
        }
    }
}

impl fmt::Debug for PluginSpd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginSpd({})", self.origin.label)
    }
}

impl Spd for PluginSpd {
    fn value(&self, lambda_nm: f64) -> f64 {
        (self.origin)
            .checked(self.spd.value(lambda_nm), |v| checked::scalar(*v))
            .unwrap_or(0.0)
    }
    fn sample(&self, u: f64) -> SpdSample {
        match (self.origin).checked(self.spd.sample(u), checked::wavelength_sample) {
            Some(s) => SpdSample {
                lambda: s.nm,
                pdf: s.pdf,
                is_delta: self.lines.iter().any(|l| l.lambda == s.nm),
            },
            None => SpdSample {
                lambda: 0.5 * (self.range.0 + self.range.1),
                pdf: 0.0,
                is_delta: false,
            },
        }
    }
    fn pdf(&self, lambda_nm: f64) -> f64 {
        (self.origin)
            .checked(self.spd.pdf(lambda_nm), |p| checked::density(*p))
            .unwrap_or(0.0)
    }
    fn range(&self) -> (f64, f64) {
        self.range
    }
    fn delta_lines(&self) -> Vec<crate::spectrum::DeltaLine> {
        self.lines.clone()
    }
    fn is_delta(&self) -> bool {
        !self.lines.is_empty()
    }
}

// ----------------------------------------------------------------------------------------------
// Observer

/// A plugin colour observer as a host [`Observer`].
pub struct PluginObserver {
    observer: ObserverBox,
    name: String,
    range: (f64, f64),
    /// [`Observer::integral_y`], summed once: integrators ask for it per path, and the sum
    /// takes one plugin call per nm of the range (it made light tracing with a plugin observer
    /// 10–30× slower).
    integral_y: OnceLock<f64>,
    origin: Origin,
}

impl PluginObserver {
    /// Wrap `observer` with its declarations.
    pub fn new(object: ObserverObject, origin: Origin) -> Self {
        Self {
            name: object.name.into_string(),
            range: (object.range.min_nm, object.range.max_nm),
            integral_y: OnceLock::new(),
            observer: object.observer,
            origin,
        }
    }
}

impl fmt::Debug for PluginObserver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginObserver({})", self.origin.label)
    }
}

impl Observer for PluginObserver {
    fn name(&self) -> &str {
        &self.name
    }
    fn range(&self) -> (f64, f64) {
        self.range
    }
    fn xyz_bar(&self, lambda_nm: f64) -> [f64; 3] {
        (self.origin)
            .checked(self.observer.xyz_bar(lambda_nm), |v| {
                checked::finite([v.x, v.y, v.z])
            })
            .map_or([0.0; 3], |v| [v.x, v.y, v.z])
    }
    fn integral_y(&self) -> f64 {
        // The trait's own sum, in the same order, so the value is the same bits.
        *self.integral_y.get_or_init(|| {
            crate::color::observer::integration_grid(self)
                .map(|l| self.xyz_bar(l)[1])
                .sum()
        })
    }
}

// ----------------------------------------------------------------------------------------------
// Material

fn material_bits(f: Flags, transmission_event: Option<bool>) -> MaterialFlags {
    let scatters = [
        material_flags::DIFFUSE,
        material_flags::GLOSSY,
        material_flags::SPECULAR,
    ]
    .iter()
    .any(|&b| f.contains(b));
    let pairs = [
        (material_flags::DIFFUSE, MaterialFlags::DIFFUSE),
        (material_flags::GLOSSY, MaterialFlags::GLOSSY),
        (material_flags::SPECULAR, MaterialFlags::SPECULAR),
        (material_flags::TRANSMISSION, MaterialFlags::TRANSMISSION),
        (material_flags::DISPERSIVE, MaterialFlags::DISPERSIVE),
        (material_flags::EMISSIVE, MaterialFlags::EMISSIVE),
        // Kept so the analysis and the scene's warnings see it. A material that declares it
        // without offering re-radiation renders its reflectance, and the scene warns.
        (material_flags::FLUORESCENT, MaterialFlags::FLUORESCENT),
    ];
    let mut out = MaterialFlags::NONE;
    for (p, h) in pairs {
        if f.contains(p) {
            out |= h;
        }
    }
    // The plugin interface has no reflection bit: a material with a lobe reflects unless an
    // event says it transmitted (a purely emissive one scatters nothing, as the built-in).
    if scatters && transmission_event != Some(true) {
        out |= MaterialFlags::REFLECTION;
    }
    out
}

/// [`material_bits`] of one scattering event (`transmission_event` read from the event's own
/// TRANSMISSION bit), in a few bit operations: the plugin interface's bits DIFFUSE, GLOSSY,
/// SPECULAR (1, 2, 4), TRANSMISSION (8) and DISPERSIVE, EMISSIVE, FLUORESCENT (16, 32, 64) are
/// the host's (4, 8, 16), (2) and (32, 64, 128), and a lobe without TRANSMISSION reflects. The
/// test `event_bits_match_material_bits` checks it against [`material_bits`] for all 128
/// combinations. Looked up in [`EVENT_TABLE`], made from these operations at compile time (one
/// load per event instead of a dozen instructions); bits above the seven are ignored, as here.
const fn event_bits_ops(b: u32) -> u32 {
    let lobes = b & 0b111;
    let transmits = (b >> 3) & 1;
    let reflects = (lobes != 0 && transmits == 0) as u32;
    reflects | (transmits << 1) | (lobes << 2) | (((b >> 4) & 0b111) << 5)
}

/// [`event_bits_ops`] of every combination of the interface's seven event bits.
const EVENT_TABLE: [u8; 128] = {
    let mut t = [0u8; 128];
    let mut b = 0;
    while b < 128 {
        t[b] = event_bits_ops(b as u32) as u8;
        b += 1;
    }
    t
};

/// The host's bits of one scattering event (see [`event_bits_ops`]).
#[inline]
fn event_bits(f: Flags) -> MaterialFlags {
    MaterialFlags(u32::from(EVENT_TABLE[(f.0 & 0x7f) as usize]))
}

/// The host's vector in the interface's layout: one SIMD register, `w` cleared (a lane select
/// against zero, one AND on SSE, so `x, y, z` keep their bits).
#[inline]
fn v4f(v: Vec3A) -> Vec4f {
    #[cfg(target_arch = "x86_64")]
    let v = glam::Vec4::select(
        glam::BVec4A::new(true, true, true, false),
        glam::Vec4::from(std::arch::x86_64::__m128::from(v)),
        glam::Vec4::ZERO,
    );
    #[cfg(not(target_arch = "x86_64"))]
    let v = v.extend(0.0);
    let [x, y, z, w] = v.to_array();
    Vec4f { x, y, z, w }
}

/// A plugin's vector as the host's; its unused `w` is not trusted (a plugin may leave anything
/// there).
#[inline]
fn host_v(v: Vec4f) -> Vec3A {
    Vec3A::new(v.x, v.y, v.z)
}

/// A plugin material as a host [`Material`]. An EMISSIVE one also describes its emission
/// ([`Material::emission`]), so the scene builds an area light on every object that uses it,
/// sampled and MIS-weighted like the built-in `emissive`. A FLUORESCENT one hands over its
/// re-radiation ([`Material::reradiation`]), which the integrators shift wavelengths with as for
/// the built-in `fluorescent`. Its declarations (spectrally flat, one value for every direction,
/// the cosine-weighted density) are checked when it is built and then relied on.
pub struct PluginMaterial {
    material: MaterialBox,
    flags: MaterialFlags,
    emission: Option<EmissionProfile>,
    /// The re-radiation, checked when the material was built.
    reradiation: Option<super::reradiation::PluginReradiation>,
    /// Declared spectrally flat and found so when built.
    flat: bool,
    /// Declared to have one BSDF value for every direction and found so when built.
    same_f: bool,
    /// Declared to sample with the cosine-weighted density and found so when built: `pdf` is
    /// then computed here ([`super::cosine_pdf`]).
    cosine: bool,
    calls: Calls,
}

impl PluginMaterial {
    /// Wrap `object`, a material of the library whose `take_error` is given, checking its
    /// declarations: a claim the material's own answers contradict is refused, naming the
    /// plugin object and `item` (the scene's name for it). A material that offers re-radiation
    /// fluoresces: it gets the FLUORESCENT flag even if it did not declare it.
    pub fn new(
        object: MaterialObject,
        take_error: TakeError,
        origin: Origin,
        item: &str,
    ) -> Result<Self, String> {
        let MaterialObject {
            material,
            flags: declared,
            emission,
            reradiation,
        } = object;
        let reradiation = match reradiation.into_option() {
            Some(rr) => Some(super::reradiation::PluginReradiation::new(
                rr,
                Origin {
                    label: format!("{} as {item}", origin.label),
                    faults: origin.faults.clone(),
                },
            )?),
            None => None,
        };
        let mut flags = material_bits(declared, None);
        if reradiation.is_some() {
            flags |= MaterialFlags::FLUORESCENT;
        }
        let calls = Calls { origin, take_error };
        let mut m = Self {
            material,
            flags,
            emission: None,
            reradiation,
            flat: false,
            same_f: false,
            cosine: false,
            calls,
        };
        if flags.contains(MaterialFlags::EMISSIVE) {
            m.emission = match emission.into_option() {
                Some(e) if checked::scalar(e.scale).is_ok() => Some(EmissionProfile {
                    spd: Arc::new(PluginSpd::new(e.spectrum, m.calls.origin.clone())),
                    scale: e.scale as f32,
                    two_sided: e.two_sided,
                }),
                Some(_) => {
                    m.calls.origin.dropped(checked::BAD_VALUE);
                    None
                }
                None => m.probe_emission(),
            };
        }
        let label = m.calls.origin.label.clone();
        if declared.contains(material_flags::SPECTRALLY_FLAT) {
            super::flatness::check(&m, m.flags, m.reradiation.is_some()).map_err(|e| {
                format!(
                    "{label} as {item}: declares itself spectrally flat (SPECTRALLY_FLAT), but {e}"
                )
            })?;
            m.flat = true;
        }
        if declared.contains(material_flags::SAME_VALUE_ALL_DIRECTIONS) {
            super::same_f::check(&m).map_err(|e| {
                format!(
                    "{label} as {item}: declares one BSDF value for every direction \
                     (SAME_VALUE_ALL_DIRECTIONS), but {e}"
                )
            })?;
            m.same_f = true;
        }
        if declared.contains(material_flags::COSINE_PDF) {
            super::cosine_pdf::check(&m).map_err(|e| {
                format!(
                    "{label} as {item}: declares the cosine-weighted density (COSINE_PDF), but {e}"
                )
            })?;
            m.cosine = true;
        }
        Ok(m)
    }

    /// The emission an area light on this material uses: `emitted` along the normal, at
    /// 360, 361, …, 830 nm, as a normalised table (linear interpolation) and its integral in
    /// W/(m²·sr); two-sided when anything leaves the back. Like the built-in area lights this
    /// takes the emission to be the same at every point and in every direction of a side
    /// (Lambertian); `None` when nothing leaves the front.
    fn probe_emission(&self) -> Option<EmissionProfile> {
        let nm: Vec<f64> = (360..=830).map(f64::from).collect();
        let ctx = ShadingContext::default();
        let side = |z: f32| -> Vec<f64> {
            let mut out = Vec::with_capacity(nm.len());
            for chunk in nm.chunks(LANES) {
                let mut lambda = SampledWavelengths {
                    lambda: [chunk[0] as f32; LANES],
                    pdf: [1.0; LANES],
                    lanes: crate::spectrum::LaneMask::ALL,
                };
                for (l, &c) in lambda.lambda.iter_mut().zip(chunk) {
                    *l = c as f32;
                }
                let v = self.emitted(Vec3A::new(0.0, 0.0, z), &ctx, &lambda);
                out.extend(v.0[..chunk.len()].iter().map(|&x| f64::from(x)));
            }
            out
        };
        let front = side(1.0);
        let integral: f64 = front.windows(2).map(|p| 0.5 * (p[0] + p[1])).sum();
        if !(integral > 0.0 && integral.is_finite()) {
            return None;
        }
        let spd = crate::spectrum::TabulatedSpd::new(
            &self.calls.origin.label,
            &nm,
            &front,
            crate::spectrum::Interpolation::Linear,
        )
        .ok()?;
        let two_sided = side(-1.0).iter().any(|&x| x > 0.0);
        Some(EmissionProfile {
            spd: Arc::new(spd),
            scale: integral as f32,
            two_sided,
        })
    }

    /// The density asked of the plugin, out of line: a material that declares the
    /// cosine-weighted density gets its `pdf` in a few instructions, as the built-in does,
    /// without this path's frame. The directions come by reference, as `pdf` got them.
    #[inline(never)]
    fn pdf_call(
        &self,
        wo: &Vec3A,
        wi: &Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> f32 {
        let p = self.material.pdf(
            super::layout::as_vec4f(wo),
            super::layout::as_vec4f(wi),
            super::layout::as_surface(ctx),
            super::layout::as_wavelengths(lambda),
            mode(m),
        );
        match checked::density_f32(p) {
            Ok(()) => p,
            Err(reason) => self.calls.refused("pdf", reason, 0.0),
        }
    }
}

impl fmt::Debug for PluginMaterial {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginMaterial({})", self.calls.origin.label)
    }
}

impl Material for PluginMaterial {
    fn flags(&self) -> MaterialFlags {
        self.flags
    }

    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        u_lobe: f32,
        u: Vec2,
        m: HostMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        // Written by the plugin straight into the caller's record (see `super::layout`), checked
        // there, and its event bits translated to the host's. The record holds a valid sample
        // or zeros when the plugin gets it (the caller's), so whatever the plugin leaves in it
        // is checked like what it writes.
        let rec = super::layout::as_scatter_mut(out);
        let status = self.material.sample(
            super::layout::as_vec4f(&wo),
            super::layout::as_surface(ctx),
            super::layout::as_wavelengths(lambda),
            u_lobe,
            u.x,
            u.y,
            mode(m),
            rec,
        );
        if status != status::WRITTEN {
            return self.calls.not_written("sample", status, None);
        }
        match checked::scatter_f32(rec) {
            Ok(()) => {
                out.flags = event_bits(Flags(out.flags.0));
                Some(out)
            }
            Err(reason) => {
                self.calls.dropped("sample", reason);
                None
            }
        }
    }

    fn eval(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> SampledSpectrum {
        let r = self.material.eval(
            super::layout::as_vec4f(&wo),
            super::layout::as_vec4f(&wi),
            super::layout::as_surface(ctx),
            super::layout::as_wavelengths(lambda),
            mode(m),
        );
        // Checked and stored as one vector (from the [f32; 4] the compiler went through
        // general registers, lane by lane).
        let v = super::layout::values_as_vec4(r);
        match checked::vector_f32(v) {
            Ok(()) => SampledSpectrum(v.to_array()),
            Err(reason) => self.calls.refused("eval", reason, SampledSpectrum::zero()),
        }
    }

    fn pdf(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> f32 {
        if self.cosine {
            return super::cosine_pdf::cosine_pdf(wo, wi);
        }
        self.pdf_call(&wo, &wi, ctx, lambda, m)
    }

    fn emission(&self) -> Option<EmissionProfile> {
        self.emission.clone()
    }

    fn spectrally_flat(&self) -> bool {
        self.flat
    }

    fn f_same_for_all_directions(&self) -> bool {
        self.same_f
    }

    fn cosine_weighted_pdf(&self) -> bool {
        self.cosine
    }

    fn reradiation(&self) -> Option<&dyn crate::spectrum::reradiation::Reradiation> {
        self.reradiation
            .as_ref()
            .map(|r| r as &dyn crate::spectrum::reradiation::Reradiation)
    }

    fn emitted(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        if !self.flags.contains(MaterialFlags::EMISSIVE) {
            return SampledSpectrum::zero();
        }
        let r = self.material.emitted(
            super::layout::as_vec4f(&wo),
            super::layout::as_surface(ctx),
            super::layout::as_wavelengths(lambda),
        );
        match checked::values_f32(&r.v) {
            Ok(()) => SampledSpectrum(r.v),
            Err(reason) => self
                .calls
                .refused("emitted", reason, SampledSpectrum::zero()),
        }
    }
}

// ----------------------------------------------------------------------------------------------
// Light

/// A plugin light with the ENVIRONMENT capability, as the radiance source of a host
/// [`EnvironmentLight`]: `radiance` on escape, and with CONNECTABLE also the plugin's own
/// incident sampling (`sample_toward`, `incident_pdf`) for next-event estimation; without it
/// the host samples directions uniformly.
struct PluginEnvironment {
    light: Arc<LightBox>,
    calls: Calls,
    spectrum: Arc<dyn Spd>,
    mean_radiance: f64,
    sampled: bool,
}

impl fmt::Debug for PluginEnvironment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginEnvironment({})", self.calls.origin.label)
    }
}

impl PluginEnvironment {
    /// Radiance integrated over 360–830 nm (trapezoid, 10 nm) and averaged over 256 directions
    /// of a Fibonacci sphere, W/(m²·sr): only the light-selection weight depends on it.
    fn estimate_mean(&self) -> f64 {
        let n_dir = 256;
        let nm: Vec<f32> = (0..48).map(|i| 360.0 + 10.0 * i as f32).collect();
        let mut sum = 0.0;
        for k in 0..n_dir {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / n_dir as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = k as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
            let d = Vec3A::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
            for chunk in nm.chunks(LANES) {
                let mut lambda = SampledWavelengths {
                    lambda: [chunk[0]; LANES],
                    pdf: [1.0; LANES],
                    lanes: crate::spectrum::LaneMask::ALL,
                };
                lambda.lambda[..chunk.len()].copy_from_slice(chunk);
                let v = self.radiance(d, &lambda);
                for (i, &l) in chunk.iter().enumerate() {
                    let edge = l == nm[0] || l == nm[nm.len() - 1];
                    sum += f64::from(v.0[i]) * if edge { 5.0 } else { 10.0 };
                }
            }
        }
        sum / n_dir as f64
    }
}

impl EnvironmentRadiance for PluginEnvironment {
    fn radiance(&self, dir: Vec3A, lambda: &SampledWavelengths) -> SampledSpectrum {
        let r = (self.light).radiance(
            super::layout::as_vec4f(&dir),
            super::layout::as_wavelengths(lambda),
        );
        match checked::values_f32(&r.v) {
            Ok(()) => SampledSpectrum(r.v),
            Err(reason) => self
                .calls
                .refused("radiance", reason, SampledSpectrum::zero()),
        }
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.spectrum.clone()
    }

    fn mean_radiance(&self) -> f64 {
        self.mean_radiance
    }

    fn sample_direction(&self, p: Vec3A, u: Vec2) -> Option<(Vec3A, f32)> {
        if !self.sampled {
            return Some((
                crate::light::sample_uniform_sphere(u),
                1.0 / (4.0 * std::f32::consts::PI),
            ));
        }
        // The direction must not depend on the wavelengths: ask at 550 nm.
        let lambda = spectrace_plugin_api::Wavelengths::at([550.0; LANES]);
        let receiver = receiver_at(p);
        let mut s = spectrace_plugin_api::Incident::default();
        let status = self
            .light
            .sample_toward(&receiver, u.x, u.y, &lambda, &mut s);
        if status != status::WRITTEN {
            return self.calls.not_written("sample_toward", status, None);
        }
        match checked::incident_f32(&s) {
            Ok(()) if s.pdf > 0.0 => Some((unit(host_v(s.direction)), s.pdf)),
            Ok(()) => None,
            Err(reason) => {
                self.calls.dropped("sample_toward", reason);
                None
            }
        }
    }

    fn direction_pdf(&self, p: Vec3A, dir: Vec3A) -> f32 {
        if !self.sampled {
            return 1.0 / (4.0 * std::f32::consts::PI);
        }
        let p = self
            .light
            .incident_pdf(&receiver_at(p), super::layout::as_vec4f(&dir));
        match checked::density_f32(p) {
            Ok(()) => p,
            Err(reason) => self.calls.refused("incident_pdf", reason, 0.0),
        }
    }
}

/// A receiver at `p` with no error bound and no normal (environment probes).
fn receiver_at(p: Vec3A) -> spectrace_plugin_api::Receiver {
    spectrace_plugin_api::Receiver {
        p: v4f(p),
        ..Default::default()
    }
}

/// A plugin light as a host [`Light`]. Without the CONNECTABLE capability it is BEAMS_ONLY:
/// integrators can only trace the beams it hands out (see [`PluginLight::next_beam`]). With the
/// ENVIRONMENT capability it is an [`EnvironmentLight`] whose radiance the plugin gives (the
/// host places and samples the emitting sphere).
///
/// The light learns the scene's extent before rendering (its power is read again afterwards: a
/// distant light's depends on it), and its declared emission SPD stands for its spectrum
/// everywhere (see [`Light::spd`]).
pub struct PluginLight {
    light: Arc<LightBox>,
    flags: LightFlags,
    power: f64,
    /// The power read again once the light knows the scene's extent.
    power_with_bounds: OnceLock<f64>,
    /// The geometry's bounds, kept from [`Light::preprocess`] for the `scene_bounds` call.
    scene_bounds: OnceLock<Aabb>,
    spectrum: Arc<dyn Spd>,
    calls: Calls,
    environment: Option<EnvironmentLight>,
    /// Converts the beams of the type's declared representation (native ones pass unchanged).
    beams: BeamConverter,
    /// Declared UNIFORM_SPECTRAL_SHAPE and, where it matters, found so.
    uniform: bool,
    /// Sampled and asked for densities through the plugin's per-sample calls: CONNECTABLE and
    /// not an environment (which the host samples itself).
    connected: bool,
    /// An environment whose light subpaths start from the plugin's own `sample_emission` and
    /// `emission_pdf` on the host's sphere (declared SPHERE_EMISSION).
    sphere_emission: bool,
}

impl PluginLight {
    /// Wrap `object`, a light of the library whose `take_error` is given, of a type whose beams
    /// are in `representation`. Its declarations are checked: a CONNECTABLE light must declare
    /// its emission spectrum, and a claim of one spectral shape everywhere that the light's own
    /// emission contradicts is refused; either error names the plugin object and `item` (the
    /// scene's name for it).
    pub fn new(
        object: LightObject,
        representation: BeamRepresentation,
        take_error: TakeError,
        origin: Origin,
        item: &str,
    ) -> Result<Self, String> {
        let LightObject {
            light,
            flags: caps,
            spectrum,
        } = object;
        let beams = BeamConverter::new(representation)
            .map_err(|e| format!("{} as {item}: {e}", origin.label))?;
        let mut flags = LightFlags::default();
        if caps.contains(light_flags::DELTA_POSITION) {
            flags = flags | LightFlags::DELTA_POSITION;
        }
        if caps.contains(light_flags::DELTA_DIRECTION) {
            flags = flags | LightFlags::DELTA_DIRECTION;
        }
        let is_environment = caps.contains(light_flags::ENVIRONMENT);
        let connectable = caps.contains(light_flags::CONNECTABLE);
        if is_environment {
            flags = LightFlags::ENVIRONMENT;
        } else if !connectable {
            flags = flags | LightFlags::BEAMS_ONLY;
        }
        let spectrum: Arc<dyn Spd> = match spectrum.into_option() {
            Some(spd) => Arc::new(PluginSpd::new(spd, origin.clone())),
            None if connectable || is_environment => {
                return Err(format!(
                    "{} as {item}: declares {} but no emission spectrum (emission_spectrum \
                     returned None); the host draws the light's wavelengths from it",
                    origin.label,
                    if is_environment {
                        "ENVIRONMENT"
                    } else {
                        "CONNECTABLE"
                    }
                ))
            }
            // Only its beams are traced, each with its own wavelength: the spectrum is never
            // sampled. Flat over the visible range, for anything that asks.
            None => match crate::spectrum::TabulatedSpd::new(
                "flat",
                &[360.0, 830.0],
                &[1.0, 1.0],
                crate::spectrum::Interpolation::Linear,
            ) {
                Ok(flat) => Arc::new(flat),
                Err(e) => return Err(format!("{}: {e}", origin.label)),
            },
        };
        let light = Arc::new(light);
        let calls = Calls { origin, take_error };
        let mut env_source = None;
        let (power, environment) = if is_environment {
            let mut source = PluginEnvironment {
                light: light.clone(),
                calls: calls.clone(),
                spectrum: spectrum.clone(),
                mean_radiance: 0.0,
                sampled: connectable,
            };
            source.mean_radiance = source.estimate_mean();
            let source = Arc::new(source);
            env_source = Some(source.clone());
            (0.0, Some(EnvironmentLight::new(source)))
        } else {
            let power = (calls.origin)
                .checked(light.total_power_w(), |p| checked::scalar(*p))
                .unwrap_or(0.0);
            (power, None)
        };
        let mut l = Self {
            light,
            flags,
            power,
            power_with_bounds: OnceLock::new(),
            scene_bounds: OnceLock::new(),
            spectrum,
            calls,
            environment,
            beams,
            uniform: false,
            connected: connectable && !is_environment,
            sphere_emission: is_environment && caps.contains(light_flags::SPHERE_EMISSION),
        };
        if caps.contains(light_flags::UNIFORM_SPECTRAL_SHAPE) {
            if !l.flags.contains(LightFlags::BEAMS_ONLY) {
                let env = env_source.as_deref().map(|e| e as &dyn EnvironmentRadiance);
                super::uniform_shape::check(&l, env, &*l.spectrum).map_err(|e| {
                    format!(
                        "{} as {item}: declares one spectral shape everywhere \
                         (UNIFORM_SPECTRAL_SHAPE), but {e}",
                        l.calls.origin.label
                    )
                })?;
            }
            l.uniform = true;
        }
        Ok(l)
    }

    /// Tell the light the scene's extent and read its power again.
    fn give_bounds(&self, view: &Aabb) {
        let scene = self.scene_bounds.get().copied().unwrap_or(*view);
        let bounds = SceneBounds {
            min: v3(scene.min),
            max: v3(scene.max),
            view_min: v3(view.min),
            view_max: v3(view.max),
        };
        let origin = &self.calls.origin;
        if origin
            .checked(self.light.scene_bounds(&bounds), |_| Ok(()))
            .is_none()
        {
            return;
        }
        let power = if self.environment.is_some() {
            // An environment may not know its power (it is optional for them): an error or a
            // non-positive value means "estimate it", and is not a fault.
            match self.light.total_power_w().into_result() {
                Ok(p) if p.is_finite() && p > 0.0 => Some(p),
                _ => None,
            }
        } else {
            origin.checked(self.light.total_power_w(), |p| checked::scalar(*p))
        };
        if let Some(p) = power {
            let _ = self.power_with_bounds.set(p);
        }
    }
}

impl PluginLight {
    /// An environment's emitted ray from the plugin's `sample_emission` (declared
    /// SPHERE_EMISSION), checked: finite, positive densities, a start on the host's sphere
    /// `e` (within 10⁻³ of its radius) and a direction into it; the sphere's inward normal is
    /// the ray's normal, whatever the plugin wrote there.
    fn sphere_emission_sample(
        &self,
        e: &EnvironmentLight,
        u1: Vec2,
        u2: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLeSample> {
        let mut s = EmittedRay::default();
        let u = [u1.x, u1.y, u2.x, u2.y];
        let status =
            (self.light).sample_emission(&u, super::layout::as_wavelengths(lambda), &mut s);
        if status != status::WRITTEN {
            return self.calls.not_written("sample_emission", status, None);
        }
        if let Err(reason) = checked::emission_f32(&s) {
            self.calls.dropped("sample_emission", reason);
            return None;
        }
        if !(s.pdf_position > 0.0 && s.pdf_direction > 0.0) {
            return None;
        }
        let (origin, dir) = (host_v(s.origin), unit(host_v(s.direction)));
        let Some(normal) = on_sphere(e, origin, dir) else {
            self.calls.dropped(
                "sample_emission",
                "an environment's emitted ray (SPHERE_EMISSION) must start on the host's \
                 sphere around the view bounds and point into it",
            );
            return None;
        };
        Some(LightLeSample {
            ray: Ray::new(origin, dir),
            radiance: SampledSpectrum(s.value),
            pdf_pos: s.pdf_position,
            pdf_dir: s.pdf_direction,
            normal,
        })
    }

    /// The densities of an environment's emitted ray from the plugin's `emission_pdf`
    /// (declared SPHERE_EMISSION); `(0, 0)` off the sphere or for a ray pointing out of it.
    fn sphere_emission_pdf(&self, e: &EnvironmentLight, ray: &Ray) -> (f32, f32) {
        let dir = unit(ray.dir);
        if on_sphere(e, ray.origin, dir).is_none() {
            return (0.0, 0.0);
        }
        let p = (self.light).emission_pdf(
            super::layout::as_vec4f(&ray.origin),
            super::layout::as_vec4f(&dir),
        );
        match checked::density_f32(p.position).and(checked::density_f32(p.direction)) {
            Ok(()) => (p.position, p.direction),
            Err(reason) => self.calls.refused("emission_pdf", reason, (0.0, 0.0)),
        }
    }
}

/// The inward unit normal of environment `e`'s sphere at `origin`, if `origin` lies on it
/// (within 10⁻³ of its radius) and `dir` points inwards.
fn on_sphere(e: &EnvironmentLight, origin: Vec3A, dir: Vec3A) -> Option<Vec3A> {
    let (c, r) = e.sphere();
    let to_c = c - origin;
    let d = to_c.length();
    // The built-in environment's own inward normal (`normalize`, not a division: the two differ
    // in the last bit, and a plugin environment must render bit-for-bit like the built-in).
    let n = to_c.normalize_or_zero();
    ((d / r - 1.0).abs() <= 1e-3 && n.dot(dir) > 0.0).then_some(n)
}

impl fmt::Debug for PluginLight {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginLight({})", self.calls.origin.label)
    }
}

impl Light for PluginLight {
    fn flags(&self) -> LightFlags {
        self.flags
    }

    fn power(&self) -> f64 {
        if let Some(&p) = self.power_with_bounds.get() {
            return p;
        }
        match &self.environment {
            Some(e) => e.power(),
            None => self.power,
        }
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.spectrum.clone()
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        if !self.connected {
            return match &self.environment {
                Some(e) => e.sample_li(ctx, u, lambda),
                None => None,
            };
        }
        // Written by the plugin in place (see `super::layout`), then checked.
        let mut s = LightLiSample {
            radiance: SampledSpectrum::zero(),
            wi: Vec3A::ZERO,
            pdf: 0.0,
            p_light: Vec3A::ZERO,
            p_light_error: Vec3A::ZERO,
            n_light: Vec3A::ZERO,
        };
        let out = super::layout::as_incident_mut(&mut s);
        let status = self.light.sample_toward(
            super::layout::as_receiver(ctx),
            u.x,
            u.y,
            super::layout::as_wavelengths(lambda),
            out,
        );
        if status != status::WRITTEN {
            return self.calls.not_written("sample_toward", status, None);
        }
        match checked::incident_f32(out) {
            Ok(()) if s.pdf > 0.0 => Some(s),
            Ok(()) => None,
            Err(reason) => {
                self.calls.dropped("sample_toward", reason);
                None
            }
        }
    }

    fn pdf_li(&self, ctx: &LightSampleContext, p_light: Vec3A, n_light: Vec3A) -> f32 {
        if let Some(e) = &self.environment {
            return e.pdf_li(ctx, p_light, n_light);
        }
        // Other plugin lights have no surface in the scene: rays cannot hit them, and a delta
        // light has no density.
        0.0
    }

    fn radiance(
        &self,
        p: Vec3A,
        n: Vec3A,
        uv: Vec2,
        w: Vec3A,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        match &self.environment {
            Some(e) => e.radiance(p, n, uv, w, lambda),
            // Other plugin lights have no surface in the scene; rays cannot hit them.
            None => SampledSpectrum::zero(),
        }
    }

    fn sample_le(&self, u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        if !self.connected {
            return match &self.environment {
                Some(e) if self.sphere_emission => self.sphere_emission_sample(e, u1, u2, lambda),
                Some(e) => e.sample_le(u1, u2, lambda),
                None => None,
            };
        }
        let mut s = EmittedRay::default();
        let u = [u1.x, u1.y, u2.x, u2.y];
        let status =
            (self.light).sample_emission(&u, super::layout::as_wavelengths(lambda), &mut s);
        if status != status::WRITTEN {
            return self.calls.not_written("sample_emission", status, None);
        }
        match checked::emission_f32(&s) {
            Ok(()) if s.pdf_position > 0.0 && s.pdf_direction > 0.0 => Some(LightLeSample {
                ray: Ray::new(host_v(s.origin), host_v(s.direction)),
                radiance: SampledSpectrum(s.value),
                pdf_pos: s.pdf_position,
                pdf_dir: s.pdf_direction,
                normal: host_v(s.normal),
            }),
            Ok(()) => None,
            Err(reason) => {
                self.calls.dropped("sample_emission", reason);
                None
            }
        }
    }

    fn next_beam(&self, u: &RandomSample) -> Option<spectrace_plugin_api::Beam> {
        if self.environment.is_some() {
            // Where an environment's beams start depends on the scene, which the plugin does
            // not know: the host's own emission sampling stands in for them.
            return None;
        }
        // Converted here, once per beam (the seed's adapter; native beams pass unchanged).
        let r = match self.light.next_beam(u) {
            RResult::ROk(b) => match self.beams.convert(&b, u) {
                Ok(b) => RResult::ROk(b),
                Err(reason) => {
                    self.calls.origin.dropped(reason);
                    return None;
                }
            },
            RResult::RErr(e) => RResult::RErr(e),
        };
        self.calls.origin.checked(r, checked::beam)
    }

    fn number_of_beams(&self) -> f64 {
        self.light.number_of_beams()
    }

    fn pdf_le(&self, ray: &Ray, n: Vec3A) -> (f32, f32) {
        if !self.connected {
            return match &self.environment {
                Some(e) if self.sphere_emission => self.sphere_emission_pdf(e, ray),
                Some(e) => e.pdf_le(ray, n),
                None => (0.0, 0.0),
            };
        }
        let p = (self.light).emission_pdf(
            super::layout::as_vec4f(&ray.origin),
            super::layout::as_vec4f(&ray.dir),
        );
        match checked::density_f32(p.position).and(checked::density_f32(p.direction)) {
            // The interface reports a delta part's density as 1; the host's own lights answer 0
            // there (no other strategy produces such a ray), and the MIS weights expect that.
            Ok(()) => (
                if self.flags.contains(LightFlags::DELTA_POSITION) {
                    0.0
                } else {
                    p.position
                },
                if self.flags.contains(LightFlags::DELTA_DIRECTION) {
                    0.0
                } else {
                    p.direction
                },
            ),
            Err(reason) => self.calls.refused("emission_pdf", reason, (0.0, 0.0)),
        }
    }

    fn escape_point(&self, ray: &Ray) -> Option<(Vec3A, Vec3A)> {
        self.environment.as_ref()?.escape_point(ray)
    }

    fn preprocess(&self, scene_bounds: &Aabb) {
        let _ = self.scene_bounds.set(*scene_bounds);
    }

    fn uniform_spectral_shape(&self) -> bool {
        self.uniform
    }

    fn preprocess_view(&self, view_bounds: &Aabb) {
        if let Some(e) = &self.environment {
            e.preprocess_view(view_bounds);
        }
        // One call with both boxes, once both are known (the scene builder calls
        // `preprocess` and then this).
        self.give_bounds(view_bounds);
    }
}

const _: () = assert!(
    LANES == spectrace_plugin_api::LANES,
    "host and ABI lane counts agree"
);

#[cfg(test)]
mod tests {
    use super::*;
    use spectrace_plugin_api::abi::sabi_trait::TD_Opaque;
    use spectrace_plugin_api::guard::{keep_error, take_kept_error};
    use spectrace_plugin_api::material::{AbiMaterial, AbiMaterial_TO, GuardedMaterial};
    use spectrace_plugin_api::{ErrorKind, PluginResult, Scatter, Surface, Values, Wavelengths};

    /// A face that answers as told: `sample` the status (writing a sample with direction `wi`),
    /// `eval` the values, `pdf` the density; with `keep`, each call that answers a failure
    /// (ERROR, NaN) first keeps that error on the thread, as the export macro's guard does.
    struct Answers {
        status: u32,
        wi: Vec4f,
        values: [f32; LANES],
        pdf: f32,
        keep: Option<&'static str>,
    }

    impl Answers {
        fn honest() -> Self {
            Self {
                status: status::WRITTEN,
                wi: Vec4f::new(0.0, 0.6, 0.8),
                values: [0.5; LANES],
                pdf: 0.25,
                keep: None,
            }
        }
        fn keep(&self, failed: bool) {
            if let (Some(m), true) = (self.keep, failed) {
                keep_error(PluginError::new(ErrorKind::Other, m));
            }
        }
    }

    impl AbiMaterial for Answers {
        fn sample(
            &self,
            _wo: &Vec4f,
            _surface: &Surface,
            _lambda: &Wavelengths,
            _u_lobe: f32,
            _u1: f32,
            _u2: f32,
            _mode: TransportMode,
            out: &mut Scatter,
        ) -> u32 {
            self.keep(self.status == status::ERROR);
            *out = Scatter {
                wi: self.wi,
                value: self.values,
                pdf: self.pdf,
                flags: material_flags::DIFFUSE,
                eta: 1.0,
            };
            self.status
        }
        fn eval(
            &self,
            _wo: &Vec4f,
            _wi: &Vec4f,
            _surface: &Surface,
            _lambda: &Wavelengths,
            _mode: TransportMode,
        ) -> Values {
            self.keep(self.values[0].is_nan());
            Values { v: self.values }
        }
        fn pdf(
            &self,
            _wo: &Vec4f,
            _wi: &Vec4f,
            _surface: &Surface,
            _lambda: &Wavelengths,
            _mode: TransportMode,
        ) -> f32 {
            self.keep(self.pdf.is_nan());
            self.pdf
        }
        fn emitted(&self, _wo: &Vec4f, _surface: &Surface, _lambda: &Wavelengths) -> Values {
            Values::ZERO
        }
        fn save_state(
            &self,
        ) -> RResult<spectrace_plugin_api::abi::std_types::RVec<u8>, PluginError> {
            RResult::ROk(Default::default())
        }
    }

    /// The root module's `take_error` as the export macro writes it (this thread's kept error).
    extern "C" fn take_kept() -> ROption<PluginError> {
        take_kept_error().into()
    }

    fn origin() -> (Origin, Arc<PluginFaults>) {
        let faults = PluginFaults::new();
        let origin = Origin {
            label: "material `grey` (plugin test 0.2.0)".to_string(),
            faults: faults.clone(),
        };
        (origin, faults)
    }

    fn object(material: MaterialBox) -> MaterialObject {
        MaterialObject {
            material,
            flags: material_flags::DIFFUSE,
            emission: ROption::RNone,
            reradiation: ROption::RNone,
        }
    }

    fn with_face(face: Answers) -> (PluginMaterial, Arc<PluginFaults>) {
        let (origin, faults) = origin();
        let face = AbiMaterial_TO::from_value(face, TD_Opaque);
        let m = PluginMaterial::new(object(face), take_kept, origin, "floor").unwrap();
        (m, faults)
    }

    fn ask(m: &PluginMaterial) -> (Option<BsdfSample>, SampledSpectrum, f32) {
        let ctx = ShadingContext::default();
        let lambda = SampledWavelengths::sample_uniform(0.3, 380.0, 780.0);
        let (wo, wi) = (Vec3A::Z, Vec3A::new(0.6, 0.0, 0.8));
        let mode = HostMode::Radiance;
        (
            m.sample(wo, &ctx, &lambda, 0.5, Vec2::splat(0.5), mode),
            m.eval(wo, wi, &ctx, &lambda, mode),
            m.pdf(wo, wi, &ctx, &lambda, mode),
        )
    }

    /// The failed calls' messages by call site.
    fn failed_sites(faults: &PluginFaults) -> Vec<(String, String)> {
        faults
            .sites()
            .into_iter()
            .map(|(who, site, n, first)| {
                assert_eq!(who, "material `grey` (plugin test 0.2.0)");
                assert_eq!(n, 1, "{site}: {first}");
                (site, first)
            })
            .collect()
    }

    // The host's calls go through the one face (its answers handed over, the sample's event
    // bits translated). A call that failed (ERROR from `sample`, NaN from `eval` and `pdf`) has
    // its kept error taken from the library and reported with the plugin object and the call
    // named; ERROR without a kept error and a status the interface does not have are reported
    // the same way; values that break the rules without an error (NaN, infinite, negative, a
    // direction that is not unit) are dropped and counted per object and call. Nothing is
    // fatal: the host gets no sample, zero, zero.
    #[test]
    fn the_answers_are_checked_and_their_errors_taken() {
        let (m, faults) = with_face(Answers::honest());
        let (s, f, p) = ask(&m);
        let s = s.expect("a sample");
        assert_eq!(
            (s.wi, s.f.0, s.pdf),
            (Vec3A::new(0.0, 0.6, 0.8), [0.5; 4], 0.25)
        );
        assert_eq!(s.flags, MaterialFlags::DIFFUSE | MaterialFlags::REFLECTION);
        assert_eq!((f.0, p), ([0.5; 4], 0.25));
        assert_eq!(faults.count() + faults.invalid_count(), 0);

        // Failed calls: their errors, each named with its call.
        let (m, faults) = with_face(Answers {
            status: status::ERROR,
            values: Values::FAILED.v,
            pdf: f32::NAN,
            keep: Some("the material broke"),
            ..Answers::honest()
        });
        let (s, f, p) = ask(&m);
        assert!(s.is_none());
        assert_eq!((f.0, p), ([0.0; 4], 0.0));
        assert_eq!((faults.count(), faults.invalid_count()), (3, 0));
        let sites = failed_sites(&faults);
        for call in ["eval", "pdf", "sample"] {
            let want = format!("error: {call}: the material broke");
            assert!(
                sites
                    .iter()
                    .any(|(site, first)| site == call && *first == want),
                "{call}: {sites:?}"
            );
        }
        assert!(take_kept_error().is_none(), "every kept error was taken");

        // An error the message of which names its call already (a caught panic) is not named
        // twice.
        let (m, faults) = with_face(Answers {
            values: Values::FAILED.v,
            keep: Some("eval panicked at lib.rs:7: boom"),
            ..Answers::honest()
        });
        assert_eq!(ask(&m).1 .0, [0.0; 4]);
        assert_eq!(
            failed_sites(&faults),
            [(
                "eval panicked at lib.rs:7".to_string(),
                "error: eval panicked at lib.rs:7: boom".to_string()
            )]
        );

        // Status words that are not the interface's, or ERROR with nothing kept.
        for (status, says) in [
            (7, "sample answered status 7, which is none of"),
            (
                status::ERROR,
                "sample answered ERROR (status 2) without keeping an error",
            ),
        ] {
            let (m, faults) = with_face(Answers {
                status,
                ..Answers::honest()
            });
            assert!(ask(&m).0.is_none());
            assert_eq!(faults.count(), 1);
            let first = faults.first().unwrap();
            assert!(
                first.starts_with(&format!(
                    "material `grey` (plugin test 0.2.0): error: {says}"
                )),
                "{first}"
            );
        }

        // Lying values without an error: dropped and counted, the call named.
        for (wi, values, pdf) in [
            (Vec4f::new(0.0, 1.2, 0.8), [0.5, f32::NAN, 0.5, 0.5], -1.0),
            (
                Vec4f::new(f32::NAN, 0.6, 0.8),
                [0.5, 0.5, f32::INFINITY, 0.5],
                f32::NAN,
            ),
        ] {
            let (m, faults) = with_face(Answers {
                wi,
                values,
                pdf,
                ..Answers::honest()
            });
            let (s, f, p) = ask(&m);
            assert!(s.is_none());
            assert_eq!((f.0, p), ([0.0; 4], 0.0));
            assert_eq!(faults.count(), 0, "{:?}", faults.report());
            let mut invalid = faults.invalid();
            invalid.sort();
            let who = "material `grey` (plugin test 0.2.0)";
            assert_eq!(
                invalid
                    .iter()
                    .map(|(who, why, n)| (who.as_str(), *why, *n))
                    .collect::<Vec<_>>(),
                [
                    (who, "eval: value NaN, infinite or negative", 1),
                    (who, "pdf: pdf NaN, infinite or negative", 1),
                    (who, "sample: direction not a finite unit vector", 1),
                ]
            );
        }
    }

    /// A plugin material through the API's own guard (what `export_plugin!` builds): its
    /// `sample` panics, its `eval` fails with an error, its `pdf` answers NaN.
    struct Broken;

    impl spectrace_plugin_api::Material for Broken {
        fn flags(&self) -> Flags {
            material_flags::DIFFUSE
        }
        fn sample(
            &self,
            _wo: &Vec4f,
            _surface: &Surface,
            _lambda: &Wavelengths,
            _u: [f32; 3],
            _mode: TransportMode,
            _out: &mut Scatter,
        ) -> PluginResult<bool> {
            panic!("broken while sampling")
        }
        fn eval(
            &self,
            _wo: &Vec4f,
            _wi: &Vec4f,
            _surface: &Surface,
            _lambda: &Wavelengths,
            _mode: TransportMode,
        ) -> PluginResult<[f32; LANES]> {
            Err(PluginError::new(ErrorKind::Other, "no value here"))
        }
        fn pdf(
            &self,
            _wo: &Vec4f,
            _wi: &Vec4f,
            _surface: &Surface,
            _lambda: &Wavelengths,
            _mode: TransportMode,
        ) -> PluginResult<f32> {
            Ok(f32::NAN)
        }
    }

    // Through the API's guard: the panic is caught on the plugin's side and kept, the error
    // kept, and both taken and reported naming object and call; the NaN density (no error) is
    // dropped and counted with its call. Each call is asked twice: nothing is left kept
    // between them.
    #[test]
    fn a_plugin_that_panics_or_fails_is_reported_not_fatal() {
        let (origin, faults) = origin();
        let m = GuardedMaterial::object(Broken, |_| Ok(Vec::new())).unwrap();
        let m = PluginMaterial::new(m, take_kept, origin, "floor").unwrap();
        for _ in 0..2 {
            let (s, f, p) = ask(&m);
            assert!(s.is_none());
            assert_eq!((f.0, p), ([0.0; 4], 0.0));
        }
        assert!(take_kept_error().is_none());
        let sites = faults.sites();
        assert_eq!(sites.len(), 2, "{sites:?}");
        let sample = sites
            .iter()
            .find(|s| s.1.starts_with("sample panicked at "));
        let sample = sample.unwrap_or_else(|| panic!("{sites:?}"));
        assert_eq!(sample.2, 2);
        assert!(
            sample.3.ends_with(": broken while sampling"),
            "{}",
            sample.3
        );
        let eval = sites.iter().find(|s| s.1 == "eval");
        let eval = eval.unwrap_or_else(|| panic!("{sites:?}"));
        assert_eq!(eval.2, 2);
        assert_eq!(eval.3, "error: eval: no value here");
        assert_eq!(
            faults.invalid(),
            [(
                "material `grey` (plugin test 0.2.0)".to_string(),
                "pdf: pdf NaN, infinite or negative",
                2
            )]
        );
    }

    // The bit-operation form of an event's flags agrees with the table form for every
    // combination of the interface's seven bits.
    #[test]
    fn event_bits_match_material_bits() {
        for b in 0..128u32 {
            let f = Flags(b);
            assert_eq!(
                event_bits(f),
                material_bits(f, Some(f.contains(material_flags::TRANSMISSION))),
                "bits {b:#09b}"
            );
        }
    }
}
