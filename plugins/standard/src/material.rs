//! The built-in materials (`host/src/builtin/material/`): `lambertian`, `mirror`, `dielectric`,
//! `rough_dielectric`, `conductor`, `emissive`, `fluorescent`, same parameters, each built by the
//! host's own constructor and called through the plugin interface (no physics here, only
//! conversions).
//!
//! Conversions: directions, values, pdfs and the surface's normals (extension v2) cross as f64
//! and come back to the host's f32 exactly (f32 → f64 → f32 is the identity). An emissive
//! material hands over its emission exactly (its own SPD and scale, extension v2), so the host
//! builds the same area light as for the built-in. A fluorescent material hands over its
//! re-radiation (extension v3), every call in f64 on both sides, so the host shifts wavelengths
//! with the very numbers of the built-in. What the interface does not carry: the
//! wavelengths' sampling densities (every lane is passed as live, density 1/nm; only thin films
//! read them, to skip terminated lanes).
//!
//! Held as the host's concrete types where the host's constructor gives one (`build_concrete`:
//! all but `emissive` and `fluorescent`), so that the interface's call reaches the host's code
//! with a direct call, and the host's wavelengths and surface are read in place
//! (`spectrace::plugin::layout`): the library adds to a call what the interface needs and no
//! second dynamic call of its own (docs/performance.md, "The standard library calling the
//! host's types directly").

use crate::wrap::{context, params_doc, plugin_error, HostParams, HostSpd};
use glam::{Vec2, Vec3A};
use spectrace::builtin::material::{
    conductor, dielectric, emissive, fluorescent, lambertian, mirror, rough_dielectric,
};
use spectrace::material::{
    BsdfSample, Material as HostMaterial, MaterialFlags, ShadingContext as HostContext,
    TransportMode as HostMode,
};
use spectrace::plugin::layout::{
    as_bsdf_sample_mut, as_shading_context, as_vec3a, as_wavelengths, as_wavelengths_v7,
};
use spectrace::scene::FactoryError;
use spectrace::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use spectrace_plugin_api::{
    material_flags, Emission, Flags, Host, LanesF32, Material, MaterialQuery, ParamDoc,
    PluginError, PluginResult, PluginType, QueryV5, QueryV7, RandomSample, Reradiation, ScatterF32,
    ScatterSample, ShadingContext, SpectralValues, SurfaceContext, SurfaceF32, TransportMode, Vec3,
    Vec4f, WavelengthDraw, Wavelengths, WavelengthsF32,
};
use std::sync::Arc;

/// Host vector (f32) from an interface vector (f64).
pub(crate) fn va(v: Vec3) -> Vec3A {
    Vec3A::new(v.x as f32, v.y as f32, v.z as f32)
}

