//! The plain data of extension v4's material calls ([`AbiMaterialV4`](crate::extension::AbiMaterialV4)):
//! the host's own single-precision layout, passed by reference, so neither side converts.
//!
//! The calls of the root module and of v2 carry `f64` [`Vec3`](crate::Vec3)s and
//! [`Wavelengths`](crate::Wavelengths) by value. The host renders in `f32` with 16-byte SIMD
//! vectors, so every call used to convert its arguments to `f64` and the results back, on both
//! sides of the boundary (measured in `docs/performance.md`, "Plugin overhead"). These types are
//! laid out as the host keeps the same data: a [`Vec4f`] is the host's 16-byte vector (`x, y, z`
//! and one unused lane), and a call takes one [`MaterialQuery`] by reference. A material that
//! computes in `f64` gets the query converted by the provided methods of
//! [`Material`](crate::Material) (`sample_v4`, `eval_v4`, `pdf_v4`), exactly as the older calls
//! converted it (f32 → f64 is exact, and the results come back rounded to f32 as before).
//!
//! | type | fields | units |
//! |---|---|---|
//! | [`Vec4f`] | `x, y, z` (`w` unused, 0) | scene units or unit direction |
//! | [`SurfaceF32`] | texture coordinates, position, geometric and shading normal (world) | scene units; normals unit or zero when unknown |
//! | [`LanesF32`] | wavelengths, their sampling densities, live-lane bits | nm, 1/nm |
//! | [`MaterialQuery`] | the surface, `wo`, `wi` (local frame), wavelengths, 3 uniforms, transport mode | |
//! | [`ScatterF32`] | sampled `wi`, BSDF value per lane, density, event bits, relative IOR | 1/sr, 1/sr |
//! | [`QueryV5`] | as [`MaterialQuery`], the surface by reference (extension v5) | |
//! | [`ReceiverF32`] | the point a light is sampled from: position, its error bound, geometric normal (extension v6) | scene units |
//! | [`IncidentF32`] | radiance per lane, unit direction to the light, density, point on the light, its error bound, light normal (extension v6) | W/(m²·sr·nm), 1/sr, scene units |
//! | [`EmissionF32`] | origin, unit direction, emitted value per lane, densities of origin and direction, normal (extension v6) | scene units, W/(sr·nm) or W/(m²·sr·nm), 1/m², 1/sr |
//! | [`WavelengthsF32`] | wavelengths, densities, live-lane bits in one byte: the host's own record (extension v7) | nm, 1/nm |
//! | [`QueryV7`] | as [`QueryV5`], the wavelengths by reference too (extension v7) | |
//! | [`ValuesF32`] | a value per lane, returned by value (extension v8's `eval`) | 1/sr |

use crate::material::{ScatterSample, SurfaceContext};
use crate::types::{Flags, RandomSample, SpectralValues, TransportMode, Vec3, Wavelengths, LANES};
use abi_stable::StableAbi;

/// A 3-vector in the host's 16-byte SIMD layout: `x, y, z` and an unused `w` (0).
#[repr(C, align(16))]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec4f {
    /// x
    pub x: f32,
    /// y
    pub y: f32,
    /// z
    pub z: f32,
    /// Unused (0); there for the layout.
    pub w: f32,
}

impl Vec4f {
    /// Build from components (`w` = 0).
    #[inline]
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Self { x, y, z, w: 0.0 }
    }
    /// As an `f64` vector (exact).
    #[inline]
    pub fn to_f64(self) -> Vec3 {
        Vec3::new(self.x as f64, self.y as f64, self.z as f64)
    }
    /// From an `f64` vector, rounded to `f32`.
    #[inline]
    pub fn from_f64(v: Vec3) -> Self {
        Self::new(v.x as f32, v.y as f32, v.z as f32)
    }
}

/// Where on the surface a material is evaluated (the `f32` form of [`SurfaceContext`]).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceF32 {
    /// Texture coordinates.
    pub uv: [f32; 2],
    /// World-space position (scene units).
    pub position: Vec4f,
    /// Geometric normal, world space, unit (zero when unknown).
    pub geometric_normal: Vec4f,
    /// Shading normal, world space, unit: the local frame's z axis (zero when unknown).
    pub shading_normal: Vec4f,
}

