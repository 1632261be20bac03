//! The standard set as a library (`plugins/standard`): the host's materials, lights (point,
//! spot, directional, environment), SPD types and CIE observers loaded from a plugin library
//! build objects that sample bit for bit like the built-ins, and scenes render bit for bit alike
//! with every type from the library, in PT, BDPT and LT; loaded next to the built-ins, the
//! library is refused naming both providers; alone it renders the Cornell box.

use spectrace::integrator::IntegratorKind;
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::RegistryFactory;
use spectrace::plugin::{Kind, Registry};
use spectrace::scene::{FactoryContext, ObjectFactory};
use spectrace_tests::{plugin_library, render_auto_xyz};
use std::sync::Arc;

fn library() -> std::path::PathBuf {
    plugin_library("spectrace-standard")
}

/// The built-ins with the library's types in place of those it exports (`--replace-builtins`).
fn library_registry() -> Registry {
    let mut r = spectrace::plugin::builtin_registry();
    r.load_plugin_replacing_builtins(&library()).unwrap();
    assert!(r.plugin_for(Kind::Spd, "spec").unwrap().is_some());
    assert!(r.plugin_for(Kind::Observer, "cie1931-2").unwrap().is_some());
    for name in [
        "lambertian",
        "mirror",
        "dielectric",
        "rough_dielectric",
        "conductor",
        "plastic",
        "rough_plastic",
        "emissive",
        "fluorescent",
    ] {
        assert!(
            r.plugin_for(Kind::Material, name).unwrap().is_some(),
            "{name}"
        );
    }
    for name in ["point", "spot", "directional", "environment"] {
        assert!(r.plugin_for(Kind::Light, name).unwrap().is_some(), "{name}");
    }
    r
}

fn factory(r: Registry) -> RegistryFactory {
    RegistryFactory::new(Arc::new(r), PluginFaults::new())
}

fn ctx(f: &RegistryFactory) -> FactoryContext {
    f.context(std::path::Path::new("."), "test".into())
}

#[test]
fn next_to_the_builtins_the_library_is_refused_naming_both() {
    let mut r = spectrace::plugin::builtin_registry();
    let e = r.load_plugin(&library()).unwrap_err().to_string();
    assert!(
        e.contains("duplicate") && e.contains("built-in") && e.contains("plugin `standard`"),
        "{e}"
    );
    assert!(r.plugins().is_empty());
}

/// Quantity: value, pdf and sampled wavelength (and whether it is a line) of the `spec` and
/// `table` SPD types, their range and spectral lines (a mixture with a line included), and x̄ȳz̄
/// and the integral of ȳ of the four CIE observers, at 471 wavelengths (360–830 nm), library
/// against built-in. Tolerance: none: both run the same host code on the same f64 parameters,
/// the plugin interface passes them unchanged, and lines cross as declared data.
#[test]
fn library_types_sample_exactly_like_the_builtins() {
    let builtin = factory(spectrace::plugin::builtin_registry());
    let lib = factory(library_registry());
    let spds: [(&str, &str); 4] = [
        ("spec", "(spec: \"blackbody:3000\")"),
        ("spec", "(spec: \"fl11\")"),
        ("spec", "(spec: \"0.75*d65 + 0.25*line:532\")"),
        (
            "table",
            "(values: [(400, 1), (500, 3), (600, 0.5), (700, 2)])",
        ),
    ];
    for (ty, params) in spds {
        let params: ron::Value = ron::from_str(params).unwrap();
        let a = builtin.spd(ty, &params, &ctx(&builtin)).unwrap();
        let b = lib.spd(ty, &params, &ctx(&lib)).unwrap();
        assert!(
            lib.registry().plugin_for(Kind::Spd, ty).unwrap().is_some(),
            "{ty} comes from the library"
        );
        assert_eq!(a.range(), b.range(), "{ty} range");
        assert_eq!(a.delta_lines(), b.delta_lines(), "{ty} lines");
        assert_eq!(a.is_delta(), b.is_delta(), "{ty} is_delta");
        for i in 0..=470 {
            let nm = 360.0 + i as f64;
            let u = i as f64 / 471.0;
            assert_eq!(a.value(nm), b.value(nm), "{ty} value at {nm}");
            assert_eq!(a.pdf(nm), b.pdf(nm), "{ty} pdf at {nm}");
            assert_eq!(a.sample(u), b.sample(u), "{ty} sample at {u}");
        }
    }
    for name in ["cie1931-2", "cie1964-10", "cie2015-2", "cie2015-10"] {
        let a = builtin
            .observer(name, &ron::Value::Unit, &ctx(&builtin))
            .unwrap();
        let b = lib.observer(name, &ron::Value::Unit, &ctx(&lib)).unwrap();
        assert_eq!(a.range(), b.range(), "{name}");
        assert_eq!(a.integral_y(), b.integral_y(), "{name}");
        for i in 0..=470 {
            let nm = 360.0 + i as f64;
            assert_eq!(a.xyz_bar(nm), b.xyz_bar(nm), "{name} at {nm}");
        }
    }
}