/// Interface vector (f64) from a host vector (f32).
pub(crate) fn v3(v: Vec3A) -> Vec3 {
    Vec3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// The host's wavelengths from the interface's: all lanes live (density 1/nm).
pub(crate) fn host_lambdas(l: &Wavelengths) -> SampledWavelengths {
    SampledWavelengths {
        lambda: l.nm.map(|x| x as f32),
        pdf: [1.0; LANES],
        lanes: spectrace::spectrum::LaneMask::ALL,
    }
}

/// Interface values from a host spectrum.
pub(crate) fn values(s: SampledSpectrum) -> SpectralValues {
    SpectralValues {
        v: s.0.map(f64::from),
    }
}

fn host_mode(m: TransportMode) -> HostMode {
    match m {
        TransportMode::Radiance => HostMode::Radiance,
        TransportMode::Importance => HostMode::Importance,
    }
}

fn host_ctx(ctx: &SurfaceContext) -> HostContext {
    HostContext::at(
        va(ctx.position),
        va(ctx.geometric_normal),
        va(ctx.shading_normal),
        Vec2::new(ctx.uv[0] as f32, ctx.uv[1] as f32),
    )
}

/// The interface's bits for host material bits (REFLECTION has no bit there: it is implied
/// unless TRANSMISSION is set for an event).
fn bits(f: MaterialFlags) -> Flags {
    let pairs = [
        (MaterialFlags::DIFFUSE, material_flags::DIFFUSE),
        (MaterialFlags::GLOSSY, material_flags::GLOSSY),
        (MaterialFlags::SPECULAR, material_flags::SPECULAR),
        (MaterialFlags::TRANSMISSION, material_flags::TRANSMISSION),
        (MaterialFlags::DISPERSIVE, material_flags::DISPERSIVE),
        (MaterialFlags::EMISSIVE, material_flags::EMISSIVE),
        (MaterialFlags::FLUORESCENT, material_flags::FLUORESCENT),
    ];
    let mut out = Flags::NONE;
    for (h, p) in pairs {
        if f.contains(h) {
            out = out | p;
        }
    }
    out
}

// Extension v4: the host's own f32 data on both sides, so nothing is converted.

/// The host's vector from an interface vector (the same four lanes).
#[inline]
pub(crate) fn host_v(v: Vec4f) -> Vec3A {
    Vec3A::from_vec4(glam::Vec4::new(v.x, v.y, v.z, v.w))
}

#[inline]
fn ctx_v4(c: &SurfaceF32) -> HostContext {
    HostContext::at(
        host_v(c.position),
        host_v(c.geometric_normal),
        host_v(c.shading_normal),
        Vec2::new(c.uv[0], c.uv[1]),
    )
}

/// The host's wavelengths exactly as the host passed them (densities and live lanes included).
#[inline]
pub(crate) fn lambdas_v4(l: &LanesF32) -> SampledWavelengths {
    SampledWavelengths {
        lambda: l.nm,
        pdf: l.pdf,
        lanes: spectrace::spectrum::LaneMask::from_bits(l.live as u8),
    }
}

/// [`bits`] in a few bit operations (the host's DIFFUSE, GLOSSY, SPECULAR are 4, 8, 16,
/// TRANSMISSION 2, DISPERSIVE, EMISSIVE, FLUORESCENT 32, 64, 128; REFLECTION and THIN_FILM have
/// no interface bit). The test below checks it against [`bits`]. Looked up in
/// [`EVENT_TABLE`], made from these operations at compile time (one load per event); bits 0
/// and above 7 are ignored, as here.
const fn event_bits_ops(b: u32) -> u32 {
    ((b >> 2) & 0b111) | (((b >> 1) & 1) << 3) | (((b >> 5) & 0b111) << 4)
}

/// [`event_bits_ops`] of every combination of the host's bits 0–7.
const EVENT_TABLE: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut b = 0;
    while b < 256 {
        t[b] = event_bits_ops(b as u32) as u8;
        b += 1;
    }
    t
};

/// The interface's bits of one scattering event (see [`event_bits_ops`]).
#[inline]
fn event_bits(f: MaterialFlags) -> Flags {
    Flags(u32::from(EVENT_TABLE[(f.0 & 0xff) as usize]))
}

/// The interface's vector from a host vector, `w` cleared (a lane select against zero, one AND
/// on SSE, as the host does it).
#[inline]
pub(crate) fn v4f(v: Vec3A) -> Vec4f {
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

/// The interface's sample from the host's (the same `f32`s).
#[inline]
fn scatter(s: BsdfSample) -> ScatterF32 {
    ScatterF32 {
        wi: v4f(s.wi),
        value: s.f.0,
        pdf: s.pdf,
        flags: event_bits(s.flags),
        eta: s.eta,
    }
}

#[inline]
fn sample_v4<M: HostMaterial + ?Sized>(m: &M, q: &MaterialQuery) -> Option<ScatterF32> {
    let s = m.sample(
        host_v(q.wo),
        &ctx_v4(&q.ctx),
        &lambdas_v4(&q.lambda),
        q.u[0],
        Vec2::new(q.u[1], q.u[2]),
        host_mode(q.mode),
    )?;
    Some(scatter(s))
}

/// The host's wavelengths of `l`: read in place (`spectrace::plugin::layout::as_wavelengths`),
/// or copied into `slot` where they cannot be.
#[inline]
pub(crate) fn wavelengths<'a>(
    l: &'a LanesF32,
    slot: &'a mut Option<SampledWavelengths>,
) -> &'a SampledWavelengths {
    match as_wavelengths(l) {
        Some(w) => w,
        None => slot.insert(lambdas_v4(l)),
    }
}

