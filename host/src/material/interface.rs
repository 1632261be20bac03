//! What a material is to the integrators: the [`Material`] trait and its sampling records.

use super::flags::MaterialFlags;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::fmt::Debug;
use std::sync::Arc;

/// How an emissive material emits, so the scene can turn its objects into area lights:
/// radiance `scale · spd(λ)` in W/(m²·sr·nm), uniform over the surface.
#[derive(Clone, Debug)]
pub struct EmissionProfile {
    /// Normalised SPD (1/nm), also used to draw light-path wavelengths.
    pub spd: Arc<dyn Spd>,
    /// Integrated radiance in W/(m²·sr).
    pub scale: f32,
    /// Whether the back side emits as well.
    pub two_sided: bool,
}

/// Which quantity a path carries. Refraction scales radiance by 1/η² but not importance, and
/// shading normals need the adjoint correction only on light paths (Veach 1997, ch. 5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Camera paths: carrying radiance towards the eye.
    Radiance,
    /// Light paths: carrying importance/flux away from lights.
    Importance,
}

/// What a material may know about the surface point besides the directions. Laid out as the
/// plugin interface's `SurfaceF32` (`#[repr(C)]`), so extension v5 passes it to plugins by
/// reference (`plugin::layout`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C)]
pub struct ShadingContext {
    /// Surface parameterisation (for textures).
    pub uv: Vec2,
    /// World-space position (scene units), for procedural materials.
    pub p: Vec3A,
    /// Geometric normal (world, unit; zero when unknown).
    pub ng: Vec3A,
    /// Shading normal (world, unit; the `z` axis of the local frame; zero when unknown).
    pub ns: Vec3A,
}

impl ShadingContext {
    /// The context of surface point `p` with geometric normal `ng`, shading normal `ns` and
    /// texture coordinates `uv`.
    pub fn at(p: Vec3A, ng: Vec3A, ns: Vec3A, uv: Vec2) -> Self {
        Self { uv, p, ng, ns }
    }
}

/// A sampled scattering direction. `#[repr(C)]` in the plugin interface's `ScatterF32` layout:
/// a plugin material writes it in place (`plugin::layout`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct BsdfSample {
    /// Sampled incident direction, local frame, unit.
    pub wi: Vec3A,
    /// BSDF value f(wo, wi) in 1/sr (for delta lobes: the delta's weight divided by |cos θi|,
    /// so `f·|cos θi|/pdf` is the throughput factor in every case).
    pub f: SampledSpectrum,
    /// Density of `wi` (1/sr), or the discrete lobe probability for delta lobes.
    pub pdf: f32,
    /// The lobe that was sampled (REFLECTION/TRANSMISSION × DIFFUSE/GLOSSY/SPECULAR, plus
    /// DISPERSIVE when the direction depended on the hero wavelength).
    pub flags: MaterialFlags,
    /// Relative IOR crossed (`n_transmitted/n_incident`), 1 for reflection.
    pub eta: f32,
}

impl BsdfSample {
    /// Write `s` here and lend it back: how a [`Material::sample_into`] answers.
    #[inline]
    pub fn write(&mut self, s: Self) -> &Self {
        *self = s;
        self
    }

    /// All zero: a record for [`Material::sample_into`] to write.
    pub const ZERO: Self = Self {
        wi: Vec3A::ZERO,
        f: SampledSpectrum::zero(),
        pdf: 0.0,
        flags: MaterialFlags::NONE,
        eta: 0.0,
    };
}

/// Effects a render switches off (see `integrator::plan`); a material that has one of them
/// offers a replacement without it through [`Material::without_effects`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EffectsOff {
    /// Dispersion off: a wavelength-dependent IOR is replaced by its value at `reference_nm`.
    pub dispersion: bool,
    /// Thin film off: the film is removed (thickness 0 nm), leaving the bare base.
    pub thin_film: bool,
    /// Wavelength (nm) at which a dispersive IOR is frozen.
    pub reference_nm: f32,
}