impl SurfaceF32 {
    /// As the `f64` [`SurfaceContext`] (exact).
    #[inline]
    pub fn to_f64(&self) -> SurfaceContext {
        SurfaceContext {
            uv: [self.uv[0] as f64, self.uv[1] as f64],
            position: self.position.to_f64(),
            geometric_normal: self.geometric_normal.to_f64(),
            shading_normal: self.shading_normal.to_f64(),
        }
    }
}

/// The wavelengths of one path: nm per lane (lane 0 the hero), each lane's sampling density
/// (1/nm; 0 for a terminated lane or one on a spectral line) and which lanes still carry light
/// (bit i = lane i).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct LanesF32 {
    /// Wavelengths, nm.
    pub nm: [f32; LANES],
    /// Sampling densities, 1/nm.
    pub pdf: [f32; LANES],
    /// Live lanes, one bit per lane.
    pub live: u32,
}

impl LanesF32 {
    /// As the `f64` [`Wavelengths`] of the older calls (exact; densities and live bits dropped,
    /// as those calls never carried them).
    #[inline]
    pub fn to_f64(&self) -> Wavelengths {
        Wavelengths {
            nm: self.nm.map(f64::from),
        }
    }
}

/// Everything one material call (sample, eval or pdf) takes, passed by reference.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq)]
pub struct MaterialQuery {
    /// The surface point.
    pub ctx: SurfaceF32,
    /// Outgoing direction, local frame, away from the surface.
    pub wo: Vec4f,
    /// Incident direction, local frame (eval and pdf; unused by sample).
    pub wi: Vec4f,
    /// The path's wavelengths.
    pub lambda: LanesF32,
    /// Uniforms in [0, 1) for sample: `u[0]` chooses a lobe, `u[1..3]` the direction (as
    /// [`RandomSample::u`]`[0..3]` of the older call).
    pub u: [f32; 3],
    /// Radiance (camera paths) or importance (light paths).
    pub mode: TransportMode,
}

impl MaterialQuery {
    /// The uniforms as the older calls' [`RandomSample`] (exact; the unused entries 0).
    #[inline]
    pub fn sample_f64(&self) -> RandomSample {
        let mut s = RandomSample::default();
        s.u[0] = self.u[0] as f64;
        s.u[1] = self.u[1] as f64;
        s.u[2] = self.u[2] as f64;
        s
    }
}

/// Everything one material call of extension v5 takes: [`MaterialQuery`] with the surface passed
/// by reference, pointing at the host's own record of the surface point (the same layout), so
/// that nothing is copied for it. The surface's vectors' `w` lanes are whatever the host's
/// memory holds there: read `x, y, z` only. [`Self::to_v4`] gives the v4 query.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq)]
pub struct QueryV5<'a> {
    /// The surface point (its vectors' `w` unspecified).
    pub ctx: &'a SurfaceF32,
    /// Outgoing direction, local frame, away from the surface (`w` = 0).
    pub wo: Vec4f,
    /// Incident direction, local frame (eval and pdf; unused by sample; `w` = 0).
    pub wi: Vec4f,
    /// The path's wavelengths.
    pub lambda: LanesF32,
    /// Uniforms in [0, 1) for sample, as [`MaterialQuery::u`].
    pub u: [f32; 3],
    /// Radiance (camera paths) or importance (light paths).
    pub mode: TransportMode,
}

impl QueryV5<'_> {
    /// The same query in v4's form (the surface copied, its `w` lanes set to 0).
    #[inline]
    pub fn to_v4(&self) -> MaterialQuery {
        let v = |v: Vec4f| Vec4f::new(v.x, v.y, v.z);
        MaterialQuery {
            ctx: SurfaceF32 {
                uv: self.ctx.uv,
                position: v(self.ctx.position),
                geometric_normal: v(self.ctx.geometric_normal),
                shading_normal: v(self.ctx.shading_normal),
            },
            wo: self.wo,
            wi: self.wi,
            lambda: self.lambda,
            u: self.u,
            mode: self.mode,
        }
    }
}

