//! A spectral unidirectional path tracer: next-event estimation with multiple importance
//! sampling (power heuristic, β = 2) between light and BSDF sampling, Russian roulette, and hero
//! wavelength sampling with several wavelength groups per path (see [`super::wavelengths::groups`]):
//! all groups share one geometric path, sampled with the hero group, until a dispersive event
//! keeps only the hero wavelength.

use super::driver::{Integrator, IntegratorInfo, IntegratorOutput, Registration};
use super::fluorescence::events::{shift_lanes, Direction, UNIT_LOBE};
use super::mis::power_heuristic;
use super::nee_guide::{NeeGuide, NO_KEY};
use super::pixel_max::PixelMaxY;
use super::render::ProgressFn;
use super::render::{PathStats, PathTracer, SampleBudget};
use super::tiled::render_tiles;
use super::wavelengths::flat_colour::FlatColour;
use super::wavelengths::groups::{PathWavelengthSampler, PathWavelengths, MAX_GROUPS};
use super::{PixelSampler, RenderError, RenderResult, RenderSettings};
use crate::camera::CameraSample;
use crate::film::spectral::SpectralBins;
use crate::film::spectral_film::LaneEnergies;
use crate::film::{FilmState, Sensor};
use crate::geometry::{spawn_ray, spawn_ray_to, Hit, Ray};
use crate::integrator::plan::RenderPlan;
use crate::light::{LightFlags, LightSampleContext};
use crate::material::{BsdfSample, Frame, Material, MaterialFlags, ShadingContext, TransportMode};
use crate::scene::Scene;
use crate::spectrum::wavelength_sampling::rotated;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use glam::Vec2;
use spectrace_plugin_api::ParamDoc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Bounce from which path tracing's Russian roulette may end a path, used wherever the render
/// settings carry the shared default ([`PathTracer::default`]'s `rr_depth`, 3, which BDPT and
/// light tracing keep); any other value in the settings is taken as given.
///
/// Why 5 and not 3: on the Cornell box (albedo about 0.7) a path's throughput after three
/// bounces is about 0.35, so roulette from bounce 3 ended two thirds of the paths there and
/// multiplied the survivors by ~3, and the light they carry is a large part of the image. At
/// 64 spp (three seeds, MSE against the Mitsuba 3 reference in linear sRGB) the MSE per pixel
/// falls from 5.17e-5 (from bounce 3) to 4.28e-5 (4), 3.80e-5 (5), 3.53e-5 (6), 3.30e-5 (8)
/// while a camera sample traces 4.63, 5.26, 5.88, 6.44, 7.42 rays: MSE × cost is lowest at
/// 5–6 (11% below 3) and rises again by 8. Mitsuba 3's path tracer also starts at 5.
pub const PT_RR_DEPTH: u32 = 5;

/// Type information of path tracing.
pub const INFO: IntegratorInfo = IntegratorInfo {
    name: "pt",
    aliases: &["path"],
    version: 1,
    description: "unidirectional path tracing, next-event estimation with power-heuristic MIS",
    params: &[
        ParamDoc::optional(
            "max_depth",
            "bounces",
            "64",
            "longest path; --max-depth or the scene's max_depth",
        ),
        ParamDoc::optional(
            "rr_depth",
            "bounces",
            "5",
            "bounce from which Russian roulette may end a path",
        ),
        ParamDoc::optional(
            "wavelengths",
            "",
            "product",
            "how camera paths draw wavelengths: product (observer × emission), visible, uniform or light; --wavelength-sampling",
        ),
        ParamDoc::optional(
            "wavelengths_per_path",
            "",
            "4",
            "wavelengths one camera path carries: 1 or a multiple of 4 up to 16; --wavelengths-per-path",
        ),
    ],
};

/// Path tracing's registration.
pub const REGISTRATION: Registration = Registration {
    info: &INFO,
    build: |settings, options| {
        Ok(Box::new(PathTracing {
            tracer: settings.tracer,
            spectral: options.spectral,
        }))
    },
};

/// Path tracing as an [`Integrator`]: the tracer's settings and the optional spectral image.
struct PathTracing {
    tracer: PathTracer,
    spectral: Option<SpectralBins>,
}

impl Integrator for PathTracing {
    fn info(&self) -> &'static IntegratorInfo {
        &INFO
    }

    fn render(
        &self,
        scene: &Scene,
        plan: &RenderPlan,
        settings: &RenderSettings,
        progress: &ProgressFn<'_>,
        cancel: Option<&AtomicBool>,
    ) -> Result<IntegratorOutput, RenderError> {
        let settings = RenderSettings {
            tracer: self.tracer,
            ..settings.clone()
        };
        let (result, film, notes) =
            render_guided(scene, plan, &settings, progress, cancel, self.spectral)?;
        Ok(IntegratorOutput {
            result,
            notes,
            strategy_images: Vec::new(),
            non_finite: film.rejected.total(),
            max_sample_y: Vec::new(),
            film,
        })
    }

    fn light_strategy(&self, flags: LightFlags) -> &'static str {
        if flags.contains(LightFlags::BEAMS_ONLY) {
            "NOT rendered by pt (beams can only be light traced; use bdpt or lt)"
        } else if !flags.can_be_hit() {
            "pt: next-event estimation only"
        } else {
            "pt: next-event estimation + BSDF hits (MIS)"
        }
    }
}

/// Radiance per wavelength group (W/(m²·sr·nm) per lane); entries past the path's group count
/// are zero.
pub type GroupRadiance = [SampledSpectrum; MAX_GROUPS];

/// A camera path's radiance as the film takes it: per wavelength group the ordinary per-lane
/// estimate, except for the contributions of spectrally flat paths (every vertex scatters the
/// same at every wavelength and the emitter has one spectral shape: [`FlatColour`]), which
/// carry their emitter's exact colour instead (no colour noise from the wavelength draw).
#[derive(Clone, Copy, Debug)]
pub struct PathRadiance {
    /// Per group: the radiance (per lane) of the contributions not in `flat_xyz`.
    pub l: GroupRadiance,
    /// Per group: the radiance (per lane) of the flat contributions, for the spectral film,
    /// which keeps the ordinary estimate.
    pub flat_lanes: GroupRadiance,
    /// The flat contributions' exact XYZ ([`FlatColour::xyz`]) summed over the groups, before
    /// the camera weight and the mean over groups.
    pub flat_xyz: [f64; 3],
}