/// A surface material as the integrator sees it. Object safe; built-ins and plugin adapters
/// implement it alike.
pub trait Material: Send + Sync + Debug {
    /// What lobes this material has (union over all lobes).
    fn flags(&self) -> MaterialFlags;

    /// Sample `wi` given `wo`, writing the sample into `out`: `Some` of it, or `None` when no
    /// light is scattered (e.g. `wo` on the wrong side of a one-sided surface; what `out` holds
    /// then is not to be read). `u_lobe` picks a lobe, `u` the direction within it.
    ///
    /// Written in place rather than returned by value so that a plugin material can write its
    /// sample straight into the caller's record (`plugin::layout`; the host checks it there): a
    /// returned `Option<BsdfSample>` was one copy on each side of the plugin boundary per call
    /// (docs/performance.md, "Plugin overhead"). The render loops keep one record per path and
    /// pass it to every bounce; [`sample`](Self::sample) returns a copy, for everything else.
    #[allow(clippy::too_many_arguments)] // `sample`'s six and the record
    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample>;

    /// [`sample_into`](Self::sample_into), the sample returned by value (a copy): for callers
    /// outside the render loops.
    fn sample(
        &self,
        wo: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        let mut s = BsdfSample::ZERO;
        self.sample_into(wo, ctx, lambda, u_lobe, u, mode, &mut s)
            .copied()
    }

    /// BSDF value f(wo, wi) in 1/sr; zero for delta lobes.
    fn eval(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        mode: TransportMode,
    ) -> SampledSpectrum;

    /// Density (1/sr) with which [`sample`](Self::sample) would return `wi`; zero for delta lobes.
    fn pdf(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        ctx: &ShadingContext,
        lambda: &SampledWavelengths,
        mode: TransportMode,
    ) -> f32;

    /// For emissive materials: the emission the area light built on this surface uses. Must agree
    /// with [`emitted`](Self::emitted).
    fn emission(&self) -> Option<EmissionProfile> {
        None
    }

    /// For emissive materials whose radiance varies over the surface: the texture it is read
    /// from (then [`emission`](Self::emission) holds its mean, and the area light built on the
    /// surface samples positions by the texture's power). `None` for uniform emitters.
    fn emission_texture(&self) -> Option<Arc<crate::texture::emission_texture::EmissionTexture>> {
        None
    }

    /// For fluorescent materials ([`MaterialFlags::FLUORESCENT`]): the wavelength-shifting
    /// data. Such a material scatters diffusely (a cosine lobe, f = 1/π per unit albedo) in both
    /// its parts; [`sample`](Self::sample)/[`eval`](Self::eval) give the part that keeps its
    /// wavelength (ρ/π) and integrators that shift wavelengths read the rest from here (see
    /// `integrator::fluorescence`).
    fn reradiation(&self) -> Option<&dyn crate::spectrum::reradiation::Reradiation> {
        None
    }

    /// True when this material scatters the same fraction of light at every wavelength, at
    /// every point of its surface and for every pair of directions (a grey reflectance, a
    /// constant IOR), and never shifts wavelengths: a path through it carries the same
    /// throughput in every lane, so its colour can be integrated exactly
    /// (`integrator::wavelengths::flat_colour`). Materials that do not scatter at all (emitters) count as
    /// flat. The default is `false`, which is always safe (plugins keep it).
    fn spectrally_flat(&self) -> bool {
        false
    }

    /// True when `f(wo, wi)` is one value for every `wi` on `wo`'s side of the surface and 0 on
    /// the other (an ideal diffuse reflector), and [`sample`](Self::sample) returns exactly
    /// that value as its `f`: the path tracer then reuses the sampled direction's `f` for
    /// next-event estimation at the same point instead of evaluating the reflectance again.
    /// The default `false` is always safe.
    fn f_same_for_all_directions(&self) -> bool {
        false
    }

    /// True when [`sample_into`](Self::sample_into) and [`sample`](Self::sample) never read
    /// their `u_lobe` argument (a material with a single lobe): the path tracer then does not
    /// compute that number (it still consumes its sampler dimension, so no other number
    /// changes). The default `false` is always safe.
    fn ignores_lobe_sample(&self) -> bool {
        false
    }