/// A sampled scattering direction (the `f32` form of [`ScatterSample`]).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct ScatterF32 {
    /// Incident direction (local frame, away from the surface), unit.
    pub wi: Vec4f,
    /// BSDF value per lane (1/sr); for delta lobes as in [`ScatterSample::value`].
    pub value: [f32; LANES],
    /// Solid-angle density of `wi` (1/sr); for delta lobes the discrete lobe probability.
    pub pdf: f32,
    /// Bits of this event ([`material_flags`](crate::material_flags)).
    pub flags: Flags,
    /// Relative index of refraction across the surface for transmission, else 1.
    pub eta: f32,
}

impl ScatterF32 {
    /// From the `f64` sample of the older calls, rounded to `f32` (what the host did before).
    #[inline]
    pub fn from_f64(s: &ScatterSample) -> Self {
        Self {
            wi: Vec4f::from_f64(s.wi),
            value: values_f32(&s.value),
            pdf: s.pdf as f32,
            flags: s.flags,
            eta: s.eta as f32,
        }
    }
}

/// Spectral values rounded to `f32`.
#[inline]
pub fn values_f32(v: &SpectralValues) -> [f32; LANES] {
    v.v.map(|x| x as f32)
}

/// The point a light is sampled from (extension v6): the `f32` form of the receiver of
/// [`LightSource::sample_toward`](crate::LightSource::sample_toward), laid out as the host's own
/// record of it and passed by reference. Vectors' `w` lanes are unspecified: read `x, y, z` only.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct ReceiverF32 {
    /// The point being lit (world, scene units).
    pub p: Vec4f,
    /// Its floating-point error bound per axis (scene units; 0 when unknown).
    pub p_error: Vec4f,
    /// Its geometric normal (world, unit; zero for points in media).
    pub n: Vec4f,
}

/// A point on a light chosen as seen from a receiver (extension v6): the `f32` form of
/// [`IncidentSample`](crate::IncidentSample), laid out as the host's own record, which the call
/// writes in place. No distance: the host measures it from the two points.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct IncidentF32 {
    /// Radiance arriving at the receiver per lane, W/(m²·sr·nm) (for delta lights `I/d²`).
    pub value: [f32; LANES],
    /// Unit direction from the receiver towards the light.
    pub direction: Vec4f,
    /// Solid-angle density of `direction` (1/sr), or 1 for delta lights; 0: no sample.
    pub pdf: f32,
    /// The point on the light (scene units).
    pub point: Vec4f,
    /// Its floating-point error bound per axis (0 when exact).
    pub point_error: Vec4f,
    /// Light surface normal at `point`; zero when the light has no surface.
    pub normal: Vec4f,
}

impl IncidentF32 {
    /// From the `f64` sample of the older calls, rounded to `f32` (what the host did with them).
    #[inline]
    pub fn from_f64(s: &crate::IncidentSample) -> Self {
        Self {
            value: values_f32(&s.value),
            direction: Vec4f::from_f64(s.direction),
            pdf: s.pdf as f32,
            point: Vec4f::from_f64(s.point),
            point_error: Vec4f::default(),
            normal: Vec4f::from_f64(s.normal),
        }
    }
}

/// A ray leaving a light (extension v6): the `f32` form of
/// [`EmissionSample`](crate::EmissionSample).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct EmissionF32 {
    /// Start point (scene units).
    pub origin: Vec4f,
    /// Unit direction of travel.
    pub direction: Vec4f,
    /// Emitted value per lane: intensity W/(sr·nm) for point-like sources, radiance
    /// W/(m²·sr·nm) for surfaces.
    pub value: [f32; LANES],
    /// Density of `origin`: per area (1/m²), or 1 for a delta position; 0: no sample.
    pub pdf_position: f32,
    /// Density of `direction`: per solid angle (1/sr), or 1 for a delta direction; 0: no sample.
    pub pdf_direction: f32,
    /// Surface normal at `origin`; zero for lights without a surface.
    pub normal: Vec4f,
}

