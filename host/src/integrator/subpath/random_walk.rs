//! The random walk that extends camera and light subpaths surface by surface (BSDF sampling,
//! Russian roulette, the forward/reverse area densities MIS needs), and the camera subpath
//! built from it.

use crate::camera::Camera;
use crate::geometry::{spawn_ray, Hit, Ray};
use crate::integrator::fluorescence::events::{self as fluorescence, Direction, UNIT_LOBE};
use crate::integrator::subpath::vertex::{SampledFor, Vertex, VertexKind, ZERO_LANES};
use crate::integrator::{PathStats, UniformSource};
use crate::material::{BsdfSample, Frame, Material, MaterialFlags, ShadingContext, TransportMode};
use crate::scene::Scene;
use crate::spectrum::reradiation::Reradiation;
use crate::spectrum::{DeltaLine, SampledSpectrum, SampledWavelengths, LANES};

/// Flip the transport direction.
fn flip(mode: TransportMode) -> TransportMode {
    match mode {
        TransportMode::Radiance => TransportMode::Importance,
        TransportMode::Importance => TransportMode::Radiance,
    }
}

/// What a walk does at a fluorescent surface (see [`crate::integrator::fluorescence::events`]); nothing unless the
/// scene renders fluorescence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WalkShift {
    /// Treat it as its reflectance (ρ/π): no wavelength ever changes.
    Off,
    /// bdpt camera subpaths: each lane keeps its wavelength or moves to an excitation
    /// wavelength on its own (as in pt), recording both ends' event probabilities for MIS.
    CameraLanes,
    /// bdpt light subpaths: each lane keeps its wavelength or moves to an emission wavelength
    /// on its own (as in light tracing), recording both ends' event probabilities for MIS.
    LightLanesRecorded,
    /// Light tracing: each lane keeps or moves to an emission wavelength on its own.
    LightLanes,
}

/// The state a walk carries from vertex to vertex.
struct Walk {
    /// Solid-angle density of the ray just traced (1/sr), converted to area at its hit.
    pdf_fwd: f32,
    /// Throughput.
    beta: SampledSpectrum,
    /// Lanes still carried (only the hero after a dispersive event).
    lanes: crate::spectrum::LaneMask,
    /// The wavelengths carried now (the pair's until a fluorescent event shifts them).
    cur: SampledWavelengths,
    /// Whether a fluorescent event has shifted some lane, and which lanes moved.
    shifted: bool,
    moved: crate::spectrum::LaneMask,
    /// Scattering-only throughput for Russian roulette (β of light paths carries watts), without
    /// the 1/η² radiance scaling of refraction: that factor is undone when the path leaves the
    /// medium again, so a roulette on it would kill camera paths inside glass with probability
    /// 1 − 1/η² and return the survivors with η² = 2.25× the throughput (fireflies through glass).
    scatter: f32,
    /// Vertices added so far.
    added: usize,
}

impl Walk {
    /// A camera path that leaves the scene ends on the environment light, if any.
    #[inline]
    fn escape(&self, scene: &Scene, ray: &Ray, path: &mut Vec<Vertex>) {
        let Some(ei) = scene.lights.environment() else {
            return;
        };
        let light = &scene.lights.lights()[ei as usize];
        if let Some((p, n)) = light.escape_point(ray) {
            let mut v = Vertex::light(ei, p, glam::Vec3A::ZERO, n, self.beta);
            v.wo = -ray.dir.normalize();
            v.lanes = self.lanes;
            v.shifted = self.shifted.then_some(self.cur.lambda);
            v.moved = self.moved;
            v.pdf_fwd = path[path.len() - 1].convert_density(self.pdf_fwd, &v);
            path.push(v);
        }
    }

    /// The surface vertex at `hit`, reached by `ray`, with its forward area density.
    #[inline]
    fn surface_vertex(&self, hit: &Hit, ray: &Ray, path: &[Vertex]) -> Vertex {
        let wo_world = -ray.dir.normalize();
        let frame = Frame::from_normal(hit.shading_normal);
        let mut v = Vertex {
            kind: VertexKind::Surface { object: hit.object },
            p: hit.point,
            p_error: hit.point_error,
            ng: hit.geometric_normal,
            ns: hit.shading_normal,
            frame,
            uv: hit.uv,
            wo: wo_world,
            beta: self.beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            delta: false,
            lanes: self.lanes,
            shifted: self.shifted.then_some(self.cur.lambda),
            unit_lobe: false,
            choice: [1.0; LANES],
            choice_rev: [1.0; LANES],
            moved: self.moved,
            sampled_f: SampledSpectrum(ZERO_LANES),
            sampled_lambda: ZERO_LANES,
            sampled_for: SampledFor::NONE,
        };
        // The previous vertex read in place (a copy of the whole vertex cost a `memcpy`).
        v.pdf_fwd = path[path.len() - 1].convert_density(self.pdf_fwd, &v);
        v
    }

