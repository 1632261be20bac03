//! Materials (seed §6): turn an incoming beam into an outgoing one. Directions are in the local
//! shading frame: z is the shading normal, and both `wo` and `wi` point away from the surface.

use crate::error::{PluginError, PluginResult};
use crate::extension::{
    AbiMaterialEmittedV6, AbiMaterialV2, AbiMaterialV4, AbiMaterialV5, AbiMaterialV7,
    AbiMaterialV8, MaterialEmission, MaterialWithV2, MaterialWithV3, MaterialWithV4,
    MaterialWithV5, MaterialWithV6, MaterialWithV7, MaterialWithV8, SpdWithLines,
};
use crate::fast::{
    status, values_f32, MaterialQuery, QueryV5, QueryV7, ScatterF32, SurfaceF32, ValuesF32, Vec4f,
    WavelengthsF32,
};
use crate::guard::{guarded, guarded_call, guarded_call_v5, keep_error};
use crate::reradiation::{GuardedReradiation, Reradiation};
use crate::spd::Spd;
use crate::types::{Flags, RandomSample, SpectralValues, TransportMode, Vec3, Wavelengths, LANES};
use abi_stable::{
    sabi_trait,
    std_types::{RBox, ROption, RResult, RVec},
    StableAbi,
};
use std::sync::Arc;

/// Capability bits of a material (and of one scattering event).
pub mod material_flags {
    use crate::types::Flags;
    /// Scatters diffusely.
    pub const DIFFUSE: Flags = Flags(1);
    /// Has glossy lobes.
    pub const GLOSSY: Flags = Flags(2);
    /// Has delta lobes (mirror, smooth glass): `eval` and `pdf` are 0 for them.
    pub const SPECULAR: Flags = Flags(4);
    /// Transmits light.
    pub const TRANSMISSION: Flags = Flags(8);
    /// Scattering direction depends on wavelength: the host keeps only the hero wavelength.
    pub const DISPERSIVE: Flags = Flags(16);
    /// Emits light (`emitted` is meaningful).
    pub const EMISSIVE: Flags = Flags(32);
    /// Shifts wavelength (fluorescence): the material offers its re-radiation through
    /// [`Material::reradiation`](crate::Material::reradiation) (extension v3). A host without
    /// that data renders the reflectance only and says so.
    pub const FLUORESCENT: Flags = Flags(64);
}

/// Where on the surface a material is evaluated.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadingContext {
    /// Surface parameterisation (texture coordinates).
    pub uv: [f64; 2],
    /// World-space position (scene units), for procedural materials.
    pub position: Vec3,
}

/// Where on the surface a material is evaluated, with the surface's normals (extension v2; the
/// `*_at` calls of [`Material`]). The local frame's z axis is `shading_normal`.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceContext {
    /// Surface parameterisation (texture coordinates).
    pub uv: [f64; 2],
    /// World-space position (scene units).
    pub position: Vec3,
    /// Geometric normal, world space, unit (the true surface's, on the side the path arrived
    /// from); zero when the host does not know it.
    pub geometric_normal: Vec3,
    /// Shading normal, world space, unit (interpolated or bumped; the local frame's z axis);
    /// zero when the host does not know it.
    pub shading_normal: Vec3,
}

impl SurfaceContext {
    /// The version-1 context (no normals).
    pub fn shading(&self) -> ShadingContext {
        ShadingContext {
            uv: self.uv,
            position: self.position,
        }
    }
}

impl From<&ShadingContext> for SurfaceContext {
    /// A context with unknown (zero) normals.
    fn from(ctx: &ShadingContext) -> Self {
        Self {
            uv: ctx.uv,
            position: ctx.position,
            ..Self::default()
        }
    }
}

/// How an emissive material emits (extension v2, [`Material::emission`]): radiance
/// `scale · spectrum(λ)` W/(m²·sr·nm), the same at every point of a side and in every direction.
pub struct Emission {
    /// Normalised SPD (1/nm): what the host draws light-path wavelengths from.
    pub spectrum: Box<dyn Spd>,
    /// Integrated radiance, W/(m²·sr).
    pub scale_w_m2_sr: f64,
    /// Whether the back side emits as well.
    pub two_sided: bool,
}

