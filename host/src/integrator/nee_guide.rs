//! [`NeeGuide`]: where on an area light the path tracer's next-event estimation aims, learned
//! per region of the scene from how much of the light is visible there.
//!
//! Why: a light seen through an opening (a sky panel behind a window, a lamp inside a
//! luminaire's housing) is mostly hidden from most receivers. Uniform light sampling then
//! spends most shadow rays on occluded points, and the estimate is a few unoccluded samples
//! among many zeros: binary visibility noise. The guide draws the light's sample numbers
//! `u ∈ [0, 1)²` from a piecewise-constant density over `CELLS × CELLS` cells, learned per key
//! (a voxel of a coarse grid over the scene bounds, and the major axis of the receiver's normal
//! turned to the side it is lit from), in proportion to the unoccluded contribution measured
//! there before rendering, mixed with the uniform density so no cell is ever starved.
//!
//! Unbiasedness: a light that offers [`Light::sample_coords`] maps `u` to its points
//! one-to-one from every receiver (an area light's chart, an environment's directions), with
//! [`Light::pdf_li`] the density of uniform `u`. Drawing `u` with
//! density `q(u)` (`q ≥ UNIFORM_SHARE > 0` everywhere) gives the point the density
//! `pdf_li · q(u)`, which next-event estimation divides by and which the MIS weight of a
//! BSDF-sampled ray that hits the light evaluates at the hit's `u` and the previous vertex's
//! key ([`NeeGuide::pdf_factor`]): both strategies see one density.
//!
//! BDPT's s = 1 strategy (a fresh light point joined to camera vertex t, next-event estimation
//! from that vertex) draws its light points with the same guide, keyed by the camera vertex
//! and the side its camera subpath arrives from; its MIS weights carry the factor wherever that
//! strategy's density enters the power heuristic (`bdpt::mis::s1_guide_factor`).
//!
//! The pre-pass ([`NeeGuide::build`]) is deterministic: a fixed number of camera paths from a
//! Sobol' sequence under the render's seed, in fixed chunks reduced in order (the same guide
//! whatever the thread count). At each non-specular vertex (BSDF-sampled paths, up to
//! [`PREPASS_DEPTH`] vertices) one light is chosen as the render chooses lights and, when it
//! offers sample coordinates, one shadow ray goes to a jittered point of each of its cells; the
//! unoccluded contribution `L·cos_receiver/pdf_li` (the light's radiance, cosine at the
//! receiver on its lit side, density of the point) is summed per key and cell. The guide is
//! switched on for a light only where it pays: when at least [`OCCLUSION_THRESHOLD`] of the
//! pre-pass contribution towards it was occluded (or when forced with
//! `--effect visibility-guide=on`).
//!
//! | parameter               | value | meaning |
//! |-------------------------|-------|---------|
//! | [`CELLS`]               | 8     | cells per side of the light's `u`-square (64 cells) |
//! | [`GRID`]                | 10    | voxels along the scene bounds' longest axis (the others in proportion, at least 1) |
//! | [`PREPASS_PATHS`]       | 2048  | camera paths of the pre-pass |
//! | [`SCOUT_PATHS`]         | 512   | paths after which the pre-pass stops when every light is less than 15% occluded (half the threshold): the guide stays off at a quarter of the cost |
//! | [`PREPASS_DEPTH`]       | 3     | non-specular vertices at most per pre-pass path |
//! | [`MIN_VERTICES`]        | 4     | pre-pass vertices a key needs before its learned density is used (else uniform) |
//! | [`UNIFORM_SHARE`]       | 0.2   | share of the uniform density in every learned one (defensive mixture: a cell's density is at least 0.2, so the estimate is at most 5× that of uniform sampling where the guide is wrong) |
//! | [`OCCLUSION_THRESHOLD`] | 0.3   | occluded share of the pre-pass contribution from which a light is guided |
//!
//! Environments (the constant sky, image maps, the CIE skies) are guided through their
//! directions: a cell of `u` is a patch of sky, the same patch from every receiver, so a
//! window's view of the sky is learned per region like a sky panel's.
//!
//! Limits: lights without sample coordinates (spheres, meshes of more than
//! [`COORDS_MAX_TRIANGLES`](crate::geometry::COORDS_MAX_TRIANGLES) triangles, plugin
//! environments, point-like lights) are sampled as before; the density ignores the BSDF (it
//! is learned for the receiver's cosine), so a glossy receiver gains only from visibility; a voxel is coarse
//! where visibility changes fast (close to an opening), where the uniform share keeps the
//! estimate sound.

