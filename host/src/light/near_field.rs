//! A luminaire with its luminous opening: the candela table of an IES or EULUMDAT file (or one
//! baked from any light or binned from a ray file) emitted from the surface of a box of width ×
//! height × length (a flat rectangle when the height is 0), instead of from one point. Close to
//! the luminaire (within a few sizes of it) light then arrives from the whole opening, as from
//! the real luminaire, while far away it is the point luminaire again.
//!
//! Model: every point of the box's surface emits the same radiance towards ω,
//! `L(ω) = I(ω) / A⊥(ω)`, where `A⊥(ω) = w·l·|ω_y| + w·h·|ω_z| + l·h·|ω_x|` is the box's
//! projected area seen from ω (frame: x the C0 axis, y up from the luminaire (−aim), z = x × y;
//! width along x, length along z, height along y). The box's intensity towards ω,
//! `∫ L cos dA` over the faces facing ω, is then `L · A⊥(ω) = I(ω)`: the stored far field
//! exactly, whatever the box. A flat opening facing down emits the lower hemisphere of the
//! table from its lower face and the upper one (if any) from its upper face.
//!
//! Sampling. Next-event estimation from a receiver picks one of the faces that face it, in
//! proportion to area, and a uniform point on it (solid-angle pdf `d² / (A_vis · |cos θ_l|)`).
//! Emitted rays take their direction from the table ([`DirectionSampler`], pdf ∝ I) and their
//! origin on the faces facing that direction in proportion to their projected area (area pdf
//! `|cos θ_l| / A⊥(ω)`), so light tracing's weight `L·|cos θ_l| / (pdf_pos · pdf_dir)` is
//! `I(ω) / pdf_dir`, as for the point luminaire. Rays do not hit the box (it is no object of
//! the scene), so these two strategies carry all the weight (flags: neither delta nor area).

use super::{Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext};
use crate::geometry::Ray;
use crate::photometry::{DirectionSampler, Luminaire};
use crate::spectrum::spd::spd_at;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::sync::Arc;

/// A luminaire with a luminous opening (module docs).
#[derive(Debug, Clone)]
pub struct NearFieldLight {
    centre: Vec3A,
    /// World directions of the frame's x, y, z.
    axes: [Vec3A; 3],
    /// Half extents along the frame's x, y, z (m).
    half: [f32; 3],
    lum: Arc<Luminaire>,
    sampler: Option<Arc<DirectionSampler>>,
    spd: Arc<dyn Spd>,
    w_per_lm: f64,
    flux_lm: f64,
}

impl NearFieldLight {
    /// A luminaire centred at `centre`, frame `axes` (x = C0, y = −aim, z = x × y), luminous
    /// opening `size_m` = (width along x, length along z, height along y) in metres (at least
    /// one face of non-zero area), table `lum`, spectrum `spd` of efficacy `efficacy_lm_per_w`.
    pub fn new(
        centre: Vec3A,
        axes: [Vec3A; 3],
        size_m: [f64; 3],
        lum: Luminaire,
        spd: Arc<dyn Spd>,
        efficacy_lm_per_w: f64,
    ) -> Self {
        let sampler = DirectionSampler::new(&lum).map(Arc::new);
        let flux_lm = lum.flux_lm();
        Self {
            centre,
            axes,
            half: [
                (size_m[0] * 0.5) as f32,
                (size_m[2] * 0.5) as f32,
                (size_m[1] * 0.5) as f32,
            ],
            lum: Arc::new(lum),
            sampler,
            spd,
            w_per_lm: 1.0 / efficacy_lm_per_w,
            flux_lm,
        }
    }

    /// True when `size_m` gives the box a face of non-zero area.
    pub fn has_opening(size_m: [f64; 3]) -> bool {
        let [w, l, h] = size_m;
        w * l > 0.0 || w * h > 0.0 || l * h > 0.0
    }

    /// Total luminous flux, lm.
    pub fn flux_lm(&self) -> f64 {
        self.flux_lm
    }

    fn local(&self, v: Vec3A) -> Vec3A {
        Vec3A::new(
            v.dot(self.axes[0]),
            v.dot(self.axes[1]),
            v.dot(self.axes[2]),
        )
    }

    fn world(&self, v: Vec3A) -> Vec3A {
        self.axes[0] * v.x + self.axes[1] * v.y + self.axes[2] * v.z
    }

    /// Area of the faces normal to axis `a` (each).
    fn face_area(&self, a: usize) -> f32 {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        4.0 * self.half[b] * self.half[c]
    }

    /// Projected area seen from local direction `d` (unit).
    fn projected_area(&self, d: Vec3A) -> f32 {
        (0..3).map(|a| self.face_area(a) * d[a].abs()).sum()
    }

