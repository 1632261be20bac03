//! An area light whose radiance is an image ([`TexturedAreaLight`]): the surface of a scene
//! object with a textured emissive material (`emissive` with `radiance: (texture: ..)`, or a
//! Mitsuba `area` emitter with a texture `radiance`).
//!
//! # Sampling by emitted power
//! On a quad the texture coordinates are the quad's own `(s, t)` chart (`corner + s·edge0 +
//! t·edge1`), so positions can be drawn in proportion to the emitted luminance: a
//! [`Distribution2D`] over a grid in `(s, t)` as fine as the texels the quad shows (at most
//! 1024 × 1024 cells) whose cell weights are the texture's luminance at the cell's centre (with
//! `uv_scale` 1 the cells are the texels, the centres the texel centres) plus 10⁻³ of the mean
//! (so every cell where a filtered texture may emit stays reachable). A point is drawn uniformly inside the drawn cell: the density per unit
//! area is the cell's probability × cells / area, and the point's `(s, t)`, hence its density,
//! are recovered exactly from any point on the quad, so next-event estimation, light subpaths
//! and BDPT's MIS all use the same density.
//!
//! On other shapes (spheres, meshes) positions are drawn uniformly by area, as for untextured
//! lights; [`Light::build_warning`] says so at run time (more noise where the texture varies
//! strongly, no bias). Their texture coordinates at a light-path start are those of
//! [`Geometry::sample_area`]; at a point given without them (the start of a light subpath
//! seen again by the camera connection) they are found by a short ray cast onto the surface.

use super::{Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext};
use crate::geometry::{spawn_ray, Geometry, Ray, WorldShape};
use crate::light::distribution2d::Distribution2D;
use crate::material::{sample_cosine_hemisphere, EmissionProfile, Frame};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use crate::texture::emission_texture::EmissionTexture;
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::sync::Arc;

/// The power distribution over a quad's `(s, t)` chart.
#[derive(Debug)]
struct QuadChart {
    corner: Vec3A,
    edge0: Vec3A,
    edge1: Vec3A,
    /// Dual basis: `s = (p − corner)·dual0`, `t = (p − corner)·dual1`.
    dual0: Vec3A,
    dual1: Vec3A,
    area: f32,
    dist: Distribution2D,
}

impl QuadChart {
    fn new(
        corner: Vec3A,
        edge0: Vec3A,
        edge1: Vec3A,
        area: f32,
        texture: &EmissionTexture,
        cells: (usize, usize),
    ) -> Option<Self> {
        let g = edge0.cross(edge1);
        let g2 = g.length_squared();
        if !(g2 > 0.0 && area > 0.0) {
            return None;
        }
        let (nu, nv) = cells;
        let mut w = Vec::with_capacity(nu * nv);
        for j in 0..nv {
            for i in 0..nu {
                let v = texture.luminance_at(Vec2::new(
                    (i as f32 + 0.5) / nu as f32,
                    (j as f32 + 0.5) / nv as f32,
                )) as f64;
                w.push(v.max(0.0));
            }
        }
        let mean = w.iter().sum::<f64>() / w.len() as f64;
        if !(mean > 0.0 && mean.is_finite()) {
            return None;
        }
        for v in &mut w {
            *v += 1e-3 * mean;
        }
        Some(Self {
            corner,
            edge0,
            edge1,
            dual0: edge1.cross(g) / g2,
            dual1: g.cross(edge0) / g2,
            area,
            dist: Distribution2D::new(&w, nu, nv)?,
        })
    }

    fn st(&self, p: Vec3A) -> Vec2 {
        let d = p - self.corner;
        Vec2::new(d.dot(self.dual0), d.dot(self.dual1))
    }

    fn point(&self, st: Vec2) -> Vec3A {
        self.corner + self.edge0 * st.x + self.edge1 * st.y
    }

    /// Density per unit area at `(s, t)` (0 off the quad).
    fn pdf_area(&self, st: Vec2) -> f32 {
        let st = Vec2::new(st.x.clamp(0.0, 0.999_999), st.y.clamp(0.0, 0.999_999));
        (self.dist.pdf(st) / self.area as f64) as f32
    }
}