use crate::camera::{Camera, CameraSample};
use crate::geometry::{spawn_ray, spawn_ray_to, Aabb};
use crate::light::{Light, LightSampleContext};
use crate::material::{Frame, MaterialFlags, ShadingContext, TransportMode};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use glam::{Vec2, Vec3A};
use rayon::prelude::*;

/// Cells per side of a light's sample square.
pub const CELLS: usize = 8;
/// Cells of a light's sample square.
const N2: usize = CELLS * CELLS;
/// Voxels along the longest axis of the scene bounds.
pub const GRID: u32 = 10;
/// Camera paths of the pre-pass.
pub const PREPASS_PATHS: u32 = 2048;
/// Non-specular vertices at most per pre-pass path.
pub const PREPASS_DEPTH: u32 = 3;
/// Pre-pass vertices a key needs before its learned density is used.
pub const MIN_VERTICES: u32 = 4;
/// Share of the uniform density in every learned density.
pub const UNIFORM_SHARE: f32 = 0.2;
/// Occluded share of the pre-pass contribution from which a light is guided.
pub const OCCLUSION_THRESHOLD: f64 = 0.3;
/// Pre-pass paths after which a pre-pass that finds every light at most half as occluded as
/// [`OCCLUSION_THRESHOLD`] stops (the guide stays off).
pub const SCOUT_PATHS: u32 = 512;
/// Pre-pass paths per work unit (fixed, so the reduction order never depends on threads).
const CHUNK: u32 = 64;
/// Key of a point the guide knows nothing about (always uniform).
pub const NO_KEY: u32 = u32::MAX;

/// One key's density over the cells: the density factor of each cell (its probability × n²,
/// the density of `u` there) and the cumulative sums that draw a cell (row from the
/// marginal, column from the row's conditional). A fixed-size table of f32 (580 bytes) so a
/// draw reads a few cache lines and scans eight entries, where the general
/// [`Distribution2D`](crate::light::distribution2d::Distribution2D) keeps heap rows of f64.
#[derive(Clone, Debug, PartialEq)]
struct CellTable {
    /// Row-major (row = `t` cell, column = `s` cell): probability × `N2`.
    factor: [f32; N2],
    /// Marginal cumulative sums over rows, `row_cdf[0] = 0`, `row_cdf[CELLS] = 1`.
    row_cdf: [f32; CELLS + 1],
    /// Per row, cumulative sums over its columns (normalised to end at 1).
    col_cdf: [[f32; CELLS + 1]; CELLS],
}

/// Index of the last cumulative entry `≤ u` among `cdf[..CELLS]` whose cell has positive
/// width, and the offset of `u` within that cell, in [0, 1).
#[inline]
fn pick(cdf: &[f32; CELLS + 1], u: f32) -> (usize, f32) {
    let mut i = 0;
    while i + 1 < CELLS && cdf[i + 1] <= u {
        i += 1;
    }
    // Cells of zero width are never chosen (a defensive mixture has none, but rounding may).
    while i > 0 && cdf[i + 1] <= cdf[i] {
        i -= 1;
    }
    let w = cdf[i + 1] - cdf[i];
    let off = if w > 0.0 {
        ((u - cdf[i]) / w).clamp(0.0, MAX_OFFSET)
    } else {
        0.5
    };
    (i, off)
}