/// Quantity: `sample` (direction, value, pdf, flags, eta), `eval`, `pdf` and `emitted` of the
/// six built-in material types (and the emission an area light is built from), and `sample_li`,
/// `pdf_li`, `sample_le`, `pdf_le`, `radiance`, `escape_point`, power and the emission spectrum
/// of `point`, `spot`, `directional` and `environment` after both learned the same scene bounds,
/// at 200 pseudo-random inputs each, library against built-in. Tolerance: none (bit-identical):
/// both run the host's own code, every f32 the host hands the library crosses as f64 and comes
/// back as the same f32, and the surface carries the normals, the
/// lights get the bounds and emitters hand over their own SPD. Not carried: the wavelengths'
/// densities (only thin films read them), so they are left at 1/nm here.
#[test]
fn library_materials_and_lights_sample_exactly_like_the_builtins() {
    use glam::{Vec2, Vec3A};
    use spectrace::geometry::{Aabb, Ray};
    use spectrace::light::LightSampleContext;
    use spectrace::material::{ShadingContext, TransportMode};
    use spectrace::spectrum::SampledWavelengths;
    let builtin = factory(spectrace::plugin::builtin_registry());
    let lib = factory(library_registry());
    // A small LCG: deterministic inputs in [0, 1).
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let materials = [
        ("lambertian", "(reflectance: \"colorchecker:13\")"),
        ("mirror", "(reflectance: 0.95)"),
        ("dielectric", "(ior: \"N-BK7\")"),
        ("rough_dielectric", "(ior: 1.5, roughness: 0.4)"),
        ("conductor", "(metal: \"gold\", roughness: 0.3)"),
        (
            "plastic",
            "(diffuse_reflectance: \"colorchecker:13\", int_ior: 1.6)",
        ),
        (
            "rough_plastic",
            "(diffuse_reflectance: 0.4, alpha: 0.2, distribution: \"beckmann\")",
        ),
        ("emissive", "(radiance: \"d65\", scale: 400.0)"),
    ];
    for (ty, params) in materials {
        let params: ron::Value = ron::from_str(params).unwrap();
        let a = builtin.material(ty, &params, &ctx(&builtin)).unwrap();
        let b = lib.material(ty, &params, &ctx(&lib)).unwrap();
        assert!(lib
            .registry()
            .plugin_for(Kind::Material, ty)
            .unwrap()
            .is_some());
        assert_eq!(a.flags(), b.flags(), "{ty} flags");
        match (a.emission(), b.emission()) {
            (None, None) => {}
            (Some(ea), Some(eb)) => {
                assert_eq!(
                    (ea.scale.to_bits(), ea.two_sided),
                    (eb.scale.to_bits(), eb.two_sided),
                    "{ty} emission"
                );
                assert_eq!(ea.spd.range(), eb.spd.range(), "{ty} emission range");
                for k in 0..=470 {
                    let nm = 360.0 + k as f64;
                    assert_eq!(ea.spd.value(nm), eb.spd.value(nm), "{ty} emission at {nm}");
                    let u = k as f64 / 471.0;
                    assert_eq!(ea.spd.sample(u), eb.spd.sample(u), "{ty} emission sample");
                }
            }
            (x, y) => panic!("{ty}: emission {:?} vs {:?}", x.is_some(), y.is_some()),
        }
        for _ in 0..200 {
            let ng = Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            let ns = (ng + 0.2 * Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5)).normalize();
            let sc = ShadingContext::at(
                Vec3A::new(rnd(), rnd(), rnd()),
                ng,
                ns,
                Vec2::new(rnd(), rnd()),
            );
            let wo = Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.3).normalize();
            let wi = Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            let mut lambda = SampledWavelengths::sample_uniform(rnd(), 360.0, 830.0);
            lambda.pdf = [1.0; spectrace::spectrum::LANES];
            let (ul, u) = (rnd(), Vec2::new(rnd(), rnd()));
            for mode in [TransportMode::Radiance, TransportMode::Importance] {
                let sa = a.sample(wo, &sc, &lambda, ul, u, mode);
                let sb = b.sample(wo, &sc, &lambda, ul, u, mode);
                assert_eq!(sa, sb, "{ty} sample");
                assert_eq!(
                    a.eval(wo, wi, &sc, &lambda, mode),
                    b.eval(wo, wi, &sc, &lambda, mode),
                    "{ty} eval"
                );
                assert_eq!(
                    a.pdf(wo, wi, &sc, &lambda, mode).to_bits(),
                    b.pdf(wo, wi, &sc, &lambda, mode).to_bits(),
                    "{ty} pdf"
                );
            }
            assert_eq!(a.emitted(wo, &sc, &lambda), b.emitted(wo, &sc, &lambda));
        }
    }
    let lights = [
        (
            "point",
            "(position: (1, 2, 3), power: 100, spd: \"blackbody:3000\")",
        ),
        (
            "spot",
            "(position: (2, 3, 2), target: (0, 0, 0), inner_angle: 15, outer_angle: 25, \
             power: 1500, spd: \"blackbody:2856\")",
        ),
        (
            "directional",
            "(direction: (-0.4, -1, -0.3), irradiance: 800, spd: \"0.9*d65 + 0.1*line:589\")",
        ),
        ("environment", "(radiance: \"blackbody:9000\", scale: 30)"),
    ];
    // The scene's geometry, and with a camera at (0, 1, 8) the view bounds.
    let bounds = Aabb {
        min: Vec3A::new(-3.0, -1.0, -3.0),
        max: Vec3A::new(3.0, 2.5, 1.0),
    };
    let view = Aabb {
        min: bounds.min,
        max: Vec3A::new(3.0, 2.5, 8.0),
    };
    for (ty, params) in lights {
        let params: ron::Value = ron::from_str(params).unwrap();
        let a = builtin.light(ty, &params, &ctx(&builtin)).unwrap();
        let b = lib.light(ty, &params, &ctx(&lib)).unwrap();
        assert!(lib
            .registry()
            .plugin_for(Kind::Light, ty)
            .unwrap()
            .is_some());
        for l in [&a, &b] {
            l.preprocess(&bounds);
            l.preprocess_view(&view);
        }
        assert_eq!(a.flags(), b.flags(), "{ty} flags");
        assert_eq!(a.power().to_bits(), b.power().to_bits(), "{ty} power");
        let (sa, sb) = (a.spd(), b.spd());
        assert_eq!(sa.range(), sb.range(), "{ty} spectrum range");
        assert_eq!(sa.delta_lines(), sb.delta_lines(), "{ty} spectrum lines");
        for _ in 0..200 {
            let u = rnd() as f64;
            assert_eq!(sa.sample(u), sb.sample(u), "{ty} wavelength sample");
            let nm = 360.0 + 470.0 * rnd() as f64;
            assert_eq!(sa.pdf(nm), sb.pdf(nm), "{ty} wavelength pdf");
            assert_eq!(sa.value(nm), sb.value(nm), "{ty} spectrum value");
            let lambda = SampledWavelengths::sample_uniform(rnd(), 360.0, 830.0);
            let lc = LightSampleContext {
                p: Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 4.0,
                p_error: Vec3A::ZERO,
                n: Vec3A::ZERO,
            };
            let u1 = Vec2::new(rnd(), rnd());
            let u2 = Vec2::new(rnd(), rnd());
            let (la, lb) = (a.sample_li(&lc, u1, &lambda), b.sample_li(&lc, u1, &lambda));
            assert_eq!(la.is_some(), lb.is_some(), "{ty} sample_li");
            if let (Some(la), Some(lb)) = (la, lb) {
                assert_eq!(
                    (la.radiance, la.wi, la.pdf, la.p_light, la.n_light),
                    (lb.radiance, lb.wi, lb.pdf, lb.p_light, lb.n_light),
                    "{ty} sample_li"
                );
                assert_eq!(
                    a.pdf_li(&lc, la.p_light, la.n_light).to_bits(),
                    b.pdf_li(&lc, lb.p_light, lb.n_light).to_bits(),
                    "{ty} pdf_li"
                );
                assert_eq!(
                    a.radiance(la.p_light, la.n_light, Vec2::ZERO, -la.wi, &lambda),
                    b.radiance(lb.p_light, lb.n_light, Vec2::ZERO, -lb.wi, &lambda),
                    "{ty} radiance"
                );
                let ray = Ray::new(lc.p, la.wi);
                assert_eq!(a.escape_point(&ray), b.escape_point(&ray), "{ty} escape");
            }
            let (ea, eb) = (a.sample_le(u1, u2, &lambda), b.sample_le(u1, u2, &lambda));
            assert_eq!(ea.is_some(), eb.is_some(), "{ty} sample_le");
            if let (Some(ea), Some(eb)) = (ea, eb) {
                assert_eq!(
                    (
                        ea.ray.origin,
                        ea.ray.dir,
                        ea.radiance,
                        ea.pdf_pos,
                        ea.pdf_dir,
                        ea.normal
                    ),
                    (
                        eb.ray.origin,
                        eb.ray.dir,
                        eb.radiance,
                        eb.pdf_pos,
                        eb.pdf_dir,
                        eb.normal
                    ),
                    "{ty} sample_le"
                );
                assert_eq!(
                    a.pdf_le(&ea.ray, ea.normal),
                    b.pdf_le(&ea.ray, ea.normal),
                    "{ty} pdf_le"
                );
            }
        }
    }
}

