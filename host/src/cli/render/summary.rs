//! What a finished render prints (step 7 of the pipeline in [`super`]): the integrator and its
//! strategies, the plan, the sampler and the wavelengths before the files are written; the
//! speed, the mean colour and what may not be what the user meant after.

use super::job::RenderJob;
use crate::effects::Effect;
use crate::film::FilmState;
use crate::integrator::{IntegratorKind, RenderResult, SamplerKind, WavelengthSampling};

/// The lines before the outputs: integrator, strategies, plan, sampler, wavelengths.
pub fn print_setup(job: &RenderJob) {
    let (args, scene, plan) = (&job.args, &job.scene, &job.plan);
    println!("integrator {}:", args.integrator);
    for line in crate::integrator::strategy_summary(scene, args.integrator) {
        println!("  {line}");
    }
    println!("  {}", plan.summary_line());
    for n in plan.notes() {
        println!("  {n}");
    }
    println!(
        "  sampler: {}",
        match job.settings.sampler {
            SamplerKind::Sobol => {
                "sobol (shuffled, Owen-scrambled Sobol' points for the first dimensions of each sample)"
            }
            SamplerKind::Independent => "independent (PCG32)",
        }
    );
    if args.integrator == IntegratorKind::Pt {
        let n = job.settings.tracer.wavelengths_per_path;
        println!("  wavelengths: {n} per path, {}", path_wavelengths(job));
    } else {
        // bdpt and lt: the density the render drew its pairs from (the plan's cached table).
        let planned = plan.scene(scene);
        let pair = crate::integrator::wavelengths::pairs::PairWavelengths::new(
            plan,
            &planned,
            job.settings.tracer.wavelengths,
        );
        println!("  wavelengths: one set per path pair, {}", pair.describe());
    }
}

/// How the path tracer drew its wavelengths, as the summary says it.
fn path_wavelengths(job: &RenderJob) -> String {
    let (scene, plan) = (&job.scene, &job.plan);
    let (sampling, n) = (
        job.settings.tracer.wavelengths,
        job.settings.tracer.wavelengths_per_path,
    );
    let sampler = crate::integrator::wavelengths::groups::PathWavelengthSampler::new(
        plan,
        sampling,
        n,
        scene.objects.fluorescence(),
    );
    let fell_back = sampling == WavelengthSampling::LightSpd
        && sampler.as_ref().is_ok_and(|s| s.light_spd_fell_back());
    let refused = sampler
        .as_ref()
        .is_ok_and(|s| s.light_spd_refused_for_fluorescence());
    if refused {
        return "light-SPD sampling requested but the scene fluoresces (light appears where no light emits): visible-importance used".to_string();
    }
    if fell_back {
        return "light-SPD sampling requested but no light has an evaluable spectrum: visible-importance used".to_string();
    }
    let used = sampler.as_ref().map_or(sampling, |s| s.sampling());
    match used {
        WavelengthSampling::Visible
            if plan.emission_wavelengths() && plan.mixture().emission_weight() >= 1.0 =>
        {
            "all from the lights' spectra (render plan: all emission is narrowband)"
        }
        WavelengthSampling::Visible if plan.emission_wavelengths() => {
            "half visible-importance, half from the lights' spectra (render plan)"
        }
        WavelengthSampling::Visible if sampling == WavelengthSampling::Product => {
            "visible-importance sampling (observer × emission does not apply: no evaluable light, or fluorescence)"
        }
        WavelengthSampling::Visible => "visible-importance sampling",
        WavelengthSampling::Product => {
            "observer × √emission importance (¾) with visible importance (¼)"
        }
        WavelengthSampling::Uniform => "uniform sampling",
        WavelengthSampling::LightSpd => "light-SPD importance sampling",
    }
    .to_string()
}

/// The speed and the mean colour.
pub fn print_totals(job: &RenderJob, result: &RenderResult) {
    let scene = &job.scene;
    let secs = result.elapsed.as_secs_f64().max(1e-9);
    let rgb = scene.options.rgb_space.xyz_to_rgb(result.image.mean_xyz());
    println!(
        "rendered {}×{} at {} spp ({} samples) in {:.2} s (scene load {:.2} s, {} threads)",
        result.image.width,
        result.image.height,
        result.spp,
        result.samples,
        secs,
        job.load_s,
        job.args.threads.unwrap_or_else(rayon::current_num_threads),
    );
    println!(
        "  {:.3} M samples/s, {:.3} M rays/s, mean linear {} ({:.5}, {:.5}, {:.5}), non-finite pixels: {}",
        result.samples as f64 / secs / 1e6,
        result.rays as f64 / secs / 1e6,
        scene.options.rgb_space_name,
        rgb[0],
        rgb[1],
        rgb[2],
        result.image.non_finite_count()
    );
}

/// What may not be what the user meant: a black image (with what the plan knows about why),
/// a dropped pass, rejected samples.
pub fn print_warnings(job: &RenderJob, result: &RenderResult, film: &FilmState) {
    if result.image.non_finite_count() == 0 && result.image.xyz.iter().all(|p| p[1] == 0.0) {
        let effects = job.plan.effects();
        let why = match job.args.integrator {
            IntegratorKind::Lt if effects.contains(Effect::DeltaBsdfs) => {
                " light tracing cannot show specular surfaces the camera sees directly \
                 (this scene has some); try --integrator bdpt or pt"
            }
            IntegratorKind::Pt if effects.contains(Effect::DeltaLights) => {
                " the path tracer cannot reach a point, spot or directional light through a \
                 specular surface (only next-event estimation finds them); try --integrator bdpt"
            }
            _ => " check that a light reaches what the camera sees (`spectrace explain`)",
        };
        println!("  warning: the image is black (every pixel 0):{why}");
    }
    if let Some(d) = result.dropped_pass {
        println!(
            "  time budget: the pass of {} spp running at its end was stopped {:.2} s in and \
             dropped; the image holds the {} spp of the whole passes",
            d.spp,
            d.after.as_secs_f64(),
            result.spp
        );
    }
    for line in film.rejected.summary() {
        println!("  {line}");
    }
}