/// Largest offset inside a cell: `(cell + offset) / CELLS` stays below the next cell for every
/// cell (1 − 2⁻²⁰ is two f32 steps below 8, the largest `cell + 1`).
const MAX_OFFSET: f32 = 1.0 - 1.0 / (1u32 << 20) as f32;

impl CellTable {
    /// From non-negative cell weights (row-major), mixed with [`UNIFORM_SHARE`] of the uniform
    /// density; `None` when they sum to nothing.
    fn new(weights: &[f64; N2]) -> Option<Self> {
        let total: f64 = weights.iter().sum();
        if !(total > 0.0) || !total.is_finite() {
            return None;
        }
        let uniform = UNIFORM_SHARE as f64 / N2 as f64;
        let learned = 1.0 - UNIFORM_SHARE as f64;
        let p: Vec<f64> = weights
            .iter()
            .map(|w| uniform + learned * w / total)
            .collect();
        // The factor a cell is drawn with, from the same cumulative sums that draw it.
        let mut row_cdf = [0.0f32; CELLS + 1];
        let mut col_cdf = [[0.0f32; CELLS + 1]; CELLS];
        let mut factor = [0.0f32; N2];
        let mut acc = 0.0f64;
        let mut rows = [0.0f64; CELLS];
        for r in 0..CELLS {
            rows[r] = p[r * CELLS..(r + 1) * CELLS].iter().sum();
        }
        let rows_total: f64 = rows.iter().sum();
        for r in 0..CELLS {
            acc += rows[r];
            row_cdf[r + 1] = (acc / rows_total) as f32;
            let mut c_acc = 0.0;
            for c in 0..CELLS {
                c_acc += p[r * CELLS + c];
                col_cdf[r][c + 1] = (c_acc / rows[r]) as f32;
            }
            col_cdf[r][CELLS] = 1.0;
        }
        row_cdf[CELLS] = 1.0;
        for r in 0..CELLS {
            let pr = row_cdf[r + 1] as f64 - row_cdf[r] as f64;
            for c in 0..CELLS {
                let pc = col_cdf[r][c + 1] as f64 - col_cdf[r][c] as f64;
                factor[r * CELLS + c] = (pr * pc * N2 as f64) as f32;
            }
        }
        Some(Self {
            factor,
            row_cdf,
            col_cdf,
        })
    }

    /// `u` drawn from the density with the numbers `v`, and its density factor.
    #[inline]
    fn sample(&self, v: Vec2) -> (Vec2, f32) {
        let (r, oy) = pick(&self.row_cdf, v.y);
        let (c, ox) = pick(&self.col_cdf[r], v.x);
        let n = CELLS as f32;
        (
            Vec2::new((c as f32 + ox) / n, (r as f32 + oy) / n),
            self.factor[r * CELLS + c],
        )
    }

    /// Density factor at `u`.
    #[inline]
    fn factor_at(&self, u: Vec2) -> f32 {
        let n = CELLS as f32;
        let c = ((u.x * n) as usize).min(CELLS - 1);
        let r = ((u.y * n) as usize).min(CELLS - 1);
        self.factor[r * CELLS + c]
    }
}

/// The coarse grid over the scene bounds that keys are made of.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Grid {
    min: Vec3A,
    inv_cell: f32,
    dims: [u32; 3],
}

impl Grid {
    /// [`GRID`] voxels along the longest axis of `bounds`; `None` for empty or infinite ones.
    fn new(bounds: &Aabb) -> Option<Self> {
        let e = bounds.max - bounds.min;
        let longest = e.max_element();
        if !(longest > 0.0) || !longest.is_finite() || !bounds.min.is_finite() {
            return None;
        }
        let cell = longest / GRID as f32;
        let dims = [e.x, e.y, e.z].map(|x| ((x / cell).ceil() as u32).clamp(1, GRID));
        Some(Self {
            min: bounds.min,
            inv_cell: 1.0 / cell,
            dims,
        })
    }