/// What every call with the surface by reference (extensions v5 and v6) reads from its query:
/// the directions, the host's own surface record and wavelengths in place
/// (`spectrace::plugin::layout`; the wavelengths copied into `slot` only where they cannot be
/// read in place) and the transport mode.
struct Read<'a> {
    wo: Vec3A,
    wi: Vec3A,
    ctx: &'a HostContext,
    lambda: &'a SampledWavelengths,
    mode: HostMode,
}

#[inline]
fn read<'a>(q: &'a QueryV5<'a>, slot: &'a mut Option<SampledWavelengths>) -> Read<'a> {
    Read {
        wo: host_v(q.wo),
        wi: host_v(q.wi),
        ctx: as_shading_context(q.ctx),
        lambda: wavelengths(&q.lambda, slot),
        mode: host_mode(q.mode),
    }
}

/// What every call of extension v7 reads from its query: as [`read`], the wavelengths in place
/// too (copied into `slot` only where they cannot be read in place).
#[inline]
fn read_v7<'a>(q: &'a QueryV7<'a>, slot: &'a mut Option<SampledWavelengths>) -> Read<'a> {
    Read {
        wo: host_v(q.wo),
        wi: host_v(q.wi),
        ctx: as_shading_context(q.ctx),
        lambda: match as_wavelengths_v7(q.lambda) {
            Some(w) => w,
            None => slot.insert(lambdas_v4(&q.lambda.to_lanes())),
        },
        mode: host_mode(q.mode),
    }
}

/// [`sample_v5`] with the wavelengths by reference and the sample written into `out`
/// (extension v7).
#[inline]
fn sample_v7<M: HostMaterial + ?Sized>(m: &M, q: &QueryV7<'_>, out: &mut ScatterF32) -> bool {
    let mut slot = None;
    let r = read_v7(q, &mut slot);
    let u = Vec2::new(q.u[1], q.u[2]);
    // The host's material writes its sample straight into `out` (the same layout), which the
    // host's own `out` is: no copy on either side.
    let rec = as_bsdf_sample_mut(out);
    let at: *const BsdfSample = rec;
    let Some(s) = m.sample_into(r.wo, r.ctx, r.lambda, q.u[0], u, r.mode, rec) else {
        return false;
    };
    if !std::ptr::eq(s, at) {
        // A material that answered with another record than the one it was given.
        let s = *s;
        *as_bsdf_sample_mut(out) = s;
    }
    out.flags = event_bits(MaterialFlags(out.flags.0));
    out.wi.w = 0.0;
    true
}

/// The host's wavelengths of `l`, read in place, or copied into `slot` where they cannot be.
#[inline]
fn wavelengths_v7<'a>(
    l: &'a WavelengthsF32,
    slot: &'a mut Option<SampledWavelengths>,
) -> &'a SampledWavelengths {
    match as_wavelengths_v7(l) {
        Some(w) => w,
        None => slot.insert(lambdas_v4(&l.to_lanes())),
    }
}

/// The host material's sample written into `out` (extension v8): its arguments as they come
/// (the host's own vectors and records, read in place), the host's sample written straight into
/// `out` (the same layout), its event bits then translated.
#[inline]
fn sample_v8<M: HostMaterial + ?Sized>(
    m: &M,
    wo: &Vec4f,
    ctx: &SurfaceF32,
    lambda: &WavelengthsF32,
    u: [f32; 3],
    mode: TransportMode,
    out: &mut ScatterF32,
) -> bool {
    let mut slot = None;
    let lambda = wavelengths_v7(lambda, &mut slot);
    let rec = as_bsdf_sample_mut(out);
    let at: *const BsdfSample = rec;
    let (wo, ctx, mode) = (*as_vec3a(wo), as_shading_context(ctx), host_mode(mode));
    let u_dir = Vec2::new(u[1], u[2]);
    let Some(s) = m.sample_into(wo, ctx, lambda, u[0], u_dir, mode, rec) else {
        return false;
    };
    if !std::ptr::eq(s, at) {
        // A material that answered with another record than the one it was given.
        let s = *s;
        *as_bsdf_sample_mut(out) = s;
    }
    out.flags = event_bits(MaterialFlags(out.flags.0));
    out.wi.w = 0.0;
    true
}

