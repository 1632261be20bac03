//! The random walk that extends camera and light subpaths surface by surface (BSDF sampling,
//! Russian roulette, the forward/reverse area densities MIS needs), and the camera subpath
//! built from it.

use crate::camera::Camera;
use crate::geometry::{spawn_ray, Ray};
use crate::integrator::fluorescence::events::{self as fluorescence, Direction, UNIT_LOBE};
use crate::integrator::subpath::vertex::{SampledFor, Vertex, VertexKind, ZERO_LANES};
use crate::integrator::{PathStats, SampleRng};
use crate::material::{BsdfSample, Frame, Material, MaterialFlags, ShadingContext, TransportMode};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};

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

/// Extend `path` by up to `max_new` surface vertices, starting with `ray` leaving the last
/// vertex of `path` with solid-angle density `pdf_dir` (1/sr) and throughput `beta`. Sets each
/// new vertex's `pdf_fwd` and its predecessor's `pdf_rev`.
#[allow(clippy::too_many_arguments)]
pub fn random_walk(
    scene: &Scene,
    mut ray: Ray,
    lambda: &SampledWavelengths,
    rng: &mut SampleRng,
    mut beta: SampledSpectrum,
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
    let mut pdf_fwd = pdf_dir;
    let mut lanes = path[path.len() - 1].lanes.intersect(lambda.lanes);
    // The wavelengths carried now (the pair's until a fluorescent event shifts them).
    let mut cur = path[path.len() - 1].wavelengths(lambda);
    let mut shifted = path[path.len() - 1].shifted.is_some();
    let mut moved = path[path.len() - 1].moved;
    // Scattering-only throughput for Russian roulette (β of light paths carries watts), without
    // the 1/η² radiance scaling of refraction: that factor is undone when the path leaves the
    // medium again, so a roulette on it would kill camera paths inside glass with probability
    // 1 − 1/η² and return the survivors with η² = 2.25× the throughput (fireflies through glass).
    let mut scatter = 1.0f32;
    let mut added = 0usize;
    // Where every bounce's BSDF sample is written (`Material::sample_into`).
    let mut record = BsdfSample::ZERO;
    // The lights' delta lines, which camera-side excitation draws include.
    let lines = scene.lights.delta_lines();
    loop {
        stats.rays += 1;
        let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
            // A camera path that leaves the scene ends on the environment light, if any.
            if mode == TransportMode::Radiance {
                if let Some(ei) = scene.lights.environment() {
                    let light = &scene.lights.lights()[ei as usize];
                    if let Some((p, n)) = light.escape_point(&ray) {
                        let mut v = Vertex::light(ei, p, glam::Vec3A::ZERO, n, beta);
                        v.wo = -ray.dir.normalize();
                        v.lanes = lanes;
                        v.shifted = shifted.then_some(cur.lambda);
                        v.moved = moved;
                        v.pdf_fwd = path[path.len() - 1].convert_density(pdf_fwd, &v);
                        path.push(v);
                    }
                }
            }
            break;
        };
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
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            delta: false,
            lanes,
            shifted: shifted.then_some(cur.lambda),
            unit_lobe: false,
            choice: [1.0; LANES],
            choice_rev: [1.0; LANES],
            moved,
            sampled_f: SampledSpectrum(ZERO_LANES),
            sampled_lambda: ZERO_LANES,
            sampled_for: SampledFor::NONE,
        };
        // The previous vertex read in place (a copy of the whole vertex cost a `memcpy`).
        v.pdf_fwd = path[path.len() - 1].convert_density(pdf_fwd, &v);
        // A fluorescent surface: the wavelength choice is made on arrival, so connections
        // from this vertex and the continuation see the new wavelengths.
        let rerad = match shift {
            WalkShift::Off => None,
            _ => scene.objects.reradiation(hit.object),
        };
        if let Some(rr) = rerad {
            cur.lanes = lanes;
            let dir = match shift {
                WalkShift::CameraLanes => Direction::Camera,
                _ => Direction::Light,
            };
            let before = cur.lambda;
            let u = rng.next_1d();
            let w = if shift == WalkShift::LightLanes {
                fluorescence::shift_lanes(rr, &mut cur, u, dir, lines)
            } else {
                let sh = fluorescence::shift_lanes_recorded(rr, &mut cur, u, dir, lines);
                v.choice = sh.own;
                v.choice_rev = sh.other;
                moved = moved.union(sh.moved);
                sh.weight
            };
            shifted |= cur.lambda != before;
            v.unit_lobe = true;
            beta *= w;
            scatter *= w.max_value();
            v.beta = beta;
            v.shifted = shifted.then_some(cur.lambda);
            v.moved = moved;
        }
        let unit_lobe = v.unit_lobe;
        path.push(v);
        added += 1;
        if added >= max_new || (rerad.is_some() && beta.is_black()) {
            break;
        }
        let material: &dyn Material = if unit_lobe {
            &UNIT_LOBE
        } else {
            scene.objects.material(hit.object)
        };
        let wo = frame.to_local(wo_world);
        let ctx = ShadingContext::at(hit.point, hit.geometric_normal, hit.shading_normal, hit.uv);
        let u_lobe = rng.next_1d();
        let u_dir = rng.next_2d();
        let Some(bs) = material.sample_into(wo, &ctx, &cur, u_lobe, u_dir, mode, &mut record)
        else {
            break;
        };
        if !(bs.pdf > 0.0) || bs.f.is_black() {
            break;
        }
        let n = path.len();
        if material.f_same_for_all_directions() {
            let v = &mut path[n - 1];
            v.sampled_f = bs.f;
            v.sampled_lambda = cur.lambda;
            v.sampled_for = SampledFor::new(mode, &cur);
        }
        let wi_world = frame.to_world(bs.wi);
        pdf_fwd = bs.pdf;
        // A specular sample makes a delta vertex: its two directions get the stand-in
        // densities of `delta_densities` (not zero: see there), and the material's reverse
        // density is not asked for (a plugin's material would cross the boundary for it).
        let pdf_rev;
        if bs.flags.is_specular() {
            path[n - 1].delta = true;
            (pdf_fwd, pdf_rev) = super::vertex::delta_densities(bs.wi, wo, bs.eta);
        } else {
            pdf_rev = material.pdf(bs.wi, wo, &ctx, &cur, flip(mode));
        }
        if bs.flags.contains(MaterialFlags::DISPERSIVE) {
            lanes = lanes.terminate_secondary();
        }
        let correction = crate::integrator::subpath::vertex::shading_normal_correction(
            hit.geometric_normal,
            hit.shading_normal,
            wo_world,
            wi_world,
            mode,
        );
        let factor = bs.wi.z.abs() / bs.pdf * correction;
        beta *= bs.f * factor;
        scatter *= (bs.f * factor).max_value();
        if mode == TransportMode::Radiance && bs.flags.contains(MaterialFlags::TRANSMISSION) {
            scatter *= bs.eta * bs.eta;
        }
        if beta.has_non_finite() || beta.is_black() {
            break;
        }
        path[n - 2].pdf_rev = path[n - 1].convert_density(pdf_rev, &path[n - 2]);
        if added as u32 >= rr_depth && scatter < 1.0 {
            let q = (1.0 - scatter).max(0.05);
            if rng.next_1d() < q {
                break;
            }
            beta = beta / (1.0 - q);
            scatter /= 1.0 - q;
        }
        ray = spawn_ray(hit.point, hit.point_error, hit.geometric_normal, wi_world);
    }
}

/// The camera subpath of one camera ray: the lens vertex plus up to `max_vertices − 1` more.
#[allow(clippy::too_many_arguments)]
pub fn generate_camera_subpath(
    scene: &Scene,
    camera: &dyn Camera,
    ray: Ray,
    weight: f32,
    lambda: &SampledWavelengths,
    rng: &mut SampleRng,
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