    /// Radiant intensity / projected area towards local direction `d`: the radiance, W/(m²·sr·nm).
    fn radiance_towards(&self, d: Vec3A, lambda: &SampledWavelengths) -> SampledSpectrum {
        let a = self.projected_area(d);
        if !(a > 0.0) {
            return SampledSpectrum::zero();
        }
        let cd = self.lum.intensity_cd([d.x as f64, d.y as f64, d.z as f64]);
        if !(cd > 0.0) {
            return SampledSpectrum::zero();
        }
        spd_at(self.spd.as_ref(), lambda) * (cd * self.w_per_lm / a as f64) as f32
    }

    /// The faces a local point `p` sees (axis, sign) with their areas, and the sum.
    fn visible_faces(&self, p: Vec3A) -> ([(usize, f32, f32); 3], usize, f32) {
        let mut faces = [(0, 0.0, 0.0); 3];
        let (mut n, mut total) = (0, 0.0);
        for a in 0..3 {
            let area = self.face_area(a);
            if !(area > 0.0) {
                continue;
            }
            let s = if p[a] > self.half[a] {
                1.0
            } else if p[a] < -self.half[a] {
                -1.0
            } else {
                continue;
            };
            faces[n] = (a, s, area);
            n += 1;
            total += area;
        }
        (faces, n, total)
    }

    /// A uniform point on face (`a`, sign `s`) from `u` (local).
    fn point_on_face(&self, a: usize, s: f32, u: Vec2) -> Vec3A {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        let mut p = Vec3A::ZERO;
        p[a] = s * self.half[a];
        p[b] = (2.0 * u.x - 1.0) * self.half[b];
        p[c] = (2.0 * u.y - 1.0) * self.half[c];
        p
    }

    fn normal(&self, a: usize, s: f32) -> Vec3A {
        self.axes[a] * s
    }
}

/// Pick index `i` of `weights[..n]` with `u` ∈ [0,1) in proportion to weight; `u` rescaled.
fn pick(weights: &[f32], total: f32, u: f32) -> (usize, f32) {
    let mut acc = 0.0;
    let x = u * total;
    for (i, &w) in weights.iter().enumerate() {
        if x < acc + w || i + 1 == weights.len() {
            return (i, ((x - acc) / w).clamp(0.0, 0.999_999_94));
        }
        acc += w;
    }
    (0, u)
}

impl Light for NearFieldLight {
    fn flags(&self) -> LightFlags {
        LightFlags(0)
    }

    fn power(&self) -> f64 {
        self.flux_lm * self.w_per_lm
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.spd.clone()
    }

    fn uniform_spectral_shape(&self) -> bool {
        true
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        let p = self.local(ctx.p - self.centre);
        let (faces, n, total) = self.visible_faces(p);
        if n == 0 {
            return None;
        }
        let areas: Vec<f32> = faces[..n].iter().map(|f| f.2).collect();
        let (i, ux) = pick(&areas, total, u.x);
        let (a, s, _) = faces[i];
        let q = self.point_on_face(a, s, Vec2::new(ux, u.y));
        let to = q - p;
        let d2 = to.length_squared();
        if !(d2 > 0.0) {
            return None;
        }
        let w_local = to / d2.sqrt();
        let cos_l = w_local[a].abs();
        if !(cos_l > 0.0) {
            return None;
        }
        let radiance = self.radiance_towards(-w_local, lambda);
        if radiance.is_black() {
            return None;
        }
        let p_light = self.centre + self.world(q);
        Some(LightLiSample {
            radiance,
            wi: self.world(w_local).normalize(),
            pdf: d2 / (total * cos_l),
            p_light,
            p_light_error: Vec3A::splat(p_light.abs().max_element() * 4.0 * f32::EPSILON),
            n_light: self.normal(a, s),
        })
    }

    fn pdf_li(&self, ctx: &LightSampleContext, p_light: Vec3A, n_light: Vec3A) -> f32 {
        let p = self.local(ctx.p - self.centre);
        let (_, n, total) = self.visible_faces(p);
        if n == 0 {
            return 0.0;
        }
        let to = p_light - ctx.p;
        let d2 = to.length_squared();
        let cos_l = n_light.dot(to).abs() / d2.sqrt();
        if !(cos_l > 0.0 && d2 > 0.0) {
            return 0.0;
        }
        d2 / (total * cos_l)
    }