/// A sampled scattering direction.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct ScatterSample {
    /// Incident direction (local frame, away from the surface).
    pub wi: Vec3,
    /// BSDF value per lane (1/sr), or for delta lobes the value that a pdf of `pdf` turns into
    /// the right weight.
    pub value: SpectralValues,
    /// Solid-angle density of `wi` (1/sr); for delta lobes the discrete lobe probability.
    pub pdf: f64,
    /// Bits of this event ([`material_flags`]): SPECULAR, TRANSMISSION, DISPERSIVE …
    pub flags: Flags,
    /// Relative index of refraction across the surface for transmission, else 1.
    pub eta: f64,
}

/// What a plugin author implements for a material.
pub trait Material: Send + Sync + 'static {
    /// Capability bits ([`material_flags`]).
    fn capabilities(&self) -> Flags;
    /// Sample `wi` given `wo` (uses `u.u[0]` to choose a lobe, `u.u[1..3]` for the direction).
    /// `Ok(None)` when the sample is absorbed.
    fn sample(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> PluginResult<Option<ScatterSample>>;
    /// BSDF value for the pair (1/sr), 0 for delta lobes.
    fn eval(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> PluginResult<SpectralValues>;
    /// Density with which `sample` would produce `wi` (1/sr).
    fn pdf(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> PluginResult<f64>;
    /// Emitted radiance towards `wo`, W/(m²·sr·nm); only for EMISSIVE materials.
    fn emitted(
        &self,
        _ctx: &ShadingContext,
        _wo: Vec3,
        _lambda: &Wavelengths,
    ) -> PluginResult<SpectralValues> {
        Ok(SpectralValues::ZERO)
    }

    // Extension v2: the same calls with the surface's normals. A host that has them calls
    // these; the defaults drop the normals and call the version-1 calls above, so a material
    // that does not read normals implements only those. One that does overrides these four and
    // may implement the version-1 calls by passing `SurfaceContext::from(ctx)` (zero normals),
    // which is what a host older than v2 would offer.

    /// [`sample`](Self::sample) with the surface's normals.
    fn sample_at(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> PluginResult<Option<ScatterSample>> {
        self.sample(&ctx.shading(), wo, lambda, u, mode)
    }
    /// [`eval`](Self::eval) with the surface's normals.
    fn eval_at(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> PluginResult<SpectralValues> {
        self.eval(&ctx.shading(), wo, wi, lambda, mode)
    }
    /// [`pdf`](Self::pdf) with the surface's normals.
    fn pdf_at(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> PluginResult<f64> {
        self.pdf(&ctx.shading(), wo, wi, lambda, mode)
    }
    /// [`emitted`](Self::emitted) with the surface's normals.
    fn emitted_at(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        lambda: &Wavelengths,
    ) -> PluginResult<SpectralValues> {
        self.emitted(&ctx.shading(), wo, lambda)
    }
    /// For EMISSIVE materials whose emission is Lambertian and uniform over the surface: that
    /// emission, exactly (extension v2). The host then builds the area light on every object
    /// using the material from it, as for its own `emissive`. `None` (the default) makes the host
    /// tabulate [`emitted`](Self::emitted) along the normal instead, at 1 nm over 360–830 nm.
    fn emission(&self) -> PluginResult<Option<Emission>> {
        Ok(None)
    }

    // Extension v3.

    /// For FLUORESCENT materials: the wavelength-shifting part (extension v3, see
    /// [`crate::reradiation`]). The host asks once, when the material is built; `Some` makes it
    /// shift wavelengths at this material, scattering diffusely in both parts (a cosine lobe:
    /// `sample`/`eval` must then be the Lambertian ρ(λ)/π with ρ =
    /// [`Reradiation::reflectance`]). `None` (the default): no re-radiation.
    fn reradiation(&self) -> Option<&dyn Reradiation> {
        None
    }

    // Extension v4.

    /// True when this material scatters the same fraction of light at every wavelength, at
    /// every point of its surface and for every pair of directions (a grey reflectance, a
    /// constant IOR), and never shifts wavelengths (extension v4). The host then gives a path
    /// whose every surface is flat the exact colour of its emitter (`flat-path-colour`), as for
    /// its own grey materials. The host asks once, when the material is built, and checks the
    /// claim at a few wavelengths and directions: a material whose answers differ between
    /// wavelengths is treated as not flat, with a warning naming it. `false` (the default) is
    /// always safe.
    fn spectrally_flat(&self) -> bool {
        false
    }
    /// True when `f(wo, wi)` is one value for every `wi` on `wo`'s side of the surface and 0 on
    /// the other (an ideal diffuse reflector), and `sample` returns exactly that value
    /// (extension v5). The host then reuses a sampled direction's value for next-event
    /// estimation at the same point instead of calling `eval` again, as for its own Lambertian.
    /// Asked once, when the material is built; the host checks the claim at a few directions
    /// and refuses a material whose answers contradict it. `false` (the default) is always safe.
    fn f_same_for_all_directions(&self) -> bool {
        false
    }
    /// True when `sample` draws `wi` with the cosine-weighted density on `wo`'s side, so that
    /// `pdf(wo, wi)` is `|cos θi|/π` for `wi` on that side and 0 on the other (an ideal diffuse
    /// reflector sampled as usual), and `sample`'s own density is that value (extension v6).
    /// The host then computes the density itself instead of calling `pdf`, as its own
    /// Lambertian costs. Asked once, when the material is built; the host checks the claim at
    /// a few directions and refuses a material whose answers contradict it. `false` (the
    /// default) is always safe.
    fn cosine_weighted_pdf(&self) -> bool {
        false
    }
    /// [`emitted_at`](Self::emitted_at) in the host's layout (extension v6), with the query
    /// of the v5 calls (`wo` and the surface; `wi` and the uniforms unused): the radiance
    /// towards `wo` per lane, W/(m²·sr·nm). The default converts the query to `f64`, calls
    /// `emitted_at` and rounds to `f32`, what the host did with the older call.
    fn emitted_v6(&self, q: &QueryV5<'_>) -> PluginResult<[f32; LANES]> {
        let v = self.emitted_at(&q.ctx.to_f64(), q.wo.to_f64(), &q.lambda.to_f64())?;
        Ok(values_f32(&v))
    }
    /// [`sample_at`](Self::sample_at) in the host's single-precision layout (extension v4; see
    /// [`crate::fast`]). The default converts the query to `f64`, calls `sample_at` and rounds
    /// the result to `f32`, exactly what the host did with the older calls; a material that
    /// computes in `f32` may override it and skip both conversions.
    fn sample_v4(&self, q: &MaterialQuery) -> PluginResult<Option<ScatterF32>> {
        let s = self.sample_at(
            &q.ctx.to_f64(),
            q.wo.to_f64(),
            &q.lambda.to_f64(),
            &q.sample_f64(),
            q.mode,
        )?;
        Ok(s.as_ref().map(ScatterF32::from_f64))
    }
    /// [`eval_at`](Self::eval_at) in the host's layout (extension v4): the BSDF value per lane,
    /// 1/sr. The default converts as [`sample_v4`](Self::sample_v4) does.
    fn eval_v4(&self, q: &MaterialQuery) -> PluginResult<[f32; LANES]> {
        let v = self.eval_at(
            &q.ctx.to_f64(),
            q.wo.to_f64(),
            q.wi.to_f64(),
            &q.lambda.to_f64(),
            q.mode,
        )?;
        Ok(values_f32(&v))
    }
    /// [`pdf_at`](Self::pdf_at) in the host's layout (extension v4), 1/sr. The default
    /// converts as [`sample_v4`](Self::sample_v4) does.
    fn pdf_v4(&self, q: &MaterialQuery) -> PluginResult<f32> {
        let p = self.pdf_at(
            &q.ctx.to_f64(),
            q.wo.to_f64(),
            q.wi.to_f64(),
            &q.lambda.to_f64(),
            q.mode,
        )?;
        Ok(p as f32)
    }
    /// [`sample_v4`](Self::sample_v4) with the surface by reference (extension v5; see
    /// [`QueryV5`]). The default copies the query into v4's form and calls `sample_v4`; a
    /// material that reads the surface in place may override it.
    fn sample_v5(&self, q: &QueryV5<'_>) -> PluginResult<Option<ScatterF32>> {
        self.sample_v4(&q.to_v4())
    }
    /// [`eval_v4`](Self::eval_v4) with the surface by reference (extension v5), as
    /// [`sample_v5`](Self::sample_v5).
    fn eval_v5(&self, q: &QueryV5<'_>) -> PluginResult<[f32; LANES]> {
        self.eval_v4(&q.to_v4())
    }
    /// [`pdf_v4`](Self::pdf_v4) with the surface by reference (extension v5), as
    /// [`sample_v5`](Self::sample_v5).
    fn pdf_v5(&self, q: &QueryV5<'_>) -> PluginResult<f32> {
        self.pdf_v4(&q.to_v4())
    }
    /// [`sample_v5`](Self::sample_v5) with the wavelengths by reference (extension v7; see
    /// [`QueryV7`]), the sample written into `out` (`Ok(false)`: absorbed, `out` untouched). The
    /// default copies the query into v5's form and calls `sample_v5`; a material that reads the
    /// wavelengths in place may override it.
    fn sample_v7(&self, q: &QueryV7<'_>, out: &mut ScatterF32) -> PluginResult<bool> {
        Ok(match self.sample_v5(&q.to_v5())? {
            Some(s) => {
                *out = s;
                true
            }
            None => false,
        })
    }
    /// [`eval_v5`](Self::eval_v5) with the wavelengths by reference (extension v7), as
    /// [`sample_v7`](Self::sample_v7): the BSDF value per lane (1/sr) written into `out`.
    fn eval_v7(&self, q: &QueryV7<'_>, out: &mut [f32; LANES]) -> PluginResult<()> {
        *out = self.eval_v5(&q.to_v5())?;
        Ok(())
    }
    /// [`pdf_v5`](Self::pdf_v5) with the wavelengths by reference (extension v7), as
    /// [`sample_v7`](Self::sample_v7).
    fn pdf_v7(&self, q: &QueryV7<'_>) -> PluginResult<f32> {
        self.pdf_v5(&q.to_v5())
    }
    /// [`sample_v7`](Self::sample_v7) with its arguments as extension v8 passes them (see
    /// [`AbiMaterialV8`]): `wo` and the records by reference (the vectors' `w` lanes
    /// unspecified), the uniforms and mode by value. The default builds v7's query (with `w`
    /// cleared) and calls `sample_v7`; a material that reads the arguments as they come may
    /// override it.
    #[allow(clippy::too_many_arguments)]
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
        let q = QueryV7 {
            ctx,
            lambda,
            wo: Vec4f::new(wo.x, wo.y, wo.z),
            wi: Vec4f::default(),
            u,
            mode,
        };
        self.sample_v7(&q, out)
    }
    /// [`eval_v7`](Self::eval_v7) with its arguments as extension v8 passes them, as
    /// [`sample_v8`](Self::sample_v8): the BSDF value per lane (1/sr).
    #[inline]
    fn eval_v8(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        ctx: &SurfaceF32,
        lambda: &WavelengthsF32,
        mode: TransportMode,
    ) -> PluginResult<[f32; LANES]> {
        let q = QueryV7 {
            ctx,
            lambda,
            wo: Vec4f::new(wo.x, wo.y, wo.z),
            wi: Vec4f::new(wi.x, wi.y, wi.z),
            u: [0.0; 3],
            mode,
        };
        let mut v = [0.0; LANES];
        self.eval_v7(&q, &mut v)?;
        Ok(v)
    }
    /// [`pdf_v7`](Self::pdf_v7) with its arguments as extension v8 passes them, as
    /// [`sample_v8`](Self::sample_v8).
    #[inline]
    fn pdf_v8(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        ctx: &SurfaceF32,
        lambda: &WavelengthsF32,
        mode: TransportMode,
    ) -> PluginResult<f32> {
        let q = QueryV7 {
            ctx,
            lambda,
            wo: Vec4f::new(wo.x, wo.y, wo.z),
            wi: Vec4f::new(wi.x, wi.y, wi.z),
            u: [0.0; 3],
            mode,
        };
        self.pdf_v7(&q)
    }
}

/// The stable-ABI face of a material.
#[sabi_trait]
pub trait AbiMaterial: Send + Sync {
    /// See [`Material::capabilities`].
    fn capabilities(&self) -> Flags;
    /// See [`Material::sample`].
    fn sample(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> RResult<abi_stable::std_types::ROption<ScatterSample>, PluginError>;
    /// See [`Material::eval`].
    fn eval(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<SpectralValues, PluginError>;
    /// See [`Material::pdf`].
    fn pdf(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<f64, PluginError>;
    /// See [`Material::emitted`].
    fn emitted(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
    ) -> RResult<SpectralValues, PluginError>;
    /// The object's state as bytes, for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// A material behind the stable ABI, owned.
pub type MaterialBox = AbiMaterial_TO<'static, RBox<()>>;

/// Wraps an author's material so panics come back as errors.
pub struct GuardedMaterial<T> {
    inner: Arc<T>,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

impl<T: Material> GuardedMaterial<T> {
    /// Box `inner` behind the ABI.
    pub fn boxed(inner: T, state: fn(&T) -> PluginResult<Vec<u8>>) -> MaterialBox {
        AbiMaterial_TO::from_value(
            Self {
                inner: Arc::new(inner),
                state,
            },
            abi_stable::sabi_trait::TD_Opaque,
        )
    }

    /// Box `inner` behind the ABI with its version-2 face (extension v2), one object behind both.
    pub fn boxed_v2(inner: T, state: fn(&T) -> PluginResult<Vec<u8>>) -> MaterialWithV2 {
        let inner = Arc::new(inner);
        MaterialWithV2 {
            material: AbiMaterial_TO::from_value(
                Self {
                    inner: inner.clone(),
                    state,
                },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            v2: crate::extension::AbiMaterialV2_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
        }
    }
}

impl<T: Material> GuardedMaterial<T> {
    /// Box `inner` behind the ABI with its version-2 face and, when it offers one, its
    /// re-radiation face (extension v3); one object behind all three.
    pub fn boxed_v3(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialWithV3, PluginError> {
        Self::faces_v3(Arc::new(inner), state)
    }

    /// The faces of versions 1–3 of the shared object `inner`.
    fn faces_v3(
        inner: Arc<T>,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialWithV3, PluginError> {
        let reradiation = match GuardedReradiation::boxed(inner.clone()) {
            RResult::ROk(r) => r,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(MaterialWithV3 {
            material: AbiMaterial_TO::from_value(
                Self {
                    inner: inner.clone(),
                    state,
                },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            v2: crate::extension::AbiMaterialV2_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            reradiation,
        })
    }
}

impl<T: Material> GuardedMaterial<T> {
    /// Box `inner` behind the ABI with every face (versions 2–4) and its declaration (extension
    /// v4); one object behind all of them.
    pub fn boxed_v4(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialWithV4, PluginError> {
        crate::guard::install();
        let spectrally_flat = match guarded("spectrally_flat", || Ok(inner.spectrally_flat())) {
            RResult::ROk(f) => f,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let inner = Arc::new(inner);
        let v3 = match Self::faces_v3(inner.clone(), state) {
            RResult::ROk(m) => m,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(MaterialWithV4 {
            material: v3.material,
            v2: v3.v2,
            reradiation: v3.reradiation,
            v4: crate::extension::AbiMaterialV4_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            spectrally_flat,
        })
    }
}

impl<T: Material> GuardedMaterial<T> {
    /// Box `inner` behind the ABI with every face (versions 2–5) and its declarations
    /// (extensions v4 and v5); one object behind all of them.
    pub fn boxed_v5(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialWithV5, PluginError> {
        crate::guard::install();
        let declared = guarded("spectrally_flat", || {
            Ok((inner.spectrally_flat(), inner.f_same_for_all_directions()))
        });
        let (spectrally_flat, f_same_for_all_directions) = match declared {
            RResult::ROk(d) => d,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let inner = Arc::new(inner);
        let v3 = match Self::faces_v3(inner.clone(), state) {
            RResult::ROk(m) => m,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(MaterialWithV5 {
            material: v3.material,
            v2: v3.v2,
            reradiation: v3.reradiation,
            v5: crate::extension::AbiMaterialV5_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            spectrally_flat,
            f_same_for_all_directions,
        })
    }
}

impl<T: Material> GuardedMaterial<T> {
    /// Box `inner` behind the ABI with every face (versions 2, 3, 5 and 6) and its
    /// declarations (extensions v4 to v6); one object behind all of them.
    pub fn boxed_v6(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialWithV6, PluginError> {
        Self::faces_v6(Arc::new(inner), state)
    }

    /// The faces and declarations of [`Self::boxed_v6`] on a shared object.
    fn faces_v6(
        inner: Arc<T>,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialWithV6, PluginError> {
        crate::guard::install();
        let declared = guarded("spectrally_flat", || {
            Ok((
                inner.spectrally_flat(),
                inner.f_same_for_all_directions(),
                inner.cosine_weighted_pdf(),
            ))
        });
        let (spectrally_flat, f_same_for_all_directions, cosine_weighted_pdf) = match declared {
            RResult::ROk(d) => d,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let v3 = match Self::faces_v3(inner.clone(), state) {
            RResult::ROk(m) => m,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(MaterialWithV6 {
            material: v3.material,
            v2: v3.v2,
            reradiation: v3.reradiation,
            v5: crate::extension::AbiMaterialV5_TO::from_value(
                Self {
                    inner: inner.clone(),
                    state,
                },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            emitted: crate::extension::AbiMaterialEmittedV6_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            spectrally_flat,
            f_same_for_all_directions,
            cosine_weighted_pdf,
        })
    }

    /// Box `inner` behind the ABI with every face (versions 2, 3, 5, 6 and 7) and its
    /// declarations (extensions v4 to v6); one object behind all of them.
    pub fn boxed_v7(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialWithV7, PluginError> {
        let inner = Arc::new(inner);
        let with_v6 = match Self::faces_v6(inner.clone(), state) {
            RResult::ROk(m) => m,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(MaterialWithV7 {
            with_v6,
            v7: crate::extension::AbiMaterialV7_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
        })
    }
}

impl<T: Material> GuardedMaterial<T> {
    /// Box `inner` behind the ABI with every face (versions 2, 3, 5, 6, 7 and 8) and its
    /// declarations (extensions v4 to v6); one object behind all of them.
    pub fn boxed_v8(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialWithV8, PluginError> {
        let inner = Arc::new(inner);
        let with_v6 = match Self::faces_v6(inner.clone(), state) {
            RResult::ROk(m) => m,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(MaterialWithV8 {
            with_v7: MaterialWithV7 {
                with_v6,
                v7: crate::extension::AbiMaterialV7_TO::from_value(
                    Self {
                        inner: inner.clone(),
                        state,
                    },
                    abi_stable::sabi_trait::TD_Opaque,
                ),
            },
            v8: crate::extension::AbiMaterialV8_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
        })
    }
}

/// A v8 call's answer: its value, or `failed` with the error kept for the host
/// ([`keep_error`]).
#[inline]
fn kept_or<T>(r: Result<T, PluginError>, failed: T) -> T {
    match r {
        Ok(v) => v,
        Err(e) => {
            keep_error(e);
            failed
        }
    }
}

impl<T: Material> AbiMaterialV8 for GuardedMaterial<T> {
    #[inline]
    fn sample(
        &self,
        wo: &Vec4f,
        ctx: &SurfaceF32,
        lambda: &WavelengthsF32,
        u_lobe: f32,
        u1: f32,
        u2: f32,
        mode: TransportMode,
        out: &mut ScatterF32,
    ) -> u32 {
        let r = guarded_call_v5("sample (v8)", || {
            let written = (self.inner).sample_v8(wo, ctx, lambda, [u_lobe, u1, u2], mode, out)?;
            Ok(if written {
                status::WRITTEN
            } else {
                status::NONE
            })
        });
        kept_or(r, status::ERROR)
    }
    #[inline]
    fn eval(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        ctx: &SurfaceF32,
        lambda: &WavelengthsF32,
        mode: TransportMode,
    ) -> ValuesF32 {
        // The values written into the answer from inside the guard, which then returns only
        // the error: a `Result<[f32; 4], PluginError>` was assembled byte by byte.
        let mut v = ValuesF32::FAILED;
        let r = guarded_call_v5("eval (v8)", || {
            v.v = self.inner.eval_v8(wo, wi, ctx, lambda, mode)?;
            Ok(())
        });
        match r {
            Ok(()) => v,
            Err(e) => {
                keep_error(e);
                ValuesF32::FAILED
            }
        }
    }
    #[inline]
    fn pdf(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        ctx: &SurfaceF32,
        lambda: &WavelengthsF32,
        mode: TransportMode,
    ) -> f32 {
        // As `eval`: the density written from inside the guard, only the error returned.
        let mut p = f32::NAN;
        let r = guarded_call_v5("pdf (v8)", || {
            p = self.inner.pdf_v8(wo, wi, ctx, lambda, mode)?;
            Ok(())
        });
        match r {
            Ok(()) => p,
            Err(e) => {
                keep_error(e);
                f32::NAN
            }
        }
    }
}

/// A v7 call's answer as its status word, the error written through `err`.
#[inline]
fn status_of(r: Result<u32, PluginError>, err: &mut ROption<PluginError>) -> u32 {
    match r {
        Ok(s) => s,
        Err(e) => {
            *err = ROption::RSome(e);
            status::ERROR
        }
    }
}

impl<T: Material> AbiMaterialV7 for GuardedMaterial<T> {
    #[inline]
    fn sample(&self, q: &QueryV7<'_>, out: &mut ScatterF32, err: &mut ROption<PluginError>) -> u32 {
        let r = guarded_call_v5("sample (v7)", || {
            Ok(if self.inner.sample_v7(q, out)? {
                status::WRITTEN
            } else {
                status::NONE
            })
        });
        status_of(r, err)
    }
    #[inline]
    fn eval(&self, q: &QueryV7<'_>, out: &mut [f32; LANES], err: &mut ROption<PluginError>) -> u32 {
        let r = guarded_call_v5("eval (v7)", || {
            self.inner.eval_v7(q, out)?;
            Ok(status::WRITTEN)
        });
        status_of(r, err)
    }
    #[inline]
    fn pdf(&self, q: &QueryV7<'_>, out: &mut f32, err: &mut ROption<PluginError>) -> u32 {
        let r = guarded_call_v5("pdf (v7)", || {
            *out = self.inner.pdf_v7(q)?;
            Ok(status::WRITTEN)
        });
        status_of(r, err)
    }
}

impl<T: Material> AbiMaterialEmittedV6 for GuardedMaterial<T> {
    #[inline]
    fn emitted(&self, q: &QueryV5<'_>, out: &mut [f32; LANES]) -> RResult<(), PluginError> {
        guarded_call_v5("emitted (v6)", || {
            *out = self.inner.emitted_v6(q)?;
            Ok(())
        })
        .into()
    }
}

impl<T: Material> AbiMaterialV5 for GuardedMaterial<T> {
    #[inline]
    fn sample(&self, q: &QueryV5<'_>, out: &mut ScatterF32) -> RResult<bool, PluginError> {
        guarded_call_v5("sample (v5)", || {
            Ok(match self.inner.sample_v5(q)? {
                Some(s) => {
                    *out = s;
                    true
                }
                None => false,
            })
        })
        .into()
    }
    #[inline]
    fn eval(&self, q: &QueryV5<'_>, out: &mut [f32; LANES]) -> RResult<(), PluginError> {
        guarded_call_v5("eval (v5)", || {
            *out = self.inner.eval_v5(q)?;
            Ok(())
        })
        .into()
    }
    #[inline]
    fn pdf(&self, q: &QueryV5<'_>, out: &mut f32) -> RResult<(), PluginError> {
        guarded_call_v5("pdf (v5)", || {
            *out = self.inner.pdf_v5(q)?;
            Ok(())
        })
        .into()
    }
}

impl<T: Material> AbiMaterialV4 for GuardedMaterial<T> {
    #[inline]
    fn sample(&self, q: &MaterialQuery) -> RResult<ROption<ScatterF32>, PluginError> {
        guarded_call("sample (v4)", || self.inner.sample_v4(q).map(Into::into))
    }
    #[inline]
    fn eval(&self, q: &MaterialQuery) -> RResult<[f32; LANES], PluginError> {
        guarded_call("eval (v4)", || self.inner.eval_v4(q))
    }
    #[inline]
    fn pdf(&self, q: &MaterialQuery) -> RResult<f32, PluginError> {
        guarded_call("pdf (v4)", || self.inner.pdf_v4(q))
    }
}

/// Saved state of an object that is part of another (an emission spectrum): there is none.
fn no_state<T>(_: &T) -> PluginResult<Vec<u8>> {
    Err(PluginError::unsupported(
        "save_state of an emission spectrum",
    ))
}

impl<T: Material> AbiMaterialV2 for GuardedMaterial<T> {
    fn sample(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> RResult<ROption<ScatterSample>, PluginError> {
        guarded("sample_at", || {
            self.inner
                .sample_at(ctx, wo, lambda, u, mode)
                .map(Into::into)
        })
    }
    fn eval(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<SpectralValues, PluginError> {
        guarded("eval_at", || self.inner.eval_at(ctx, wo, wi, lambda, mode))
    }
    fn pdf(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<f64, PluginError> {
        guarded("pdf_at", || self.inner.pdf_at(ctx, wo, wi, lambda, mode))
    }
    fn emitted(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        lambda: &Wavelengths,
    ) -> RResult<SpectralValues, PluginError> {
        guarded("emitted_at", || self.inner.emitted_at(ctx, wo, lambda))
    }
    fn emission(&self) -> RResult<ROption<MaterialEmission>, PluginError> {
        let e = match guarded("emission", || self.inner.emission()) {
            RResult::ROk(e) => e,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let Some(e) = e else {
            return RResult::ROk(ROption::RNone);
        };
        SpdWithLines::new(e.spectrum, no_state).map(|spectrum| {
            ROption::RSome(MaterialEmission {
                spectrum,
                scale: e.scale_w_m2_sr,
                two_sided: e.two_sided,
            })
        })
    }
}

impl<T: Material> AbiMaterial for GuardedMaterial<T> {
    fn capabilities(&self) -> Flags {
        guarded("capabilities", || Ok(self.inner.capabilities())).unwrap_or(Flags::NONE)
    }
    fn sample(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> RResult<abi_stable::std_types::ROption<ScatterSample>, PluginError> {
        guarded("sample", || {
            self.inner.sample(ctx, wo, lambda, u, mode).map(Into::into)
        })
    }
    fn eval(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<SpectralValues, PluginError> {
        guarded("eval", || self.inner.eval(ctx, wo, wi, lambda, mode))
    }
    fn pdf(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<f64, PluginError> {
        guarded("pdf", || self.inner.pdf(ctx, wo, wi, lambda, mode))
    }
    fn emitted(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
    ) -> RResult<SpectralValues, PluginError> {
        guarded("emitted", || self.inner.emitted(ctx, wo, lambda))
    }
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}