/// What a path has gathered so far, for `G` groups ([`PathRadiance`]), and the flat-path
/// colour tables while every vertex so far is flat.
struct Gathered<'a, const G: usize, const FLAT: bool> {
    l: [SampledSpectrum; G],
    flat_lanes: [SampledSpectrum; G],
    flat_xyz: [f64; 3],
    /// `Some` while the path so far is spectrally flat (and the render has the tables).
    flat: Option<&'a FlatColour>,
}

impl<'a, const G: usize, const FLAT: bool> Gathered<'a, G, FLAT> {
    fn new(flat: Option<&'a FlatColour>) -> Self {
        Self {
            l: [SampledSpectrum::zero(); G],
            flat_lanes: [SampledSpectrum::zero(); G],
            flat_xyz: [0.0; 3],
            flat,
        }
    }

    /// Adds group `g`'s contribution `v` (per lane, at wavelengths `lambda`) of light
    /// `light`: its exact colour where the path so far is flat, every lane is live and the
    /// light has one shape, else the ordinary per-lane estimate.
    #[inline]
    fn add(
        &mut self,
        g: usize,
        v: SampledSpectrum,
        lambda: &SampledWavelengths,
        light: Option<usize>,
    ) {
        if !FLAT {
            self.l[g] += v;
            return;
        }
        if let (Some(fc), Some(li)) = (self.flat, light) {
            if lambda.lanes.is_all() {
                if let Some(xyz) = fc.xyz(li as u32, &v, lambda) {
                    self.flat_lanes[g] += v;
                    for (sum, x) in self.flat_xyz.iter_mut().zip(xyz) {
                        *sum += x;
                    }
                    return;
                }
            }
        }
        self.l[g] += v;
    }

    /// The path's radiance, groups past `G` zero.
    fn finish(self) -> PathRadiance {
        let mut out = PathRadiance {
            l: [SampledSpectrum::zero(); MAX_GROUPS],
            flat_lanes: [SampledSpectrum::zero(); MAX_GROUPS],
            flat_xyz: self.flat_xyz,
        };
        out.l[..G].copy_from_slice(&self.l);
        if FLAT {
            out.flat_lanes[..G].copy_from_slice(&self.flat_lanes);
        }
        out
    }
}

/// True when two sampled delta events are the same scattering event: same lobe and the same
/// direction up to rounding (cos of the angle between them within 1e-6 of 1, about 0.08°).
fn same_delta_event(a: &crate::material::BsdfSample, b: &crate::material::BsdfSample) -> bool {
    let lobe = MaterialFlags::REFLECTION | MaterialFlags::TRANSMISSION | MaterialFlags::SPECULAR;
    (a.flags & lobe) == (b.flags & lobe) && a.wi.dot(b.wi) >= 1.0 - 1e-6
}

impl PathTracer {
    /// These settings as path tracing uses them: the shared default roulette depth replaced by
    /// [`PT_RR_DEPTH`]; everything else (and any other roulette depth) unchanged.
    pub fn for_path_tracing(self) -> PathTracer {
        if self.rr_depth == PathTracer::default().rr_depth {
            PathTracer {
                rr_depth: PT_RR_DEPTH,
                ..self
            }
        } else {
            self
        }
    }

    /// Radiance (W/(m²·sr·nm) per lane) arriving along `ray` for one group of wavelengths
    /// (ignores [`wavelengths_per_path`](Self::wavelengths_per_path)). `lambda` may be modified
    /// (a dispersive event terminates the secondary lanes); the caller must use the returned
    /// wavelengths' pdfs for the film.
    pub fn li(
        &self,
        scene: &Scene,
        ray: Ray,
        lambda: &mut SampledWavelengths,
        rng: &mut PixelSampler,
        stats: &mut PathStats,
    ) -> SampledSpectrum {
        let mut groups = PathWavelengths::from_groups(&[*lambda]);
        let l = self.li_groups(scene, None, ray, &mut groups, rng, stats);
        *lambda = groups.groups()[0];
        l[0]
    }

    /// Radiance arriving along `ray` for every wavelength group of `lambdas` (entry `g` belongs
    /// to group `g`). Directions are sampled with the hero group (group 0); the other groups
    /// evaluate the same scattering events and light samples with their own wavelengths, which
    /// is unbiased because the direction density does not depend on wavelength for
    /// non-dispersive events. A dispersive event (or a delta event that turns out to choose a
    /// different lobe for another group) keeps only the hero wavelength
    /// ([`PathWavelengths::terminate_secondary`]); the caller must use the returned pdfs.
    /// `guide`, when given, draws next-event estimation's light points for the lights it
    /// guides (and weighs the path's hits on them with the same density).
    pub fn li_groups(
        &self,
        scene: &Scene,
        guide: Option<&NeeGuide>,
        ray: Ray,
        lambdas: &mut PathWavelengths,
        rng: &mut PixelSampler,
        stats: &mut PathStats,
    ) -> GroupRadiance {
        self.li_film(scene, guide, None, ray, lambdas, rng, stats).l
    }

