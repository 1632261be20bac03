//! bdpt's MIS weights in a scene that renders fluorescence: per lane, because each lane of a
//! subpath keeps or shifts its wavelength on its own at a fluorescent vertex (as in pt and lt,
//! [`super::fluorescence`]), so the lanes of one connection are different paths in the
//! wavelength-extended path space.
//!
//! The density of strategy (s, t) for lane k of a path is the product of
//! - the area densities of its vertices, each from the subpath that makes it (as without
//!   fluorescence),
//! - at every fluorescent vertex, the probability of its event (keep, or shift λᵢ → λₒ with
//!   the density of the new wavelength) for the subpath that makes the vertex: the camera's
//!   excitation draw (with its line/continuous mixture) or the light's emission draw. Each
//!   vertex stores both ([`Vertex::choice`] for its own subpath, [`Vertex::choice_rev`] for
//!   the other), so moving a vertex to the other side multiplies by `choice_rev / choice`,
//! - the density of the wavelength drawn at the end the strategy starts from: the pair's
//!   mixture density at the observed wavelength λ_obs for strategies that start at the camera
//!   (s = 0, s = 1), at the emitted wavelength λ_emit for t = 1.
//!
//! Both subpaths start at the pair's wavelength and a shift only lengthens it (Stokes), so a
//! lane that shifted anywhere on the path has λ_emit < λ_obs and can be made only by the
//! strategies that sample every vertex on one subpath (s = 0, s = 1: the camera subpath; t = 1:
//! the light subpath); for them the end densities differ and enter the ratio. Every other
//! (s, t) joins two subpaths that started at the same wavelength and has density 0 for such a
//! lane (its connection gives it nothing, see `bdpt::connect`). A lane that never shifted is
//! made by every strategy, all starting from the same pair wavelength (which cancels), with
//! the keep probabilities of both ends in the densities.
//!
//! The structure mirrors [`super::bdpt::mis_weight`] (the same overrides of the densities at
//! the joined vertices) with a per-lane ratio and per-lane validity.

use super::bdpt::mis_weight_overrides;
use super::vertex::{remap0, Vertex};
use super::wavelength_mixture::WavelengthMixture;
use crate::camera::Camera;
use crate::scene::Scene;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};

/// Per-lane power-heuristic weight of strategy (s, t) for the lane paths it produced, relative
/// to every strategy that can make the same lane path (module docs). `sampled` as for
/// [`super::bdpt::mis_weight`].
pub fn mis_weight_lanes(
    scene: &Scene,
    camera: &dyn Camera,
    mixture: &WavelengthMixture,
    (light_path, camera_path): (&[Vertex], &[Vertex]),
    sampled: Option<&Vertex>,
    (s, t): (usize, usize),
    lambda: &SampledWavelengths,
) -> SampledSpectrum {
    let o = mis_weight_overrides(
        scene,
        camera,
        light_path,
        camera_path,
        sampled,
        s,
        t,
        lambda,
    );
    let pt = o.pt;
    let qs = o.qs;
    // (pdf_fwd, pdf_rev, delta, choice, choice_rev) of camera vertex i and light vertex i.
    let cam = |i: usize| -> (f32, f32, bool, [f32; LANES], [f32; LANES]) {
        if i + 1 == t {
            (pt.pdf_fwd, o.pt_rev, false, pt.choice, pt.choice_rev)
        } else {
            let v = &camera_path[i];
            let rev = if i + 2 == t {
                o.pt_minus_rev.unwrap_or(v.pdf_rev)
            } else {
                v.pdf_rev
            };
            (v.pdf_fwd, rev, v.delta, v.choice, v.choice_rev)
        }
    };
    let light_v = |i: usize| -> &Vertex {
        match (&qs, i + 1 == s) {
            (Some(q), true) => q,
            _ => &light_path[i],
        }
    };
    let light = |i: usize| -> (f32, f32, bool) {
        let v = light_v(i);
        if i + 1 == s {
            (v.pdf_fwd, o.qs_rev.unwrap_or(v.pdf_rev), false)
        } else if i + 2 == s {
            (v.pdf_fwd, o.qs_minus_rev.unwrap_or(v.pdf_rev), v.delta)
        } else {
            (v.pdf_fwd, v.pdf_rev, v.delta)
        }
    };
    // The lanes shifted somewhere on this strategy's path, and the ratio of the end densities
    // (the other end's over this strategy's own) for them.
    let camera_start = t >= 2 && s <= 1;
    let (moved, far_end) = if camera_start {
        (pt.moved, Some(pt.wavelengths(lambda)))
    } else if t == 1 {
        let q = qs.as_ref().unwrap_or(&light_path[s - 1]);
        (q.moved, Some(q.wavelengths(lambda)))
    } else {
        (LaneMask::NONE, None)
    };
    let mut end_ratio = [1.0f32; LANES];
    if let Some(far) = far_end {
        for (k, r) in end_ratio.iter_mut().enumerate() {
            if moved.contains(k) && lambda.pdf[k] > 0.0 {
                *r = (mixture.lane_density(far.lambda[k]) / lambda.pdf[k] as f64) as f32;
            }
        }
    }
    let sq = |x: f32| x * x;
    let mut sum = [0.0f32; LANES];
    // Camera vertices moved to the light subpath, one at a time: strategy (s + t − i, i).
    let mut ri = [1.0f32; LANES];
    for i in (1..t).rev() {
        let (fwd, rev, delta, own, other) = cam(i);
        let structural = !delta && !cam(i - 1).2;
        let s_alt = s + t - i;
        for k in 0..LANES {
            ri[k] *= sq(remap0(rev) * other[k] / (remap0(fwd) * own[k]));
            if i == 1 && camera_start {
                ri[k] *= sq(end_ratio[k]);
            }
            if structural && (!moved.contains(k) || s_alt <= 1 || i == 1) {
                sum[k] += ri[k];
            }
        }
    }
    // Light vertices moved to the camera subpath: strategy (i, s + t − i).
    ri = [1.0f32; LANES];
    for i in (0..s).rev() {
        let (fwd, rev, delta) = light(i);
        let v = light_v(i);
        let delta_before = if i > 0 {
            light(i - 1).2
        } else {
            light_v(0).is_unhittable_light(scene)
        };
        let structural = !delta && !delta_before;
        for k in 0..LANES {
            ri[k] *= sq(remap0(rev) * v.choice_rev[k] / (remap0(fwd) * v.choice[k]));
            if i + 1 == s && t == 1 {
                ri[k] *= sq(end_ratio[k]);
            }
            if structural && (!moved.contains(k) || i <= 1) {
                sum[k] += ri[k];
            }
        }
    }
    SampledSpectrum(std::array::from_fn(|k| {
        let w = 1.0 / (1.0 + sum[k]);
        if w.is_finite() {
            w
        } else {
            0.0
        }
    }))
}
