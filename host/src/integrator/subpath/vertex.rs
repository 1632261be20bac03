//! Path vertices for bidirectional path tracing (Veach 1997, ch. 10): a point on the camera, on
//! a light or on a surface, the throughput `beta` of the subpath that reached it, and the two
//! area densities the MIS weights need: `pdf_fwd` (density with which *this* subpath generated
//! the vertex) and `pdf_rev` (density with which the *other* direction would have generated it).
//!
//! Densities are in area measure (1/m², scene units) except where noted; `delta` marks vertices
//! scattered by a Dirac lobe (mirror, smooth glass), where no connection can be made, and whose
//! directions carry the stand-in densities of [`delta_densities`].

use crate::camera::Camera;
use crate::geometry::{spawn_ray_to, Ray};
use crate::integrator::fluorescence::events::UNIT_LOBE;
use crate::light::{Light, LightFlags};
use crate::material::{Frame, Material, ShadingContext, TransportMode};
use crate::scene::Scene;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};

/// What a vertex lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexKind {
    /// The camera lens (first vertex of a camera subpath).
    Camera,
    /// A light's emitting point (first vertex of a light subpath, or a sampled light for s = 1).
    Light {
        /// Index in the scene's light manager.
        light: u32,
    },
    /// A scene surface.
    Surface {
        /// Scene object index (material, and area light if emissive).
        object: u32,
    },
}

/// One vertex of a camera or light subpath.
#[derive(Clone, Copy, Debug)]
pub struct Vertex {
    /// Where it lies.
    pub kind: VertexKind,
    /// Position (world).
    pub p: Vec3A,
    /// Error bound of `p`, for spawning connection rays.
    pub p_error: Vec3A,
    /// Geometric normal (zero for point-like lights and the camera).
    pub ng: Vec3A,
    /// Shading normal (equal to `ng` except on meshes with vertex normals).
    pub ns: Vec3A,
    /// `Frame::from_normal(ns)`, built once: connections evaluate the BSDF and its densities
    /// at a vertex many times (BDPT joins it with every vertex of the other subpath, and each
    /// MIS weight asks for four densities), and rebuilding the frame each time cost 2.7% of
    /// BDPT's instructions on the Cornell box.
    pub frame: Frame,
    /// Texture coordinates (surfaces).
    pub uv: Vec2,
    /// Unit direction towards the previous vertex of its own subpath (zero for the first).
    pub wo: Vec3A,
    /// Subpath throughput up to and including this vertex: radiance-like weight on camera
    /// subpaths (1/(W·…) importance units), flux-like (W/nm) on light subpaths.
    pub beta: SampledSpectrum,
    /// Area density (1/m²) of this vertex under its own subpath's sampling.
    pub pdf_fwd: f32,
    /// Area density (1/m²) of this vertex if sampled from the other end.
    pub pdf_rev: f32,
    /// Scattered by a Dirac lobe: connections through it are impossible.
    pub delta: bool,
    /// Wavelength lanes still valid at this vertex of its own subpath: every lane until a
    /// wavelength-dependent (dispersive) event before it leaves only the hero.
    pub lanes: LaneMask,
    /// The wavelengths (nm) its subpath carries on from here once a fluorescent event at or
    /// before this vertex has shifted them; `None` while they are the pair's wavelengths.
    pub shifted: Option<[f32; LANES]>,
    /// The spectral part of a fluorescent surface is in `beta`: connections and sampling use
    /// the unit cosine lobe ([`UNIT_LOBE`]) instead of the material's ρ/π.
    pub unit_lobe: bool,
    /// bdpt's MIS, per lane: the probability (a density for a shift) of the keep/shift choice
    /// its own subpath made at this fluorescent vertex; 1 elsewhere.
    pub choice: [f32; LANES],
    /// bdpt's MIS, per lane: the probability with which a subpath from the other end would
    /// make the same event here (see `fluorescence::event_probability`); 1 elsewhere.
    pub choice_rev: [f32; LANES],
    /// Lanes whose wavelength a fluorescent shift at or before this vertex (on its own
    /// subpath) has changed: they can be joined only by strategies that sample every shift on
    /// one subpath (s = 0, s = 1 for camera subpaths, t = 1 for light subpaths).
    pub moved: LaneMask,
    /// The BSDF value `sample` returned here when the material says
    /// `f_same_for_all_directions` (one value for every `wi` on `wo`'s side, 0 on the other),
    /// valid when [`sampled_for`](Self::sampled_for) is not [`SampledFor::NONE`]: a connection
    /// through this vertex with the same wavelengths and transport mode takes it instead of
    /// evaluating the material again, as the path tracer's next-event estimation does (the
    /// same value, so the same image). BDPT evaluates both ends of every connection: on the
    /// Cornell box this was about a million `eval` calls per sample per pixel.
    pub sampled_f: SampledSpectrum,
    /// The wavelengths (nm) `sampled_f` was drawn for.
    pub sampled_lambda: [f32; LANES],
    /// The transport mode and live lanes `sampled_f` was drawn for, or none.
    pub sampled_for: SampledFor,
}