    /// [`li_groups`](Self::li_groups) for the film: with the flat-path colour tables `flat`,
    /// the contributions of spectrally flat paths carry their emitter's exact colour
    /// ([`PathRadiance`]).
    #[allow(clippy::too_many_arguments)]
    pub fn li_film(
        &self,
        scene: &Scene,
        guide: Option<&NeeGuide>,
        flat: Option<&FlatColour>,
        ray: Ray,
        lambdas: &mut PathWavelengths,
        rng: &mut PixelSampler,
        stats: &mut PathStats,
    ) -> PathRadiance {
        // One group (the default, 4 wavelengths a path): the walk compiled for one, so the
        // per-group loops and arrays of every bounce shrink to the hero's (same results); and
        // compiled without the flat-path colour where the render has none.
        let args = (scene, guide, flat, ray);
        match (lambdas.len() == 1, flat.is_some()) {
            (true, false) => self.li_groups_n::<1, false>(args, lambdas, rng, stats),
            (true, true) => self.li_groups_n::<1, true>(args, lambdas, rng, stats),
            (false, false) => self.li_groups_n::<MAX_GROUPS, false>(args, lambdas, rng, stats),
            (false, true) => self.li_groups_n::<MAX_GROUPS, true>(args, lambdas, rng, stats),
        }
    }

    /// [`li_film`](Self::li_film) for at most `G` groups (`lambdas.len() <= G`).
    fn li_groups_n<const G: usize, const FLAT: bool>(
        &self,
        (scene, guide, flat, mut ray): (&Scene, Option<&NeeGuide>, Option<&FlatColour>, Ray),
        lambdas: &mut PathWavelengths,
        rng: &mut PixelSampler,
        stats: &mut PathStats,
    ) -> PathRadiance {
        let n = lambdas.len();
        debug_assert!(n <= G);
        let mut l = Gathered::<G, FLAT>::new(flat);
        let mut beta = [SampledSpectrum::zero(); G];
        for b in beta.iter_mut().take(n) {
            *b = SampledSpectrum::splat(1.0);
        }
        let mut specular_bounce = true;
        let mut prev_bsdf_pdf = 0.0f32;
        let mut prev_ctx = LightSampleContext {
            p: ray.origin,
            p_error: glam::Vec3A::ZERO,
            n: glam::Vec3A::ZERO,
        };
        // The guide's key of the previous vertex (see `Seen::prev_key`).
        let mut prev_key = NO_KEY;
        // Product of η² over the refractions so far: β carries refraction's 1/η² radiance
        // scaling, which leaving the medium undoes, so Russian roulette must not read it as a
        // loss (it would kill paths inside glass and return the survivors η² too bright).
        let mut eta_scale = 1.0f32;
        let max_depth = if self.direct_only { 1 } else { self.max_depth };
        let mut depth = 0u32;
        let fluorescence = scene.objects.fluorescence();
        // The wavelengths each group's lanes carry now, once a fluorescent event has shifted
        // one (see `super::fluorescence::events`); the film keeps weighing `lambdas`, the observed ones.
        let mut shifted: Option<[[f32; LANES]; MAX_GROUPS]> = None;
        // Filled only once a fluorescent event has shifted a lane (most paths never do).
        let mut cur_buf: Option<[SampledWavelengths; MAX_GROUPS]> = None;
        // Where every bounce's BSDF samples are written (`Material::sample_into`).
        let mut record = BsdfSample::ZERO;
        let mut again_record = BsdfSample::ZERO;
        loop {
            let cur = current(lambdas.groups(), shifted.as_ref(), &mut cur_buf);
            stats.rays += 1;
            let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
                let seen = Seen {
                    directly: depth == 0 || specular_bounce,
                    prev_ctx: &prev_ctx,
                    prev_bsdf_pdf,
                    guide,
                    prev_key,
                };
                add_escaped(
                    scene,
                    &ray,
                    &seen,
                    cur,
                    lambdas.active_groups(),
                    &beta,
                    &mut l,
                );
                break;
            };
            let material = scene.objects.material(hit.object);
            let flags = material.flags();
            let frame = Frame::from_normal(hit.shading_normal);
            let wo = frame.to_local(-ray.dir.normalize());
            let sctx =
                ShadingContext::at(hit.point, hit.geometric_normal, hit.shading_normal, hit.uv);
            // Groups still carrying wavelengths (all but the hero end at a dispersive event).
            let active = lambdas.active_groups();

            // Emission found by the path itself.
            if flags.contains(MaterialFlags::EMISSIVE) {
                let seen = Seen {
                    directly: depth == 0 || specular_bounce,
                    prev_ctx: &prev_ctx,
                    prev_bsdf_pdf,
                    guide,
                    prev_key,
                };
                let found = Found {
                    hit: &hit,
                    ray: &ray,
                    material,
                    sctx: &sctx,
                };
                add_emission(scene, &found, &seen, &cur[..active], &beta, &mut l);
            }
            if depth >= max_depth {
                break;
            }
            if !flags.intersects(
                MaterialFlags::DIFFUSE | MaterialFlags::GLOSSY | MaterialFlags::SPECULAR,
            ) {
                break;
            }
            // The path stays flat while every vertex it scatters at is (emission found here
            // needed only the vertices before).
            if let Some(fc) = l.flat {
                if !fc.object_is_flat(hit.object) {
                    l.flat = None;
                }
            }
            let ctx = LightSampleContext {
                p: hit.point,
                p_error: hit.point_error,
                n: hit.geometric_normal,
            };
            // A fluorescent surface: each lane keeps its wavelength or moves to an excitation
            // wavelength now, so next-event estimation and the continuation use the new one;
            // the spectral weight goes into β and the surface scatters as a unit cosine lobe.
            let rerad = if fluorescence {
                scene.objects.reradiation(hit.object)
            } else {
                None
            };
            let material: &dyn Material = match rerad {
                Some(rr) => {
                    // A fluorescent event moves lanes: no longer one spectral shape.
                    l.flat = None;
                    let mut sh = shifted.unwrap_or_else(|| {
                        std::array::from_fn(|g| {
                            lambdas.groups().get(g).map_or([0.0; LANES], |w| w.lambda)
                        })
                    });
                    let u = rng.next_1d();
                    for g in 0..active {
                        let mut lam = cur[g];
                        let ug = rotated(u as f64, g, LANES * active) as f32;
                        beta[g] *= shift_lanes(
                            rr,
                            &mut lam,
                            ug,
                            Direction::Camera,
                            scene.lights.delta_lines(),
                        );
                        sh[g] = lam.lambda;
                    }
                    shifted = Some(sh);
                    &UNIT_LOBE
                }
                None => material,
            };
            let cur = current(lambdas.groups(), shifted.as_ref(), &mut cur_buf);
            let hero = &cur[0];

            // Next-event estimation: one light point (drawn for the hero), emission and BSDF per
            // group, one shadow ray.
            // With one light the choice ignores its number: its dimension is consumed without
            // computing it (`skip_1d`; every other number stays the same).
            let u_light = if scene.lights.lights().len() > 1 {
                rng.next_1d()
            } else {
                rng.skip_1d();
                0.0
            };
            let u_light2 = rng.next_2d();
            // The continuation's numbers and BSDF sample come before next-event estimation
            // (the same numbers in the same order: the light sample draws none), so that a
            // surface whose f is the same in every direction (`f_same_for_all_directions`)
            // lends the hero's f to the light sample instead of evaluating it again.
            let u_lobe = if material.ignores_lobe_sample() {
                rng.skip_1d();
                0.0
            } else {
                rng.next_1d()
            };
            let u_dir = rng.next_2d();
            let sampled = material.sample_into(
                wo,
                &sctx,
                hero,
                u_lobe,
                u_dir,
                TransportMode::Radiance,
                &mut record,
            );
            // The scattering surface (the unit lobe in place of a fluorescent material).
            let found = Found {
                hit: &hit,
                ray: &ray,
                material,
                sctx: &sctx,
            };
            let hero_f = sampled
                .filter(|_| material.f_same_for_all_directions())
                .map(|bs| bs.f);
            // The guide's key here: next-event estimation draws with it, and the path's hit on
            // a light from here is weighed with it.
            let key = match guide {
                Some(g) if flags.has_non_specular() => {
                    g.key(hit.point, hit.geometric_normal, -ray.dir)
                }
                _ => NO_KEY,
            };
            if flags.has_non_specular() {
                let event = NextEvent {
                    frame: &frame,
                    wo,
                    ctx: &ctx,
                    hero_f,
                    u_light,
                    u_light2,
                    guide,
                    key,
                };
                add_next_event(scene, &found, &event, &cur[..active], &beta, &mut l, stats);
            }

            // Continue the path with the BSDF sample drawn with the hero group above.
            let Some(bs) = sampled else {
                break;
            };
            if !(bs.pdf > 0.0) {
                break;
            }
            // f(wo, wi) of every group for this event (for a delta lobe: its weight over |cos|).
            let (f_groups, wavelength_dependent) = event_f_per_group::<G>(
                &found,
                wo,
                bs,
                &cur[..active],
                (u_lobe, u_dir),
                &mut again_record,
            );
            let keep = if wavelength_dependent { 1 } else { active };
            if f_groups[..keep].iter().all(|f| f.is_black()) {
                break;
            }
            if wavelength_dependent {
                lambdas.terminate_secondary();
            }
            // Same direction density for every group: f_g·|cos θ|/pdf_hero.
            let mut non_finite = false;
            for (b, f) in beta.iter_mut().zip(&f_groups).take(keep) {
                *b *= *f * (bs.wi.z.abs() / bs.pdf);
                non_finite |= b.has_non_finite();
            }
            for b in beta.iter_mut().take(active).skip(keep) {
                *b = SampledSpectrum::zero();
            }
            if non_finite {
                break;
            }
            let active = keep;
            if bs.flags.contains(MaterialFlags::TRANSMISSION) {
                eta_scale *= bs.eta * bs.eta;
            }
            specular_bounce = bs.flags.is_specular();
            prev_bsdf_pdf = bs.pdf;
            prev_ctx = ctx;
            prev_key = key;
            let wi_world = frame.to_world(bs.wi);
            ray = spawn_ray(hit.point, hit.point_error, hit.geometric_normal, wi_world);
            depth += 1;

            if depth >= self.rr_depth && !survives_roulette(&mut beta[..active], eta_scale, rng) {
                break;
            }
        }
        l.finish()
    }
}