    fn keys(&self) -> usize {
        self.dims.iter().map(|&d| d as usize).product::<usize>() * 6
    }

    /// The key of point `p` with the normal `n` turned to the lit side: its voxel (clamped to
    /// the grid) and the major axis of `n` with its sign.
    #[inline]
    fn key(&self, p: Vec3A, n: Vec3A) -> u32 {
        let q = (p - self.min) * self.inv_cell;
        let v = [q.x, q.y, q.z];
        let mut idx = 0u32;
        for a in (0..3).rev() {
            let c = (v[a].max(0.0) as u32).min(self.dims[a] - 1);
            idx = idx * self.dims[a] + c;
        }
        let a = n.abs();
        let axis = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let neg = ([n.x, n.y, n.z][axis] < 0.0) as u32;
        idx * 6 + axis as u32 * 2 + neg
    }
}

/// The guide of one light: a table index per key (`u32::MAX`: uniform) and the tables.
#[derive(Clone, Debug)]
struct LightGuide {
    index: Vec<u32>,
    tables: Vec<CellTable>,
}

/// What the pre-pass found for one light (see [`NeeGuide::reports`]).
#[derive(Clone, Debug, PartialEq)]
pub struct LightReport {
    /// Index of the light in the scene's list.
    pub light: usize,
    /// Share of the pre-pass's unoccluded-or-not contribution towards it that was occluded.
    pub occluded_share: f64,
    /// Keys with a learned density.
    pub keys: usize,
    /// Guided in the render.
    pub on: bool,
}

/// The visibility guide of a render (see the module docs).
#[derive(Clone, Debug)]
pub struct NeeGuide {
    grid: Grid,
    /// Per light of the scene, its guide when it is on.
    lights: Vec<Option<LightGuide>>,
    reports: Vec<LightReport>,
    seconds: f64,
}

/// One pre-pass vertex's measurement: its key, the light, the unoccluded contribution per
/// cell and the total contribution with occluded rays counted.
struct Record {
    key: u32,
    light: u32,
    visible: [f32; N2],
    all: f64,
}

/// Per-light sums of the pre-pass, in the order records arrive.
#[derive(Default)]
struct LightSums {
    /// key → (vertices, per-cell sums), sparse.
    keys: std::collections::HashMap<u32, (u32, Box<[f64; N2]>)>,
    visible: f64,
    all: f64,
}

