//! The built-in materials (`host/src/builtin/material/`): `lambertian`, `mirror`, `dielectric`,
//! `rough_dielectric`, `conductor`, `plastic`, `rough_plastic`, `emissive`, `fluorescent`, same
//! parameters, each built by the
//! host's own constructor and called through the plugin interface (no physics here, only
//! passing the host's records through).
//!
//! The interface's per-sample calls carry the host's own records by reference (the surface, the
//! wavelengths with their densities and live lanes) and the sample is written into the host's
//! record in place (`spectrace::plugin::layout`): nothing is converted. An emissive material
//! hands over its emission exactly (its own SPD and scale), so the host builds the same area
//! light as for the built-in; a fluorescent material hands over its re-radiation, so the host
//! shifts wavelengths with the very numbers of the built-in. Each declares exactly what the
//! built-in declares (spectrally flat, one value for every direction, the cosine density);
//! `plastic` and `rough_plastic`, which only reflect, also declare RECIPROCAL (f(ωo, ωi) =
//! f(ωi, ωo)), which the conformance kit checks.
//!
//! Held as the host's concrete types where the host's constructor gives one (`build_concrete`:
//! all but `emissive` and `fluorescent`), so that the interface's call reaches the host's code
//! with a direct call (docs/performance.md, "The standard library calling the host's types
//! directly").

use crate::wrap::{context, params_doc, plugin_error, HostParams, HostSpd};
use glam::{Vec2, Vec3A};
use spectrace::builtin::material::{
    conductor, dielectric, emissive, fluorescent, lambertian, mirror, plastic, rough_dielectric,
    rough_plastic,
};
use spectrace::material::{
    BsdfSample, Material as HostMaterial, MaterialFlags, TransportMode as HostMode,
};
use spectrace::plugin::layout::{
    as_bsdf_sample_mut, as_host_wavelengths, as_shading_context, as_vec3a,
};
use spectrace::scene::FactoryError;
use spectrace::spectrum::{SampledWavelengths, LANES};
use spectrace_plugin_api::{
    material_flags, Emission, Flags, Host, Material, ParamDoc, PluginError, PluginResult,
    PluginType, Reradiation, Scatter, Surface, TransportMode, Vec3, Vec4f, WavelengthDraw,
    Wavelengths,
};
use std::sync::Arc;

/// Host vector (f32) from an interface vector (f64).
pub(crate) fn va(v: Vec3) -> Vec3A {
    Vec3A::new(v.x as f32, v.y as f32, v.z as f32)
}