/// Russian roulette on the throughput (the largest lane of all groups), with refraction's
/// radiance scaling `eta_scale` taken out: false when the path ends, else the survivors'
/// throughput divided by the survival probability.
#[inline]
fn survives_roulette(beta: &mut [SampledSpectrum], eta_scale: f32, rng: &mut PixelSampler) -> bool {
    let m = beta.iter().map(|b| b.max_value()).fold(f32::MIN, f32::max) * eta_scale;
    if m < 1.0 {
        let q = (1.0 - m).max(0.05);
        if rng.next_1d() < q {
            return false;
        }
        for b in beta.iter_mut() {
            *b = *b / (1.0 - q);
        }
    }
    true
}

/// How the path reached its current point: `directly` (camera ray or after a delta event: no
/// next-event estimate competes), else from `prev_ctx` with BSDF density `prev_bsdf_pdf`.
struct Seen<'a> {
    directly: bool,
    prev_ctx: &'a LightSampleContext,
    prev_bsdf_pdf: f32,
    /// The visibility guide, if any, and its key of the previous vertex: the light density
    /// next-event estimation had there.
    guide: Option<&'a NeeGuide>,
    prev_key: u32,
}

impl Seen<'_> {
    /// The MIS weight of emission found by the path on light `li` at `p` (normal `n`) against
    /// that light's next-event estimation.
    #[inline]
    fn weight(&self, scene: &Scene, li: usize, p: glam::Vec3A, n: glam::Vec3A) -> f32 {
        let light = &scene.lights.lights()[li];
        let mut light_pdf = scene.lights.pmf(li) * light.pdf_li(self.prev_ctx, p, n);
        if let Some(g) = self.guide {
            light_pdf *= g.pdf_factor(li, self.prev_key, light.as_ref(), self.prev_ctx.p, p);
        }
        power_heuristic(self.prev_bsdf_pdf, light_pdf)
    }
}