impl NeeGuide {
    /// The guide for `scene` seen through `camera` under the render seed `seed`, or `None`
    /// when no light is guided. `force`: `Some(true)` guides every light that offers sample
    /// coordinates whatever its occlusion, `Some(false)` none (no pre-pass), `None` those past
    /// [`OCCLUSION_THRESHOLD`]. `threads` run the pre-pass (the render's; `None`: one per
    /// core).
    pub fn build(
        scene: &Scene,
        camera: &dyn Camera,
        seed: u64,
        force: Option<bool>,
        threads: Option<usize>,
    ) -> Option<Self> {
        if force == Some(false) {
            return None;
        }
        let start = std::time::Instant::now();
        let lights = scene.lights.lights();
        let eligible: Vec<bool> = lights.iter().map(|l| Self::can_guide(l.as_ref())).collect();
        if !eligible.iter().any(|&e| e) {
            return None;
        }
        let grid = Grid::new(&scene.geometry.bounds())?;
        let pool = super::tiled::thread_pool(threads).ok()?;
        let trace = |chunks: std::ops::Range<u32>| -> Vec<Vec<Record>> {
            let chunks: Vec<u32> = chunks.collect();
            pool.install(|| {
                chunks
                    .par_iter()
                    .map(|&c| {
                        let mut out = Vec::new();
                        let end = ((c + 1) * CHUNK).min(PREPASS_PATHS);
                        for i in c * CHUNK..end {
                            trace_prepass_path(scene, camera, &grid, &eligible, seed, i, &mut out);
                        }
                        out
                    })
                    .collect()
            })
        };
        // A first [`SCOUT_PATHS`] paths; where no light is half-way to the threshold (a light
        // visible from nearly everywhere) the guide stays off at a quarter of the cost.
        let scout = SCOUT_PATHS.div_ceil(CHUNK);
        let mut records = trace(0..scout);
        if force != Some(true) {
            let (mut vis, mut all) = (vec![0.0f64; lights.len()], vec![0.0f64; lights.len()]);
            for r in records.iter().flatten() {
                vis[r.light as usize] += r.visible.iter().map(|&v| v as f64).sum::<f64>();
                all[r.light as usize] += r.all;
            }
            let promising = (0..lights.len())
                .any(|l| all[l] > 0.0 && 1.0 - vis[l] / all[l] >= 0.5 * OCCLUSION_THRESHOLD);
            if !promising {
                return None;
            }
        }
        records.extend(trace(scout..PREPASS_PATHS.div_ceil(CHUNK)));
        let mut sums: Vec<LightSums> = (0..lights.len()).map(|_| LightSums::default()).collect();
        for r in records.iter().flatten() {
            let s = &mut sums[r.light as usize];
            let (count, cells) = s
                .keys
                .entry(r.key)
                .or_insert_with(|| (0, Box::new([0.0; N2])));
            *count += 1;
            let mut vis = 0.0;
            for (acc, v) in cells.iter_mut().zip(&r.visible) {
                *acc += *v as f64;
                vis += *v as f64;
            }
            s.visible += vis;
            s.all += r.all;
        }
        let mut guides = Vec::with_capacity(lights.len());
        let mut reports = Vec::new();
        for (li, s) in sums.into_iter().enumerate() {
            if !eligible[li] || !(s.all > 0.0) {
                guides.push(None);
                continue;
            }
            let occluded_share = (1.0 - s.visible / s.all).clamp(0.0, 1.0);
            let on = force == Some(true) || occluded_share >= OCCLUSION_THRESHOLD;
            let mut g = LightGuide {
                index: Vec::new(),
                tables: Vec::new(),
            };
            if on {
                g.index = vec![u32::MAX; grid.keys()];
                // Keys in increasing order: the same tables whatever the hash map's order.
                let mut keys: Vec<_> = s.keys.into_iter().collect();
                keys.sort_unstable_by_key(|(k, _)| *k);
                for (k, (count, cells)) in keys {
                    if count < MIN_VERTICES {
                        continue;
                    }
                    if let Some(t) = CellTable::new(&cells) {
                        g.index[k as usize] = g.tables.len() as u32;
                        g.tables.push(t);
                    }
                }
            }
            // A light with no region learned (too few pre-pass vertices anywhere, as among
            // many lights) is sampled as before and holds no index.
            let on = on && !g.tables.is_empty();
            reports.push(LightReport {
                light: li,
                occluded_share,
                keys: g.tables.len(),
                on,
            });
            guides.push(on.then_some(g));
        }
        let seconds = start.elapsed().as_secs_f64();
        Some(Self {
            grid,
            lights: guides,
            reports,
            seconds,
        })
        .filter(|g| g.lights.iter().any(Option::is_some))
    }

    /// True when the guide can draw `light`'s points: an area or environment light that
    /// offers sample coordinates ([`Light::sample_coords`]; asked for the point where one of
    /// its emitted rays starts, seen from a receiver along that ray, where every light with a
    /// chart or a direction map has one).
    pub fn can_guide(light: &dyn Light) -> bool {
        use crate::light::LightFlags;
        let flags = light.flags();
        (flags.contains(LightFlags::AREA) || flags.contains(LightFlags::ENVIRONMENT))
            && light
                .sample_le(Vec2::splat(0.5), Vec2::splat(0.5), &probe_wavelengths())
                .and_then(|s| light.sample_coords(s.ray.origin + s.ray.dir, s.ray.origin))
                .is_some()
    }