    /// A fluorescent surface: the wavelength choice is made on arrival, so connections from
    /// `v` and the continuation see the new wavelengths.
    #[inline]
    fn fluoresce<S: UniformSource>(
        &mut self,
        rr: &dyn Reradiation,
        shift: WalkShift,
        lines: &[DeltaLine],
        rng: &mut S,
        v: &mut Vertex,
    ) {
        self.cur.lanes = self.lanes;
        let dir = match shift {
            WalkShift::CameraLanes => Direction::Camera,
            _ => Direction::Light,
        };
        let before = self.cur.lambda;
        let u = rng.next_1d();
        let w = if shift == WalkShift::LightLanes {
            fluorescence::shift_lanes(rr, &mut self.cur, u, dir, lines)
        } else {
            let sh = fluorescence::shift_lanes_recorded(rr, &mut self.cur, u, dir, lines);
            v.choice = sh.own;
            v.choice_rev = sh.other;
            self.moved = self.moved.union(sh.moved);
            sh.weight
        };
        self.shifted |= self.cur.lambda != before;
        v.unit_lobe = true;
        self.beta *= w;
        self.scatter *= w.max_value();
        v.beta = self.beta;
        v.shifted = self.shifted.then_some(self.cur.lambda);
        v.moved = self.moved;
    }

    /// Sample the BSDF at the last vertex of `path` (at `hit`), update the throughput and the
    /// densities, play Russian roulette: the next ray, or `None` where the walk ends.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn scatter_at<S: UniformSource>(
        &mut self,
        scene: &Scene,
        hit: &Hit,
        mode: TransportMode,
        rr_depth: u32,
        rng: &mut S,
        record: &mut BsdfSample,
        path: &mut [Vertex],
    ) -> Option<Ray> {
        let n = path.len();
        let (unit_lobe, wo_world, frame) = {
            let v = &path[n - 1];
            (v.unit_lobe, v.wo, v.frame)
        };
        let material: &dyn Material = if unit_lobe {
            &UNIT_LOBE
        } else {
            scene.objects.material(hit.object)
        };
        let wo = frame.to_local(wo_world);
        let ctx = ShadingContext::at(hit.point, hit.geometric_normal, hit.shading_normal, hit.uv);
        let u_lobe = rng.next_1d();
        let u_dir = rng.next_2d();
        let bs = material.sample_into(wo, &ctx, &self.cur, u_lobe, u_dir, mode, record)?;
        if !(bs.pdf > 0.0) || bs.f.is_black() {
            return None;
        }
        if material.f_same_for_all_directions() {
            let v = &mut path[n - 1];
            v.sampled_f = bs.f;
            v.sampled_lambda = self.cur.lambda;
            v.sampled_for = SampledFor::new(mode, &self.cur);
        }
        let wi_world = frame.to_world(bs.wi);
        self.pdf_fwd = bs.pdf;
        // A specular sample makes a delta vertex: its two directions get the stand-in
        // densities of `delta_densities` (not zero: see there), and the material's reverse
        // density is not asked for (a plugin's material would cross the boundary for it).
        let pdf_rev;
        if bs.flags.is_specular() {
            path[n - 1].delta = true;
            (self.pdf_fwd, pdf_rev) = super::vertex::delta_densities(bs.wi, wo, bs.eta);
        } else {
            pdf_rev = material.pdf(bs.wi, wo, &ctx, &self.cur, flip(mode));
        }
        if bs.flags.contains(MaterialFlags::DISPERSIVE) {
            self.lanes = self.lanes.terminate_secondary();
        }
        let correction = crate::integrator::subpath::vertex::shading_normal_correction(
            hit.geometric_normal,
            hit.shading_normal,
            wo_world,
            wi_world,
            mode,
        );
        let factor = bs.wi.z.abs() / bs.pdf * correction;
        self.beta *= bs.f * factor;
        self.scatter *= (bs.f * factor).max_value();
        if mode == TransportMode::Radiance && bs.flags.contains(MaterialFlags::TRANSMISSION) {
            self.scatter *= bs.eta * bs.eta;
        }
        if self.beta.has_non_finite() || self.beta.is_black() {
            return None;
        }
        path[n - 2].pdf_rev = path[n - 1].convert_density(pdf_rev, &path[n - 2]);
        if self.added as u32 >= rr_depth && self.scatter < 1.0 {
            let q = (1.0 - self.scatter).max(0.05);
            if rng.next_1d() < q {
                return None;
            }
            self.beta = self.beta / (1.0 - q);
            self.scatter /= 1.0 - q;
        } else {
            // Every bounce consumes the same requests (see `random_walk`).
            rng.skip_1d();
        }
        Some(spawn_ray(
            hit.point,
            hit.point_error,
            hit.geometric_normal,
            wi_world,
        ))
    }
}