    /// True when [`sample`](Self::sample) draws `wi` with the cosine-weighted density, so that
    /// [`pdf`](Self::pdf) is `|cos θi|/π` on `wo`'s side and 0 on the other (an ideal diffuse
    /// reflector): a plugin material that declares it has its density computed by the host
    /// instead of called for (`plugin::cosine_pdf`). The default `false` is always safe.
    fn cosine_weighted_pdf(&self) -> bool {
        false
    }

    /// This material with the effects in `off` switched off (the render plan's
    /// `--effect NAME=off`), and one sentence saying what changed; `None` when none of them
    /// applies or the material cannot switch them off.
    fn without_effects(&self, _off: &EffectsOff) -> Option<(Arc<dyn Material>, String)> {
        None
    }

    /// Radiance emitted towards `wo` in W/(m²·sr·nm) (only for [`MaterialFlags::EMISSIVE`]).
    fn emitted(
        &self,
        _wo: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }
}

/// True when `a` and `b` lie on the same side of the local surface.
#[inline]
pub fn same_hemisphere(a: Vec3A, b: Vec3A) -> bool {
    a.z * b.z > 0.0
}

/// Mirror `wo` about the normal `n` (both unit, pointing away from the surface).
#[inline]
pub fn reflect(wo: Vec3A, n: Vec3A) -> Vec3A {
    -wo + n * (2.0 * wo.dot(n))
}

/// Refract `wi` through a surface with normal `n` (on `wi`'s side) and relative IOR
/// `eta = n_transmitted / n_incident`. `None` under total internal reflection.
#[inline]
pub fn refract(wi: Vec3A, n: Vec3A, eta: f32) -> Option<Vec3A> {
    let cos_i = n.dot(wi);
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wi / eta + n * (cos_i / eta - cos_t))
}

/// Cosine-weighted direction on the upper hemisphere (Malley's method, concentric disk mapping
/// so strata stay compact).
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3A {
    let d = sample_concentric_disk(u);
    let z = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    Vec3A::new(d.x, d.y, z)
}

/// A direction `wi` from the cosine lobe on `wo`'s side of the surface (shading frame) and its
/// density `|cos θ|/π` (1/sr): the sampling of every diffuse lobe. `None` for a grazing `wo`
/// or a zero density.
#[inline]
pub fn sample_cosine_lobe(wo: Vec3A, u: Vec2) -> Option<(Vec3A, f32)> {
    if wo.z == 0.0 {
        return None;
    }
    let mut wi = sample_cosine_hemisphere(u);
    if wo.z < 0.0 {
        wi.z = -wi.z;
    }
    let pdf = wi.z.abs() * std::f32::consts::FRAC_1_PI;
    (pdf != 0.0).then_some((wi, pdf))
}

/// Uniform point on the unit disk with low distortion (Shirley & Chiu 1997): the square's
/// concentric squares go to circles of radius `r` (the larger coordinate of `2u - 1`), the
/// smaller over the larger coordinate `t ∈ [-1, 1]` to the angle `π/4·t` from the axis of the
/// larger one. Its cosine and sine come from [`quarter_pi_sin_cos`] (no libm call).
#[inline]
pub fn sample_concentric_disk(u: Vec2) -> Vec2 {
    #[cfg(target_arch = "x86_64")]
    {
        let o = u * 2.0 - Vec2::ONE;
        if o.x == 0.0 && o.y == 0.0 {
            return Vec2::ZERO;
        }
        concentric_sse2(o)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        sample_concentric_disk_scalar(u)
    }
}