/// [`sample_v4`] with the surface by reference (extension v5).
#[inline]
fn sample_v5<M: HostMaterial + ?Sized>(m: &M, q: &QueryV5<'_>) -> Option<ScatterF32> {
    let mut slot = None;
    let r = read(q, &mut slot);
    let u = Vec2::new(q.u[1], q.u[2]);
    let s = m.sample(r.wo, r.ctx, r.lambda, q.u[0], u, r.mode)?;
    Some(scatter(s))
}

/// How the library holds a host material: as its concrete type where the host's constructor
/// gives one (its calls then reach the host's code directly, not through a second dynamic call
/// behind the interface's), otherwise behind `Arc<dyn Material>`.
trait Held: Send + Sync + 'static {
    /// The host material called.
    type M: HostMaterial + ?Sized;
    /// The host material (the value itself, or what the `Arc` points to).
    fn get(&self) -> &Self::M;
    /// The re-radiation face of a fluorescent one.
    fn reradiation_face(&self) -> PluginResult<Option<HostReradiation>>;
}

impl Held for Arc<dyn HostMaterial> {
    type M = dyn HostMaterial;
    #[inline]
    fn get(&self) -> &Self::M {
        &**self
    }
    fn reradiation_face(&self) -> PluginResult<Option<HostReradiation>> {
        Ok(HostReradiation::of(self))
    }
}

macro_rules! held_concrete {
    ($($t:ty),*) => {$(
        impl Held for $t {
            type M = $t;
            #[inline]
            fn get(&self) -> &Self::M {
                self
            }
            // These types never fluoresce; should one start to, it is refused here rather than
            // rendered without its re-radiation (it then belongs behind `Arc`).
            fn reradiation_face(&self) -> PluginResult<Option<HostReradiation>> {
                match HostMaterial::reradiation(self) {
                    None => Ok(None),
                    Some(_) => Err(PluginError::unsupported(concat!(
                        stringify!($t),
                        " fluoresces but is held as its concrete type"
                    ))),
                }
            }
        }
    )*};
}

held_concrete!(
    spectrace::material::Lambertian,
    spectrace::material::Mirror,
    spectrace::material::SmoothDielectric,
    spectrace::material::RoughDielectric,
    spectrace::material::RoughConductor
);

/// The host's constructor of a material held behind `Arc<dyn Material>`.
type BuildDyn<P> =
    fn(&P, &spectrace::scene::FactoryContext) -> Result<Arc<dyn HostMaterial>, FactoryError>;

/// Sample through the host material `m`.
fn sample<M: HostMaterial + ?Sized>(
    m: &M,
    ctx: &SurfaceContext,
    wo: Vec3,
    lambda: &Wavelengths,
    u: &RandomSample,
    mode: TransportMode,
) -> Option<ScatterSample> {
    let s = m.sample(
        va(wo),
        &host_ctx(ctx),
        &host_lambdas(lambda),
        u.u[0] as f32,
        Vec2::new(u.u[1] as f32, u.u[2] as f32),
        host_mode(mode),
    )?;
    Some(ScatterSample {
        wi: v3(s.wi),
        value: values(s.f),
        pdf: s.pdf as f64,
        flags: bits(s.flags),
        eta: s.eta as f64,
    })
}

/// A host material's re-radiation (`spectrace::spectrum::reradiation`) as the interface's
/// [`Reradiation`]: the same calls, f64 in and out.
pub struct HostReradiation(Arc<dyn HostMaterial>);

impl HostReradiation {
    /// For a host material that offers re-radiation; `None` otherwise.
    fn of(material: &Arc<dyn HostMaterial>) -> Option<Self> {
        material
            .reradiation()
            .is_some()
            .then(|| Self(material.clone()))
    }

    fn data(&self) -> PluginResult<&dyn spectrace::spectrum::reradiation::Reradiation> {
        self.0
            .reradiation()
            .ok_or_else(|| PluginError::unsupported("the host material lost its re-radiation"))
    }
}

fn drawn(d: Option<(f64, f64)>) -> Option<WavelengthDraw> {
    d.map(|(lambda_nm, pdf)| WavelengthDraw { lambda_nm, pdf })
}