/// The path leaves the scene: the environment's radiance, weighted against its next-event
/// estimation like an area light found by the path.
#[inline]
fn add_escaped<const G: usize, const FLAT: bool>(
    scene: &Scene,
    ray: &Ray,
    seen: &Seen<'_>,
    cur: &[SampledWavelengths],
    active: usize,
    beta: &[SampledSpectrum; G],
    l: &mut Gathered<'_, G, FLAT>,
) {
    let Some(ei) = scene.lights.environment() else {
        return;
    };
    let light = &scene.lights.lights()[ei as usize];
    let Some((p_env, n_env)) = light.escape_point(ray) else {
        return;
    };
    let w = if seen.directly {
        1.0
    } else {
        seen.weight(scene, ei as usize, p_env, n_env)
    };
    let back = -ray.dir.normalize();
    for (g, lam) in cur.iter().enumerate().take(active) {
        let mut le = light.radiance(p_env, n_env, glam::Vec2::ZERO, back, lam);
        keep_line_power_only(scene, ei as usize, lam, &mut le);
        l.add(g, beta[g] * le * w, lam, Some(ei as usize));
    }
}

/// [`LightSourceManager::keep_line_power_only`](crate::light::LightSourceManager::keep_line_power_only) behind
/// the scene's own test for line emission, so that a scene without lines (most) makes no call
/// for every light term; the same result, since the manager returns at once there.
#[inline]
fn keep_line_power_only(
    scene: &Scene,
    light: usize,
    lambda: &SampledWavelengths,
    l: &mut SampledSpectrum,
) {
    if !scene.lights.delta_lines().is_empty() {
        scene.lights.keep_line_power_only(light, lambda, l);
    }
}

/// A surface the path found: the hit, the ray that found it, its material and shading context.
struct Found<'a> {
    hit: &'a Hit,
    ray: &'a Ray,
    material: &'a dyn Material,
    sctx: &'a ShadingContext,
}

/// Emission found by the path itself on an emissive surface, each active group in `cur`,
/// weighted against next-event estimation (one weight for every group: both strategies
/// sampled with the hero).
#[inline]
fn add_emission<const G: usize, const FLAT: bool>(
    scene: &Scene,
    found: &Found<'_>,
    seen: &Seen<'_>,
    cur: &[SampledWavelengths],
    beta: &[SampledSpectrum; G],
    l: &mut Gathered<'_, G, FLAT>,
) {
    let hit = found.hit;
    // Which side emits is a property of the surface (its geometric normal, as the area light
    // sees it), not of an interpolated shading normal.
    let wo_geo = Frame::from_normal(hit.geometric_normal).to_local(-found.ray.dir.normalize());
    let mut weight: Option<f32> = None;
    for (g, lam) in cur.iter().enumerate() {
        let mut le = found.material.emitted(wo_geo, found.sctx, lam);
        if let Some(li) = scene.lights.light_of_object(hit.object) {
            keep_line_power_only(scene, li as usize, lam, &mut le);
        }
        if le.is_black() {
            continue;
        }
        let light = scene
            .lights
            .light_of_object(hit.object)
            .map(|li| li as usize);
        if seen.directly {
            l.add(g, beta[g] * le, lam, light);
        } else if let Some(li) = light {
            let w = *weight
                .get_or_insert_with(|| seen.weight(scene, li, hit.point, hit.geometric_normal));
            l.add(g, beta[g] * le * w, lam, light);
        } else {
            l.add(g, beta[g] * le, lam, None);
        }
    }
}

/// One next-event estimate's inputs at a surface: its frame, the outgoing direction (local),
/// the light sampling context, the hero's f when it is the same in every direction, the
/// numbers of the light choice and the light point, and the visibility guide with this
/// point's key.
struct NextEvent<'a> {
    frame: &'a Frame,
    wo: glam::Vec3A,
    ctx: &'a LightSampleContext,
    hero_f: Option<SampledSpectrum>,
    u_light: f32,
    u_light2: Vec2,
    guide: Option<&'a NeeGuide>,
    key: u32,
}

/// Next-event estimation: one light point (drawn for the hero), emission and BSDF per group
/// of `cur`, one shadow ray, weighted against the path finding the light.
#[inline]
fn add_next_event<const G: usize, const FLAT: bool>(
    scene: &Scene,
    found: &Found<'_>,
    event: &NextEvent<'_>,
    cur: &[SampledWavelengths],
    beta: &[SampledSpectrum; G],
    l: &mut Gathered<'_, G, FLAT>,
    stats: &mut PathStats,
) {
    let (hit, material, sctx, wo) = (found.hit, found.material, found.sctx, event.wo);
    let hero = &cur[0];
    let Some((li, pmf)) = scene.lights.sample(event.u_light) else {
        return;
    };
    let light = &scene.lights.lights()[li];
    // The light's numbers, from the guide's density for this point's key where it guides the
    // light (the point's density is then pdf_li times `guided`), else as drawn.
    let (u_light2, guided) = match event.guide {
        Some(g) if g.guides(li) => g.sample(li, event.key, event.u_light2),
        _ => (event.u_light2, 1.0),
    };
    let Some(ls) = light.sample_li(event.ctx, u_light2, hero) else {
        return;
    };
    if !(ls.pdf > 0.0) {
        return;
    }
    let wi = event.frame.to_local(ls.wi);
    // (f·|cos θ|, radiance) per group; zero where nothing arrives.
    let mut terms = [(SampledSpectrum::zero(), SampledSpectrum::zero()); G];
    let mut any = false;
    for (g, (term, lam)) in terms.iter_mut().zip(cur).enumerate() {
        let mut radiance = if g == 0 {
            ls.radiance
        } else {
            // The same light point for the group's wavelengths (light sampling is
            // wavelength-independent for every built-in).
            match light.sample_li(event.ctx, u_light2, lam) {
                Some(s) if s.p_light == ls.p_light => s.radiance,
                _ => SampledSpectrum::zero(),
            }
        };
        keep_line_power_only(scene, li, lam, &mut radiance);
        if radiance.is_black() {
            continue;
        }
        let f = match event.hero_f {
            Some(f) if g == 0 => {
                if crate::material::same_hemisphere(wo, wi) {
                    f
                } else {
                    SampledSpectrum::zero()
                }
            }
            _ => material.eval(wo, wi, sctx, lam, TransportMode::Radiance),
        } * wi.z.abs();
        if !f.is_black() {
            *term = (f, radiance);
            any = true;
        }
    }
    if !any {
        return;
    }
    let (shadow, t_max) = spawn_ray_to(
        hit.point,
        hit.point_error,
        hit.geometric_normal,
        ls.p_light,
        ls.p_light_error,
        ls.n_light,
    );
    stats.shadow_rays += 1;
    if scene.geometry.occluded(&shadow, t_max) {
        return;
    }
    let light_pdf = pmf * ls.pdf * guided;
    // No BSDF-hit term exists for a light rays cannot find.
    let w = if !light.flags().can_be_hit() {
        1.0
    } else {
        let bsdf_pdf = material.pdf(wo, wi, sctx, hero, TransportMode::Radiance);
        power_heuristic(light_pdf, bsdf_pdf)
    };
    for (g, lam) in cur.iter().enumerate() {
        let (f, radiance) = terms[g];
        if !f.is_black() {
            l.add(g, beta[g] * f * radiance * (w / light_pdf), lam, Some(li));
        }
    }
}