fn host_mode(m: TransportMode) -> HostMode {
    match m {
        TransportMode::Radiance => HostMode::Radiance,
        TransportMode::Importance => HostMode::Importance,
    }
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

/// The host's vector from an interface vector (the same four lanes).
#[inline]
pub(crate) fn host_v(v: Vec4f) -> Vec3A {
    Vec3A::from_vec4(glam::Vec4::new(v.x, v.y, v.z, v.w))
}

/// The host's wavelengths exactly as the host passed them (densities and live lanes included),
/// a copy.
#[inline]
fn lambdas_copy(l: &Wavelengths) -> SampledWavelengths {
    SampledWavelengths {
        lambda: l.nm,
        pdf: l.pdf,
        lanes: spectrace::spectrum::LaneMask::from_bits(l.live & 0b1111),
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

/// The host's wavelengths: its own record in place (the same memory) when `live` holds only
/// lane bits, as every host's does; else a copy in `slot`.
#[inline]
pub(crate) fn wavelengths<'a>(
    l: &'a Wavelengths,
    slot: &'a mut Option<SampledWavelengths>,
) -> &'a SampledWavelengths {
    match as_host_wavelengths(l) {
        Some(w) => w,
        None => slot.insert(lambdas_copy(l)),
    }
}

/// What every call with the surface by reference (extensions v5 and v6) reads from its query:
/// the directions, the host's own surface record and wavelengths in place
/// (`spectrace::plugin::layout`; the wavelengths copied into `slot` only where they cannot be
/// read in place) and the transport mode.
/// `sample` through the host material `m`: its sample written straight into the host's record
/// `out` (the same layout), its event bits translated.
#[inline]
fn sample_into<M: HostMaterial + ?Sized>(
    m: &M,
    wo: &Vec4f,
    ctx: &Surface,
    lambda: &Wavelengths,
    u: [f32; 3],
    mode: TransportMode,
    out: &mut Scatter,
) -> bool {
    let mut slot = None;
    let lambda = wavelengths(lambda, &mut slot);
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

/// How a type holds its host material: as the concrete type or behind an `Arc`.
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
    spectrace::material::RoughConductor,
    spectrace::material::Plastic
);

/// The host's constructor of a material held behind `Arc<dyn Material>`.
type BuildDyn<P> =
    fn(&P, &spectrace::scene::FactoryContext) -> Result<Arc<dyn HostMaterial>, FactoryError>;

/// Sample through the host material `m`.
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
        material_type!($ty, $module, $params, $held, $build, Flags::NONE);
    };
    // `$extra`: interface flags declared besides the host material's (RECIPROCAL).
    ($ty:ident, $module:ident, $params:ty, $held:ty, $build:expr, $extra:expr) => {
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
            fn flags(&self) -> Flags {
                // Declared exactly where the built-in declares it.
                let m = self.material.get();
                let mut f = bits(m.flags()) | $extra;
                if m.spectrally_flat() {
                    f = f | material_flags::SPECTRALLY_FLAT;
                }
                if m.f_same_for_all_directions() {
                    f = f | material_flags::SAME_VALUE_ALL_DIRECTIONS;
                }
                if m.cosine_weighted_pdf() {
                    f = f | material_flags::COSINE_PDF;
                }
                f
            }
            #[inline]
            fn sample(
                &self,
                wo: &Vec4f,
                surface: &Surface,
                lambda: &Wavelengths,
                u: [f32; 3],
                mode: TransportMode,
                out: &mut Scatter,
            ) -> PluginResult<bool> {
                Ok(sample_into(
                    self.material.get(),
                    wo,
                    surface,
                    lambda,
                    u,
                    mode,
                    out,
                ))
            }
            #[inline]
            fn eval(
                &self,
                wo: &Vec4f,
                wi: &Vec4f,
                surface: &Surface,
                lambda: &Wavelengths,
                mode: TransportMode,
            ) -> PluginResult<[f32; LANES]> {
                let mut slot = None;
                let lambda = wavelengths(lambda, &mut slot);
                let ctx = as_shading_context(surface);
                let (wo, wi) = (*as_vec3a(wo), *as_vec3a(wi));
                Ok(self
                    .material
                    .get()
                    .eval(wo, wi, ctx, lambda, host_mode(mode))
                    .0)
            }
            #[inline]
            fn pdf(
                &self,
                wo: &Vec4f,
                wi: &Vec4f,
                surface: &Surface,
                lambda: &Wavelengths,
                mode: TransportMode,
            ) -> PluginResult<f32> {
                let mut slot = None;
                let lambda = wavelengths(lambda, &mut slot);
                let ctx = as_shading_context(surface);
                let (wo, wi) = (*as_vec3a(wo), *as_vec3a(wi));
                Ok(self
                    .material
                    .get()
                    .pdf(wo, wi, ctx, lambda, host_mode(mode)))
            }
            fn emitted(
                &self,
                wo: &Vec4f,
                surface: &Surface,
                lambda: &Wavelengths,
            ) -> PluginResult<[f32; LANES]> {
                let mut slot = None;
                let lambda = wavelengths(lambda, &mut slot);
                let ctx = as_shading_context(surface);
                Ok(self.material.get().emitted(*as_vec3a(wo), ctx, lambda).0)
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
    Plastic,
    plastic,
    plastic::PlasticParams,
    spectrace::material::Plastic,
    plastic::build_concrete,
    material_flags::RECIPROCAL
);
material_type!(
    RoughPlastic,
    rough_plastic,
    rough_plastic::RoughPlasticParams,
    spectrace::material::Plastic,
    rough_plastic::build_concrete,
    material_flags::RECIPROCAL
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
