//! Plugin objects seen through the host adapters behave like the host's own: the plugin point and
//! spot lights (plugins/point-light) against the host's independent implementations
//! (host/src/light), a lent SPD against the original, and faults recorded instead of panics.

use glam::{Vec2, Vec3A};
use spectrace::light::{Light, LightFlags, LightSampleContext, PointLight, SpotLight};
use spectrace::plugin::adapter::{Origin, PluginFaults, PluginLight, PluginSpd};
use spectrace::plugin::services::lend_spd;
use spectrace::plugin::Registry;
use spectrace::spectrum::{parse_spd_spec, SampledWavelengths, Spd};
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::RandomSample;
use spectrace_tests::plugin_library;
use std::sync::Arc;

fn origin(label: &str) -> (Origin, Arc<PluginFaults>) {
    let faults = PluginFaults::new();
    (
        Origin {
            label: label.to_string(),
            faults: faults.clone(),
        },
        faults,
    )
}

fn plugin_light(lib: &str, ty: &str, params: &str) -> (PluginLight, Arc<PluginFaults>) {
    let mut r = Registry::new();
    r.load_plugin(&plugin_library(lib)).unwrap();
    let light = r
        .create_plugin_light(ty, ObjectSource::Params(RStr::from_str(params)))
        .unwrap();
    let (o, f) = origin(ty);
    let plugin = r.plugins()[0].clone();
    let beams = plugin
        .info
        .types
        .iter()
        .find(|t| t.name.as_str() == ty)
        .map(|t| t.beams)
        .unwrap_or_default();
    let l = PluginLight::new(light, beams, plugin.module.take_error(), o, ty)
        .unwrap_or_else(|e| panic!("{e}"));
    (l, f)
}

fn receivers() -> Vec<Vec3A> {
    let mut v = Vec::new();
    for i in 0..40 {
        let t = i as f32 * 0.37;
        v.push(Vec3A::new(
            3.0 * t.sin(),
            -2.0 + 0.1 * i as f32,
            2.5 * t.cos(),
        ));
    }
    v
}

/// Relative agreement of two f32 spectra: both implementations compute the same closed form in
/// f32 (host) and f64 (plugin), so 1e-4 covers f32 rounding of d², cos θ and the smoothstep.
fn assert_close(a: f32, b: f32, what: &str) {
    let scale = a.abs().max(b.abs()).max(1e-30);
    assert!((a - b).abs() / scale < 1e-4, "{what}: {a} vs {b}");
}

#[test]
fn plugin_and_host_point_lights_agree() {
    let spd: Arc<dyn Spd> = Arc::new(parse_spd_spec("d65").unwrap());
    let host = PointLight::new(Vec3A::new(0.5, 1.5, -0.25), spd, 60.0);
    let (plugin, faults) = plugin_light(
        "spectrace-point-light",
        "isotropic_point",
        "(position: (0.5, 1.5, -0.25), power_w: 60, spd: \"d65\")",
    );
    assert_eq!(plugin.flags(), LightFlags::DELTA_POSITION);
    assert_eq!(plugin.power(), host.power());
    let lambda = SampledWavelengths::sample_uniform(0.3, 360.0, 830.0);
    for p in receivers() {
        let ctx = LightSampleContext {
            p,
            p_error: Vec3A::ZERO,
            n: Vec3A::Y,
        };
        let a = host.sample_li(&ctx, Vec2::new(0.2, 0.7), &lambda).unwrap();
        let b = plugin
            .sample_li(&ctx, Vec2::new(0.2, 0.7), &lambda)
            .unwrap();
        for i in 0..4 {
            assert_close(a.radiance[i], b.radiance[i], "point radiance");
        }
        assert!((a.wi - b.wi).length() < 1e-5);
        assert_eq!(a.pdf, b.pdf);
    }
    assert_eq!(faults.count(), 0);
}