/// f(wo, wi) of every group of `cur` for the event `bs` sampled with the hero (for a delta
/// lobe: its weight over |cos|, by sampling it again with the same numbers `u` and the group's
/// wavelengths), and whether the event depends on wavelength (dispersive, or a delta event
/// that chose another lobe for some group): then only the hero's entry is meaningful.
#[inline]
fn event_f_per_group<const G: usize>(
    found: &Found<'_>,
    wo: glam::Vec3A,
    bs: &BsdfSample,
    cur: &[SampledWavelengths],
    (u_lobe, u_dir): (f32, Vec2),
    again_record: &mut BsdfSample,
) -> ([SampledSpectrum; G], bool) {
    let mut f_groups = [SampledSpectrum::zero(); G];
    f_groups[0] = bs.f;
    let mut wavelength_dependent = bs.flags.contains(MaterialFlags::DISPERSIVE);
    // Only the groups after the hero's are evaluated again (none in a walk compiled for one
    // group, where the iterator's `skip` cost more than the bounce's other bookkeeping).
    if !wavelength_dependent && G > 1 && cur.len() > 1 {
        for (f_g, lam) in f_groups.iter_mut().zip(cur).skip(1) {
            *f_g = if bs.flags.is_specular() {
                let again = found.material.sample_into(
                    wo,
                    found.sctx,
                    lam,
                    u_lobe,
                    u_dir,
                    TransportMode::Radiance,
                    again_record,
                );
                match again {
                    Some(b) if same_delta_event(b, bs) => b.f,
                    _ => {
                        wavelength_dependent = true;
                        break;
                    }
                }
            } else {
                found
                    .material
                    .eval(wo, bs.wi, found.sctx, lam, TransportMode::Radiance)
            };
        }
    }
    (f_groups, wavelength_dependent)
}

/// The wavelengths the groups carry now: `groups` itself until a fluorescent event, then a copy
/// in `buf` with the shifted wavelengths (pdfs and lane masks stay the observed ones').
fn current<'a>(
    groups: &'a [SampledWavelengths],
    shifted: Option<&[[f32; LANES]; MAX_GROUPS]>,
    buf: &'a mut Option<[SampledWavelengths; MAX_GROUPS]>,
) -> &'a [SampledWavelengths] {
    let Some(sh) = shifted else {
        return groups;
    };
    let buf = buf.get_or_insert([groups[0]; MAX_GROUPS]);
    for (g, w) in groups.iter().enumerate() {
        buf[g] = SampledWavelengths {
            lambda: sh[g],
            ..*w
        };
    }
    &buf[..groups.len()]
}

/// The flat-path colour tables of a path-traced render (see [`PathRadiance`]), where the plan
/// has them and some surface that scatters light is spectrally flat. Without such a surface
/// the only flat paths are emitters seen directly, and the walk compiled without the tables
/// runs instead (measured: their tests cost the Cornell box 0.27% of the path tracer's
/// instructions per camera sample, 10,889 against 10,860).
pub(crate) fn flat_colour(
    scene: &Scene,
    plan: &RenderPlan,
    sensor: &Sensor,
    wavelengths: &PathWavelengthSampler,
) -> Option<FlatColour> {
    let scatters_flatly = scene.objects.objects().iter().any(|o| {
        o.material.spectrally_flat() && !o.material.flags().contains(MaterialFlags::EMISSIVE)
    });
    if !scatters_flatly {
        return None;
    }
    plan.flat_colour(scene, sensor.observer().as_ref(), &|nm| {
        wavelengths.lane_density(nm)
    })
}

/// A camera sample's XYZ: the mean over wavelength groups of each group's sensor response to
/// its radiance `r.l` (scaled by the camera weight), plus the flat contributions' exact colour
/// (the same mean and weight). One group gives exactly `Sensor::to_xyz`.
pub(crate) fn film_xyz(
    sensor: &Sensor,
    r: &PathRadiance,
    lambdas: &PathWavelengths,
    camera_weight: f32,
) -> [f64; 3] {
    let (l, groups) = (&r.l, lambdas.groups());
    let mut xyz = sensor.to_xyz(&(l[0] * camera_weight), &groups[0]);
    if groups.len() > 1 {
        for (lg, wg) in l.iter().zip(groups).skip(1) {
            let x = sensor.to_xyz(&(*lg * camera_weight), wg);
            for c in 0..3 {
                xyz[c] += x[c];
            }
        }
        let inv = 1.0 / groups.len() as f64;
        for v in &mut xyz {
            *v *= inv;
        }
    }
    if r.flat_xyz != [0.0; 3] {
        let k = camera_weight as f64 / groups.len() as f64;
        for (v, f) in xyz.iter_mut().zip(r.flat_xyz) {
            *v += f * k;
        }
    }
    xyz
}
/// The camera sample of pixel `(x, y)` from `rng`, after the wavelengths: the filter's offset
/// and the lens point. A pinhole never reads the lens numbers: their request is skipped (the
/// same numbers for every later request). BDPT's path-tracing pilot draws the same sample.
#[inline]
pub(crate) fn camera_sample(
    cam: &crate::camera::manager::NamedCamera,
    pinhole: bool,
    rng: &mut PixelSampler,
    (x, y): (u32, u32),
) -> CameraSample {
    let offset = cam.filter.sample(rng.next_2d());
    let p_lens = if pinhole {
        rng.skip_2d();
        Vec2::ZERO
    } else {
        rng.next_2d()
    };
    CameraSample {
        p_film: Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset,
        p_lens,
    }
}

