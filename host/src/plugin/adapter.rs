//! Adapters: plugin objects dressed as the host's own traits, so the integrator never knows
//! where an object came from. Each adapter converts once per call between the ABI's f64 plain
//! data and the renderer's f32 types (the seed: wrap a light whose beams are in another
//! representation, and convert in the call).
//!
//! The host traits are infallible (a hot path full of `Result`s would cost every built-in), but
//! a plugin call can fail. The adapter then returns "no contribution" and records the error in the
//! shared [`PluginFaults`]; the renderer checks it between passes and stops cleanly, keeping what
//! was rendered, with the plugin's message.

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
use spectrace_plugin_api::extension::{
    LightV2Box, LightV6Box, LightWithV2, LightWithV4, LightWithV6, MaterialEmittedV6Box,
    MaterialV2Box, MaterialV4Box, MaterialV5Box, MaterialV7Box, MaterialV8Box, MaterialWithV2,
    MaterialWithV3, MaterialWithV4, MaterialWithV5, MaterialWithV6, MaterialWithV7, MaterialWithV8,
    RepresentedLightBox, SpdWithLines,
};
use spectrace_plugin_api::fast::{
    status, EmissionF32, LanesF32, MaterialQuery, QueryV5, QueryV7, ScatterF32, SurfaceF32, Vec4f,
};
use spectrace_plugin_api::{
    light_flags, material_flags, spd_flags, Beam, Flags, LightBox, MaterialBox, ObserverBox,
    PluginError, RandomSample, SceneBounds, SpdBox, SpectralValues, SurfaceContext, TransportMode,
    Vec3, Wavelengths,
};
use std::collections::BTreeMap;
use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// Errors raised by plugin calls while rendering: the first message and how many there were;
/// per call site, how many and the first message; per object and reason, how many results
/// were dropped as invalid (see [`super::checked`]).
#[derive(Default, Debug)]
pub struct PluginFaults {
    first: Mutex<Option<String>>,
    count: AtomicU64,
    sites: Mutex<BTreeMap<(String, String), (u64, String)>>,
    invalid: Mutex<BTreeMap<(String, &'static str), u64>>,
    invalid_count: AtomicU64,
}

/// Distinct call sites remembered; beyond, failures are counted under one "other" entry, so a
/// plugin whose messages vary per call cannot grow the table without bound.
const MAX_SITES: usize = 64;

impl PluginFaults {
    /// A new, empty collector shared by every adapter of one scene.
    pub fn new() -> Arc<Self> {
        Arc::new(Self::default())
    }

    /// Record `error` raised by `who`. The call site is the message up to its first `": "`
    /// (for a caught panic: the call and the panic's file:line, see the API's `guard`).
    pub fn record(&self, who: &str, error: &PluginError) {
        if self.count.fetch_add(1, Ordering::Relaxed) == 0 {
            if let Ok(mut first) = self.first.lock() {
                first.get_or_insert_with(|| format!("{who}: {error}"));
            }
        }
        let site = error.message.split(": ").next().unwrap_or_default();
        if let Ok(mut sites) = self.sites.lock() {
            let mut key = (who.to_string(), site.chars().take(200).collect::<String>());
            if !sites.contains_key(&key) && sites.len() >= MAX_SITES {
                key = (who.to_string(), "(other call sites)".to_string());
            }
            sites.entry(key).or_insert_with(|| (0, error.to_string())).0 += 1;
        }
    }

    /// Record that a result of `who` was dropped as invalid, for `reason`.
    pub fn record_invalid(&self, who: &str, reason: &'static str) {
        self.invalid_count.fetch_add(1, Ordering::Relaxed);
        if let Ok(mut invalid) = self.invalid.lock() {
            *invalid.entry((who.to_string(), reason)).or_insert(0) += 1;
        }
    }

    /// The first recorded error, if any.
    pub fn first(&self) -> Option<String> {
        self.first.lock().ok().and_then(|f| f.clone())
    }

    /// How many errors were recorded.
    pub fn count(&self) -> u64 {
        self.count.load(Ordering::Relaxed)
    }

    /// How many results were dropped as invalid.
    pub fn invalid_count(&self) -> u64 {
        self.invalid_count.load(Ordering::Relaxed)
    }

