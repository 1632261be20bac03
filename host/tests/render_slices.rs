//! Slices, merges and checkpoints give the single render's image bit for bit: merging 1, 2, 3
//! and 7 slices, and stopping after some passes then resuming, for path tracing, BDPT and light
//! tracing; parts that do not belong together are refused with errors naming them; a real
//! SIGTERM to the binary writes a checkpoint that resumes to the uninterrupted image. The
//! spectral image (`--spectral-exr`) travels with the film and is held to the same standard.
//! Run: `cargo test --release -p spectrace --test render_slices`

use spectrace::film::spectral::SpectralBins;
use spectrace::film::{FilmState, RenderState, SliceSpec};
use spectrace::integrator::{
    render_with_options, IntegratorKind, IntegratorOptions, IntegratorOutput, PathTracer,
    RenderSettings, SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// A spot on a floor, a wall and a mirror (so BDPT and light tracing splat, and light paths
/// reach the camera only through connections), 20×12 pixels.
const SCENE: &str = r#"(
    observer: "cie1931-2",
    output: (spp: 7, max_depth: 6, rgb_space: "srgb"),
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: 0.6)),
        (name: "wall", type: "lambertian", params: (reflectance: 0.8)),
        (name: "mirror", type: "mirror", params: (reflectance: 0.95)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2.5, 0, 2), edge0: (5, 0, 0), edge1: (0, 0, -4))),
        (name: "back", type: "quad", material: "wall",
         params: (corner: (-2.5, 0, -2), edge0: (5, 0, 0), edge1: (0, 3, 0))),
        (name: "mirror", type: "quad", material: "mirror",
         params: (corner: (1.9, 0.9, -0.6), edge0: (0, 0, 1.2), edge1: (0, 1.2, 0))),
    ],
    lights: [
        (name: "spot", type: "spot",
         params: (position: (0, 2.5, 1.5), target: (1.0, 0.8, -0.5), inner_angle: 20,
                  outer_angle: 40, power: 300, spd: "blackbody:3200")),
    ],
    cameras: [
        (name: "front", type: "perspective",
         params: (position: (0, 1.5, 5), look_at: (0, 0.8, -1), fov: 40, resolution: (20, 12))),
    ],
)"#;