/// For which transport mode and live lanes [`Vertex::sampled_f`] holds (those, with the
/// wavelengths, are all of the wavelength record a material that can say
/// `f_same_for_all_directions` reads: plugins see the wavelengths and live lanes only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampledFor {
    /// 0: nothing held; 1: radiance; 2: importance.
    mode: u8,
    /// The live lanes' bits.
    lanes: LaneMask,
}

impl SampledFor {
    /// Nothing held.
    pub const NONE: Self = Self {
        mode: 0,
        lanes: LaneMask::NONE,
    };

    /// Held for `mode` and `lambda`'s live lanes.
    #[inline]
    pub fn new(mode: TransportMode, lambda: &SampledWavelengths) -> Self {
        Self {
            mode: if mode == TransportMode::Radiance {
                1
            } else {
                2
            },
            lanes: lambda.lanes,
        }
    }
}

/// Four zero lanes (what an empty `sampled_f` and `sampled_lambda` hold).
pub const ZERO_LANES: [f32; LANES] = [0.0; LANES];

/// The solid-angle densities (1/sr) that stand in for a specular (Dirac) lobe's in the MIS
/// ratios: `(towards wi, towards wo)` at a vertex that scattered `wo` into `wi` (local shading
/// frame), `eta` the relative index crossed (`n` on `wi`'s side over `n` on `wo`'s side, 1 for
/// reflection).
///
/// Why not zero: a specular vertex `x_i` between `x_{i−1}` and `x_{i+1}` is made by either
/// subpath, and both make it with the same Dirac delta *in the measure the lobe preserves*:
/// `n²·|cos θ|·dω` (projected solid angle times the squared index: a mirror maps it onto
/// itself, a refraction too, by étendue `n_i²cos θ_i dω_i = n_t²cos θ_t dω_t`). In that measure
/// the delta cancels between two strategies, but what remains does not: the area densities of
/// the vertices it reaches, `n²|cos θ_x_i|·|cos θ_next|/d²`, a generalised geometry term on
/// each side of the specular vertex. Zeroing both densities (and mapping zero to one in the
/// ratio, pbrt's `remap0`) drops those terms, so the ratio between, say, light tracing and a
/// camera path that hits the light through a glass ball is off by `G(glass, light) /
/// G(floor, glass)`: for the caustic of a 0.1 m ball on a floor lit by a lamp 0.8 m up
/// (`scenes/bench/glass_sphere.ron`), a factor of about 1/900, which handed the caustic to the
/// far noisier `s = 0` (`host/tests/integrators_caustic_mis.rs` checks the weights against
/// densities computed from scratch).
/// The Fresnel choice of lobe is left out: it is the same for both directions through a
/// dielectric interface (Fresnel reflectance is reciprocal), so it would cancel. The factors
/// `n²` matter only where a chain starts and ends in different media; they are given relative
/// to `wo`'s side, whose common factor cancels within each chain.
#[inline]
pub fn delta_densities(wi: Vec3A, wo: Vec3A, eta: f32) -> (f32, f32) {
    let eta2 = if eta > 0.0 && eta.is_finite() {
        eta * eta
    } else {
        1.0
    };
    (wi.z.abs() * eta2, wo.z.abs())
}