/// [`sample_concentric_disk`]'s mapping of `o = 2u - 1` (not both zero) with SSE2: both
/// quotients `o.y/o.x`, `o.x/o.y` in one division and the wanted one picked by a mask after it,
/// instead of the division of the picked operands. The division heads the chain of dependent
/// steps (division, polynomials, the cosine lobe's square root) that a diffuse bounce's next
/// ray waits for, and now starts as soon as `o` is known, not after the comparison and the
/// blend. The masks stay SIMD: written as scalar bit blends, LLVM turned one of them into a
/// branch, taken half the time. The same IEEE operations on the same numbers as
/// [`sample_concentric_disk_scalar`], so the same bits (test `concentric_mappings_agree`).
#[cfg(target_arch = "x86_64")]
#[inline]
fn concentric_sse2(o: Vec2) -> Vec2 {
    use std::arch::x86_64::*;
    // SAFETY: SSE2 is part of x86-64; register operations only.
    unsafe {
        let ov = _mm_setr_ps(o.x, o.y, 1.0, 1.0);
        let sw = _mm_setr_ps(o.y, o.x, 1.0, 1.0);
        let abs = _mm_castsi128_ps(_mm_set1_epi32(0x7FFF_FFFF));
        // Lane 0: |o.x| > |o.y| (false on NaN, as the scalar comparison), on every lane.
        let gt = _mm_cmpgt_ps(_mm_and_ps(ov, abs), _mm_and_ps(sw, abs));
        let x_major = _mm_shuffle_ps::<0>(gt, gt);
        let pick =
            |a: __m128, b: __m128| _mm_or_ps(_mm_and_ps(x_major, a), _mm_andnot_ps(x_major, b));
        // (o.y/o.x, o.x/o.y, 1, 1).
        let q = _mm_div_ps(sw, ov);
        let t = _mm_cvtss_f32(pick(q, _mm_shuffle_ps::<0b01>(q, q)));
        let r = _mm_cvtss_f32(pick(ov, sw));
        let (s, c) = quarter_pi_sin_cos(t);
        let v = _mm_setr_ps(r * c, r * s, 0.0, 0.0);
        let d = pick(v, _mm_shuffle_ps::<0b0001>(v, v));
        let mut out = [0.0f32; 4];
        _mm_storeu_ps(out.as_mut_ptr(), d);
        Vec2::new(out[0], out[1])
    }
}

/// [`sample_concentric_disk`] by its definition, without SIMD (the mapping on other targets,
/// and the reference the x86-64 one is tested against).
#[inline]
pub fn sample_concentric_disk_scalar(u: Vec2) -> Vec2 {
    let o = u * 2.0 - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // Which coordinate is larger is a coin toss for every sample, so the two cases are
    // blended by a bit mask rather than branched on (a branch mispredicted half the time cost
    // more than the rest of the mapping). With `x` larger: r = o.x, t = o.y/o.x and the point
    // (r·cos, r·sin); else r = o.y, t = o.x/o.y and the angle π/2 - π/4·t, whose cosine is
    // sin(π/4·t): the point (r·sin, r·cos).
    let x_major = 0u32.wrapping_sub((o.x.abs() > o.y.abs()) as u32);
    let pick = |a: f32, b: f32| f32::from_bits((a.to_bits() & x_major) | (b.to_bits() & !x_major));
    let r = pick(o.x, o.y);
    let (s, c) = quarter_pi_sin_cos(pick(o.y, o.x) / r);
    let (rc, rs) = (r * c, r * s);
    Vec2::new(pick(rc, rs), pick(rs, rc))
}