#[test]
fn plugin_and_host_spot_lights_agree() {
    let spd: Arc<dyn Spd> = Arc::new(parse_spd_spec("blackbody:3200").unwrap());
    let pos = Vec3A::new(0.0, 2.0, 0.0);
    let target = Vec3A::new(0.3, 0.0, 0.1);
    let host = SpotLight::new(pos, target, 15.0, 40.0, spd, 12.0).unwrap();
    let dir = target - pos;
    let (plugin, _) = plugin_light(
        "spectrace-point-light",
        "smooth_spot",
        &format!(
            "(position: (0, 2, 0), direction: ({}, {}, {}), cone_angle_deg: 40, falloff_start_deg: 15, power_w: 12, spd: \"blackbody:3200\")",
            dir.x, dir.y, dir.z
        ),
    );
    let lambda = SampledWavelengths::sample_uniform(0.8, 360.0, 830.0);
    let pairs: Vec<_> = (0..400)
        .map(|i| {
            // Receivers on the floor across the cone edge.
            let p = Vec3A::new(-2.0 + 0.01 * i as f32, 0.0, 0.1 + 0.003 * i as f32);
            let ctx = LightSampleContext {
                p,
                p_error: Vec3A::ZERO,
                n: Vec3A::Y,
            };
            let a = host.sample_li(&ctx, Vec2::ZERO, &lambda);
            let b = plugin.sample_li(&ctx, Vec2::ZERO, &lambda);
            (
                a.map(|s| s.radiance).unwrap_or_default(),
                b.map(|s| s.radiance).unwrap_or_default(),
            )
        })
        .collect();
    let peak = pairs
        .iter()
        .map(|(a, _)| a.max_value())
        .fold(0.0f32, f32::max);
    let mut lit = 0;
    for (ra, rb) in &pairs {
        for k in 0..4 {
            // Relative 1e-4 as for the point light, plus an absolute 1e-5 of the peak: near the
            // cut-off the host's f32 smoothstep loses digits to cancellation in cos − cos_outer
            // (relative error ≈ 2ε/(cos − cos_outer)), while the value itself is ≪ the peak.
            let tol = 1e-4 * ra[k].abs().max(rb[k].abs()) + 1e-5 * peak;
            assert!(
                (ra[k] - rb[k]).abs() <= tol,
                "spot radiance {} vs {}",
                ra[k],
                rb[k]
            );
        }
        if !ra.is_black() {
            lit += 1;
        }
    }
    assert!(
        lit > 50 && lit < 400,
        "receivers should straddle the cone edge ({lit} lit)"
    );
}

#[test]
fn beams_only_lights_are_flagged_and_still_emit() {
    let (laser, faults) = plugin_light(
        "spectrace-example-laser",
        "laser",
        "(origin: (0,0,0), direction: (1,0,0), wavelength_nm: 650, power_w: 0.001)",
    );
    assert!(laser.flags().contains(LightFlags::BEAMS_ONLY));
    let ctx = LightSampleContext {
        p: Vec3A::new(1.0, 1.0, 0.0),
        p_error: Vec3A::ZERO,
        n: Vec3A::Y,
    };
    let lambda = SampledWavelengths::sample_uniform(0.5, 360.0, 830.0);
    assert!(laser.sample_li(&ctx, Vec2::ZERO, &lambda).is_none());
    let beam = laser.next_beam(&RandomSample::default()).unwrap();
    assert_eq!(beam.wavelength_nm, 650.0);
    assert_eq!(laser.number_of_beams(), 1.0);
    assert_eq!(faults.count(), 0);
}

#[test]
fn plugin_failures_become_faults_not_panics() {
    let (light, faults) = plugin_light("spectrace-fixture-panicking-light", "panicking", "()");
    let mut u = RandomSample::default();
    u.u[0] = 0.75;
    assert!(light.next_beam(&u).is_none());
    assert_eq!(faults.count(), 1);
    let msg = faults.first().unwrap();
    assert!(
        msg.contains("panicking") && msg.contains("deliberate panic"),
        "{msg}"
    );
}

#[test]
fn a_lent_spd_reads_back_identically() {
    // Host SPD → ABI (lend_spd) → host again (PluginSpd): the double conversion is exact in f64.
    let d65: Arc<dyn Spd> = Arc::new(parse_spd_spec("d65").unwrap());
    let (o, _) = origin("d65");
    let round = PluginSpd::new(lend_spd(d65.clone()).unwrap(), o);
    assert_eq!(round.range(), d65.range());
    for i in 0..1000 {
        let u = (i as f64 + 0.5) / 1000.0;
        let nm = 360.0 + 470.0 * u;
        assert_eq!(round.value(nm), d65.value(nm));
        assert_eq!(round.pdf(nm), d65.pdf(nm));
        let (a, b) = (round.sample(u), d65.sample(u));
        assert_eq!((a.lambda, a.pdf), (b.lambda, b.pdf));
    }
}