/// `x` if non-zero, else 1: a density left at zero (one no sampling procedure gives, such as the
/// reverse density of a subpath's first vertex) cancels in the MIS ratio instead of producing
/// 0/0.
#[inline]
pub fn remap0(x: f32) -> f32 {
    if x != 0.0 {
        x
    } else {
        1.0
    }
}

/// Adjoint BSDF correction for shading normals on light subpaths (Veach 1997, §5.3):
/// `|wo·ns||wi·ng| / (|wo·ng||wi·ns|)` in importance mode, 1 otherwise. Without it light tracing
/// and path tracing disagree wherever interpolated normals differ from the true ones.
#[inline]
pub fn shading_normal_correction(
    ng: Vec3A,
    ns: Vec3A,
    wo: Vec3A,
    wi: Vec3A,
    mode: TransportMode,
) -> f32 {
    if mode == TransportMode::Radiance {
        return 1.0;
    }
    let num = wo.dot(ns).abs() * wi.dot(ng).abs();
    let den = wo.dot(ng).abs() * wi.dot(ns).abs();
    if den == 0.0 {
        0.0
    } else {
        num / den
    }
}

impl Vertex {
    /// A camera vertex at lens point `p` looking along `forward`, with throughput `beta`.
    pub fn camera(p: Vec3A, forward: Vec3A, beta: SampledSpectrum) -> Self {
        Self {
            kind: VertexKind::Camera,
            p,
            p_error: Vec3A::ZERO,
            ng: forward,
            ns: forward,
            frame: Frame::from_normal(forward),
            uv: Vec2::ZERO,
            wo: Vec3A::ZERO,
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            delta: false,
            lanes: LaneMask::ALL,
            shifted: None,
            unit_lobe: false,
            choice: [1.0; LANES],
            choice_rev: [1.0; LANES],
            moved: LaneMask::NONE,
            sampled_f: SampledSpectrum(ZERO_LANES),
            sampled_lambda: ZERO_LANES,
            sampled_for: SampledFor::NONE,
        }
    }

    /// A light vertex of light `light` at `p` (normal `n`, zero for point-like lights).
    pub fn light(light: u32, p: Vec3A, p_error: Vec3A, n: Vec3A, beta: SampledSpectrum) -> Self {
        Self {
            kind: VertexKind::Light { light },
            p,
            p_error,
            ng: n,
            ns: n,
            frame: Frame::from_normal(n),
            uv: Vec2::ZERO,
            wo: Vec3A::ZERO,
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            delta: false,
            lanes: LaneMask::ALL,
            shifted: None,
            unit_lobe: false,
            choice: [1.0; LANES],
            choice_rev: [1.0; LANES],
            moved: LaneMask::NONE,
            sampled_f: SampledSpectrum(ZERO_LANES),
            sampled_lambda: ZERO_LANES,
            sampled_for: SampledFor::NONE,
        }
    }

    /// What a material at this vertex may know about the surface point.
    #[inline]
    pub fn shading_context(&self) -> ShadingContext {
        ShadingContext::at(self.p, self.ng, self.ns, self.uv)
    }

    /// True on a surface with a normal (area lights count): cosines at this vertex apply.
    #[inline]
    pub fn on_surface(&self) -> bool {
        self.ng != Vec3A::ZERO && !matches!(self.kind, VertexKind::Camera)
    }