    /// What the pre-pass found, per light that offers sample coordinates.
    pub fn reports(&self) -> &[LightReport] {
        &self.reports
    }

    /// Wall-clock seconds of the pre-pass.
    pub fn seconds(&self) -> f64 {
        self.seconds
    }

    /// The run-time notes of the guided lights, naming them with `name(light)`.
    pub fn notes(&self, name: impl Fn(usize) -> String) -> Vec<String> {
        self.reports
            .iter()
            .filter(|r| r.on)
            .map(|r| {
                format!(
                    "visibility-guide on for {}: {:.0}% of its pre-pass contribution occluded, \
                     {} regions learned, pre-pass {:.3} s (counted in the render time; \
                     --effect visibility-guide=off samples it uniformly)",
                    name(r.light),
                    100.0 * r.occluded_share,
                    r.keys,
                    self.seconds
                )
            })
            .collect()
    }

    /// True when light `light` is guided.
    #[inline]
    pub fn guides(&self, light: usize) -> bool {
        self.lights.get(light).is_some_and(Option::is_some)
    }

    /// The key of a receiver at `p` with geometric normal `n`, lit from the side of `w`
    /// (the direction back along the path).
    #[inline]
    pub fn key(&self, p: Vec3A, n: Vec3A, w: Vec3A) -> u32 {
        let n = if n.dot(w) < 0.0 { -n } else { n };
        self.grid.key(p, n)
    }

    /// The light's sample numbers for next-event estimation from key `key`, drawn from the
    /// numbers `v`, and the density factor of the point they make (multiply the light's
    /// `pdf_li` by it): `(v, 1)` where the light or the key is not guided.
    #[inline]
    pub fn sample(&self, light: usize, key: u32, v: Vec2) -> (Vec2, f32) {
        match self.table(light, key) {
            Some(t) => t.sample(v),
            None => (v, 1.0),
        }
    }

    /// The density factor of the point `p_light` of light `light` from the receiver at
    /// `receiver` of key `key`: the same as [`sample`](Self::sample) gives for the numbers
    /// that make it.
    #[inline]
    pub fn pdf_factor(
        &self,
        light: usize,
        key: u32,
        l: &dyn Light,
        receiver: Vec3A,
        p_light: Vec3A,
    ) -> f32 {
        match self.table(light, key) {
            Some(t) => l
                .sample_coords(receiver, p_light)
                .map_or(1.0, |u| t.factor_at(u)),
            None => 1.0,
        }
    }

    #[inline]
    fn table(&self, light: usize, key: u32) -> Option<&CellTable> {
        let g = self.lights.get(light)?.as_ref()?;
        let i = *g.index.get(key as usize)?;
        g.tables.get(i as usize)
    }
}

/// Fixed wavelengths for the pre-pass's radiance (the guide is one density for all).
fn probe_wavelengths() -> SampledWavelengths {
    SampledWavelengths::sample_visible(0.5)
}

/// Salt of the pre-pass's sampler seed (independent of the render's numbers).
const PREPASS_SALT: u64 = 0x6E65_655F_6775_6964;