/// `(sin(π/4·t), cos(π/4·t))` for `t ∈ [-1, 1]` by polynomials in `t²` (sine odd, degree 7;
/// cosine even, degree 6) fitted for minimax error on that interval, then scaled by
/// `1 - 2.4e-7` so that `sin² + cos² < 1` in f32 for every `t` (at most 0.99999964 on 4·10⁶
/// points): a disk point never lands outside the unit disk, and `√(1 - |d|²)` stays positive
/// even on the square's edge, where the cosine-weighted direction is grazing. The error is at
/// most 3.3e-7 in either (a few ulp of values near 1; the test checks 4e-7 on 2·10⁵ points),
/// without libm's call and range reduction. The disk mapping needs nothing else: its angles
/// never leave ±π/4 of an axis.
#[inline]
pub fn quarter_pi_sin_cos(t: f32) -> (f32, f32) {
    let s2 = t * t;
    let sin = t
        * (7.853_979_5e-1 + s2 * (-8.074_541_4e-2 + s2 * (2.490_000_8e-3 + s2 * -3.595_074_7e-5)));
    let cos = 9.999_997e-1 + s2 * (-3.084_241_7e-1 + s2 * (1.584_991_6e-2 + s2 * -3.188_838_6e-4));
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quantity: the disk point of `sample_concentric_disk` against
    /// `sample_concentric_disk_scalar`, bit for bit (no tolerance: the same IEEE operations), on
    /// the 1025² grid of the square with its edges and centre lines (ties |o.x| = |o.y| on the
    /// diagonals, o.x = 0 or o.y = 0 on the axes), and on 10⁶ random points, plus NaN inputs.
    #[test]
    fn concentric_mappings_agree() {
        let bits = |v: Vec2| (v.x.to_bits(), v.y.to_bits());
        let n = 1024;
        for i in 0..=n {
            for j in 0..=n {
                let u = Vec2::new(i as f32 / n as f32, j as f32 / n as f32);
                assert_eq!(
                    bits(sample_concentric_disk(u)),
                    bits(sample_concentric_disk_scalar(u)),
                    "{u:?}"
                );
            }
        }
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        for _ in 0..1_000_000 {
            let u = Vec2::new(next(), next());
            assert_eq!(
                bits(sample_concentric_disk(u)),
                bits(sample_concentric_disk_scalar(u)),
                "{u:?}"
            );
        }
        for u in [
            Vec2::new(f32::NAN, 0.3),
            Vec2::new(0.3, f32::NAN),
            Vec2::splat(f32::NAN),
        ] {
            assert_eq!(
                bits(sample_concentric_disk(u)),
                bits(sample_concentric_disk_scalar(u)),
                "{u:?}"
            );
        }
    }

    /// Quantity: `quarter_pi_sin_cos(t)` against f64 `sin`/`cos` of `π/4·t` at 200 001 points
    /// of [-1, 1] (ends included); tolerance 4e-7 absolute (the scaled fit's f32 error is
    /// 3.3e-7), and `sin² + cos² < 1` in f32 at every point. And the concentric mapping against
    /// the same mapping in f64 with libm's trigonometry, at 401² points of the square (edges
    /// included): within 6e-7, never outside the unit disk, and the cosine-weighted direction
    /// on it has z > 0 (a grazing direction on the edge, not a zero density).
    #[test]
    fn disk_mapping_trigonometry_is_accurate() {
        let n = 100_000;
        for k in -n..=n {
            let t = k as f32 / n as f32;
            let (s, c) = quarter_pi_sin_cos(t);
            let a = std::f64::consts::FRAC_PI_4 * t as f64;
            assert!((s as f64 - a.sin()).abs() < 4e-7, "sin at t = {t}");
            assert!((c as f64 - a.cos()).abs() < 4e-7, "cos at t = {t}");
            assert!(s * s + c * c < 1.0, "sin² + cos² at t = {t}");
        }
        let m = 400;
        for i in 0..=m {
            for j in 0..=m {
                let u = Vec2::new(i as f32 / m as f32, j as f32 / m as f32);
                let d = sample_concentric_disk(u);
                let (ox, oy) = (2.0 * u.x as f64 - 1.0, 2.0 * u.y as f64 - 1.0);
                let (ex, ey) = if ox == 0.0 && oy == 0.0 {
                    (0.0, 0.0)
                } else if ox.abs() > oy.abs() {
                    let th = std::f64::consts::FRAC_PI_4 * (oy / ox);
                    (ox * th.cos(), ox * th.sin())
                } else {
                    let th = std::f64::consts::FRAC_PI_2 - std::f64::consts::FRAC_PI_4 * (ox / oy);
                    (oy * th.cos(), oy * th.sin())
                };
                assert!(
                    (d.x as f64 - ex).abs() < 6e-7 && (d.y as f64 - ey).abs() < 6e-7,
                    "u = {u}: {d} against ({ex}, {ey})"
                );
                assert!(d.length_squared() < 1.0, "u = {u}: {d}");
                assert!(sample_cosine_hemisphere(u).z > 0.0, "u = {u}");
            }
        }
    }
}