    /// The scene light this vertex emits from: the light of a light vertex, or the area light of
    /// an emissive surface.
    pub fn light_index(&self, scene: &Scene) -> Option<u32> {
        match self.kind {
            VertexKind::Light { light } => Some(light),
            VertexKind::Surface { object } => scene.lights.light_of_object(object),
            VertexKind::Camera => None,
        }
    }

    /// True when a path can be connected here: a surface whose material has a non-delta lobe
    /// (whatever lobe its own subpath sampled next: a smooth plastic's vertex that continued by
    /// its specular coating is still joined through its diffuse base, as the MIS weights of
    /// the other strategies assume, with the endpoints taken as non-delta), any other vertex
    /// unless it scattered by a delta lobe.
    #[inline]
    pub fn connectible(&self, scene: &Scene) -> bool {
        if !self.delta {
            return true;
        }
        match self.kind {
            VertexKind::Surface { .. } => self
                .material(scene)
                .is_some_and(|m| m.flags().has_non_specular()),
            _ => false,
        }
    }

    fn material<'a>(&self, scene: &'a Scene) -> Option<&'a dyn Material> {
        match self.kind {
            VertexKind::Surface { .. } if self.unit_lobe => Some(&UNIT_LOBE),
            VertexKind::Surface { object } => Some(scene.objects.material(object)),
            _ => None,
        }
    }

    /// The wavelengths its subpath carries at this vertex: `pair` (the camera/light pair's)
    /// with the shifted values, if a fluorescent event changed them (pdfs and mask stay).
    #[inline]
    pub fn wavelengths(&self, pair: &SampledWavelengths) -> SampledWavelengths {
        match self.shifted {
            Some(lambda) => SampledWavelengths { lambda, ..*pair },
            None => *pair,
        }
    }

    /// Convert a solid-angle density `pdf` (1/sr) at this vertex towards `next` into an area
    /// density (1/m²) at `next`: `pdf · |cos θ_next| / d²`.
    pub fn convert_density(&self, pdf: f32, next: &Vertex) -> f32 {
        let w = next.p - self.p;
        let d2 = w.length_squared();
        if !(d2 > 0.0) {
            return 0.0;
        }
        let mut pdf = pdf / d2;
        if next.on_surface() {
            pdf *= (next.ng.dot(w) / d2.sqrt()).abs();
        }
        pdf
    }

    /// BSDF value (1/sr) for scattering from this vertex's `wo` towards `next`, with the adjoint
    /// shading-normal correction in importance mode. Zero for non-surface vertices.
    pub fn f(
        &self,
        scene: &Scene,
        next: &Vertex,
        lambda: &SampledWavelengths,
        mode: TransportMode,
    ) -> SampledSpectrum {
        let Some(m) = self.material(scene) else {
            return SampledSpectrum::zero();
        };
        let wi = next.p - self.p;
        let len = wi.length();
        if !(len > 0.0) {
            return SampledSpectrum::zero();
        }
        let wi = wi / len;
        let frame = &self.frame;
        let (wo_local, wi_local) = (frame.to_local(self.wo), frame.to_local(wi));
        let f = if self.sampled_for == SampledFor::new(mode, lambda)
            && self.sampled_lambda == lambda.lambda
        {
            if crate::material::same_hemisphere(wo_local, wi_local) {
                self.sampled_f
            } else {
                SampledSpectrum::zero()
            }
        } else {
            m.eval(wo_local, wi_local, &self.shading_context(), lambda, mode)
        };
        f * shading_normal_correction(self.ng, self.ns, self.wo, wi, mode)
    }

    /// Area density (1/m²) at `next` of this vertex sampling `next`, having been reached from
    /// `prev` (ignored at light and camera vertices). `mode` is the transport direction of that
    /// sampling (importance when `prev` lies towards the light).
    #[allow(clippy::too_many_arguments)]
    pub fn pdf(
        &self,
        scene: &Scene,
        camera: &dyn Camera,
        prev: Option<&Vertex>,
        next: &Vertex,
        lambda: &SampledWavelengths,
        mode: TransportMode,
    ) -> f32 {
        match self.kind {
            VertexKind::Light { .. } => return self.pdf_light(scene, next),
            VertexKind::Camera => {
                let w = next.p - self.p;
                if !(w.length_squared() > 0.0) {
                    return 0.0;
                }
                let (_, pdf_dir) = camera.pdf_we(&Ray::new(self.p, w.normalize()));
                return self.convert_density(pdf_dir, next);
            }
            VertexKind::Surface { .. } => {}
        }
        let Some(m) = self.material(scene) else {
            return 0.0;
        };
        let Some(prev) = prev else {
            return 0.0;
        };
        let wp = prev.p - self.p;
        let wn = next.p - self.p;
        if !(wp.length_squared() > 0.0 && wn.length_squared() > 0.0) {
            return 0.0;
        }
        let frame = &self.frame;
        let ctx = self.shading_context();
        let pdf = m.pdf(
            frame.to_local(wp.normalize()),
            frame.to_local(wn.normalize()),
            &ctx,
            lambda,
            mode,
        );
        self.convert_density(pdf, next)
    }

    /// Area density (1/m²) at `next` of the light at this vertex emitting towards `next`
    /// (`sample_le`'s directional density, converted). Directional lights emit parallel rays
    /// with positional density `pdf_pos` on a disk across the scene, so the density at `next`
    /// is `pdf_pos · |cos θ_next|` whatever the distance.
    pub fn pdf_light(&self, scene: &Scene, next: &Vertex) -> f32 {
        let Some(li) = self.light_index(scene) else {
            return 0.0;
        };
        let light = &scene.lights.lights()[li as usize];
        let w = next.p - self.p;
        let d2 = w.length_squared();
        if !(d2 > 0.0) {
            return 0.0;
        }
        let w = w / d2.sqrt();
        let ray = Ray::new(self.p, w);
        let (pdf_pos, pdf_dir) = light.pdf_le(&ray, self.ng);
        let cos_next = if next.on_surface() {
            next.ng.dot(w).abs()
        } else {
            1.0
        };
        if light.flags().contains(LightFlags::DELTA_DIRECTION) {
            return pdf_pos * cos_next;
        }
        pdf_dir / d2 * cos_next
    }

    /// Density of choosing this light point as a light subpath's origin, with the subpath
    /// leaving towards `next`: light pmf × positional density (1/m², or 1 for point lights).
    pub fn pdf_light_origin(&self, scene: &Scene, next: &Vertex) -> f32 {
        let Some(li) = self.light_index(scene) else {
            return 0.0;
        };
        let light = &scene.lights.lights()[li as usize];
        let w = next.p - self.p;
        if !(w.length_squared() > 0.0) {
            return 0.0;
        }
        // A light at one point has positional density 1: its `pdf_le` is not asked (its answer
        // was thrown away; a plugin's light crossed the boundary for it).
        let ray = Ray::new(self.p, w.normalize());
        let pdf_pos = if light.flags().contains(LightFlags::DELTA_POSITION) {
            1.0
        } else {
            light.pdf_le(&ray, self.ng).0
        };
        scene.lights.pmf(li as usize) * pdf_pos
    }

    /// Radiance (W/(m²·sr·nm)) this vertex emits towards `toward` (area lights, and the
    /// environment where a camera path left the scene).
    pub fn le(
        &self,
        scene: &Scene,
        toward: &Vertex,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        let w = toward.p - self.p;
        if !(w.length_squared() > 0.0) {
            return SampledSpectrum::zero();
        }
        let object = match self.kind {
            VertexKind::Surface { object } => object,
            // A camera path that left the scene ends on the environment light.
            VertexKind::Light { light } => {
                return scene.lights.lights()[light as usize].radiance(
                    self.p,
                    self.ng,
                    self.uv,
                    w.normalize(),
                    lambda,
                );
            }
            VertexKind::Camera => return SampledSpectrum::zero(),
        };
        let m = scene.objects.material(object);
        let frame = Frame::from_normal(self.ng);
        m.emitted(
            frame.to_local(w.normalize()),
            &self.shading_context(),
            lambda,
        )
    }

    /// True when this light vertex's light cannot be found by a ray (delta lights, and
    /// connectable plugin lights without a surface): no camera path ends on it, so s = 0 is no
    /// strategy for it.
    pub fn is_unhittable_light(&self, scene: &Scene) -> bool {
        match self.kind {
            VertexKind::Light { light } => {
                !scene.lights.lights()[light as usize].flags().can_be_hit()
            }
            _ => false,
        }
    }
}