    /// Failed calls per (object, call site): `(who, site, count, first message)`, sorted.
    pub fn sites(&self) -> Vec<(String, String, u64, String)> {
        self.sites
            .lock()
            .map(|s| {
                s.iter()
                    .map(|((w, site), (n, msg))| (w.clone(), site.clone(), *n, msg.clone()))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Dropped results per (object, reason): `(who, reason, count)`, sorted.
    pub fn invalid(&self) -> Vec<(String, &'static str, u64)> {
        self.invalid
            .lock()
            .map(|s| s.iter().map(|((w, r), n)| (w.clone(), *r, *n)).collect())
            .unwrap_or_default()
    }

    /// The render summary's lines: one per call site that failed and one per (object, reason)
    /// whose results were dropped, each with its count. Empty when all went well.
    pub fn report(&self) -> Vec<String> {
        let mut lines: Vec<String> = self
            .sites()
            .into_iter()
            .map(|(who, site, n, first)| {
                format!("{who}: {n} failed call(s) at `{site}`; first: {first}")
            })
            .collect();
        lines.extend(
            self.invalid()
                .into_iter()
                .map(|(who, reason, n)| format!("{who}: {n} result(s) dropped: {reason}")),
        );
        lines
    }

    /// How a command ends after rendering with plugins: `Err` when plugin calls failed (the
    /// image was still written; the message lists each failing call site once, with its
    /// count), else `Ok` with one warning line per (object, reason) whose results were dropped.
    pub fn outcome(&self) -> Result<Vec<String>, String> {
        if self.count() == 0 {
            return Ok(self.report());
        }
        Err(format!(
            "{} plugin call(s) failed during rendering (their samples contributed nothing; the \
             image was still written):\n  {}",
            self.count(),
            self.report().join("\n  ")
        ))
    }
}

fn v3(v: Vec3A) -> Vec3 {
    Vec3::new(v.x as f64, v.y as f64, v.z as f64)
}

fn va(v: Vec3) -> Vec3A {
    Vec3A::new(v.x as f32, v.y as f32, v.z as f32)
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

fn lambdas(l: &SampledWavelengths) -> Wavelengths {
    Wavelengths {
        nm: l.lambda.map(|x| x as f64),
    }
}

fn spectrum(v: SpectralValues) -> SampledSpectrum {
    SampledSpectrum(std::array::from_fn(|i| v.v[i] as f32))
}

fn sample_from(u: &[f32]) -> RandomSample {
    let mut s = RandomSample::default();
    for (dst, &src) in s.u.iter_mut().zip(u) {
        *dst = src as f64;
    }
    s
}

fn mode(m: HostMode) -> TransportMode {
    match m {
        HostMode::Radiance => TransportMode::Radiance,
        HostMode::Importance => TransportMode::Importance,
    }
}

/// Who an adapter speaks for, in error messages.
#[derive(Clone, Debug)]
pub struct Origin {
    /// e.g. "light `spot` (plugin point-light 0.1.0)".
    pub label: String,
    /// Where errors go.
    pub faults: Arc<PluginFaults>,
}

impl Origin {
    #[cold]
    #[inline(never)]
    fn fail<T>(&self, e: PluginError, fallback: T) -> T {
        self.faults.record(&self.label, &e);
        fallback
    }

    /// Record a v7 call that answered `status` other than its result (extension v7): the error
    /// it wrote, or, for a status that does not say so, an error naming it (a plugin that
    /// answers `ERROR` without an error, or a status word the interface does not have).
    #[cold]
    #[inline(never)]
    fn status_fault<T>(
        &self,
        call: &str,
        status: u32,
        err: ROption<PluginError>,
        fallback: T,
    ) -> T {
        let e = match (status, err.into_option()) {
            (status::ERROR, Some(e)) => e,
            (status::NONE, _) => PluginError::new(
                spectrace_plugin_api::ErrorKind::Other,
                format!("{call} answered NONE (status 0), which only `sample` may answer"),
            ),
            (status::ERROR, None) => PluginError::new(
                spectrace_plugin_api::ErrorKind::Other,
                format!("{call} answered ERROR (status 2) without writing an error"),
            ),
            (other, _) => PluginError::new(
                spectrace_plugin_api::ErrorKind::Other,
                format!(
                    "{call} answered status {other}, which is none of NONE (0, sample only), \
                     WRITTEN (1) and ERROR (2)"
                ),
            ),
        };
        self.fail(e, fallback)
    }

    /// Record a result dropped for `reason` (kept out of the callers' hot code).
    #[cold]
    #[inline(never)]
    fn dropped(&self, reason: checked::Reason) {
        self.faults.record_invalid(&self.label, reason);
    }

    /// `value` when its `check` passed; otherwise `fallback`, the dropped result counted.
    #[inline]
    fn kept<T>(&self, check: Result<(), checked::Reason>, value: T, fallback: T) -> T {
        match check {
            Ok(()) => value,
            Err(reason) => {
                self.dropped(reason);
                fallback
            }
        }
    }

    /// The call's value if it passes `check`; otherwise `None`, with the error or the
    /// dropped result recorded.
    pub(crate) fn checked<T>(
        &self,
        r: RResult<T, PluginError>,
        check: impl FnOnce(&T) -> Result<(), super::checked::Reason>,
    ) -> Option<T> {
        match r {
            RResult::ROk(v) => match check(&v) {
                Ok(()) => Some(v),
                Err(reason) => {
                    self.faults.record_invalid(&self.label, reason);
                    None
                }
            },
            RResult::RErr(e) => self.fail(e, None),
        }
    }
}

// ----------------------------------------------------------------------------------------------
// SPD

/// A plugin SPD as a host [`Spd`].
pub struct PluginSpd {
    spd: SpdBox,
    range: (f64, f64),
    has_lines: bool,
    /// The spectral lines, when the plugin listed them (extension v2): then a line draw is
    /// recognised by its wavelength and weighed by the line's share, exactly as the host's own
    /// line SPDs are. Without them (`None`) a line draw is recognised by a zero density.
    lines: Option<Vec<crate::spectrum::DeltaLine>>,
    origin: Origin,
}

impl PluginSpd {
    /// Wrap `spd`.
    pub fn new(spd: SpdBox, origin: Origin) -> Self {
        let r = spd.range_nm();
        let has_lines = spd.capabilities().contains(spd_flags::HAS_LINES);
        Self {
            spd,
            range: (r.min_nm, r.max_nm),
            has_lines,
            lines: None,
            origin,
        }
    }

    /// Wrap an SPD built through extension v2, with its lines. Lines with a wavelength or
    /// weight that is not finite and positive are dropped and counted.
    pub fn with_lines(spd: SpdWithLines, origin: Origin) -> Self {
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
        let mut out = Self::new(spd.spd, origin);
        out.has_lines |= !lines.is_empty();
        out.lines = Some(lines);
        out
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
                is_delta: match &self.lines {
                    Some(lines) => lines.iter().any(|l| l.lambda == s.nm),
                    // A line carries probability, not density: its continuous pdf is zero there.
                    None => self.has_lines && self.pdf(s.nm) == 0.0,
                },
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
        self.lines.clone().unwrap_or_default()
    }
    fn is_delta(&self) -> bool {
        self.has_lines
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
    /// Wrap `observer`.
    pub fn new(observer: ObserverBox, origin: Origin) -> Self {
        let r = observer.range_nm();
        Self {
            name: observer.name().into_string(),
            range: (r.min_nm, r.max_nm),
            integral_y: OnceLock::new(),
            observer,
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
        // Kept so the analysis and the scene's warnings see it. Its re-radiation crosses the
        // interface through extension v3 (`PluginMaterial::new_v3`); a material without it
        // renders its reflectance, and the scene warns.
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

/// The path's wavelengths in the interface's layout (the same `f32`s).
#[inline]
fn lanes_f32(lambda: &SampledWavelengths) -> LanesF32 {
    LanesF32 {
        nm: lambda.lambda,
        pdf: lambda.pdf,
        live: u32::from(lambda.lanes.bits()),
    }
}

/// One extension-v4 material query: the host's own `f32` data copied into the interface's
/// layout (no conversion).
#[inline]
fn query(
    wo: Vec3A,
    wi: Vec3A,
    ctx: &ShadingContext,
    lambda: &SampledWavelengths,
    u: [f32; 3],
    m: HostMode,
) -> MaterialQuery {
    MaterialQuery {
        ctx: SurfaceF32 {
            uv: [ctx.uv.x, ctx.uv.y],
            position: v4f(ctx.p),
            geometric_normal: v4f(ctx.ng),
            shading_normal: v4f(ctx.ns),
        },
        wo: v4f(wo),
        wi: v4f(wi),
        lambda: lanes_f32(lambda),
        u,
        mode: mode(m),
    }
}

/// One extension-v5 material query: the surface by reference (the host's own record, see
/// [`super::layout`]), the rest copied as for v4.
#[inline]
fn query_v5<'a>(
    wo: Vec3A,
    wi: Vec3A,
    ctx: &'a ShadingContext,
    lambda: &SampledWavelengths,
    u: [f32; 3],
    m: HostMode,
) -> QueryV5<'a> {
    QueryV5 {
        ctx: super::layout::as_surface(ctx),
        wo: v4f(wo),
        wi: v4f(wi),
        lambda: lanes_f32(lambda),
        u,
        mode: mode(m),
    }
}

/// One extension-v7 material query: the host's surface and wavelengths by reference (the same
/// memory, `super::layout`), the directions and uniforms copied.
#[inline]
fn query_v7<'a>(
    wo: Vec3A,
    wi: Vec3A,
    ctx: &'a ShadingContext,
    lambda: &'a SampledWavelengths,
    u: [f32; 3],
    m: HostMode,
) -> QueryV7<'a> {
    QueryV7 {
        ctx: super::layout::as_surface(ctx),
        lambda: super::layout::as_wavelengths_f32(lambda),
        wo: v4f(wo),
        wi: v4f(wi),
        u,
        mode: mode(m),
    }
}

/// Extension v8's `take_error`: the error of the last failed v8 call on this thread.
pub type TakeError = extern "C" fn() -> ROption<PluginError>;

/// The faces of a material newer than v6 (each `None` when its library predates it).
struct Newer {
    v7: Option<MaterialV7Box>,
    v8: Option<(MaterialV8Box, TakeError)>,
}

impl Newer {
    const NONE: Self = Self { v7: None, v8: None };
}

/// A call of extension v8's material face, as its reports name it.
#[derive(Clone, Copy, Debug)]
enum CallV8 {
    Sample,
    Eval,
    Pdf,
}

impl CallV8 {
    fn name(self) -> &'static str {
        match self {
            Self::Sample => "sample (v8)",
            Self::Eval => "eval (v8)",
            Self::Pdf => "pdf (v8)",
        }
    }

    /// An error of this call that says `what` it did.
    fn error(self, what: fmt::Arguments<'_>) -> PluginError {
        PluginError::new(
            spectrace_plugin_api::ErrorKind::Other,
            format!("{} {what}", self.name()),
        )
    }

    /// `reason` (one of those [`checked`] gives for this call's results) with the call named,
    /// as the dropped results of a v8 face are counted.
    fn reason(self, reason: checked::Reason) -> checked::Reason {
        match (self, reason) {
            (Self::Sample, checked::BAD_DIRECTION) => {
                "sample (v8): direction not a finite unit vector"
            }
            (Self::Sample, checked::BAD_DENSITY) => "sample (v8): pdf NaN, infinite or negative",
            (Self::Sample, checked::BAD_VALUE) => "sample (v8): value NaN, infinite or negative",
            (Self::Eval, checked::BAD_VALUE) => "eval (v8): value NaN, infinite or negative",
            (Self::Pdf, checked::BAD_DENSITY) => "pdf (v8): pdf NaN, infinite or negative",
            _ => reason,
        }
    }
}

/// A plugin material as a host [`Material`]. An EMISSIVE one also describes its emission
/// ([`Material::emission`]), so the scene builds an area light on every object that uses it,
/// sampled and MIS-weighted like the built-in `emissive`. A FLUORESCENT one built through
/// extension v3 hands over its re-radiation ([`Material::reradiation`]), which the integrators
/// shift wavelengths with as for the built-in `fluorescent`.
pub struct PluginMaterial {
    material: MaterialBox,
    /// The same material's version-2 face (extension v2): when present, the four calls go
    /// through it with the surface's normals.
    v2: Option<MaterialV2Box>,
    flags: MaterialFlags,
    emission: Option<EmissionProfile>,
    /// The re-radiation (extension v3), checked when the material was built.
    reradiation: Option<super::reradiation::PluginReradiation>,
    /// The same material's version-4 face (extension v4): when present, `sample`, `eval` and
    /// `pdf` go through it, in the host's own layout.
    v4: Option<MaterialV4Box>,
    /// The same material's version-5 face (extension v5): when present, `sample`, `eval` and
    /// `pdf` go through it (results written through a reference, no thread-local guard).
    v5: Option<MaterialV5Box>,
    /// The same material's version-7 face (extension v7): when present, `sample`, `eval` and
    /// `pdf` go through it (the wavelengths by reference, a status word for an answer).
    v7: Option<MaterialV7Box>,
    /// The same material's version-8 face (extension v8): when present, `sample`, `eval` and
    /// `pdf` go through it (the arguments as the host's own calls take them, no error slot).
    v8: Option<MaterialV8Box>,
    /// Where the errors of the v8 face's failed calls are taken (extension v8's module).
    take_error: Option<TakeError>,
    /// Declared spectrally flat (extension v4) and found so when built ([`Self::new_v4`]).
    flat: bool,
    /// Declared to have one BSDF value for every direction (extension v5) and found so when
    /// built ([`Self::new_v5`]).
    same_f: bool,
    /// The same material's emission in the host's layout (extension v6).
    emitted_v6: Option<MaterialEmittedV6Box>,
    /// Declared to sample with the cosine-weighted density (extension v6) and found so when
    /// built ([`Self::new_v6`]): `pdf` is then computed here ([`super::cosine_pdf`]).
    cosine: bool,
    origin: Origin,
}

impl PluginMaterial {
    /// Wrap `material` (a library without extension v2: no normals, emission tabulated).
    pub fn new(material: MaterialBox, origin: Origin) -> Self {
        Self::build(material, None, origin)
    }

    /// Wrap a material built through extension v2: its calls see the surface's normals, and its
    /// emission, when it describes one, is used exactly (its own SPD and scale).
    pub fn new_v2(material: MaterialWithV2, origin: Origin) -> Self {
        Self::build(material.material, Some(material.v2), origin)
    }

    /// Wrap a material built through extension v3: as [`Self::new_v2`], plus the re-radiation
    /// of a fluorescent one, checked (see `plugin::reradiation`; an error names the plugin
    /// object and `item`, the scene's name for it, and says what is wrong). A material that
    /// offers re-radiation fluoresces: it gets the FLUORESCENT flag even if it did not declare it.
    pub fn new_v3(material: MaterialWithV3, origin: Origin, item: &str) -> Result<Self, String> {
        let reradiation = match material.reradiation.into_option() {
            Some(rr) => Some(super::reradiation::PluginReradiation::new(
                rr,
                Origin {
                    label: format!("{} as {item}", origin.label),
                    faults: origin.faults.clone(),
                },
            )?),
            None => None,
        };
        let mut m = Self::build(material.material, Some(material.v2), origin);
        if reradiation.is_some() {
            m.flags |= MaterialFlags::FLUORESCENT;
        }
        m.reradiation = reradiation;
        Ok(m)
    }

    /// Wrap a material built through extension v4: as [`Self::new_v3`], with `sample`, `eval`
    /// and `pdf` through the v4 face, and its declaration of spectral flatness, checked (see
    /// [`super::flatness`]): a claim the material's own answers contradict is refused, naming the
    /// plugin object and `item`.
    pub fn new_v4(material: MaterialWithV4, origin: Origin, item: &str) -> Result<Self, String> {
        let MaterialWithV4 {
            material,
            v2,
            reradiation,
            v4,
            spectrally_flat,
        } = material;
        let mut m = Self::new_v3(
            MaterialWithV3 {
                material,
                v2,
                reradiation,
            },
            origin,
            item,
        )?;
        m.v4 = Some(v4);
        if spectrally_flat {
            super::flatness::check(&m, m.flags, m.reradiation.is_some()).map_err(|e| {
                format!(
                    "{} as {item}: declares itself spectrally flat (extension v4), but {e}",
                    m.origin.label
                )
            })?;
            m.flat = true;
        }
        Ok(m)
    }

    /// Wrap a material built through extension v5: as [`Self::new_v3`], with `sample`, `eval`
    /// and `pdf` through the v5 face, and its declarations checked: spectral flatness (see
    /// [`super::flatness`]) and one BSDF value for every direction (see [`super::same_f`]). A
    /// claim the material's own answers contradict is refused, naming the plugin object and
    /// `item`.
    pub fn new_v5(material: MaterialWithV5, origin: Origin, item: &str) -> Result<Self, String> {
        Self::with_v5(material, Newer::NONE, origin, item)
    }

    /// [`Self::new_v5`] with the v7 face, when there is one, set before the declarations are
    /// checked: the checks ask the face that renders.
    fn with_v5(
        material: MaterialWithV5,
        newer: Newer,
        origin: Origin,
        item: &str,
    ) -> Result<Self, String> {
        let MaterialWithV5 {
            material,
            v2,
            reradiation,
            v5,
            spectrally_flat,
            f_same_for_all_directions,
        } = material;
        let mut m = Self::new_v3(
            MaterialWithV3 {
                material,
                v2,
                reradiation,
            },
            origin,
            item,
        )?;
        m.v5 = Some(v5);
        m.v7 = newer.v7;
        if let Some((v8, take_error)) = newer.v8 {
            m.v8 = Some(v8);
            m.take_error = Some(take_error);
        }
        if spectrally_flat {
            super::flatness::check(&m, m.flags, m.reradiation.is_some()).map_err(|e| {
                format!(
                    "{} as {item}: declares itself spectrally flat (extension v4), but {e}",
                    m.origin.label
                )
            })?;
            m.flat = true;
        }
        if f_same_for_all_directions {
            super::same_f::check(&m).map_err(|e| {
                format!(
                    "{} as {item}: declares one BSDF value for every direction \
                     (f_same_for_all_directions, extension v5), but {e}",
                    m.origin.label
                )
            })?;
            m.same_f = true;
        }
        Ok(m)
    }

    /// Wrap a material built through extension v6: as [`Self::new_v5`] (the v5 calls, both
    /// declarations checked), with its emission in the host's layout and its declaration of the
    /// cosine-weighted density, checked (see [`super::cosine_pdf`]): a claim the material's own
    /// answers contradict is refused, naming the plugin object and `item`.
    pub fn new_v6(material: MaterialWithV6, origin: Origin, item: &str) -> Result<Self, String> {
        Self::with_v6(material, Newer::NONE, origin, item)
    }

    /// Wrap a material built through extension v7: as [`Self::new_v6`] (every declaration
    /// checked, through the v7 face), with `sample`, `eval` and `pdf` through the v7 face.
    pub fn new_v7(material: MaterialWithV7, origin: Origin, item: &str) -> Result<Self, String> {
        let newer = Newer {
            v7: Some(material.v7),
            v8: None,
        };
        Self::with_v6(material.with_v6, newer, origin, item)
    }

    /// Wrap a material built through extension v8: as [`Self::new_v7`] (every declaration
    /// checked, through the v8 face), with `sample`, `eval` and `pdf` through the v8 face, whose
    /// errors are taken with `take_error` (the library's v8 module).
    pub fn new_v8(
        material: MaterialWithV8,
        take_error: TakeError,
        origin: Origin,
        item: &str,
    ) -> Result<Self, String> {
        let newer = Newer {
            v7: Some(material.with_v7.v7),
            v8: Some((material.v8, take_error)),
        };
        Self::with_v6(material.with_v7.with_v6, newer, origin, item)
    }

    /// [`Self::new_v6`] with the newer faces, as [`Self::with_v5`].
    fn with_v6(
        material: MaterialWithV6,
        newer: Newer,
        origin: Origin,
        item: &str,
    ) -> Result<Self, String> {
        let MaterialWithV6 {
            material,
            v2,
            reradiation,
            v5,
            emitted,
            spectrally_flat,
            f_same_for_all_directions,
            cosine_weighted_pdf,
        } = material;
        let mut m = Self::with_v5(
            MaterialWithV5 {
                material,
                v2,
                reradiation,
                v5,
                spectrally_flat,
                f_same_for_all_directions,
            },
            newer,
            origin,
            item,
        )?;
        m.emitted_v6 = Some(emitted);
        if cosine_weighted_pdf {
            super::cosine_pdf::check(&m).map_err(|e| {
                format!(
                    "{} as {item}: declares the cosine-weighted density \
                     (cosine_weighted_pdf, extension v6), but {e}",
                    m.origin.label
                )
            })?;
            m.cosine = true;
        }
        Ok(m)
    }

    fn build(material: MaterialBox, v2: Option<MaterialV2Box>, origin: Origin) -> Self {
        let flags = material_bits(material.capabilities(), None);
        let emission = if flags.contains(MaterialFlags::EMISSIVE) {
            let described = v2.as_ref().and_then(|v2| {
                let e = origin.checked(v2.emission(), |e| match e {
                    ROption::RSome(e) => checked::scalar(e.scale),
                    ROption::RNone => Ok(()),
                })?;
                let e = e.into_option()?;
                Some(EmissionProfile {
                    spd: Arc::new(PluginSpd::with_lines(e.spectrum, origin.clone())),
                    scale: e.scale as f32,
                    two_sided: e.two_sided,
                })
            });
            described.or_else(|| Self::probe_emission(&material, &origin))
        } else {
            None
        };
        Self {
            material,
            v2,
            flags,
            emission,
            reradiation: None,
            v4: None,
            v5: None,
            v7: None,
            v8: None,
            take_error: None,
            flat: false,
            same_f: false,
            emitted_v6: None,
            cosine: false,
            origin,
        }
    }

    /// The emission an area light on this material uses: `emitted` along the normal, at
    /// 360, 361, …, 830 nm, as a normalised table (linear interpolation) and its integral in
    /// W/(m²·sr); two-sided when anything leaves the back. Like the built-in area lights this
    /// takes the emission to be the same at every point and in every direction of a side
    /// (Lambertian); `None` when nothing leaves the front.
    fn probe_emission(material: &MaterialBox, origin: &Origin) -> Option<EmissionProfile> {
        let nm: Vec<f64> = (360..=830).map(f64::from).collect();
        let ctx = spectrace_plugin_api::ShadingContext::default();
        let side = |z: f64| -> Vec<f64> {
            let mut out = Vec::with_capacity(nm.len());
            for chunk in nm.chunks(LANES) {
                let mut w = Wavelengths {
                    nm: [chunk[0]; LANES],
                };
                w.nm[..chunk.len()].copy_from_slice(chunk);
                // Non-finite and negative values are sanitised below, not dropped.
                let v = (origin)
                    .checked(material.emitted(&ctx, Vec3::new(0.0, 0.0, z), &w), |_| {
                        Ok(())
                    })
                    .unwrap_or(SpectralValues::ZERO);
                out.extend(v.v[..chunk.len()].iter().map(|x| {
                    if x.is_finite() {
                        x.max(0.0)
                    } else {
                        0.0
                    }
                }));
            }
            out
        };
        let front = side(1.0);
        let integral: f64 = front.windows(2).map(|p| 0.5 * (p[0] + p[1])).sum();
        if !(integral > 0.0 && integral.is_finite()) {
            return None;
        }
        let spd = crate::spectrum::TabulatedSpd::new(
            &origin.label,
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

    fn ctx(ctx: &ShadingContext) -> spectrace_plugin_api::ShadingContext {
        spectrace_plugin_api::ShadingContext {
            uv: [ctx.uv.x as f64, ctx.uv.y as f64],
            position: v3(ctx.p),
        }
    }

    /// The host's sample from a checked v4 sample (no conversion: the same `f32`s).
    #[inline]
    fn bsdf_sample(s: &ScatterF32) -> BsdfSample {
        BsdfSample {
            wi: host_v(s.wi),
            f: SampledSpectrum(s.value),
            pdf: s.pdf,
            flags: event_bits(s.flags),
            eta: s.eta,
        }
    }

    fn surface(ctx: &ShadingContext) -> SurfaceContext {
        SurfaceContext {
            uv: [ctx.uv.x as f64, ctx.uv.y as f64],
            position: v3(ctx.p),
            geometric_normal: v3(ctx.ng),
            shading_normal: v3(ctx.ns),
        }
    }
}

/// The calls of libraries older than extension v7, out of line: the v7 path of each call stays a
/// small function (its frame and saved registers are what that path needs, not these).
impl PluginMaterial {
    /// The density asked of the plugin, out of line: a material that declares the
    /// cosine-weighted density (extension v6) gets its `pdf` in a few instructions, as the
    /// built-in does, without this path's frame.
    /// The directions come by reference, as `pdf` got them: passed on as they are, with no
    /// copy of either on this frame.
    #[inline(never)]
    fn pdf_call(
        &self,
        wo: &Vec3A,
        wi: &Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> f32 {
        let Some(v8) = &self.v8 else {
            return self.pdf_before_v8(*wo, *wi, ctx, lambda, m);
        };
        let p = v8.pdf(
            super::layout::as_vec4f(wo),
            super::layout::as_vec4f(wi),
            super::layout::as_surface(ctx),
            super::layout::as_wavelengths_f32(lambda),
            mode(m),
        );
        match checked::density_f32(p) {
            Ok(()) => p,
            Err(reason) => self.v8_refused(CallV8::Pdf, reason, 0.0),
        }
    }

    /// `pdf` of a v7 library and of older ones.
    #[inline(never)]
    fn pdf_before_v8(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> f32 {
        let Some(v7) = &self.v7 else {
            return self.pdf_before_v7(wo, wi, ctx, lambda, m);
        };
        let q = query_v7(wo, wi, ctx, lambda, [0.0; 3], m);
        let mut p = 0.0;
        let mut err = ROption::RNone;
        match v7.pdf(&q, &mut p, &mut err) {
            status::WRITTEN => self.origin.kept(checked::density_f32(p), p, 0.0),
            other => self.origin.status_fault("pdf (v7)", other, err, 0.0),
        }
    }

    /// `pdf` of a v5 or v6 library and of older ones.
    #[inline(never)]
    fn pdf_before_v7(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> f32 {
        if let Some(v5) = &self.v5 {
            let q = query_v5(wo, wi, ctx, lambda, [0.0; 3], m);
            let mut p = 0.0;
            return match v5.pdf(&q, &mut p) {
                RResult::ROk(()) => self.origin.kept(checked::density_f32(p), p, 0.0),
                RResult::RErr(e) => self.origin.fail(e, 0.0),
            };
        }
        if let Some(v4) = &self.v4 {
            let q = query(wo, wi, ctx, lambda, [0.0; 3], m);
            return match v4.pdf(&q) {
                RResult::ROk(p) => self.origin.kept(checked::density_f32(p), p, 0.0),
                RResult::RErr(e) => self.origin.fail(e, 0.0),
            };
        }
        let (wo, wi, lambda) = (v3(wo), v3(wi), lambdas(lambda));
        let r = match &self.v2 {
            Some(v2) => v2.pdf(&Self::surface(ctx), wo, wi, &lambda, mode(m)),
            None => (self.material).pdf(&Self::ctx(ctx), wo, wi, &lambda, mode(m)),
        };
        (self.origin)
            .checked(r, |p| checked::density(*p))
            .map_or(0.0, |v| v as f32)
    }

    /// `sample` of a v7 library and of older ones. The uniforms come first, `wo` after them:
    /// they then sit in the vector registers where `sample_into` got them and the v8 call wants
    /// them (with `wo` first, passed in the first vector register, the hot function moved the
    /// three uniforms up one register and back on every call).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn sample_before_v8<'a>(
        &self,
        u_lobe: f32,
        u: Vec2,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        let Some(v7) = &self.v7 else {
            return self.sample_before_v7(wo, ctx, lambda, u_lobe, u, m, out);
        };
        let q = query_v7(wo, Vec3A::ZERO, ctx, lambda, [u_lobe, u.x, u.y], m);
        // Written by the plugin straight into the caller's record (see `super::layout`), checked
        // there, and its event bits translated to the host's. The record holds a valid sample
        // or zeros when the plugin gets it (the caller's), so whatever the plugin leaves in it
        // is checked like what it writes.
        let rec = super::layout::as_scatter_mut(out);
        let mut err = ROption::RNone;
        match v7.sample(&q, rec, &mut err) {
            status::WRITTEN => match checked::scatter_f32(rec) {
                Ok(()) => {
                    out.flags = event_bits(Flags(out.flags.0));
                    Some(out)
                }
                Err(reason) => {
                    self.origin.dropped(reason);
                    None
                }
            },
            status::NONE => None,
            other => self.origin.status_fault("sample (v7)", other, err, None),
        }
    }

    /// A v8 `sample` that answered other than `WRITTEN`: absorbed (`NONE`), failed (`ERROR`:
    /// its kept error taken and reported with the call named), or a status the interface does
    /// not have.
    #[cold]
    #[inline(never)]
    fn sample_not_written<'a>(&self, status: u32) -> Option<&'a BsdfSample> {
        if status == status::NONE {
            return None;
        }
        let call = CallV8::Sample;
        let e = if status == status::ERROR {
            self.take_v8_error(call).unwrap_or_else(|| {
                call.error(format_args!(
                    "answered ERROR (status 2) without keeping an error"
                ))
            })
        } else {
            call.error(format_args!(
                "answered status {status}, which is none of NONE (0), WRITTEN (1) and ERROR (2)"
            ))
        };
        self.origin.fail(e, None)
    }

    /// A v8 answer refused for `reason`: the call's error when it kept one (a failed `eval` or
    /// `pdf` answers NaN), else the value dropped; either reported with the call named.
    #[cold]
    #[inline(never)]
    fn v8_refused<T>(&self, call: CallV8, reason: checked::Reason, fallback: T) -> T {
        match self.take_v8_error(call) {
            Some(e) => self.origin.fail(e, fallback),
            None => {
                self.origin.dropped(call.reason(reason));
                fallback
            }
        }
    }

    /// A v8 sample refused for `reason` (it said `WRITTEN`: no error to take).
    #[cold]
    #[inline(never)]
    fn v8_dropped(&self, reason: checked::Reason) {
        self.origin.dropped(CallV8::Sample.reason(reason));
    }

    /// The error a failed v8 call kept on this thread, taken from the library, with the call
    /// named in front of it unless it names itself (a caught panic's message starts with its
    /// call, see the API's `guard`).
    fn take_v8_error(&self, call: CallV8) -> Option<PluginError> {
        let mut e = self.take_error.and_then(|take| take().into_option())?;
        if !e.message.starts_with(call.name()) {
            e.message = format!("{}: {}", call.name(), e.message).into();
        }
        Some(e)
    }

    /// `sample` of a v5 or v6 library (the sample written in place, as for v7) and of older ones
    /// (returned by value, copied into `out`).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn sample_before_v7<'a>(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        u_lobe: f32,
        u: Vec2,
        m: HostMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        let Some(v5) = &self.v5 else {
            return (self.sample_before_v5(wo, ctx, lambda, u_lobe, u, m)).map(|s| out.write(s));
        };
        let q = query_v5(wo, Vec3A::ZERO, ctx, lambda, [u_lobe, u.x, u.y], m);
        // Written by the plugin in place, as for v7.
        let rec = super::layout::as_scatter_mut(out);
        match v5.sample(&q, rec) {
            RResult::ROk(true) => match checked::scatter_f32(rec) {
                Ok(()) => {
                    out.flags = event_bits(Flags(out.flags.0));
                    Some(out)
                }
                Err(reason) => {
                    self.origin.dropped(reason);
                    None
                }
            },
            RResult::ROk(false) => None,
            RResult::RErr(e) => self.origin.fail(e, None),
        }
    }

    #[inline(never)]
    fn sample_before_v5(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        u_lobe: f32,
        u: Vec2,
        m: HostMode,
    ) -> Option<BsdfSample> {
        if let Some(v4) = &self.v4 {
            let q = query(wo, Vec3A::ZERO, ctx, lambda, [u_lobe, u.x, u.y], m);
            return match v4.sample(&q) {
                RResult::ROk(ROption::RSome(s)) => match checked::scatter_f32(&s) {
                    Ok(()) => Some(Self::bsdf_sample(&s)),
                    Err(reason) => {
                        self.origin.dropped(reason);
                        None
                    }
                },
                RResult::ROk(ROption::RNone) => None,
                RResult::RErr(e) => self.origin.fail(e, None),
            };
        }
        let (wo, lambda, u) = (v3(wo), lambdas(lambda), sample_from(&[u_lobe, u.x, u.y]));
        let r = match &self.v2 {
            Some(v2) => v2.sample(&Self::surface(ctx), wo, &lambda, &u, mode(m)),
            None => (self.material).sample(&Self::ctx(ctx), wo, &lambda, &u, mode(m)),
        };
        let r = self.origin.checked(r, |s| match s {
            ROption::RSome(s) => checked::scatter(s),
            ROption::RNone => Ok(()),
        });
        match r {
            Some(s) => s.into_option().map(|s| BsdfSample {
                wi: va(s.wi),
                f: spectrum(s.value),
                pdf: s.pdf as f32,
                flags: material_bits(
                    s.flags,
                    Some(s.flags.contains(material_flags::TRANSMISSION)),
                ),
                eta: s.eta as f32,
            }),
            None => None,
        }
    }

    /// `eval` of a v7 library and of older ones.
    #[inline(never)]
    fn eval_before_v8(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> SampledSpectrum {
        let Some(v7) = &self.v7 else {
            return self.eval_before_v7(wo, wi, ctx, lambda, m);
        };
        let q = query_v7(wo, wi, ctx, lambda, [0.0; 3], m);
        let mut v = [0.0; LANES];
        let mut err = ROption::RNone;
        match v7.eval(&q, &mut v, &mut err) {
            status::WRITTEN => match checked::values_f32(&v) {
                Ok(()) => SampledSpectrum(v),
                Err(reason) => {
                    self.origin.dropped(reason);
                    SampledSpectrum::zero()
                }
            },
            other => self
                .origin
                .status_fault("eval (v7)", other, err, SampledSpectrum::zero()),
        }
    }

    /// `eval` of a v5 or v6 library and of older ones.
    #[inline(never)]
    fn eval_before_v7(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> SampledSpectrum {
        if let Some(v5) = &self.v5 {
            let q = query_v5(wo, wi, ctx, lambda, [0.0; 3], m);
            let mut v = [0.0; LANES];
            return match v5.eval(&q, &mut v) {
                RResult::ROk(()) => (self.origin).kept(
                    checked::values_f32(&v),
                    SampledSpectrum(v),
                    SampledSpectrum::zero(),
                ),
                RResult::RErr(e) => self.origin.fail(e, SampledSpectrum::zero()),
            };
        }
        self.eval_before_v5(wo, wi, ctx, lambda, m)
    }

    #[inline(never)]
    fn eval_before_v5(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        m: HostMode,
    ) -> SampledSpectrum {
        if let Some(v4) = &self.v4 {
            let q = query(wo, wi, ctx, lambda, [0.0; 3], m);
            return match v4.eval(&q) {
                RResult::ROk(v) => (self.origin).kept(
                    checked::values_f32(&v),
                    SampledSpectrum(v),
                    SampledSpectrum::zero(),
                ),
                RResult::RErr(e) => self.origin.fail(e, SampledSpectrum::zero()),
            };
        }
        let (wo, wi, lambda) = (v3(wo), v3(wi), lambdas(lambda));
        let r = match &self.v2 {
            Some(v2) => v2.eval(&Self::surface(ctx), wo, wi, &lambda, mode(m)),
            None => (self.material).eval(&Self::ctx(ctx), wo, wi, &lambda, mode(m)),
        };
        (self.origin)
            .checked(r, checked::values)
            .map_or(SampledSpectrum::zero(), spectrum)
    }
}

impl fmt::Debug for PluginMaterial {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginMaterial({})", self.origin.label)
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
        let Some(v8) = &self.v8 else {
            return self.sample_before_v8(u_lobe, u, wo, ctx, lambda, m, out);
        };
        // Written by the plugin straight into the caller's record (see `super::layout`), checked
        // there, and its event bits translated to the host's. The record holds a valid sample
        // or zeros when the plugin gets it (the caller's), so whatever the plugin leaves in it
        // is checked like what it writes.
        let rec = super::layout::as_scatter_mut(out);
        let status = v8.sample(
            super::layout::as_vec4f(&wo),
            super::layout::as_surface(ctx),
            super::layout::as_wavelengths_f32(lambda),
            u_lobe,
            u.x,
            u.y,
            mode(m),
            rec,
        );
        if status != status::WRITTEN {
            return self.sample_not_written(status);
        }
        match checked::scatter_f32(rec) {
            Ok(()) => {
                out.flags = event_bits(Flags(out.flags.0));
                Some(out)
            }
            Err(reason) => {
                self.v8_dropped(reason);
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
        let Some(v8) = &self.v8 else {
            return self.eval_before_v8(wo, wi, ctx, lambda, m);
        };
        let r = v8.eval(
            super::layout::as_vec4f(&wo),
            super::layout::as_vec4f(&wi),
            super::layout::as_surface(ctx),
            super::layout::as_wavelengths_f32(lambda),
            mode(m),
        );
        // Checked and stored as one vector (from the [f32; 4] the compiler went through
        // general registers, lane by lane).
        let v = super::layout::values_as_vec4(r);
        match checked::vector_f32(v) {
            Ok(()) => SampledSpectrum(v.to_array()),
            Err(reason) => self.v8_refused(CallV8::Eval, reason, SampledSpectrum::zero()),
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
        if let Some(e) = &self.emitted_v6 {
            let q = query_v5(wo, Vec3A::ZERO, ctx, lambda, [0.0; 3], HostMode::Radiance);
            let mut v = [0.0; LANES];
            return match e.emitted(&q, &mut v) {
                RResult::ROk(()) => (self.origin).kept(
                    checked::values_f32(&v),
                    SampledSpectrum(v),
                    SampledSpectrum::zero(),
                ),
                RResult::RErr(e) => self.origin.fail(e, SampledSpectrum::zero()),
            };
        }
        let r = match &self.v2 {
            Some(v2) => v2.emitted(&Self::surface(ctx), v3(wo), &lambdas(lambda)),
            None => (self.material).emitted(&Self::ctx(ctx), v3(wo), &lambdas(lambda)),
        };
        (self.origin)
            .checked(r, checked::values)
            .map_or(SampledSpectrum::zero(), spectrum)
    }
}

// ----------------------------------------------------------------------------------------------
// Light

/// A plugin light's wavelength distribution, seen as an SPD: what light subpaths draw from.
struct LightSpectrum {
    light: Arc<LightBox>,
    origin: Origin,
    lines: std::sync::OnceLock<Vec<crate::spectrum::DeltaLine>>,
}

impl fmt::Debug for LightSpectrum {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "LightSpectrum({})", self.origin.label)
    }
}

impl Spd for LightSpectrum {
    fn value(&self, lambda_nm: f64) -> f64 {
        self.pdf(lambda_nm)
    }
    fn sample(&self, u: f64) -> SpdSample {
        let r = self.light.sample_wavelength(u);
        match self.origin.checked(r, checked::wavelength_sample) {
            Some(s) => SpdSample {
                lambda: s.nm,
                pdf: s.pdf,
                is_delta: s.pdf > 0.0 && self.pdf(s.nm) == 0.0,
            },
            None => SpdSample {
                lambda: 550.0,
                pdf: 0.0,
                is_delta: false,
            },
        }
    }
    fn pdf(&self, lambda_nm: f64) -> f64 {
        (self.origin)
            .checked(self.light.wavelength_pdf(lambda_nm), |p| {
                checked::density(*p)
            })
            .unwrap_or(0.0)
    }
    fn range(&self) -> (f64, f64) {
        (360.0, 830.0)
    }
    fn delta_lines(&self) -> Vec<crate::spectrum::DeltaLine> {
        self.lines
            .get_or_init(|| {
                let n = 4096;
                let mut lines: Vec<crate::spectrum::DeltaLine> = Vec::new();
                for k in 0..n {
                    let s = self.sample((k as f64 + 0.5) / n as f64);
                    if !s.is_delta {
                        continue;
                    }
                    match lines.iter_mut().find(|l| l.lambda == s.lambda) {
                        Some(l) => l.weight += 1.0 / n as f64,
                        None => lines.push(crate::spectrum::DeltaLine {
                            lambda: s.lambda,
                            weight: 1.0 / n as f64,
                        }),
                    }
                }
                lines
            })
            .clone()
    }
}

/// A plugin light with the ENVIRONMENT capability, as the radiance source of a host
/// [`EnvironmentLight`]: `radiance` on escape, and with CONNECTABLE also the plugin's own
/// incident sampling (`sample_toward`, `incident_pdf`) for next-event estimation; without it
/// the host samples directions uniformly.
struct PluginEnvironment {
    light: Arc<LightBox>,
    spectrum: Arc<dyn Spd>,
    mean_radiance: f64,
    sampled: bool,
    origin: Origin,
}

impl fmt::Debug for PluginEnvironment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginEnvironment({})", self.origin.label)
    }
}

impl PluginEnvironment {
    /// Radiance integrated over 360–830 nm (trapezoid, 10 nm) and averaged over 256 directions
    /// of a Fibonacci sphere, W/(m²·sr): only the light-selection weight depends on it.
    fn estimate_mean(light: &LightBox, origin: &Origin) -> f64 {
        let n_dir = 256;
        let nm: Vec<f64> = (0..48).map(|i| 360.0 + 10.0 * i as f64).collect();
        let mut sum = 0.0;
        for k in 0..n_dir {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / n_dir as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = k as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
            let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            for chunk in nm.chunks(LANES) {
                let mut w = Wavelengths {
                    nm: [chunk[0]; LANES],
                };
                w.nm[..chunk.len()].copy_from_slice(chunk);
                let v = (origin)
                    .checked(light.radiance(d, &w), checked::values)
                    .unwrap_or(SpectralValues::ZERO);
                for (i, &l) in chunk.iter().enumerate() {
                    let edge = l == nm[0] || l == nm[nm.len() - 1];
                    sum += v.v[i] * if edge { 5.0 } else { 10.0 };
                }
            }
        }
        sum / n_dir as f64
    }
}

impl EnvironmentRadiance for PluginEnvironment {
    fn radiance(&self, dir: Vec3A, lambda: &SampledWavelengths) -> SampledSpectrum {
        let r = self.light.radiance(v3(dir), &lambdas(lambda));
        (self.origin)
            .checked(r, checked::values)
            .map_or(SampledSpectrum::zero(), spectrum)
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
        let w = Wavelengths { nm: [550.0; LANES] };
        match self
            .light
            .sample_toward(v3(p), &sample_from(&[u.x, u.y]), &w)
            .into_result()
        {
            Ok(s) if s.pdf > 0.0 => Some((unit(va(s.direction)), s.pdf as f32)),
            Ok(_) => None,
            Err(e) => self.origin.fail(e, None),
        }
    }

    fn direction_pdf(&self, p: Vec3A, dir: Vec3A) -> f32 {
        if !self.sampled {
            return 1.0 / (4.0 * std::f32::consts::PI);
        }
        let r = self.light.incident_pdf(v3(p), v3(dir));
        (self.origin)
            .checked(r, |p| checked::density(*p))
            .map_or(0.0, |p| p as f32)
    }
}

/// A plugin light as a host [`Light`]. Without the CONNECTABLE capability it is BEAMS_ONLY:
/// integrators can only trace the beams it hands out (see [`PluginLight::next_beam`]). With the
/// ENVIRONMENT capability it is an [`EnvironmentLight`] whose radiance the plugin gives (the
/// host places and samples the emitting sphere).
///
/// Built through extension v2, the light learns the scene's extent before rendering (its power
/// is read again afterwards: a distant light's depends on it) and hands over its own emission
/// SPD, which then stands for its spectrum everywhere (see [`Light::spd`]).
pub struct PluginLight {
    light: Arc<LightBox>,
    /// The same light's version-2 face (extension v2).
    v2: Option<LightV2Box>,
    flags: LightFlags,
    power: f64,
    /// The power read again once the light knows the scene's extent (extension v2).
    power_with_bounds: OnceLock<f64>,
    /// The geometry's bounds, kept from [`Light::preprocess`] for the v2 call.
    scene_bounds: OnceLock<Aabb>,
    spectrum: Arc<dyn Spd>,
    origin: Origin,
    environment: Option<EnvironmentLight>,
    /// The object handing out beams in the type's own representation, with its converter,
    /// when the type declares one (see [`super::representation`]).
    represented: Option<(RepresentedLightBox, BeamConverter)>,
    /// Declared through extension v4: the emission has one spectral shape everywhere.
    uniform: bool,
    /// The same light's calls in the host's layout (extension v6); not for environments,
    /// which the host samples itself, nor for lights that only hand out beams (neither is
    /// sampled or asked for a density through them), so that its presence alone selects the
    /// calls' short path.
    v6: Option<LightV6Box>,
}

impl PluginLight {
    /// Wrap `light` (a library without extension v2).
    pub fn new(light: LightBox, origin: Origin) -> Self {
        Self::build(light, None, origin)
    }

    /// Wrap a light built through extension v2.
    pub fn new_v2(light: LightWithV2, origin: Origin) -> Self {
        Self::build(light.light, Some(light.v2), origin)
    }

    /// Wrap a light built through extension v4: as [`Self::new_v2`], with its declaration of
    /// one spectral shape everywhere ([`Light::uniform_spectral_shape`]), checked where it
    /// matters (see [`super::uniform_shape`]): a claim the light's own emission contradicts is
    /// refused, naming the plugin object, `item` (the scene's name for it) and the wavelength.
    /// A light that only hands out beams gets no exact colour, so its claim is not probed.
    pub fn new_v4(light: LightWithV4, origin: Origin, item: &str) -> Result<Self, String> {
        let mut l = Self::build(light.light, Some(light.v2), origin);
        if light.uniform_spectral_shape && !l.flags.contains(LightFlags::BEAMS_ONLY) {
            super::uniform_shape::check(&l.light, &*l.spectrum, l.environment.is_some()).map_err(
                |e| {
                    format!(
                        "{} as {item}: declares one spectral shape everywhere \
                         (uniform_spectral_shape, extension v4), but {e}",
                        l.origin.label
                    )
                },
            )?;
        }
        l.uniform = light.uniform_spectral_shape;
        Ok(l)
    }

    /// Wrap a light built through extension v6: as [`Self::new_v4`] (its declaration checked),
    /// with `sample_li`, `sample_le` and `pdf_le` through the v6 face, in the host's layout.
    pub fn new_v6(light: LightWithV6, origin: Origin, item: &str) -> Result<Self, String> {
        let LightWithV6 {
            light,
            v2,
            v6,
            uniform_spectral_shape,
        } = light;
        let mut l = Self::new_v4(
            LightWithV4 {
                light,
                v2,
                uniform_spectral_shape,
            },
            origin,
            item,
        )?;
        if l.environment.is_none() && !l.flags.contains(LightFlags::BEAMS_ONLY) {
            l.v6 = Some(v6);
        }
        Ok(l)
    }

    fn build(light: LightBox, v2: Option<LightV2Box>, origin: Origin) -> Self {
        let caps = light.capabilities();
        let mut flags = LightFlags::default();
        if caps.contains(light_flags::DELTA_POSITION) {
            flags = flags | LightFlags::DELTA_POSITION;
        }
        if caps.contains(light_flags::DELTA_DIRECTION) {
            flags = flags | LightFlags::DELTA_DIRECTION;
        }
        let is_environment = caps.contains(light_flags::ENVIRONMENT);
        if is_environment {
            flags = LightFlags::ENVIRONMENT;
        } else if !caps.contains(light_flags::CONNECTABLE) {
            flags = flags | LightFlags::BEAMS_ONLY;
        }
        let light = Arc::new(light);
        // The light's own SPD when it hands one over (v2), else its spectrum as seen through
        // `sample_wavelength` and `wavelength_pdf`.
        let own = v2.as_ref().and_then(|v2| {
            origin
                .checked(v2.emission_spectrum(), |_| Ok(()))
                .and_then(ROption::into_option)
        });
        let spectrum: Arc<dyn Spd> = match own {
            Some(spd) => Arc::new(PluginSpd::with_lines(spd, origin.clone())),
            None => Arc::new(LightSpectrum {
                light: light.clone(),
                origin: origin.clone(),
                lines: std::sync::OnceLock::new(),
            }),
        };
        let (power, environment) = if is_environment {
            let source = PluginEnvironment {
                light: light.clone(),
                spectrum: spectrum.clone(),
                mean_radiance: PluginEnvironment::estimate_mean(&light, &origin),
                sampled: caps.contains(light_flags::CONNECTABLE),
                origin: origin.clone(),
            };
            (0.0, Some(EnvironmentLight::new(Arc::new(source))))
        } else {
            let power = (origin)
                .checked(light.total_power_w(), |p| checked::scalar(*p))
                .unwrap_or(0.0);
            (power, None)
        };
        Self {
            spectrum,
            light,
            v2,
            flags,
            power,
            power_with_bounds: OnceLock::new(),
            scene_bounds: OnceLock::new(),
            origin,
            environment,
            represented: None,
            uniform: false,
            v6: None,
        }
    }

    /// Hand out beams from `represented` (the same light, built in its own representation),
    /// converted once per beam. An error says what in the declared representation is unusable.
    pub fn with_represented(mut self, represented: RepresentedLightBox) -> Result<Self, String> {
        let converter = BeamConverter::new(represented.representation())?;
        self.represented = Some((represented, converter));
        Ok(self)
    }

    /// Tell a v2 light the scene's extent and read its power again.
    fn give_bounds(&self, v2: &LightV2Box, view: &Aabb) {
        let scene = self.scene_bounds.get().copied().unwrap_or(*view);
        let bounds = SceneBounds {
            min: v3(scene.min),
            max: v3(scene.max),
            view_min: v3(view.min),
            view_max: v3(view.max),
        };
        if self
            .origin
            .checked(v2.scene_bounds(&bounds), |_| Ok(()))
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
            (self.origin).checked(self.light.total_power_w(), |p| checked::scalar(*p))
        };
        if let Some(p) = power {
            let _ = self.power_with_bounds.set(p);
        }
    }
}

/// The light calls of environments, of lights that only hand out beams and of libraries older
/// than extension v6, out of line: the v6 path of each call stays a small function (its frame
/// and saved registers are what that path needs, not these), chosen by the presence of the v6
/// face alone (the `v6` field).
impl PluginLight {
    /// `sample_li` without the v6 face.
    #[inline(never)]
    fn sample_li_other(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        if let Some(e) = &self.environment {
            return e.sample_li(ctx, u, lambda);
        }
        if self.flags.contains(LightFlags::BEAMS_ONLY) {
            return None;
        }
        let r = self
            .light
            .sample_toward(v3(ctx.p), &sample_from(&[u.x, u.y]), &lambdas(lambda));
        match self.origin.checked(r, checked::incident) {
            Some(s) if s.pdf > 0.0 => Some(LightLiSample {
                radiance: spectrum(s.value),
                wi: va(s.direction),
                pdf: s.pdf as f32,
                p_light: va(s.point),
                p_light_error: Vec3A::ZERO,
                n_light: va(s.normal),
            }),
            _ => None,
        }
    }

    /// `sample_le` without the v6 face.
    #[inline(never)]
    fn sample_le_other(
        &self,
        u1: Vec2,
        u2: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLeSample> {
        if let Some(e) = &self.environment {
            return e.sample_le(u1, u2, lambda);
        }
        if self.flags.contains(LightFlags::BEAMS_ONLY) {
            return None;
        }
        let r = self
            .light
            .sample_emission(&sample_from(&[u1.x, u1.y, u2.x, u2.y]), &lambdas(lambda));
        match self.origin.checked(r, checked::emission) {
            Some(s) if s.pdf_position > 0.0 && s.pdf_direction > 0.0 => Some(LightLeSample {
                ray: Ray::new(va(s.origin), va(s.direction)),
                radiance: spectrum(s.value),
                pdf_pos: s.pdf_position as f32,
                pdf_dir: s.pdf_direction as f32,
                normal: va(s.normal),
            }),
            _ => None,
        }
    }

    /// `pdf_le` without the v6 face.
    #[inline(never)]
    fn pdf_le_other(&self, ray: &Ray, n: Vec3A) -> (f32, f32) {
        if let Some(e) = &self.environment {
            return e.pdf_le(ray, n);
        }
        if self.flags.contains(LightFlags::BEAMS_ONLY) {
            return (0.0, 0.0);
        }
        let r = self.light.emission_pdf(v3(ray.origin), v3(ray.dir));
        match self.origin.checked(r, |p| {
            checked::density(p.position).and(checked::density(p.direction))
        }) {
            Some(p) => (p.position as f32, p.direction as f32),
            None => (0.0, 0.0),
        }
    }
}

impl fmt::Debug for PluginLight {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginLight({})", self.origin.label)
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
        match &self.v6 {
            Some(v6) => {
                // Written by the plugin in place (see `super::layout`), then checked.
                let mut s = LightLiSample {
                    radiance: SampledSpectrum::zero(),
                    wi: Vec3A::ZERO,
                    pdf: 0.0,
                    p_light: Vec3A::ZERO,
                    p_light_error: Vec3A::ZERO,
                    n_light: Vec3A::ZERO,
                };
                let receiver = super::layout::as_receiver(ctx);
                let out = super::layout::as_incident_mut(&mut s);
                match v6.sample_toward(receiver, &[u.x, u.y], &lanes_f32(lambda), out) {
                    RResult::ROk(true) => match checked::incident_f32(out) {
                        Ok(()) if s.pdf > 0.0 => Some(s),
                        Ok(()) => None,
                        Err(reason) => {
                            self.origin.dropped(reason);
                            None
                        }
                    },
                    RResult::ROk(false) => None,
                    RResult::RErr(e) => self.origin.fail(e, None),
                }
            }
            None => self.sample_li_other(ctx, u, lambda),
        }
    }

    fn pdf_li(&self, ctx: &LightSampleContext, p_light: Vec3A, n_light: Vec3A) -> f32 {
        if let Some(e) = &self.environment {
            return e.pdf_li(ctx, p_light, n_light);
        }
        if self.flags.is_delta() || self.flags.contains(LightFlags::BEAMS_ONLY) {
            return 0.0;
        }
        let dir = (p_light - ctx.p).normalize_or_zero();
        let r = self.light.incident_pdf(v3(ctx.p), v3(dir));
        (self.origin)
            .checked(r, |p| checked::density(*p))
            .map_or(0.0, |p| p as f32)
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
        if let Some(v6) = &self.v6 {
            let mut s = EmissionF32::default();
            let u = [u1.x, u1.y, u2.x, u2.y];
            return match v6.sample_emission(&u, &lanes_f32(lambda), &mut s) {
                RResult::ROk(true) => match checked::emission_f32(&s) {
                    Ok(()) if s.pdf_position > 0.0 && s.pdf_direction > 0.0 => {
                        Some(LightLeSample {
                            ray: Ray::new(host_v(s.origin), host_v(s.direction)),
                            radiance: SampledSpectrum(s.value),
                            pdf_pos: s.pdf_position,
                            pdf_dir: s.pdf_direction,
                            normal: host_v(s.normal),
                        })
                    }
                    Ok(()) => None,
                    Err(reason) => {
                        self.origin.dropped(reason);
                        None
                    }
                },
                RResult::ROk(false) => None,
                RResult::RErr(e) => self.origin.fail(e, None),
            };
        }
        self.sample_le_other(u1, u2, lambda)
    }

    fn next_beam(&self, u: &RandomSample) -> Option<Beam> {
        if self.environment.is_some() {
            // Where an environment's beams start depends on the scene, which the plugin does
            // not know: the host's own emission sampling stands in for them.
            return None;
        }
        let r = match &self.represented {
            None => self.light.next_beam(u),
            // Another representation: converted here, once per beam (the seed's adapter).
            Some((light, c)) => match light.next_represented_beam(u) {
                RResult::ROk(b) => match c.convert(&b, u) {
                    Ok(b) => RResult::ROk(b),
                    Err(reason) => {
                        self.origin
                            .faults
                            .record_invalid(&self.origin.label, reason);
                        return None;
                    }
                },
                RResult::RErr(e) => RResult::RErr(e),
            },
        };
        self.origin.checked(r, checked::beam)
    }

    fn number_of_beams(&self) -> f64 {
        match &self.represented {
            None => self.light.number_of_beams(),
            Some((light, _)) => light.number_of_beams(),
        }
    }

    fn pdf_le(&self, ray: &Ray, n: Vec3A) -> (f32, f32) {
        if let Some(v6) = &self.v6 {
            let mut p = [0.0; 2];
            return match v6.emission_pdf(&v4f(ray.origin), &v4f(ray.dir), &mut p) {
                RResult::ROk(()) => {
                    match checked::density_f32(p[0]).and(checked::density_f32(p[1])) {
                        Ok(()) => (p[0], p[1]),
                        Err(reason) => {
                            self.origin.dropped(reason);
                            (0.0, 0.0)
                        }
                    }
                }
                RResult::RErr(e) => self.origin.fail(e, (0.0, 0.0)),
            };
        }
        self.pdf_le_other(ray, n)
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
        if let Some(v2) = &self.v2 {
            self.give_bounds(v2, view_bounds);
        }
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
    use spectrace_plugin_api::extension::{
        AbiMaterialV7, AbiMaterialV7_TO, AbiMaterialV8, AbiMaterialV8_TO,
    };
    use spectrace_plugin_api::fast::{SurfaceF32, ValuesF32, WavelengthsF32};
    use spectrace_plugin_api::guard::{keep_error, take_kept_error};
    use spectrace_plugin_api::material::GuardedMaterial;
    use spectrace_plugin_api::ErrorKind;
    use spectrace_plugin_api::{PluginResult, ScatterSample, ShadingContext as ApiContext};

    /// A plugin Lambertian in `f64` (the v6 faces the checks of the declarations use).
    struct Grey;

    impl spectrace_plugin_api::Material for Grey {
        fn capabilities(&self) -> Flags {
            material_flags::DIFFUSE
        }
        fn sample(
            &self,
            _ctx: &ApiContext,
            _wo: Vec3,
            _lambda: &Wavelengths,
            _u: &RandomSample,
            _mode: TransportMode,
        ) -> PluginResult<Option<ScatterSample>> {
            Ok(None)
        }
        fn eval(
            &self,
            _ctx: &ApiContext,
            _wo: Vec3,
            _wi: Vec3,
            _lambda: &Wavelengths,
            _mode: TransportMode,
        ) -> PluginResult<SpectralValues> {
            Ok(SpectralValues { v: [0.5; LANES] })
        }
        fn pdf(
            &self,
            _ctx: &ApiContext,
            _wo: Vec3,
            _wi: Vec3,
            _lambda: &Wavelengths,
            _mode: TransportMode,
        ) -> PluginResult<f64> {
            Ok(0.25)
        }
    }

    /// A v7 face that answers a fixed status word, writing `wi` as given when it says WRITTEN
    /// and no error when it says ERROR: what a lying or broken plugin can do.
    struct Answers {
        status: u32,
        wi: Vec4f,
    }

    impl AbiMaterialV7 for Answers {
        fn sample(
            &self,
            _q: &QueryV7<'_>,
            out: &mut ScatterF32,
            _e: &mut ROption<PluginError>,
        ) -> u32 {
            *out = ScatterF32 {
                wi: self.wi,
                value: [0.5; LANES],
                pdf: 0.3,
                flags: material_flags::DIFFUSE,
                eta: 1.0,
            };
            self.status
        }
        fn eval(
            &self,
            _q: &QueryV7<'_>,
            out: &mut [f32; LANES],
            _e: &mut ROption<PluginError>,
        ) -> u32 {
            *out = [0.5; LANES];
            self.status
        }
        fn pdf(&self, _q: &QueryV7<'_>, out: &mut f32, _e: &mut ROption<PluginError>) -> u32 {
            *out = 0.25;
            self.status
        }
    }

    fn with_face(face: Answers) -> (PluginMaterial, Arc<PluginFaults>) {
        let faults = PluginFaults::new();
        let origin = Origin {
            label: "material `grey` (plugin test 0.1.0)".to_string(),
            faults: faults.clone(),
        };
        let with_v6 = GuardedMaterial::boxed_v6(Grey, |_| Ok(Vec::new())).unwrap();
        let v7 = AbiMaterialV7_TO::from_value(face, TD_Opaque);
        let m = PluginMaterial::new_v7(MaterialWithV7 { with_v6, v7 }, origin, "floor").unwrap();
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

    // Extension v7's status word: WRITTEN hands over what the face wrote (the sample's event
    // bits translated); a status the interface does not have, ERROR without an error, and NONE
    // from eval or pdf are each refused (0 / no sample) and reported naming the plugin object,
    // the call and the status; a sample whose direction is not unit is dropped as for every face.
    #[test]
    fn the_v7_status_word_is_checked() {
        let (m, faults) = with_face(Answers {
            status: status::WRITTEN,
            wi: Vec4f::new(0.0, 0.6, 0.8),
        });
        let (s, f, p) = ask(&m);
        let s = s.expect("a sample");
        assert_eq!(
            (s.wi, s.f.0, s.pdf),
            (Vec3A::new(0.0, 0.6, 0.8), [0.5; 4], 0.3)
        );
        assert_eq!(s.flags, MaterialFlags::DIFFUSE | MaterialFlags::REFLECTION);
        assert_eq!((f.0, p), ([0.5; 4], 0.25));
        assert_eq!(faults.count() + faults.invalid_count(), 0);

        for (status, says) in [
            (7, "answered status 7, which is none of"),
            (
                status::ERROR,
                "answered ERROR (status 2) without writing an error",
            ),
        ] {
            let (m, faults) = with_face(Answers {
                status,
                wi: Vec4f::new(0.0, 0.6, 0.8),
            });
            let (s, f, p) = ask(&m);
            assert!(s.is_none());
            assert_eq!((f.0, p), ([0.0; 4], 0.0));
            assert_eq!(faults.count(), 3);
            let first = faults.first().unwrap();
            assert!(
                first.starts_with("material `grey` (plugin test 0.1.0): "),
                "{first}"
            );
            assert!(first.contains(&format!("sample (v7) {says}")), "{first}");
        }

        let (m, faults) = with_face(Answers {
            status: status::NONE,
            wi: Vec4f::new(0.0, 0.6, 0.8),
        });
        let (s, f, p) = ask(&m);
        assert!(s.is_none());
        assert_eq!((f.0, p), ([0.0; 4], 0.0));
        assert_eq!(faults.count(), 2, "eval and pdf may not answer NONE");
        let sites = faults.sites();
        assert!(sites.iter().any(|s| s
            .3
            .contains("eval (v7) answered NONE (status 0), which only `sample` may answer")));

        let (m, faults) = with_face(Answers {
            status: status::WRITTEN,
            wi: Vec4f::new(0.0, 1.2, 0.8),
        });
        assert!(ask(&m).0.is_none());
        assert_eq!(faults.invalid_count(), 1);
        assert_eq!(faults.invalid()[0].0, "material `grey` (plugin test 0.1.0)");
    }

    /// A v8 face that answers as told: `sample` the status (writing a sample with direction
    /// `wi`), `eval` the values, `pdf` the density; with `keep`, each call that answers a
    /// failure (ERROR, NaN) first keeps that error on the thread, as the export macro's guard
    /// does.
    struct AnswersV8 {
        status: u32,
        wi: Vec4f,
        values: [f32; LANES],
        pdf: f32,
        keep: Option<&'static str>,
    }

    impl AnswersV8 {
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

    impl AbiMaterialV8 for AnswersV8 {
        fn sample(
            &self,
            _wo: &Vec4f,
            _ctx: &SurfaceF32,
            _lambda: &WavelengthsF32,
            _u_lobe: f32,
            _u1: f32,
            _u2: f32,
            _mode: TransportMode,
            out: &mut ScatterF32,
        ) -> u32 {
            self.keep(self.status == status::ERROR);
            *out = ScatterF32 {
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
            _ctx: &SurfaceF32,
            _lambda: &WavelengthsF32,
            _mode: TransportMode,
        ) -> ValuesF32 {
            self.keep(self.values[0].is_nan());
            ValuesF32 { v: self.values }
        }
        fn pdf(
            &self,
            _wo: &Vec4f,
            _wi: &Vec4f,
            _ctx: &SurfaceF32,
            _lambda: &WavelengthsF32,
            _mode: TransportMode,
        ) -> f32 {
            self.keep(self.pdf.is_nan());
            self.pdf
        }
    }

    /// Extension v8's `take_error` as the export macro writes it (this thread's kept error).
    extern "C" fn take_kept() -> ROption<PluginError> {
        take_kept_error().into()
    }

    fn origin() -> (Origin, Arc<PluginFaults>) {
        let faults = PluginFaults::new();
        let origin = Origin {
            label: "material `grey` (plugin test 0.1.0)".to_string(),
            faults: faults.clone(),
        };
        (origin, faults)
    }

    fn with_face_v8(face: AnswersV8) -> (PluginMaterial, Arc<PluginFaults>) {
        let (origin, faults) = origin();
        let with_v6 = GuardedMaterial::boxed_v6(Grey, |_| Ok(Vec::new())).unwrap();
        let v7 = AbiMaterialV7_TO::from_value(
            Answers {
                status: status::WRITTEN,
                wi: Vec4f::new(0.0, 0.6, 0.8),
            },
            TD_Opaque,
        );
        let v8 = AbiMaterialV8_TO::from_value(face, TD_Opaque);
        let with_v7 = MaterialWithV7 { with_v6, v7 };
        let m = PluginMaterial::new_v8(MaterialWithV8 { with_v7, v8 }, take_kept, origin, "floor")
            .unwrap();
        (m, faults)
    }

    /// The failed calls' messages by call site.
    fn failed_sites(faults: &PluginFaults) -> Vec<(String, String)> {
        faults
            .sites()
            .into_iter()
            .map(|(who, site, n, first)| {
                assert_eq!(who, "material `grey` (plugin test 0.1.0)");
                assert_eq!(n, 1, "{site}: {first}");
                (site, first)
            })
            .collect()
    }

    // Extension v8's face: the host's calls go through it (its answers handed over, the
    // sample's event bits translated). A call that failed (ERROR from `sample`, NaN from `eval`
    // and `pdf`) has its kept error taken from the library and reported with the plugin
    // object and the call named; ERROR without a kept error and a status the interface does not
    // have are reported the same way; values that break the rules without an error (NaN,
    // infinite, negative, a direction that is not unit) are dropped and counted per object and
    // call. Nothing is fatal: the host gets no sample, zero, zero.
    #[test]
    fn the_v8_answers_are_checked_and_their_errors_taken() {
        let (m, faults) = with_face_v8(AnswersV8::honest());
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
        let (m, faults) = with_face_v8(AnswersV8 {
            status: status::ERROR,
            values: ValuesF32::FAILED.v,
            pdf: f32::NAN,
            keep: Some("the material broke"),
            ..AnswersV8::honest()
        });
        let (s, f, p) = ask(&m);
        assert!(s.is_none());
        assert_eq!((f.0, p), ([0.0; 4], 0.0));
        assert_eq!((faults.count(), faults.invalid_count()), (3, 0));
        let sites = failed_sites(&faults);
        for call in ["eval (v8)", "pdf (v8)", "sample (v8)"] {
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
        let (m, faults) = with_face_v8(AnswersV8 {
            values: ValuesF32::FAILED.v,
            keep: Some("eval (v8) panicked at lib.rs:7: boom"),
            ..AnswersV8::honest()
        });
        assert_eq!(ask(&m).1 .0, [0.0; 4]);
        assert_eq!(
            failed_sites(&faults),
            [(
                "eval (v8) panicked at lib.rs:7".to_string(),
                "error: eval (v8) panicked at lib.rs:7: boom".to_string()
            )]
        );

        // Status words that are not the interface's, or ERROR with nothing kept.
        for (status, says) in [
            (7, "sample (v8) answered status 7, which is none of"),
            (
                status::ERROR,
                "sample (v8) answered ERROR (status 2) without keeping an error",
            ),
        ] {
            let (m, faults) = with_face_v8(AnswersV8 {
                status,
                ..AnswersV8::honest()
            });
            assert!(ask(&m).0.is_none());
            assert_eq!(faults.count(), 1);
            let first = faults.first().unwrap();
            assert!(
                first.starts_with(&format!(
                    "material `grey` (plugin test 0.1.0): error: {says}"
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
            let (m, faults) = with_face_v8(AnswersV8 {
                wi,
                values,
                pdf,
                ..AnswersV8::honest()
            });
            let (s, f, p) = ask(&m);
            assert!(s.is_none());
            assert_eq!((f.0, p), ([0.0; 4], 0.0));
            assert_eq!(faults.count(), 0, "{:?}", faults.report());
            let mut invalid = faults.invalid();
            invalid.sort();
            assert_eq!(
                invalid
                    .iter()
                    .map(|(who, why, n)| (who.as_str(), *why, *n))
                    .collect::<Vec<_>>(),
                [
                    (
                        "material `grey` (plugin test 0.1.0)",
                        "eval (v8): value NaN, infinite or negative",
                        1
                    ),
                    (
                        "material `grey` (plugin test 0.1.0)",
                        "pdf (v8): pdf NaN, infinite or negative",
                        1
                    ),
                    (
                        "material `grey` (plugin test 0.1.0)",
                        "sample (v8): direction not a finite unit vector",
                        1
                    ),
                ]
            );
        }
    }

    /// A plugin material through the API's own v8 guard (what `export_plugin!` builds): its
    /// `sample` panics, its `eval` fails with an error, its `pdf` answers NaN.
    struct Broken;

    impl spectrace_plugin_api::Material for Broken {
        fn capabilities(&self) -> Flags {
            material_flags::DIFFUSE
        }
        fn sample(
            &self,
            _ctx: &ApiContext,
            _wo: Vec3,
            _lambda: &Wavelengths,
            _u: &RandomSample,
            _mode: TransportMode,
        ) -> PluginResult<Option<ScatterSample>> {
            panic!("broken while sampling")
        }
        fn eval(
            &self,
            _ctx: &ApiContext,
            _wo: Vec3,
            _wi: Vec3,
            _lambda: &Wavelengths,
            _mode: TransportMode,
        ) -> PluginResult<SpectralValues> {
            Err(PluginError::new(ErrorKind::Other, "no value here"))
        }
        fn pdf(
            &self,
            _ctx: &ApiContext,
            _wo: Vec3,
            _wi: Vec3,
            _lambda: &Wavelengths,
            _mode: TransportMode,
        ) -> PluginResult<f64> {
            Ok(f64::NAN)
        }
    }

    // Through the API's v8 guard: the panic is caught on the plugin's side and kept, the error
    // kept, and both taken and reported naming object and call; the NaN density (no error) is
    // dropped and counted with its call. Each call is asked twice: nothing is left kept
    // between them.
    #[test]
    fn a_v8_plugin_that_panics_or_fails_is_reported_not_fatal() {
        let (origin, faults) = origin();
        let m = GuardedMaterial::boxed_v8(Broken, |_| Ok(Vec::new())).unwrap();
        let m = PluginMaterial::new_v8(m, take_kept, origin, "floor").unwrap();
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
            .find(|s| s.1.starts_with("sample (v8) panicked at "));
        let sample = sample.unwrap_or_else(|| panic!("{sites:?}"));
        assert_eq!(sample.2, 2);
        assert!(
            sample.3.ends_with(": broken while sampling"),
            "{}",
            sample.3
        );
        let eval = sites.iter().find(|s| s.1 == "eval (v8)");
        let eval = eval.unwrap_or_else(|| panic!("{sites:?}"));
        assert_eq!(eval.2, 2);
        assert_eq!(eval.3, "error: eval (v8): no value here");
        let first = faults.first().unwrap();
        assert!(
            first.starts_with("material `grey` (plugin test 0.1.0): "),
            "{first}"
        );
        assert_eq!(
            faults.invalid(),
            [(
                "material `grey` (plugin test 0.1.0)".to_string(),
                "pdf (v8): pdf NaN, infinite or negative",
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