/// The textured emitting surface of scene object `object` (see the module docs).
#[derive(Debug)]
pub struct TexturedAreaLight {
    geometry: Arc<Geometry>,
    object: u32,
    emission: EmissionProfile,
    texture: Arc<EmissionTexture>,
    area: f32,
    chart: Option<QuadChart>,
    /// Scene length scale for the short ray that finds a point's texture coordinates.
    eps: f32,
}

/// A point sampled on the light: position, error bound, normal, texture coordinates and the
/// density per unit area.
struct Spot {
    point: Vec3A,
    error: Vec3A,
    normal: Vec3A,
    uv: Vec2,
    pdf_area: f32,
}

impl TexturedAreaLight {
    /// The light on `object` of `geometry`, emitting `texture` (the emissive material's
    /// profile holds its mean).
    pub fn new(
        geometry: Arc<Geometry>,
        object: u32,
        emission: EmissionProfile,
        texture: Arc<EmissionTexture>,
        texels: (u32, u32),
    ) -> Self {
        let area = geometry.object_area(object);
        let chart = match geometry.shape(object) {
            Some(WorldShape::Quad(q)) => {
                let v = q.vertices;
                let cells = (
                    (texels.0 as usize).clamp(1, 1024),
                    (texels.1 as usize).clamp(1, 1024),
                );
                QuadChart::new(v[0], v[1] - v[0], v[3] - v[0], area, &texture, cells)
            }
            _ => None,
        };
        let b = geometry.bounds();
        let eps = 1e-4 * (b.max - b.min).max_element().max(1e-3);
        Self {
            geometry,
            object,
            emission,
            texture,
            area,
            chart,
            eps,
        }
    }

    /// True when positions are drawn by the texture's power (quads).
    pub fn samples_by_power(&self) -> bool {
        self.chart.is_some()
    }

    fn emits_towards(&self, n: Vec3A, w: Vec3A) -> bool {
        let c = n.dot(w);
        c > 0.0 || (self.emission.two_sided && c < 0.0)
    }

    /// A point on the light from `u`.
    fn sample_point(&self, u: Vec2) -> Option<Spot> {
        match &self.chart {
            Some(c) => {
                let s = c.dist.sample(u);
                let st = s.uv;
                let point = c.point(st);
                let pdf_area = c.pdf_area(st);
                let error = (c.corner.abs() + c.edge0.abs() + c.edge1.abs()) * (4.0 * f32::EPSILON);
                Some(Spot {
                    point,
                    error,
                    normal: self.normal(),
                    uv: st,
                    pdf_area,
                })
            }
            None => {
                let s = self.geometry.sample_area(self.object, u)?;
                Some(Spot {
                    point: s.point,
                    error: s.point_error,
                    normal: s.normal,
                    uv: s.uv,
                    pdf_area: s.pdf,
                })
            }
        }
    }

    fn normal(&self) -> Vec3A {
        match self.geometry.shape(self.object) {
            Some(WorldShape::Quad(q)) => q.normal,
            _ => Vec3A::ZERO,
        }
    }

    /// Density per unit area of [`Self::sample_point`] at `p`.
    fn pdf_area_at(&self, p: Vec3A) -> f32 {
        match &self.chart {
            Some(c) => c.pdf_area(c.st(p)),
            None => self.geometry.pdf_area(self.object),
        }
    }

    /// Texture coordinates of the surface point `p` (normal `n`): the quad's chart, else the
    /// surface found by a short ray along ∓n, else `uv` as given.
    fn uv_at(&self, p: Vec3A, n: Vec3A, uv: Vec2) -> Vec2 {
        if let Some(c) = &self.chart {
            return c.st(p);
        }
        let n = n.normalize_or_zero();
        if n == Vec3A::ZERO {
            return uv;
        }
        let reach = self.eps * (1.0 + p.abs().max_element());
        for side in [1.0f32, -1.0] {
            let ray = Ray::new(p + n * (side * reach), -n * side);
            if let Some(h) = self.geometry.intersect(&ray, 2.0 * reach) {
                if h.object == self.object {
                    return h.uv;
                }
            }
        }
        uv
    }
}

impl Light for TexturedAreaLight {
    fn flags(&self) -> LightFlags {
        LightFlags::AREA
    }