/// Mutual visibility of two vertices (a shadow ray between their offset positions).
pub fn unoccluded(scene: &Scene, a: &Vertex, b: &Vertex) -> bool {
    let (ray, t_max) = spawn_ray_to(a.p, a.p_error, a.ng, b.p, b.p_error, b.ng);
    !scene.geometry.occluded(&ray, t_max)
}

/// Generalised geometry term between two vertices without visibility: `|cos_a||cos_b|/d²`, the
/// cosines taken with the shading normals at surface vertices and omitted elsewhere.
pub fn geometry_term(a: &Vertex, b: &Vertex) -> f32 {
    let d = a.p - b.p;
    let d2 = d.length_squared();
    if !(d2 > 0.0) {
        return 0.0;
    }
    let w = d / d2.sqrt();
    let mut g = 1.0 / d2;
    if a.on_surface() {
        g *= a.ns.dot(w).abs();
    }
    if b.on_surface() {
        g *= b.ns.dot(w).abs();
    }
    g
}

/// Shorthand used when a light needs the trait object.
pub fn light_of<'a>(scene: &'a Scene, v: &Vertex) -> Option<&'a dyn Light> {
    v.light_index(scene)
        .map(|i| scene.lights.lights()[i as usize].as_ref())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::test_support::for_each_camera_subpath;
    use glam::Vec2;

    // A connection through a vertex that holds its sampled value (`sampled_f`) gets what the
    // material's own `eval` gives, to the bit, on `wo`'s side and (0) on the other: that is
    // what keeps BDPT's and LT's images unchanged. Quantity: `Vertex::f` towards points on
    // both sides of every Lambertian vertex of 64 Cornell camera subpaths, against the same
    // vertex with the value dropped (so `eval` runs); tolerance none (equal bits). Also: the
    // value is held at all, and not for other wavelengths or the other transport mode.
    #[test]
    fn the_sampled_value_at_a_vertex_is_what_eval_gives() {
        let scene = crate::scene::default_scene().unwrap();
        let mut held = 0;
        for_each_camera_subpath(
            &scene,
            7,
            64,
            (Vec2::new(64.0, 64.0), Vec2::new(64.0, 64.0)),
            (6, 8),
            |path, lambda| {
                for v in path.iter().filter(|v| v.sampled_for != SampledFor::NONE) {
                    held += 1;
                    let mut dropped = *v;
                    dropped.sampled_for = SampledFor::NONE;
                    for side in [1.0f32, -1.0] {
                        let mut next = *v;
                        next.p = v.p + side * 0.3 * v.ns + 0.2 * v.frame.to_world(Vec3A::X);
                        let mode = TransportMode::Radiance;
                        let reused = v.f(&scene, &next, lambda, mode);
                        let evaluated = dropped.f(&scene, &next, lambda, mode);
                        assert_eq!(reused.0.map(f32::to_bits), evaluated.0.map(f32::to_bits));
                    }
                    // Another mode or other wavelengths: not what was held.
                    let other = SampledWavelengths {
                        lambda: lambda.lambda.map(|l| l + 1.0),
                        ..*lambda
                    };
                    assert!(v.sampled_for != SampledFor::new(TransportMode::Importance, lambda));
                    assert!(v.sampled_lambda != other.lambda);
                }
            },
        );
        assert!(held > 32, "only {held} vertices held a sampled value");
    }
}