/// Pre-pass path `index`: a camera ray through a Sobol' point of the film, then BSDF sampling;
/// at each non-specular vertex one light chosen as the render chooses and, when it is
/// eligible, one shadow ray per cell (a [`Record`] into `out`).
fn trace_prepass_path(
    scene: &Scene,
    camera: &dyn Camera,
    grid: &Grid,
    eligible: &[bool],
    seed: u64,
    index: u32,
    out: &mut Vec<Record>,
) {
    let mut rng = PixelSampler::new(seed ^ PREPASS_SALT, 0, index);
    let (w, h) = camera.resolution();
    let film = rng.next_2d();
    let lens = rng.next_2d();
    let lambda = SampledWavelengths::sample_visible(rng.next_1d());
    let sample = CameraSample {
        p_film: Vec2::new(film.x * w as f32, film.y * h as f32),
        p_lens: lens,
    };
    let Some(cr) = camera.generate_ray(&sample) else {
        return;
    };
    let mut ray = cr.ray;
    let mut vertices = 0;
    let mut record = crate::material::BsdfSample::ZERO;
    for _bounce in 0..4 * PREPASS_DEPTH {
        let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
            return;
        };
        let material = scene.objects.material(hit.object);
        let flags = material.flags();
        if !flags
            .intersects(MaterialFlags::DIFFUSE | MaterialFlags::GLOSSY | MaterialFlags::SPECULAR)
        {
            return;
        }
        let back = -ray.dir.normalize();
        let u_light = rng.next_1d();
        let u_lobe = rng.next_1d();
        let u_dir = rng.next_2d();
        if flags.has_non_specular() {
            vertices += 1;
            if let Some((li, _)) = scene.lights.sample(u_light) {
                if eligible[li] {
                    let two_sided = flags.contains(MaterialFlags::TRANSMISSION);
                    out.push(measure(
                        scene,
                        grid,
                        &hit,
                        back,
                        two_sided,
                        (li, scene.lights.lights()[li].as_ref()),
                        &lambda,
                        &mut rng,
                    ));
                }
            }
            if vertices >= PREPASS_DEPTH {
                return;
            }
        }
        let frame = Frame::from_normal(hit.shading_normal);
        let wo = frame.to_local(back);
        let sctx = ShadingContext::at(hit.point, hit.geometric_normal, hit.shading_normal, hit.uv);
        let Some(bs) = material.sample_into(
            wo,
            &sctx,
            &lambda,
            u_lobe,
            u_dir,
            TransportMode::Radiance,
            &mut record,
        ) else {
            return;
        };
        if !(bs.pdf > 0.0) || bs.f.is_black() {
            return;
        }
        ray = spawn_ray(
            hit.point,
            hit.point_error,
            hit.geometric_normal,
            frame.to_world(bs.wi),
        );
    }
}