/// Render `scene` by path tracing with `settings` (the tracer's settings from
/// `settings.tracer`). `progress` may be called from several threads.
/// `cancel`, when set, stops after the tiles in flight; the film of the whole passes done is
/// returned.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<RenderResult, RenderError> {
    render_film(scene, settings, progress, cancel).map(|(r, _)| r)
}

/// [`render`], also returning the exact film (for slices and checkpoints).
pub fn render_film(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<(RenderResult, FilmState), RenderError> {
    let plan = RenderPlan::auto(scene);
    render_film_spectral(scene, &plan, settings, progress, cancel, None)
}

/// A camera sample's lanes for the spectral film, group by group: `e = L·w/(pdf·LANES·G)` for
/// the lanes [`Sensor::to_xyz`] counts (the same terms as [`film_xyz`]; flat contributions
/// too, as their ordinary per-lane estimate).
fn lane_energies(
    r: &PathRadiance,
    lambdas: &PathWavelengths,
    camera_weight: f32,
) -> ([LaneEnergies; MAX_GROUPS], usize) {
    let groups = lambdas.groups();
    let mut out = [LaneEnergies::default(); MAX_GROUPS];
    let scale = 1.0 / (groups.len() as f64 * LANES as f64);
    for (((o, lg), fg), wg) in out.iter_mut().zip(&r.l).zip(&r.flat_lanes).zip(groups) {
        o.lambda = wg.lambda;
        let v = (*lg + *fg) * camera_weight;
        for i in 0..LANES {
            let p = wg.pdf[i];
            if p != 0.0 && v.0[i] != 0.0 && wg.lanes.contains(i) {
                o.e[i] = v.0[i] as f64 / p as f64 * scale;
            }
        }
    }
    (out, groups.len())
}

/// [`render_film`] under `plan` (made for `scene`), also accumulating a spectral image at the nodes `spectral` (the film
/// state's `spectral` sums) from the same camera samples; with `None` nothing extra is
/// computed.
pub fn render_film_spectral(
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
    spectral: Option<SpectralBins>,
) -> Result<(RenderResult, FilmState), RenderError> {
    render_guided(scene, plan, settings, progress, cancel, spectral).map(|(r, f, _)| (r, f))
}

/// [`render_film_spectral`], also returning the run-time notes (the visibility guide's, when
/// it is on: see [`NeeGuide`]). The guide's pre-pass is part of the render: its time is in
/// the result's `elapsed`.
fn render_guided(
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
    spectral: Option<SpectralBins>,
) -> Result<(RenderResult, FilmState, Vec<String>), RenderError> {
    let cam = scene
        .cameras
        .get(settings.camera.as_deref())
        .map_err(RenderError::Setup)?;
    let prepass = std::time::Instant::now();
    let guide = NeeGuide::build(
        scene,
        cam.camera.as_ref(),
        settings.seed,
        plan.visibility_guide(),
        settings.threads,
    );
    let notes = guide_notes(scene, guide.as_ref());
    let prepared = Prepared {
        guide: guide.as_ref(),
        prepass: prepass.elapsed(),
        pixel_max: None,
    };
    let (result, film) =
        render_prepared(scene, plan, settings, progress, cancel, spectral, prepared)?;
    Ok((result, film, notes))
}

/// The visibility guide's run-time notes as the path tracer words them (none without a guide).
pub(crate) fn guide_notes(scene: &Scene, guide: Option<&NeeGuide>) -> Vec<String> {
    guide.map_or_else(Vec::new, |g| {
        g.notes(|i| {
            scene
                .options
                .light_items
                .get(i)
                .map_or_else(|| format!("light {i}"), |n| format!("light {i} ({n})"))
        })
    })
}

/// What a caller hands [`render_prepared`]: the visibility guide it built (the pre-pass that
/// [`render_guided`] would run, the same arguments), the time spent before sampling (counted in
/// the render's, and taken from a time budget), and where to record each pixel's largest
/// sample luminance.
pub(crate) struct Prepared<'a> {
    pub guide: Option<&'a NeeGuide>,
    pub prepass: std::time::Duration,
    pub pixel_max: Option<&'a PixelMaxY>,
}