/// Extend `path` by up to `max_new` surface vertices, starting with `ray` leaving the last
/// vertex of `path` with solid-angle density `pdf_dir` (1/sr) and throughput `beta`. Sets each
/// new vertex's `pdf_fwd` and its predecessor's `pdf_rev`.
///
/// Requests drawn from `rng`, the same at every vertex so that bounce `k` always reads the
/// same dimensions of a stratified source: in a scene that renders fluorescence, the
/// wavelength-shift choice (1D, skipped at a non-fluorescent surface); then, when the walk
/// goes on from the vertex, the lobe (1D), the direction (2D) and Russian roulette (1D,
/// skipped where roulette does not play): 3 requests a bounce, 4 with fluorescence.
#[allow(clippy::too_many_arguments)]
pub fn random_walk<S: UniformSource>(
    scene: &Scene,
    mut ray: Ray,
    lambda: &SampledWavelengths,
    rng: &mut S,
    beta: SampledSpectrum,
    pdf_dir: f32,
    max_new: usize,
    mode: TransportMode,
    rr_depth: u32,
    path: &mut Vec<Vertex>,
    stats: &mut PathStats,
    shift: WalkShift,
) {
    if max_new == 0 || path.is_empty() {
        return;
    }
    let shift = if scene.objects.fluorescence() {
        shift
    } else {
        WalkShift::Off
    };
    let last = &path[path.len() - 1];
    let mut walk = Walk {
        pdf_fwd: pdf_dir,
        beta,
        lanes: last.lanes.intersect(lambda.lanes),
        cur: last.wavelengths(lambda),
        shifted: last.shifted.is_some(),
        moved: last.moved,
        scatter: 1.0,
        added: 0,
    };
    // Where every bounce's BSDF sample is written (`Material::sample_into`).
    let mut record = BsdfSample::ZERO;
    // The lights' delta lines, which camera-side excitation draws include.
    let lines = scene.lights.delta_lines();
    loop {
        stats.rays += 1;
        let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
            if mode == TransportMode::Radiance {
                walk.escape(scene, &ray, path);
            }
            break;
        };
        let mut v = walk.surface_vertex(&hit, &ray, path);
        let rerad = match shift {
            WalkShift::Off => None,
            _ => scene.objects.reradiation(hit.object),
        };
        if let Some(rr) = rerad {
            walk.fluoresce(rr, shift, lines, rng, &mut v);
        } else if shift != WalkShift::Off {
            rng.skip_1d();
        }
        path.push(v);
        walk.added += 1;
        if walk.added >= max_new || (rerad.is_some() && walk.beta.is_black()) {
            break;
        }
        match walk.scatter_at(scene, &hit, mode, rr_depth, rng, &mut record, path) {
            Some(next) => ray = next,
            None => break,
        }
    }
}

/// The camera subpath of one camera ray: the lens vertex plus up to `max_vertices − 1` more.
#[allow(clippy::too_many_arguments)]
pub fn generate_camera_subpath<S: UniformSource>(
    scene: &Scene,
    camera: &dyn Camera,
    ray: Ray,
    weight: f32,
    lambda: &SampledWavelengths,
    rng: &mut S,
    max_vertices: usize,
    rr_depth: u32,
    path: &mut Vec<Vertex>,
    stats: &mut PathStats,
) {
    path.clear();
    if max_vertices == 0 {
        return;
    }
    let beta = SampledSpectrum::splat(weight);
    path.push(Vertex::camera(ray.origin, camera.forward(), beta));
    let (_, pdf_dir) = camera.pdf_we(&ray);
    random_walk(
        scene,
        ray,
        lambda,
        rng,
        beta,
        pdf_dir,
        max_vertices - 1,
        TransportMode::Radiance,
        rr_depth,
        path,
        stats,
        WalkShift::CameraLanes,
    );
}