/// One pre-pass vertex's shadow rays towards light `li`: one jittered point per cell.
#[allow(clippy::too_many_arguments)]
fn measure(
    scene: &Scene,
    grid: &Grid,
    hit: &crate::geometry::Hit,
    back: Vec3A,
    two_sided: bool,
    (li, light): (usize, &dyn Light),
    lambda: &SampledWavelengths,
    rng: &mut PixelSampler,
) -> Record {
    let n = hit.geometric_normal;
    let n_lit = if n.dot(back) < 0.0 { -n } else { n };
    let ctx = LightSampleContext {
        p: hit.point,
        p_error: hit.point_error,
        n,
    };
    let mut rec = Record {
        key: grid.key(hit.point, n_lit),
        light: li as u32,
        visible: [0.0; N2],
        all: 0.0,
    };
    let inv = 1.0 / CELLS as f32;
    for (c, vis) in rec.visible.iter_mut().enumerate() {
        let j = rng.next_2d();
        let u = Vec2::new(
            ((c % CELLS) as f32 + j.x) * inv,
            ((c / CELLS) as f32 + j.y) * inv,
        );
        let Some(ls) = light.sample_li(&ctx, u, lambda) else {
            continue;
        };
        let cos = ls.wi.dot(n_lit);
        let cos = if two_sided { cos.abs() } else { cos.max(0.0) };
        if !(ls.pdf > 0.0) || !(cos > 0.0) {
            continue;
        }
        let value = ls.radiance.average() * cos / ls.pdf;
        if !(value > 0.0) || !value.is_finite() {
            continue;
        }
        rec.all += value as f64;
        let (shadow, t_max) = spawn_ray_to(
            hit.point,
            hit.point_error,
            n,
            ls.p_light,
            ls.p_light_error,
            ls.n_light,
        );
        if !scene.geometry.occluded(&shadow, t_max) {
            *vis = value;
        }
    }
    rec
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table's density factors average to 1 over the cells (the density of `u` integrates
    /// to 1 over [0, 1]², to f32 rounding: 1e-5), each is at least the uniform share (0.2,
    /// up to 1e-5), and its draws land in the cells with the frequencies it claims: 200 000
    /// draws from a low-discrepancy-free hash sequence, chi-square over the 64 cells below
    /// 120 (63 degrees of freedom: the 99.999th percentile is about 118; a wrong cell
    /// probability of 10% in one cell of probability 1/64 adds ~31 by itself).
    #[test]
    fn table_density_integrates_to_one_and_matches_its_draws() {
        let mut w = [0.0f64; N2];
        for (i, x) in w.iter_mut().enumerate() {
            // A lopsided pattern with empty cells, like a window's view of a sky.
            *x = if (i % CELLS) > 4 || (i / CELLS) < 2 {
                0.0
            } else {
                (1 + i * 7 % 13) as f64
            };
        }
        let t = CellTable::new(&w).unwrap();
        let mean: f64 = t.factor.iter().map(|&f| f as f64).sum::<f64>() / N2 as f64;
        assert!((mean - 1.0).abs() < 1e-5, "mean density {mean}");
        let floor = t.factor.iter().cloned().fold(f32::MAX, f32::min);
        assert!(floor >= UNIFORM_SHARE - 1e-5, "smallest density {floor}");
        let n = 200_000u64;
        let mut counts = [0u64; N2];
        let mut state = 0x1234_5678_9abc_def0u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 40) as f32) / (1u64 << 24) as f32
        };
        for _ in 0..n {
            let v = Vec2::new(next(), next());
            let (u, f) = t.sample(v);
            assert!(
                (0.0..1.0).contains(&u.x) && (0.0..1.0).contains(&u.y),
                "{u:?}"
            );
            assert_eq!(
                f,
                t.factor_at(u),
                "the draw's factor is the one at its point"
            );
            counts[(u.y * CELLS as f32) as usize * CELLS + (u.x * CELLS as f32) as usize] += 1;
        }
        let chi2: f64 = counts
            .iter()
            .zip(&t.factor)
            .map(|(&c, &f)| {
                let e = n as f64 * f as f64 / N2 as f64;
                (c as f64 - e).powi(2) / e
            })
            .sum();
        assert!(chi2 < 120.0, "chi-square {chi2} over 64 cells");
    }

    /// Keys: the voxel and the signed major axis; points past the bounds clamp to the edge
    /// voxel; the normal is turned to the side the path arrives from.
    #[test]
    fn keys_follow_voxel_and_lit_side() {
        let n = GRID as f32;
        let bounds = Aabb {
            min: Vec3A::ZERO,
            max: Vec3A::new(n, n / 2.0, 1.0),
        };
        let g = Grid::new(&bounds).unwrap();
        assert_eq!(g.dims, [GRID, GRID / 2, 1]);
        assert_eq!(g.key(Vec3A::new(0.5, 0.5, 0.5), Vec3A::Y), 2);
        assert_eq!(g.key(Vec3A::new(-3.0, 0.5, 0.5), -Vec3A::Y), 3);
        let far = Vec3A::new(n - 0.5, n / 2.0 - 0.5, 9.0);
        assert_eq!(g.key(far, Vec3A::X), ((GRID / 2 - 1) * GRID + GRID - 1) * 6);
        assert_eq!(
            g.key(far, -Vec3A::Z),
            ((GRID / 2 - 1) * GRID + GRID - 1) * 6 + 5
        );
    }
}