impl Reradiation for HostReradiation {
    fn reflectance(&self, lambda_nm: f64) -> PluginResult<f64> {
        Ok(self.data()?.reflectance(lambda_nm))
    }
    fn reradiation(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> PluginResult<f64> {
        Ok(self.data()?.reradiation(lambda_i_nm, lambda_o_nm))
    }
    fn reradiated_fraction(&self, lambda_i_nm: f64) -> PluginResult<f64> {
        Ok(self.data()?.reradiated_fraction(lambda_i_nm))
    }
    fn excitation_fraction(&self, lambda_o_nm: f64) -> PluginResult<f64> {
        Ok(self.data()?.excitation_fraction(lambda_o_nm))
    }
    fn sample_emission(&self, lambda_i_nm: f64, u: f64) -> PluginResult<Option<WavelengthDraw>> {
        Ok(drawn(self.data()?.sample_emission(lambda_i_nm, u)))
    }
    fn emission_pdf(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> PluginResult<f64> {
        Ok(self.data()?.emission_pdf(lambda_i_nm, lambda_o_nm))
    }
    fn sample_excitation(&self, lambda_o_nm: f64, u: f64) -> PluginResult<Option<WavelengthDraw>> {
        Ok(drawn(self.data()?.sample_excitation(lambda_o_nm, u)))
    }
    fn excitation_pdf(&self, lambda_o_nm: f64, lambda_i_nm: f64) -> PluginResult<f64> {
        Ok(self.data()?.excitation_pdf(lambda_o_nm, lambda_i_nm))
    }
    fn range_nm(&self) -> PluginResult<(f64, f64)> {
        Ok(self.data()?.range())
    }
}

macro_rules! material_type {
    ($ty:ident, $module:ident, $params:ty, $held:ty, $build:expr) => {
        /// The host's material of the same name.
        pub struct $ty {
            params: HostParams<$params>,
            material: $held,
            reradiation: Option<HostReradiation>,
        }

        impl PluginType for $ty {
            const TYPE_NAME: &'static str = $module::TYPE.name;
            const TYPE_VERSION: u32 = $module::TYPE.version;
            const DESCRIPTION: &'static str = $module::TYPE.description;
            type Params = HostParams<$params>;

            fn params_doc() -> Vec<ParamDoc> {
                params_doc(&$module::TYPE)
            }

            fn new(params: Self::Params, _host: &Host<'_, '_>) -> PluginResult<Self> {
                let build: fn(
                    &$params,
                    &spectrace::scene::FactoryContext,
                ) -> Result<$held, FactoryError> = $build;
                let material = build(&params.0, &context(Self::TYPE_NAME)).map_err(plugin_error)?;
                let reradiation = Held::reradiation_face(&material)?;
                Ok(Self {
                    params,
                    material,
                    reradiation,
                })
            }

            fn params(&self) -> &Self::Params {
                &self.params
            }
        }

        impl Material for $ty {
            fn capabilities(&self) -> Flags {
                bits(self.material.get().flags())
            }
            // A host older than extension v2 gives no normals: the built-ins then see zero
            // normals, as they did before v2.
            fn sample(
                &self,
                ctx: &ShadingContext,
                wo: Vec3,
                lambda: &Wavelengths,
                u: &RandomSample,
                mode: TransportMode,
            ) -> PluginResult<Option<ScatterSample>> {
                self.sample_at(&SurfaceContext::from(ctx), wo, lambda, u, mode)
            }
            fn eval(
                &self,
                ctx: &ShadingContext,
                wo: Vec3,
                wi: Vec3,
                lambda: &Wavelengths,
                mode: TransportMode,
            ) -> PluginResult<SpectralValues> {
                self.eval_at(&SurfaceContext::from(ctx), wo, wi, lambda, mode)
            }
            fn pdf(
                &self,
                ctx: &ShadingContext,
                wo: Vec3,
                wi: Vec3,
                lambda: &Wavelengths,
                mode: TransportMode,
            ) -> PluginResult<f64> {
                self.pdf_at(&SurfaceContext::from(ctx), wo, wi, lambda, mode)
            }
            fn emitted(
                &self,
                ctx: &ShadingContext,
                wo: Vec3,
                lambda: &Wavelengths,
            ) -> PluginResult<SpectralValues> {
                self.emitted_at(&SurfaceContext::from(ctx), wo, lambda)
            }
            fn sample_at(
                &self,
                ctx: &SurfaceContext,
                wo: Vec3,
                lambda: &Wavelengths,
                u: &RandomSample,
                mode: TransportMode,
            ) -> PluginResult<Option<ScatterSample>> {
                Ok(sample(self.material.get(), ctx, wo, lambda, u, mode))
            }
            fn eval_at(
                &self,
                ctx: &SurfaceContext,
                wo: Vec3,
                wi: Vec3,
                lambda: &Wavelengths,
                mode: TransportMode,
            ) -> PluginResult<SpectralValues> {
                let f = self.material.get().eval(
                    va(wo),
                    va(wi),
                    &host_ctx(ctx),
                    &host_lambdas(lambda),
                    host_mode(mode),
                );
                Ok(values(f))
            }
            fn pdf_at(
                &self,
                ctx: &SurfaceContext,
                wo: Vec3,
                wi: Vec3,
                lambda: &Wavelengths,
                mode: TransportMode,
            ) -> PluginResult<f64> {
                let p = self.material.get().pdf(
                    va(wo),
                    va(wi),
                    &host_ctx(ctx),
                    &host_lambdas(lambda),
                    host_mode(mode),
                );
                Ok(p as f64)
            }
            fn emitted_at(
                &self,
                ctx: &SurfaceContext,
                wo: Vec3,
                lambda: &Wavelengths,
            ) -> PluginResult<SpectralValues> {
                let e = self
                    .material
                    .emitted(va(wo), &host_ctx(ctx), &host_lambdas(lambda));
                Ok(values(e))
            }
            fn emission(&self) -> PluginResult<Option<Emission>> {
                Ok(self.material.get().emission().map(|e| Emission {
                    spectrum: Box::new(HostSpd(e.spd)),
                    scale_w_m2_sr: e.scale as f64,
                    two_sided: e.two_sided,
                }))
            }
            fn reradiation(&self) -> Option<&dyn Reradiation> {
                self.reradiation.as_ref().map(|r| r as &dyn Reradiation)
            }
            fn spectrally_flat(&self) -> bool {
                self.material.get().spectrally_flat()
            }
            fn f_same_for_all_directions(&self) -> bool {
                self.material.get().f_same_for_all_directions()
            }
            #[inline]
            fn sample_v5(&self, q: &QueryV5<'_>) -> PluginResult<Option<ScatterF32>> {
                Ok(sample_v5(self.material.get(), q))
            }
            #[inline]
            fn eval_v5(&self, q: &QueryV5<'_>) -> PluginResult<[f32; LANES]> {
                let mut slot = None;
                let r = read(q, &mut slot);
                Ok(self
                    .material
                    .get()
                    .eval(r.wo, r.wi, r.ctx, r.lambda, r.mode)
                    .0)
            }
            #[inline]
            fn pdf_v5(&self, q: &QueryV5<'_>) -> PluginResult<f32> {
                let mut slot = None;
                let r = read(q, &mut slot);
                Ok(self.material.get().pdf(r.wo, r.wi, r.ctx, r.lambda, r.mode))
            }
            #[inline]
            fn sample_v7(&self, q: &QueryV7<'_>, out: &mut ScatterF32) -> PluginResult<bool> {
                Ok(sample_v7(self.material.get(), q, out))
            }
            #[inline]
            fn eval_v7(&self, q: &QueryV7<'_>, out: &mut [f32; LANES]) -> PluginResult<()> {
                let mut slot = None;
                let r = read_v7(q, &mut slot);
                *out = self
                    .material
                    .get()
                    .eval(r.wo, r.wi, r.ctx, r.lambda, r.mode)
                    .0;
                Ok(())
            }
            #[inline]
            fn pdf_v7(&self, q: &QueryV7<'_>) -> PluginResult<f32> {
                let mut slot = None;
                let r = read_v7(q, &mut slot);
                Ok(self.material.get().pdf(r.wo, r.wi, r.ctx, r.lambda, r.mode))
            }
            #[inline]
            fn sample_v8(
                &self,
                wo: &Vec4f,
                ctx: &SurfaceF32,
                lambda: &WavelengthsF32,
                u: [f32; 3],
                mode: TransportMode,
                out: &mut ScatterF32,
            ) -> PluginResult<bool> {
                Ok(sample_v8(
                    self.material.get(),
                    wo,
                    ctx,
                    lambda,
                    u,
                    mode,
                    out,
                ))
            }
            #[inline]
            fn eval_v8(
                &self,
                wo: &Vec4f,
                wi: &Vec4f,
                ctx: &SurfaceF32,
                lambda: &WavelengthsF32,
                mode: TransportMode,
            ) -> PluginResult<[f32; LANES]> {
                let mut slot = None;
                let lambda = wavelengths_v7(lambda, &mut slot);
                let ctx = as_shading_context(ctx);
                let (wo, wi) = (*as_vec3a(wo), *as_vec3a(wi));
                Ok(self
                    .material
                    .get()
                    .eval(wo, wi, ctx, lambda, host_mode(mode))
                    .0)
            }
            #[inline]
            fn pdf_v8(
                &self,
                wo: &Vec4f,
                wi: &Vec4f,
                ctx: &SurfaceF32,
                lambda: &WavelengthsF32,
                mode: TransportMode,
            ) -> PluginResult<f32> {
                let mut slot = None;
                let lambda = wavelengths_v7(lambda, &mut slot);
                let ctx = as_shading_context(ctx);
                let (wo, wi) = (*as_vec3a(wo), *as_vec3a(wi));
                Ok(self
                    .material
                    .get()
                    .pdf(wo, wi, ctx, lambda, host_mode(mode)))
            }
            // Extension v6: declared exactly where the built-in declares it.
            fn cosine_weighted_pdf(&self) -> bool {
                self.material.get().cosine_weighted_pdf()
            }
            #[inline]
            fn emitted_v6(&self, q: &QueryV5<'_>) -> PluginResult<[f32; LANES]> {
                let mut slot = None;
                let r = read(q, &mut slot);
                Ok(self.material.get().emitted(r.wo, r.ctx, r.lambda).0)
            }
            #[inline]
            fn sample_v4(&self, q: &MaterialQuery) -> PluginResult<Option<ScatterF32>> {
                Ok(sample_v4(self.material.get(), q))
            }
            #[inline]
            fn eval_v4(&self, q: &MaterialQuery) -> PluginResult<[f32; LANES]> {
                let f = self.material.get().eval(
                    host_v(q.wo),
                    host_v(q.wi),
                    &ctx_v4(&q.ctx),
                    &lambdas_v4(&q.lambda),
                    host_mode(q.mode),
                );
                Ok(f.0)
            }
            #[inline]
            fn pdf_v4(&self, q: &MaterialQuery) -> PluginResult<f32> {
                Ok(self.material.get().pdf(
                    host_v(q.wo),
                    host_v(q.wi),
                    &ctx_v4(&q.ctx),
                    &lambdas_v4(&q.lambda),
                    host_mode(q.mode),
                ))
            }
        }
    };
}

material_type!(
    Lambertian,
    lambertian,
    lambertian::LambertianParams,
    spectrace::material::Lambertian,
    lambertian::build_concrete
);
material_type!(
    Mirror,
    mirror,
    mirror::MirrorParams,
    spectrace::material::Mirror,
    mirror::build_concrete
);
material_type!(
    Dielectric,
    dielectric,
    dielectric::DielectricParams,
    spectrace::material::SmoothDielectric,
    dielectric::build_concrete
);
material_type!(
    RoughDielectric,
    rough_dielectric,
    rough_dielectric::RoughDielectricParams,
    spectrace::material::RoughDielectric,
    rough_dielectric::build_concrete
);
material_type!(
    Conductor,
    conductor,
    conductor::ConductorParams,
    spectrace::material::RoughConductor,
    conductor::build_concrete
);
material_type!(
    Emissive,
    emissive,
    emissive::EmissiveParams,
    Arc<dyn HostMaterial>,
    emissive::build as BuildDyn<_>
);
material_type!(
    Fluorescent,
    fluorescent,
    fluorescent::FluorescentParams,
    Arc<dyn HostMaterial>,
    fluorescent::build as BuildDyn<_>
);

#[cfg(test)]
mod tests {
    use super::*;

    // The bit-operation form agrees with the table form for every combination of the host's
    // nine bits.
    #[test]
    fn event_bits_match_bits() {
        for b in 0..512u32 {
            assert_eq!(
                event_bits(MaterialFlags(b)),
                bits(MaterialFlags(b)),
                "{b:#011b}"
            );
        }
    }
}