    fn radiance(
        &self,
        _p: Vec3A,
        _n: Vec3A,
        _uv: Vec2,
        _w: Vec3A,
        _l: &SampledWavelengths,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    fn sample_le(&self, u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        let sampler = self.sampler.as_ref()?;
        let (d, _) = sampler.sample(&self.lum, u2.x as f64, u2.y as f64);
        let d_local = Vec3A::new(d[0] as f32, d[1] as f32, d[2] as f32).normalize();
        let w = self.world(d_local).normalize();
        let d_local = self.local(w);
        let pdf_dir = sampler.pdf(
            &self.lum,
            [d_local.x as f64, d_local.y as f64, d_local.z as f64],
        );
        let a_proj = self.projected_area(d_local);
        if !(pdf_dir > 0.0 && a_proj > 0.0) {
            return None;
        }
        let weights: [f32; 3] = std::array::from_fn(|a| self.face_area(a) * d_local[a].abs());
        let (a, ux) = pick(&weights, a_proj, u1.x);
        let s = if d_local[a] >= 0.0 { 1.0 } else { -1.0 };
        let q = self.point_on_face(a, s, Vec2::new(ux, u1.y));
        let origin = self.centre + self.world(q);
        Some(LightLeSample {
            ray: Ray::new(origin, w),
            radiance: self.radiance_towards(d_local, lambda),
            pdf_pos: d_local[a].abs() / a_proj,
            pdf_dir: pdf_dir as f32,
            normal: self.normal(a, s),
        })
    }

    fn pdf_le(&self, ray: &Ray, n: Vec3A) -> (f32, f32) {
        let Some(sampler) = &self.sampler else {
            return (0.0, 0.0);
        };
        let d = self.local(ray.dir.normalize());
        let pdf_dir = sampler.pdf(&self.lum, [d.x as f64, d.y as f64, d.z as f64]) as f32;
        let nl = self.local(n);
        let a = (0..3)
            .max_by(|&i, &j| nl[i].abs().total_cmp(&nl[j].abs()))
            .unwrap_or(1);
        let a_proj = self.projected_area(d);
        if !(a_proj > 0.0) || d[a] * nl[a] <= 0.0 {
            return (0.0, pdf_dir);
        }
        (d[a].abs() / a_proj, pdf_dir)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photometry::{PhotometricType, SourceFormat, Symmetry};
    use crate::spectrum::parse_spd_spec;

    /// A Lambertian panel's table: I(γ) = I0·cos γ below, nothing above (type C, axial).
    fn lambertian(i0: f64, size_m: [f64; 3]) -> Luminaire {
        let v_deg: Vec<f64> = (0..=180).map(|i| i as f64).collect();
        let candela = v_deg
            .iter()
            .map(|&v: &f64| {
                if v <= 90.0 {
                    i0 * v.to_radians().cos().max(0.0)
                } else {
                    0.0
                }
            })
            .collect();
        Luminaire {
            format: SourceFormat::Table,
            photometric_type: PhotometricType::C,
            symmetry: Symmetry::Axial,
            h_deg: vec![0.0],
            v_deg,
            candela,
            lamps: vec![],
            multipliers: vec![],
            absolute: true,
            rated_lamp_lumens: None,
            size_m,
            tilt: None,
            header: vec![],
            warnings: vec![],
        }
    }

    /// Irradiance at distance `h` below the corner of a uniform Lambertian `a × b` rectangle of
    /// radiance `l` (parallel planes): E = L · F · π, with the configuration factor of a
    /// differential area to a parallel rectangle at its corner normal (Howell's catalogue, C-11):
    /// F = 1/(2π) [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))], X = a/h, Y = b/h.
    fn corner_irradiance(l: f64, a: f64, b: f64, h: f64) -> f64 {
        let (x, y) = (a / h, b / h);
        let f = (x / (1.0 + x * x).sqrt() * (y / (1.0 + x * x).sqrt()).atan()
            + y / (1.0 + y * y).sqrt() * (x / (1.0 + y * y).sqrt()).atan())
            / (2.0 * std::f64::consts::PI);
        l * f * std::f64::consts::PI
    }

    /// Near field against the analytic panel: a 1 m × 1 m Lambertian panel table (I0 = 1000 cd
    /// per unit SPD, so L = I0 / A lm/(m²·sr)) made a near-field light, lux measured by
    /// next-event estimation 0.1 m and 0.5 m below its centre and below a point off the panel,
    /// against the sum of four corner configuration factors. 400 000 samples: standard error
    /// < 0.6 % (uniform points on the panel seen at 0.1 m are the worst case), tolerance
    /// 4σ + 0.2 % (the bilinear 1° table against cos γ adds < 0.1 %). The point
    /// luminaire gives I0/h² instead, 100 000 lx at 0.1 m where the panel gives ~6 300 lx.
    #[test]
    fn panel_lux_matches_the_uniform_rectangle() {
        let (w, l) = (1.0f64, 1.0f64);
        let i0 = 1000.0;
        let spd: Arc<dyn Spd> = Arc::new(parse_spd_spec("line:555").unwrap());
        let k = crate::photometry::efficacy::luminous_efficacy_lm_per_w(spd.as_ref());
        let light = NearFieldLight::new(
            Vec3A::ZERO,
            [Vec3A::X, Vec3A::Y, Vec3A::Z],
            [w, l, 0.0],
            lambertian(i0, [w, l, 0.0]),
            spd.clone(),
            k,
        );
        let lambda = SampledWavelengths {
            lambda: [555.0; 4],
            pdf: [1.0; 4],
            lanes: crate::spectrum::LaneMask::ALL,
        };
        let s555 = spd_at(spd.as_ref(), &lambda)[0] as f64;
        let lum_radiance = i0 / (w * l);
        for (x, z, h) in [(0.0f64, 0.0f64, 0.1f64), (0.0, 0.0, 0.5), (0.8, 0.3, 0.25)] {
            // Rectangle [-0.5, 0.5]² split at (x, z) into four corner rectangles (signed).
            let e_exact: f64 = [
                (0.5 - x, 0.5 - z),
                (0.5 + x, 0.5 - z),
                (0.5 - x, 0.5 + z),
                (0.5 + x, 0.5 + z),
            ]
            .iter()
            .map(|&(a, b): &(f64, f64)| {
                a.signum() * b.signum() * corner_irradiance(lum_radiance, a.abs(), b.abs(), h)
            })
            .sum();
            let ctx = LightSampleContext {
                p: Vec3A::new(x as f32, -h as f32, z as f32),
                p_error: Vec3A::ZERO,
                n: Vec3A::Y,
            };
            let n = 400_000;
            let (mut s, mut s2) = (0.0f64, 0.0f64);
            let mut rng = 0x9E3779B97F4A7C15u64;
            let mut next = || {
                rng ^= rng << 13;
                rng ^= rng >> 7;
                rng ^= rng << 17;
                (rng >> 40) as f32 / (1u64 << 24) as f32
            };
            for _ in 0..n {
                let u = Vec2::new(next(), next());
                let Some(ls) = light.sample_li(&ctx, u, &lambda) else {
                    continue;
                };
                let cos = ls.wi.dot(ctx.n).max(0.0) as f64;
                // Back to lux: W per unit SPD × K.
                let e = ls.radiance[0] as f64 / s555 * k * cos / ls.pdf as f64;
                // pdf_li agrees with sample_li.
                let pdf = light.pdf_li(&ctx, ls.p_light, ls.n_light);
                assert!((pdf / ls.pdf - 1.0).abs() < 1e-3, "{pdf} vs {}", ls.pdf);
                s += e;
                s2 += e * e;
            }
            let mean = s / n as f64;
            let se = ((s2 / n as f64 - mean * mean) / n as f64).sqrt();
            println!("({x}, {z}) at {h} m: {mean:.2} ± {se:.2} lx, analytic {e_exact:.2} lx");
            assert!(se / mean < 0.006, "se {se} of {mean}");
            assert!(
                (mean - e_exact).abs() < 4.0 * se + 0.002 * e_exact,
                "{mean} vs {e_exact}"
            );
        }
    }

    /// Emission sampling integrates to the power (I/pdf_dir averaged) and `pdf_le` returns the
    /// densities `sample_le` used, for a box with all three dimensions.
    #[test]
    fn emission_sampling_is_consistent() {
        let spd: Arc<dyn Spd> = Arc::new(parse_spd_spec("e").unwrap());
        let k = crate::photometry::efficacy::luminous_efficacy_lm_per_w(spd.as_ref());
        let light = NearFieldLight::new(
            Vec3A::new(1.0, 2.0, 3.0),
            [Vec3A::X, Vec3A::Y, Vec3A::Z],
            [0.6, 0.3, 0.2],
            lambertian(500.0, [0.6, 0.3, 0.2]),
            spd,
            k,
        );
        let lambda = SampledWavelengths::sample_uniform(0.3, 360.0, 830.0);
        let s_at = spd_at(light.spd.as_ref(), &lambda);
        let mut sum = 0.0f64;
        let n = 50_000;
        for i in 0..n {
            let u1 = Vec2::new(
                ((i * 7919) % n) as f32 / n as f32,
                ((i * 104_729) % n) as f32 / n as f32,
            );
            let u2 = Vec2::new(
                (i as f32 + 0.5) / n as f32,
                ((i * 31) % n) as f32 / n as f32,
            );
            let Some(s) = light.sample_le(u1, u2, &lambda) else {
                continue;
            };
            let (pp, pd) = light.pdf_le(&s.ray, s.normal);
            assert!((pp / s.pdf_pos - 1.0).abs() < 1e-4 && (pd / s.pdf_dir - 1.0).abs() < 1e-4);
            let cos = s.normal.dot(s.ray.dir).abs();
            sum += (s.radiance[0] / s_at[0] * cos / (s.pdf_pos * s.pdf_dir)) as f64;
        }
        let mean = sum / n as f64;
        assert!(
            (mean / light.power() - 1.0).abs() < 0.01,
            "{mean} vs {}",
            light.power()
        );
    }
}