    fn power(&self) -> f64 {
        let sides = if self.emission.two_sided { 2.0 } else { 1.0 };
        (PI * self.area * self.emission.scale) as f64 * sides
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.emission.spd.clone()
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        let (point, error, normal, uv, pdf) = if self.chart.is_some() {
            let s = self.sample_point(u)?;
            let d = s.point - ctx.p;
            let d2 = d.length_squared();
            let cos = s.normal.dot(d).abs() / d2.sqrt();
            if !(d2 > 0.0 && cos > 0.0) {
                return None;
            }
            (s.point, s.error, s.normal, s.uv, s.pdf_area * d2 / cos)
        } else {
            let s = self.geometry.sample_solid_angle(self.object, ctx.p, u)?;
            (s.point, s.point_error, s.normal, s.uv, s.pdf)
        };
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let d = point - ctx.p;
        let dist = d.length();
        if !(dist > 0.0) {
            return None;
        }
        let wi = d / dist;
        if !self.emits_towards(normal, -wi) {
            return None;
        }
        let radiance = self.texture.eval(uv, lambda);
        if radiance.is_black() {
            return None;
        }
        Some(LightLiSample {
            radiance,
            wi,
            pdf,
            p_light: point,
            p_light_error: error,
            n_light: normal,
        })
    }

    fn pdf_li(&self, ctx: &LightSampleContext, p_light: Vec3A, n_light: Vec3A) -> f32 {
        if self.chart.is_none() {
            return self
                .geometry
                .pdf_solid_angle(self.object, ctx.p, p_light, n_light);
        }
        let d = p_light - ctx.p;
        let d2 = d.length_squared();
        let cos = n_light.dot(d).abs() / d2.sqrt();
        if !(d2 > 0.0 && cos > 0.0) {
            return 0.0;
        }
        self.pdf_area_at(p_light) * d2 / cos
    }

    // With a chart both draw from it; without one, spheres are sampled by their cone from
    // outside and every other shape by area, as `sample_le`.
    fn li_points_as_le(&self) -> bool {
        self.chart.is_some()
            || !matches!(
                self.geometry.shape(self.object),
                Some(WorldShape::Sphere(_))
            )
    }

    fn radiance(
        &self,
        p: Vec3A,
        n: Vec3A,
        uv: Vec2,
        w: Vec3A,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        if self.emits_towards(n, w) {
            self.texture.eval(self.uv_at(p, n, uv), lambda)
        } else {
            SampledSpectrum::zero()
        }
    }

    fn sample_le(&self, u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        let s = self.sample_point(u1)?;
        let (mut u2, mut n, mut side_pdf) = (u2, s.normal, 1.0);
        if self.emission.two_sided {
            side_pdf = 0.5;
            if u2.x < 0.5 {
                u2.x *= 2.0;
            } else {
                u2.x = (u2.x - 0.5) * 2.0;
                n = -n;
            }
        }
        let local = sample_cosine_hemisphere(u2);
        let w = Frame::from_normal(n).to_world(local);
        let pdf_dir = local.z / PI * side_pdf;
        if !(pdf_dir > 0.0 && s.pdf_area > 0.0) {
            return None;
        }
        Some(LightLeSample {
            ray: spawn_ray(s.point, s.error, n, w),
            radiance: self.texture.eval(s.uv, lambda),
            pdf_pos: s.pdf_area,
            pdf_dir,
            normal: n,
        })
    }

    fn pdf_le(&self, ray: &Ray, n: Vec3A) -> (f32, f32) {
        let cos = n.dot(ray.dir.normalize());
        let side = if self.emission.two_sided { 0.5 } else { 1.0 };
        let pdf_dir = if cos > 0.0 || (self.emission.two_sided && cos < 0.0) {
            cos.abs() / PI * side
        } else {
            0.0
        };
        (self.pdf_area_at(ray.origin), pdf_dir)
    }

    fn object(&self) -> Option<u32> {
        Some(self.object)
    }