/// [`render_guided`]'s sampling, with the guide and pre-pass time given (`prepared`).
pub(crate) fn render_prepared(
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
    spectral: Option<SpectralBins>,
    prepared: Prepared<'_>,
) -> Result<(RenderResult, FilmState), RenderError> {
    let cam = scene
        .cameras
        .get(settings.camera.as_deref())
        .map_err(RenderError::Setup)?;
    let (width, height) = cam.camera.resolution();
    let wavelength_sampler = PathWavelengthSampler::new(
        plan,
        settings.tracer.wavelengths,
        settings.tracer.wavelengths_per_path,
        scene.objects.fluorescence(),
    )
    .map_err(RenderError::Setup)?;
    let sensor = Sensor::new(scene.observer.clone());
    let flat = flat_colour(scene, plan, &sensor, &wavelength_sampler);
    let Prepared {
        guide,
        prepass,
        pixel_max,
    } = prepared;
    // The pre-pass is part of the render: a time budget counts it.
    let settings = &RenderSettings {
        tracer: settings.tracer.for_path_tracing(),
        budget: match &settings.budget {
            SampleBudget::Time(d) => SampleBudget::Time(d.saturating_sub(prepass)),
            other => *other,
        },
        ..settings.clone()
    };
    let rays = AtomicU64::new(0);
    let pinhole = cam.camera.pinhole();
    let outcome = render_tiles(
        (width, height),
        settings,
        progress,
        cancel,
        false,
        spectral,
        |buf, samples, _, spectral| {
            let mut stats = PathStats::default();
            // One wavelength buffer per tile, overwritten by every sample's draw.
            let mut lambdas = PathWavelengths::default();
            // One sampler per tile, restarted for every sample: it keeps a pixel's scramble
            // seeds across the pixel's samples (the same numbers as a new sampler each time).
            let mut rng = PixelSampler::memoised(
                settings.sampler,
                settings.seed,
                buf.y0 as u64 * width as u64 + buf.x0 as u64,
                0,
            );
            for y in buf.y0..buf.y0 + buf.h {
                for x in buf.x0..buf.x0 + buf.w {
                    let pixel = y as u64 * width as u64 + x as u64;
                    for s in samples.clone() {
                        rng.restart(pixel, s);
                        wavelength_sampler.sample_into(&mut rng, &mut lambdas);
                        let sample = camera_sample(cam, pinhole, &mut rng, (x, y));
                        let xyz = match cam.camera.generate_ray(&sample) {
                            Some(r) => {
                                let l = settings.tracer.li_film(
                                    scene,
                                    guide,
                                    flat.as_ref(),
                                    r.ray,
                                    &mut lambdas,
                                    &mut rng,
                                    &mut stats,
                                );
                                let xyz = film_xyz(&sensor, &l, &lambdas, r.weight);
                                if let Some(sf) = spectral {
                                    let (e, n) = lane_energies(&l, &lambdas, r.weight);
                                    sf.add(x, y, &xyz, &e[..n]);
                                }
                                xyz
                            }
                            None => [0.0; 3],
                        };
                        if let Some(m) = pixel_max {
                            m.record(x as f32 + 0.5, y as f32 + 0.5, xyz[1]);
                        }
                        // The film's guard keeps NaN/Inf/negative samples out and counts them.
                        buf.add(x, y, xyz, "pt camera path");
                    }
                }
            }
            rays.fetch_add(stats.rays + stats.shadow_rays, Ordering::Relaxed);
        },
    )?;
    let film = outcome.film;
    Ok((
        RenderResult {
            image: film.image(),
            spp: outcome.spp,
            samples: film.camera.sample_count(),
            rays: rays.load(Ordering::Relaxed),
            elapsed: outcome.elapsed + prepass,
            dropped_pass: outcome.dropped_pass,
        },
        film,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Power heuristic: symmetric weights sum to 1; a delta pdf (∞) takes all the weight.
    #[test]
    fn power_heuristic_properties() {
        let (a, b) = (0.3f32, 1.7f32);
        assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        assert_eq!(power_heuristic(f32::INFINITY, 1.0), 1.0);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }

    /// Russian roulette must not count refraction's 1/η² radiance scaling as a loss. Quantity:
    /// the radiance of single paths from a camera looking through a glass ball (IOR 1.5) at a
    /// wall emitting exactly 1 W/(m²·sr·nm), roulette from the first bounce, 20 000 paths.
    /// Every path's estimate is at most 1/(1 − 0.05) ≈ 1.053 of the wall's radiance (Fresnel
    /// transmission < 1, the η² of entering and leaving cancel, and a roulette step divides by
    /// at most 1 − q with q ≥ 0.05); bound 1.06 for f32 rounding. A roulette that read the 0.44
    /// after entering as a loss returns its survivors at η²·T² ≈ 2.1.
    #[test]
    fn roulette_ignores_the_radiance_scaling_of_refraction() {
        let text = r#"(
            materials: [
                (name: "glass", type: "dielectric", params: (ior: 1.5)),
                (name: "wall", type: "emissive", params: (radiance: [(300, 1.0), (900, 1.0)])),
            ],
            objects: [
                (name: "ball", type: "sphere", material: "glass",
                 params: (center: (0, 0, -3), radius: 1)),
                (name: "wall", type: "quad", material: "wall",
                 params: (corner: (-20, -20, -10), edge0: (40, 0, 0), edge1: (0, 40, 0))),
            ],
            cameras: [(name: "c", type: "perspective",
                       params: (position: (0, 0, 0), look_at: (0, 0, -1), fov: 20,
                                resolution: (8, 8)))],
        )"#;
        let file = std::path::Path::new("glass.ron");
        let desc = crate::scene::parse_scene_str(text, file).unwrap();
        let scene = crate::scene::build_scene(
            &desc,
            std::path::Path::new("."),
            file,
            &[&crate::scene::BuiltinFactory],
        )
        .unwrap();
        let tracer = PathTracer {
            rr_depth: 1,
            ..PathTracer::default()
        };
        let (mut worst, mut through) = (0.0f32, 0u32);
        let mut stats = PathStats::default();
        for k in 0..20_000u32 {
            let mut rng = PixelSampler::new(3, u64::from(k % 64), k);
            let mut lambda = SampledWavelengths::sample_visible(rng.next_1d());
            let u = rng.next_2d();
            // Rays within the ball's silhouette (half-angle ≈ 19.5°), spread over 0.3 rad.
            let dir = glam::Vec3A::new(0.3 * (u.x - 0.5), 0.3 * (u.y - 0.5), -1.0).normalize();
            let ray = Ray::new(glam::Vec3A::ZERO, dir);
            let l = tracer.li(&scene, ray, &mut lambda, &mut rng, &mut stats);
            let m = l.max_value();
            if m > 0.5 {
                through += 1;
            }
            worst = worst.max(m);
        }
        assert!(
            through > 5_000,
            "too few paths came through the glass: {through}"
        );
        assert!(
            worst <= 1.06,
            "a path returned {worst}× the wall's radiance"
        );
    }
}