/// `desc` built with the types of `registry`, with the factory (for its fault counts).
fn build(
    desc: &spectrace::scene::SceneDescription,
    registry: Registry,
) -> (spectrace::scene::Scene, RegistryFactory) {
    let f = factory(registry);
    let factories: [&dyn ObjectFactory; 1] = [&f];
    let scene = spectrace::scene::build_scene(
        desc,
        std::path::Path::new("."),
        std::path::Path::new("scene"),
        &factories,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (scene, f)
}

/// Render `desc` with `kind` (`spp` samples per pixel, `seed`) with the types of `registry`,
/// effects as `--effects auto` chooses them (the exact colour of spectrally flat paths on
/// wherever a light has one spectral shape).
fn render_xyz(
    desc: &spectrace::scene::SceneDescription,
    registry: Registry,
    kind: IntegratorKind,
    spp: u32,
    seed: u64,
) -> Vec<[f64; 3]> {
    let (scene, f) = build(desc, registry);
    // `flat-path-colour` stays as `auto` decides: by their declared bits the library's types
    // declare spectral flatness and uniform emission shapes exactly where the built-ins do (see
    // `library_declares_flatness_where_the_builtins_do`), so both are estimated alike.
    render_auto_xyz(&scene, &f, kind, spp, seed)
}

/// The first camera's resolution set to `w`×`h`.
fn at_resolution(
    mut desc: spectrace::scene::SceneDescription,
    w: u32,
    h: u32,
) -> spectrace::scene::SceneDescription {
    if let ron::Value::Map(m) = &mut desc.cameras[0].params {
        m.insert(
            ron::Value::String("resolution".into()),
            ron::from_str(&format!("({w}, {h})")).unwrap(),
        );
    }
    desc
}

/// The scenes of the bit-for-bit comparison, each small.
fn scenes() -> Vec<(&'static str, spectrace::scene::SceneDescription)> {
    let parse = |text: &str, name: &str| {
        spectrace::scene::parse_scene_str(text, std::path::Path::new(name)).unwrap()
    };
    vec![
        (
            "cornell",
            at_resolution(spectrace::scene::cornell_box_description().unwrap(), 24, 24),
        ),
        (
            "materials",
            at_resolution(
                parse(include_str!("../../scenes/materials.ron"), "materials.ron"),
                64,
                40,
            ),
        ),
        (
            "sun_and_sky",
            at_resolution(
                parse(
                    include_str!("../../scenes/sun_and_sky.ron"),
                    "sun_and_sky.ron",
                ),
                48,
                32,
            ),
        ),
        (
            "fluorescence",
            at_resolution(
                parse(
                    include_str!("../../scenes/fluorescence.ron"),
                    "fluorescence.ron",
                ),
                40,
                24,
            ),
        ),
    ]
}

/// Quantity: every pixel's X, Y and Z of three scenes rendered with the built-ins and with ALL
/// their types from the library (`--replace-builtins`), same seed and spp, in PT, BDPT and LT:
/// the Cornell box (one area light; 24×24, 4 spp), `scenes/materials.ron` (every built-in
/// material under an emissive quad and a spot light; 64×40, 4 spp) and
/// `scenes/sun_and_sky.ron` (a directional and an environment light; 48×32, 4 spp) and
/// `scenes/fluorescence.ron` (two measured fluorescent samples and their non-fluorescent twins
/// under a near-UV and a D65 panel; 40×24, 4 spp: the re-radiation crosses through extension
/// v3). Effects as `--effects auto` decides, so the exact colour of spectrally flat paths is on
/// (`flat-path-colour`; every scene has area lights): by their declared bits the library's types
/// declare spectral flatness where the built-ins do (test below). Tolerance: none,
/// bit-identical (what `spectrace compare --json` reports as RMSE 0).
///
/// Why this holds, and what it took: the objects are bit-identical (test above), and the host
/// also sees the emitters' spectra as the built-ins do (declared once). Without a declared
/// emission the host knows a plugin emitter's spectrum only through sampled values: an emissive plugin material's
/// area light was `emitted` tabulated at 1 nm over 360–830 nm, with the table's trapezoid
/// integral as its scale. For D65 (defined from 300 nm) that integral leaves out the 300–360 nm
/// part, so the area light's power, and with it the light-selection probabilities, differed
/// from the built-in's. Measured on `materials.ron` (PT, 64×40, 16 spp, 16 seeds, library before
/// v2 over built-in): the emissive quad alone rendered alike up to f32 rounding of the table
/// (mean ratio 1 + 1e-7), the spot light alone bit for bit, both together −0.19% ± 0.03% in X,
/// −0.16% ± 0.03% in Y, −0.05% ± 0.02% in Z. So the offset came from the changed selection
/// probabilities alone; that a change of them moves the mean by 6σ is not explained here (the
/// materials' sampled and evaluated densities agree), and it no longer arises between the
/// library and the built-ins, whose probabilities are now the same bits.
#[test]
fn scenes_render_bit_for_bit_with_all_types_from_the_library() {
    let scenes = scenes();
    for (name, desc) in &scenes {
        for kind in [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt] {
            let a = render_xyz(desc, spectrace::plugin::builtin_registry(), kind, 4, 7);
            let b = render_xyz(desc, library_registry(), kind, 4, 7);
            let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
            let mean_y = a.iter().map(|p| p[1]).sum::<f64>() / a.len() as f64;
            eprintln!("{name} {kind}: {differ} of {} pixels differ", a.len());
            assert!(mean_y > 0.0, "{name} {kind}: black");
            assert_eq!(
                differ,
                0,
                "{name} {kind}: {differ} of {} pixels differ",
                a.len()
            );
        }
    }
}

/// Quantity: per object of each scene of the bit-for-bit comparison, whether its material is
/// spectrally flat (`Material::spectrally_flat`), and per light whether its emission has one
/// spectral shape (`Light::uniform_spectral_shape`), built-ins against the library (extension
/// v4, the library's flatness claims checked by the host when built). Tolerance: none, the same
/// answers. The scenes must hold flat objects and uniform lights (else the comparison would
/// pass with no declaration crossing the interface at all): the emitters and the grey
/// materials of `fluorescence.ron` (flat objects: Cornell box 1 of 8, `materials.ron` 1 of 7,
/// `sun_and_sky.ron` 0 of 3, `fluorescence.ron` 3 of 7), and the area lights (1, 1, 0, 2).
/// Likewise whether its BSDF value is the same for every direction
/// (`SAME_VALUE_ALL_DIRECTIONS`, also checked by the host when built;
/// the Lambertian surfaces, which every scene but `sun_and_sky.ron` has), and whether it samples
/// with the cosine-weighted density (`COSINE_PDF`, checked
/// when built; the same Lambertian surfaces).
#[test]
fn library_declares_flatness_where_the_builtins_do() {
    let (mut flat, mut uniform, mut same_f, mut cosine) = (0, 0, 0, 0);
    for (name, desc) in scenes() {
        let (a, _) = build(&desc, spectrace::plugin::builtin_registry());
        let (b, _) = build(&desc, library_registry());
        let objects = |s: &spectrace::scene::Scene| -> Vec<(String, bool)> {
            s.objects
                .objects()
                .iter()
                .map(|o| (o.name.clone(), o.material.spectrally_flat()))
                .collect()
        };
        let lights = |s: &spectrace::scene::Scene| -> Vec<bool> {
            s.lights
                .lights()
                .iter()
                .map(|l| l.uniform_spectral_shape())
                .collect()
        };
        assert_eq!(objects(&a), objects(&b), "{name}: spectrally flat objects");
        assert_eq!(lights(&a), lights(&b), "{name}: uniform lights");
        let same = |s: &spectrace::scene::Scene| -> Vec<bool> {
            s.objects
                .objects()
                .iter()
                .map(|o| o.material.f_same_for_all_directions())
                .collect()
        };
        assert_eq!(same(&a), same(&b), "{name}: f the same for all directions");
        same_f += same(&a).iter().filter(|&&f| f).count();
        let cos = |s: &spectrace::scene::Scene| -> Vec<bool> {
            s.objects
                .objects()
                .iter()
                .map(|o| o.material.cosine_weighted_pdf())
                .collect()
        };
        assert_eq!(cos(&a), cos(&b), "{name}: cosine-weighted density");
        cosine += cos(&a).iter().filter(|&&c| c).count();
        flat += objects(&a).iter().filter(|o| o.1).count();
        uniform += lights(&a).iter().filter(|&&u| u).count();
        eprintln!(
            "{name}: {} flat object(s) of {}, {} uniform light(s) of {}",
            objects(&a).iter().filter(|o| o.1).count(),
            objects(&a).len(),
            lights(&a).iter().filter(|&&u| u).count(),
            lights(&a).len()
        );
    }
    assert!(
        flat > 0 && uniform > 0 && same_f > 0 && cosine > 0,
        "flat {flat}, uniform {uniform}, same f {same_f}, cosine {cosine}"
    );
}

/// Quantity: the Cornell box with no built-in materials, lights, SPDs or observers
/// (`--no-builtins`) and the library: every type it uses comes from the library and the image
/// is not black. Tolerance: mean Y > 0 (a black image would mean the emitter was lost).
#[test]
fn without_builtins_the_library_renders_the_cornell_box() {
    let mut r = spectrace::plugin::core_registry();
    r.load_plugin(&library()).unwrap();
    assert!(r.plugin_for(Kind::Material, "emissive").unwrap().is_some());
    let desc = at_resolution(spectrace::scene::cornell_box_description().unwrap(), 16, 16);
    let img = render_xyz(&desc, r, IntegratorKind::Pt, 2, 1);
    let y = img.iter().map(|p| p[1]).sum::<f64>() / img.len() as f64;
    assert!(y > 0.0 && y.is_finite(), "mean Y {y}");
}

/// Quantity: every call of the host's re-radiation interface (reflectance, r(λᵢ → λₒ), the two
/// fractions, both draws with their densities, both densities, the range) of the library's
/// `fluorescent` (its re-radiation handed over) against the built-in, for a measured matrix (IXCRLALE) and the
/// parametric model, at 300 pseudo-random wavelength pairs and uniforms each over 300–800 nm;
/// and that the non-fluorescent twin offers none. Tolerance: none (bit-identical): both run the
/// host's own code, and every argument and result crosses the interface as f64 unchanged.
#[test]
fn library_fluorescent_reradiates_exactly_like_the_builtin() {
    let builtin = factory(spectrace::plugin::builtin_registry());
    let lib = factory(library_registry());
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for params in [
        "(bfc: \"IXCRLALE\")",
        "(reflectance: 0.3, absorption: ((340, 0), (350, 0.6), (450, 0.6), (460, 0)), \
          emission: \"gaussian:520:40\", quantum_yield: 0.8)",
    ] {
        let params: ron::Value = ron::from_str(params).unwrap();
        let a = builtin
            .material("fluorescent", &params, &ctx(&builtin))
            .unwrap();
        let b = lib.material("fluorescent", &params, &ctx(&lib)).unwrap();
        assert_eq!(a.flags(), b.flags(), "{params:?} flags");
        let (ra, rb) = (
            a.reradiation().unwrap(),
            b.reradiation().expect("offered through v3"),
        );
        assert_eq!(ra.range(), rb.range());
        for _ in 0..300 {
            let (l1, l2, u) = (300.0 + 500.0 * rnd(), 300.0 + 500.0 * rnd(), rnd());
            assert_eq!(ra.reflectance(l1), rb.reflectance(l1), "{l1}");
            assert_eq!(ra.reradiation(l1, l2), rb.reradiation(l1, l2), "{l1} {l2}");
            assert_eq!(ra.reradiated_fraction(l1), rb.reradiated_fraction(l1));
            assert_eq!(ra.excitation_fraction(l1), rb.excitation_fraction(l1));
            assert_eq!(ra.sample_emission(l1, u), rb.sample_emission(l1, u));
            assert_eq!(ra.sample_excitation(l1, u), rb.sample_excitation(l1, u));
            assert_eq!(ra.emission_pdf(l1, l2), rb.emission_pdf(l1, l2));
            assert_eq!(ra.excitation_pdf(l1, l2), rb.excitation_pdf(l1, l2));
        }
    }
    let twin: ron::Value = ron::from_str("(bfc: \"IXCRLALE\", reradiate: false)").unwrap();
    let b = lib.material("fluorescent", &twin, &ctx(&lib)).unwrap();
    assert!(b.reradiation().is_none());
    assert!(!b
        .flags()
        .contains(spectrace::material::MaterialFlags::FLUORESCENT));
    assert_eq!(lib.faults().count() + lib.faults().invalid_count(), 0);
}