    fn build_warning(&self) -> Option<String> {
        (self.chart.is_none()).then(|| {
            format!(
                "the emission texture {} is on a surface that is not a quad: light positions on \
                 it are drawn uniformly by area, not by the texture's power (only quads are), so \
                 expect more noise where the texture varies strongly",
                self.texture.name()
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Shape, ShapeDesc, Transform};
    use crate::texture::image_file::{LoadedImage, RgbImage};
    use crate::texture::image_texture::{Filter, TexelLookup, Wrap};

    /// A 1 × 1 m quad in z = 0 (normal +z) textured with a 2 × 1 image: left texel
    /// `left`, right texel `right` (nearest filter).
    fn light(left: [f32; 3], right: [f32; 3]) -> TexturedAreaLight {
        let quad = ShapeDesc {
            shape: Shape::Quad {
                corner: Vec3A::new(-0.5, -0.5, 0.0),
                edge0: Vec3A::X,
                edge1: Vec3A::Y,
            },
            transform: Transform::IDENTITY,
        };
        let geometry = Arc::new(Geometry::build(vec![quad]).unwrap());
        let img = LoadedImage::Rgb(RgbImage {
            width: 2,
            height: 1,
            pixels: vec![left, right],
        });
        let lookup = TexelLookup {
            width: 2,
            height: 1,
            filter: Filter::Nearest,
            wrap: Wrap::Clamp,
            uv_scale: Vec2::ONE,
            uv_offset: Vec2::ZERO,
        };
        let tex = Arc::new(EmissionTexture::new("t", img, lookup, 1.0).unwrap());
        let e = crate::material::Emissive::textured(tex.clone(), false).unwrap();
        use crate::material::Material;
        TexturedAreaLight::new(geometry, 0, e.emission().unwrap(), tex, (2, 1))
    }

    /// Positions follow the texture's power: with the right half 9× as luminous as the left,
    /// 90% of 100k `sample_le` origins land on the right (binomial: within 4 SE, SE ≈ 0.001,
    /// the 10⁻³ floor shifts the share by < 1e-3); every sample's `pdf_le` and `pdf_li` give the
    /// densities `sample_le` and `sample_li` reported (1e-4 relative); the density is
    /// 2·(0.9 + f)/(1 + 2f) /m² on the right half and 2·(0.1 + f)/(1 + 2f) on the left, f = 5e-4
    /// the floor (1e-4 relative: f32); the radiance carried is the texel's.
    #[test]
    fn positions_follow_the_texture_power() {
        let l = light([0.1, 0.1, 0.1], [0.9, 0.9, 0.9]);
        assert!(l.samples_by_power() && l.build_warning().is_none());
        let lambda = SampledWavelengths::sample_visible(0.3);
        let (n, mut right) = (100_000usize, 0usize);
        let mut state = 77u64;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let ctx = LightSampleContext {
            p: Vec3A::new(0.2, 0.1, 1.0),
            p_error: Vec3A::ZERO,
            n: -Vec3A::Z,
        };
        // Cell weights: luminance 0.1 and 0.9 plus the floor 10⁻³ × their mean 0.5.
        let f = 1e-3 * 0.5;
        let (want_left, want_right) = (
            2.0 * (0.1 + f) / (1.0 + 2.0 * f),
            2.0 * (0.9 + f) / (1.0 + 2.0 * f),
        );
        for _ in 0..n {
            let s = l
                .sample_le(Vec2::new(rnd(), rnd()), Vec2::new(rnd(), rnd()), &lambda)
                .unwrap();
            let x = s.ray.origin.x;
            let want = if x > 0.0 { want_right } else { want_left };
            assert!(
                (s.pdf_pos / want - 1.0).abs() < 1e-4,
                "{} vs {want}",
                s.pdf_pos
            );
            let (pp, pd) = l.pdf_le(&s.ray, s.normal);
            assert!((pp / s.pdf_pos - 1.0).abs() < 1e-4 && (pd / s.pdf_dir - 1.0).abs() < 1e-4);
            if x.abs() > 1e-4 {
                let texel = l.texture.eval(Vec2::new(x + 0.5, 0.5), &lambda);
                assert_eq!(s.radiance, texel);
            }
            if x > 0.0 {
                right += 1;
            }
            let li = l.sample_li(&ctx, Vec2::new(rnd(), rnd()), &lambda).unwrap();
            let back = l.pdf_li(&ctx, li.p_light, li.n_light);
            assert!((back / li.pdf - 1.0).abs() < 1e-4, "{back} vs {}", li.pdf);
        }
        let share = right as f64 / n as f64;
        let se = (0.9 * 0.1 / n as f64).sqrt();
        assert!((share - 0.9).abs() < 4.0 * se + 1e-3, "share {share}");
    }
}