fn scene() -> Scene {
    let file = Path::new("slices.ron");
    let desc = parse_scene_str(SCENE, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

const KINDS: [IntegratorKind; 3] = [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt];
const SPP: u32 = 7;

fn settings(budget: SampleBudget, threads: usize) -> RenderSettings {
    RenderSettings {
        sampler: Default::default(),
        budget,
        seed: 9,
        threads: Some(threads),
        camera: None,
        tile_size: 8,
        tracer: PathTracer {
            max_depth: 6,
            ..PathTracer::default()
        },
    }
}

/// The render with a spectral film (nodes 380:780:5, the default).
fn render_with(
    scene: &Scene,
    settings: &RenderSettings,
    kind: IntegratorKind,
    progress: &(dyn Fn(u64, u64) + Sync),
    cancel: Option<&AtomicBool>,
) -> IntegratorOutput {
    let options = IntegratorOptions {
        strategy_images: false,
        spectral: Some(SpectralBins::parse("380:780:5").unwrap()),
    };
    render_with_options(scene, settings, kind, options, progress, cancel).unwrap()
}

fn film(scene: &Scene, kind: IntegratorKind, budget: SampleBudget) -> FilmState {
    render_with(scene, &settings(budget, 2), kind, &|_, _| {}, None).film
}

/// The film's spectral image, as f64 bits.
fn spectral_bits(f: &FilmState) -> Vec<u64> {
    let img = f.spectral_image().expect("spectral sums");
    assert!(img.values.iter().any(|v| *v > 0.0), "black spectral image");
    img.values.iter().map(|v| v.to_bits()).collect()
}

fn state(film: FilmState, slice: SliceSpec, seed: u64, settings: &str) -> RenderState {
    RenderState {
        scene: None,
        fingerprint: 1,
        settings: settings.into(),
        args: Vec::new(),
        seed,
        spp_total: SPP,
        done_until: slice.range(SPP).end,
        slice,
        rgb_space: "srgb".into(),
        png_exposure: 1.0,
        film,
    }
}

/// Quantity: every pixel's XYZ (f64 bits) of the merged image against the single 7 spp render,
/// for 1, 2, 3 and 7 slices, each slice rendered on its own (the parts given in reverse order),
/// and every pixel's spectral image value (f64 bits, 81 nodes). Tolerance 0: the sums are
/// exact, so neither the split nor the merge order changes a bit.
#[test]
fn merged_slices_equal_the_single_render_bit_for_bit() {
    let scene = scene();
    for kind in KINDS {
        let whole = render_with(
            &scene,
            &settings(SampleBudget::Spp(SPP), 2),
            kind,
            &|_, _| {},
            None,
        );
        assert!(whole.result.image.mean_xyz()[1] > 0.0, "{kind}: black");
        for m in [1, 2, 3, 7] {
            let mut parts = Vec::new();
            for k in (1..=m).rev() {
                let slice = SliceSpec { index: k, count: m };
                let r = slice.range(SPP);
                let f = film(
                    &scene,
                    kind,
                    SampleBudget::Range {
                        start: r.start,
                        end: r.end,
                    },
                );
                parts.push((PathBuf::from(format!("part{k}")), state(f, slice, 9, "x")));
            }
            let merged = RenderState::merge_parts(&parts).unwrap();
            assert_eq!(
                merged.film.image(),
                whole.result.image,
                "{kind}: {m} slices differ from the single render"
            );
            assert!(
                spectral_bits(&merged.film) == spectral_bits(&whole.film),
                "{kind}: {m} slices' spectral image differs from the single render's"
            );
        }
    }
}

/// Parts that do not belong together are refused, and the error names the culprit: a missing
/// slice (by K/M), a repeated one (both files), another seed, other settings, an unfinished
/// checkpoint.
#[test]
fn mismatched_missing_repeated_and_foreign_parts_are_refused() {
    let empty = || FilmState::new(2, 2, true);
    let s = |k: u32, seed: u64, set: &str| {
        (
            PathBuf::from(format!("s{k}-{seed}-{set}.state")),
            state(empty(), SliceSpec { index: k, count: 3 }, seed, set),
        )
    };
    let err = |parts: Vec<(PathBuf, RenderState)>| RenderState::merge_parts(&parts).unwrap_err();
    let e = err(vec![s(1, 9, "a"), s(3, 9, "a")]);
    assert!(e.contains("missing slice(s) 2/3"), "{e}");
    let e = err(vec![s(1, 9, "a"), s(2, 9, "a"), s(2, 9, "a"), s(3, 9, "a")]);
    assert!(e.contains("slice 2/3 is given twice"), "{e}");
    let e = err(vec![s(1, 9, "a"), s(2, 4, "a"), s(3, 9, "a")]);
    assert!(e.contains("s2-4-a.state") && e.contains("seed"), "{e}");
    let e = err(vec![s(1, 9, "a"), s(2, 9, "b"), s(3, 9, "a")]);
    assert!(
        e.contains("s2-9-b.state") && e.contains("scene/settings"),
        "{e}"
    );
    let mut unfinished = s(2, 9, "a");
    unfinished.1.done_until -= 1;
    let e = err(vec![s(1, 9, "a"), unfinished, s(3, 9, "a")]);
    assert!(e.contains("--resume"), "{e}");
    assert!(RenderState::merge_parts(&[s(1, 9, "a"), s(2, 9, "a"), s(3, 9, "a")]).is_ok());
}

/// Quantity: the image of a render stopped after `k` progress units (the internal hook: the
/// cancel flag raised from the progress callback), then resumed from the whole passes it kept,
/// against the uninterrupted render, for stopping points in the first, second and third pass
/// (passes of 1, 1, 2, 3 spp). Tolerance 0 (exact sums).
#[test]
fn stopped_and_resumed_equals_uninterrupted() {
    let scene = scene();
    for kind in KINDS {
        let whole_film = film(&scene, kind, SampleBudget::Spp(SPP));
        let whole = whole_film.image();
        // Progress units: 6 tiles per pass for pt/bdpt, one light-path chunk per pass for lt.
        let stops: &[u64] = if kind == IntegratorKind::Lt {
            &[1, 2, 3]
        } else {
            &[1, 8, 15]
        };
        for &k in stops {
            let stop = AtomicBool::new(false);
            let progress = |done: u64, _total: u64| {
                if done >= k {
                    stop.store(true, Ordering::Relaxed);
                }
            };
            let out = render_with(
                &scene,
                &settings(SampleBudget::Spp(SPP), 1),
                kind,
                &progress,
                Some(&stop),
            );
            let done = out.result.spp;
            assert!(done < SPP, "{kind}: the hook did not stop the render");
            let mut f = out.film;
            assert_eq!(f.spp, done as u64);
            let rest = film(
                &scene,
                kind,
                SampleBudget::Range {
                    start: done,
                    end: SPP,
                },
            );
            f.merge(&rest);
            assert_eq!(f.image(), whole, "{kind}: stopped after {k} units");
            assert!(
                spectral_bits(&f) == spectral_bits(&whole_film),
                "{kind}: spectral image, stopped after {k} units"
            );
        }
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spectrace-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A real SIGTERM to the binary mid-render: it exits non-zero naming the checkpoint, writes the
/// partial image and the checkpoint, and `render --resume` finishes to an EXR whose bytes equal
/// those of an uninterrupted run (same seed and spp), the spectral EXR too. Tolerance 0.
#[cfg(unix)]
#[test]
fn sigterm_writes_a_checkpoint_that_resumes_bit_for_bit() {
    use std::io::{BufRead, BufReader};
    use std::process::{Command, Stdio};
    let exe = env!("CARGO_BIN_EXE_spectrace");
    let dir = temp_dir("sigterm");
    let scene_file = dir.join("scene.ron");
    std::fs::write(&scene_file, SCENE).unwrap();
    let common = |out: &Path| {
        let mut c = Command::new(exe);
        c.arg("render")
            .arg(&scene_file)
            .args([
                "--integrator",
                "bdpt",
                "--spp",
                "9",
                "--seed",
                "3",
                "--quiet",
            ])
            .arg("-o")
            .arg(out)
            .arg("--spectral-exr")
            .arg(out.with_extension("spectral.exr"));
        c
    };
    let full = dir.join("full.exr");
    assert!(common(&full).status().unwrap().success());
    let part = dir.join("part.exr");
    let mut child = common(&part)
        .args(["--wait-for-signal-after-units", "4", "--threads", "1"])
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    while err.read_line(&mut line).unwrap() > 0 && !line.contains("waiting for a signal") {
        line.clear();
    }
    assert!(
        line.contains("waiting for a signal"),
        "the hook never fired"
    );
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut err, &mut rest).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(1), "{rest}");
    assert!(rest.contains("--resume"), "{rest}");
    let ckpt = dir.join("part.exr.state");
    let st = RenderState::load(&ckpt).unwrap();
    assert!(!st.is_complete() && st.done_until > 0, "{}", st.done_until);
    assert!(part.exists(), "no partial image");
    let resumed = Command::new(exe)
        .arg("render")
        .arg("--resume")
        .arg(&ckpt)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_eq!(
        std::fs::read(&full).unwrap(),
        std::fs::read(&part).unwrap(),
        "resumed EXR differs from the uninterrupted one"
    );
    assert!(
        std::fs::read(full.with_extension("spectral.exr")).unwrap()
            == std::fs::read(part.with_extension("spectral.exr")).unwrap(),
        "resumed spectral EXR differs from the uninterrupted one"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Through the command line: `render --slice` parts merged with `spectrace merge` give the EXR
/// bytes of the single render (light tracing, 3 slices), and the merged spectral EXR (written
/// beside the output as `merged.spectral.exr`) the bytes of the single render's; merging with a
/// slice missing fails and names it.
#[test]
fn cli_slices_and_merge() {
    use std::process::Command;
    let exe = env!("CARGO_BIN_EXE_spectrace");
    let dir = temp_dir("cli-merge");
    let scene_file = dir.join("scene.ron");
    std::fs::write(&scene_file, SCENE).unwrap();
    let render = |extra: &[&str], out: &Path| {
        let o = Command::new(exe)
            .arg("render")
            .arg(&scene_file)
            .args(["--integrator", "lt", "--spp", "5", "--quiet"])
            .arg("--spectral-exr")
            .arg(dir.join("full.spectral.exr"))
            .args(extra)
            .arg("-o")
            .arg(out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let full = dir.join("full.exr");
    render(&[], &full);
    let mut parts = Vec::new();
    for k in 1..=3 {
        let p = dir.join(format!("p{k}.state"));
        render(
            &["--slice", &format!("{k}/3"), "--state", p.to_str().unwrap()],
            &full,
        );
        parts.push(p);
    }
    let merged = dir.join("merged.exr");
    let o = Command::new(exe)
        .arg("merge")
        .args(&parts)
        .arg("-o")
        .arg(&merged)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(&full).unwrap(),
        std::fs::read(&merged).unwrap()
    );
    assert!(
        std::fs::read(dir.join("full.spectral.exr")).unwrap()
            == std::fs::read(dir.join("merged.spectral.exr")).unwrap(),
        "merged spectral EXR differs from the single render's"
    );
    let o = Command::new(exe)
        .arg("merge")
        .args(&parts[..2])
        .arg("-o")
        .arg(&merged)
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && e.contains("missing slice(s) 3/3"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A state written when bdpt drew its wavelengths from another density (before the settings
/// fingerprint recorded `wavelength_density`, which a default may change) is refused on
/// resume, naming the setting, instead of being continued from another density into an image
/// no uninterrupted render makes. The old state is simulated by taking the entry out of a
/// fresh state's settings and fingerprint (the fingerprint as the renderer computes it: the
/// scene file's bytes, then the settings).
#[test]
fn a_state_from_another_wavelength_density_is_refused() {
    use std::process::Command;
    let exe = env!("CARGO_BIN_EXE_spectrace");
    let dir = temp_dir("density-key");
    let scene_file = dir.join("scene.ron");
    std::fs::write(&scene_file, SCENE).unwrap();
    let ckpt = dir.join("part.state");
    let o = Command::new(exe)
        .arg("render")
        .arg(&scene_file)
        .args([
            "--integrator",
            "bdpt",
            "--spp",
            "4",
            "--slice",
            "1/2",
            "--quiet",
        ])
        .arg("--state")
        .arg(&ckpt)
        .arg("-o")
        .arg(dir.join("out.exr"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut st = RenderState::load(&ckpt).unwrap();
    assert!(
        st.settings.contains(" wavelength_density=product "),
        "{}",
        st.settings
    );
    st.settings = st.settings.replace(" wavelength_density=product", "");
    st.fingerprint =
        spectrace::film::state_file::fnv1a64(&[SCENE.as_bytes(), st.settings.as_bytes()]);
    st.save(&ckpt).unwrap();
    let o = Command::new(exe)
        .arg("render")
        .arg("--resume")
        .arg(&ckpt)
        .arg("--quiet")
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success()
            && e.contains("settings changed")
            && e.contains("now `wavelength_density=product`"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