impl EmissionF32 {
    /// From the `f64` sample of the older calls, rounded to `f32`.
    #[inline]
    pub fn from_f64(s: &crate::EmissionSample) -> Self {
        Self {
            origin: Vec4f::from_f64(s.origin),
            direction: Vec4f::from_f64(s.direction),
            value: values_f32(&s.value),
            pdf_position: s.pdf_position as f32,
            pdf_direction: s.pdf_direction as f32,
            normal: Vec4f::from_f64(s.normal),
        }
    }
}

/// The wavelengths of one path as extension v7 passes them: by reference, in the host's own
/// record (no copy). As [`LanesF32`] with the live-lane bits in one byte (bit i = lane i; the
/// three bytes after it are padding, not to be read).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct WavelengthsF32 {
    /// Wavelengths, nm.
    pub nm: [f32; LANES],
    /// Sampling densities, 1/nm.
    pub pdf: [f32; LANES],
    /// Live lanes, one bit per lane.
    pub live: u8,
}

impl WavelengthsF32 {
    /// As v4's and v5's [`LanesF32`] (a copy).
    #[inline]
    pub fn to_lanes(&self) -> LanesF32 {
        LanesF32 {
            nm: self.nm,
            pdf: self.pdf,
            live: u32::from(self.live),
        }
    }
}

/// Everything one material call of extension v7 takes: [`QueryV5`] with the wavelengths by
/// reference too (the host's own record, [`WavelengthsF32`]). The surface's vectors' `w` lanes
/// are unspecified: read `x, y, z` only. [`Self::to_v5`] gives the v5 query.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq)]
pub struct QueryV7<'a> {
    /// The surface point (its vectors' `w` unspecified).
    pub ctx: &'a SurfaceF32,
    /// The path's wavelengths.
    pub lambda: &'a WavelengthsF32,
    /// Outgoing direction, local frame, away from the surface (`w` = 0).
    pub wo: Vec4f,
    /// Incident direction, local frame (eval and pdf; unused by sample; `w` = 0).
    pub wi: Vec4f,
    /// Uniforms in [0, 1) for sample, as [`MaterialQuery::u`].
    pub u: [f32; 3],
    /// Radiance (camera paths) or importance (light paths).
    pub mode: TransportMode,
}

impl<'a> QueryV7<'a> {
    /// The same query in v5's form (the wavelengths copied).
    #[inline]
    pub fn to_v5(&self) -> QueryV5<'a> {
        QueryV5 {
            ctx: self.ctx,
            wo: self.wo,
            wi: self.wi,
            lambda: self.lambda.to_lanes(),
            u: self.u,
            mode: self.mode,
        }
    }
}

/// What a material call of extension v7 answers, as one word: [`status::NONE`],
/// [`status::WRITTEN`] or [`status::ERROR`]. A plain `u32` rather than an enum so that any value
/// a plugin returns is a valid one; the host treats every other value as an error of the plugin.
pub mod status {
    /// `sample`: absorbed, nothing written.
    pub const NONE: u32 = 0;
    /// The result was written through `out`.
    pub const WRITTEN: u32 = 1;
    /// The call failed (an error, or a panic caught on the plugin's side): the error was written
    /// through `err`; `out` is not to be read.
    pub const ERROR: u32 = 2;
}

/// A value per lane, returned by value (extension v8's `eval`: in two SIMD registers on x86-64,
/// no memory in between). All lanes NaN: the call failed, its error kept for the module's
/// `take_error` ([`AbiMaterialV8`](crate::extension::AbiMaterialV8)).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct ValuesF32 {
    /// The value of each lane.
    pub v: [f32; LANES],
}

impl ValuesF32 {
    /// What a failed call answers: NaN in every lane.
    pub const FAILED: Self = Self {
        v: [f32::NAN; LANES],
    };
}
