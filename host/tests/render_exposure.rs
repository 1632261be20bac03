//! `render --exposure`, the automatic PNG exposure and `--resolution`, through the command
//! line: a realistic lamp (200 W, 2700 K, 2.5 m above a floor) gives a readable PNG by default.

use std::path::{Path, PathBuf};
use std::process::Command;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("spectrace-exposure-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 200 W, 2700 K point lamp 2.5 m above a 6 m square grey floor (ρ = 0.5), camera at eye
/// height; the scene file sets no `png_exposure`.
fn lamp_scene(dir: &Path, extra_output: &str) -> PathBuf {
    let p = dir.join(format!("lamp{}.ron", extra_output.len()));
    std::fs::write(
        &p,
        format!(
            r#"(
    units: "m",
    output: ({extra_output}),
    materials: [ (name: "grey", type: "lambertian", params: (reflectance: 0.5)) ],
    objects: [ (name: "floor", type: "mesh", material: "grey",
                params: (positions: [(-3, 0, -3), (-3, 0, 3), (3, 0, 3), (3, 0, -3)],
                         indices: [(0, 1, 2), (0, 2, 3)])) ],
    lights: [ (name: "lamp", type: "point",
               params: (position: (0, 2.5, 0), power: 200, spd: "blackbody:2700")) ],
    cameras: [ (name: "eye", type: "pinhole",
                params: (position: (0, 1.6, 4), look_at: (0, 0, 0), fov: 60, resolution: (640, 480))) ],
)"#
        ),
    )
    .unwrap();
    p
}

/// Render `scene` with `args` into `out`.png; stdout, the PNG's size and its mean 8-bit value.
fn render(scene: &Path, out: &Path, args: &[&str]) -> (String, (u32, u32), f64) {
    let o = Command::new(env!("CARGO_BIN_EXE_spectrace"))
        .arg("render")
        .arg(scene)
        .args(["--spp", "2", "--quiet", "--integrator", "pt", "-o"])
        .arg(out)
        .args(args)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(out).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let bytes = &buf[..info.buffer_size()];
    let mean = bytes.iter().map(|&b| b as f64).sum::<f64>() / bytes.len() as f64;
    (stdout, (info.width, info.height), mean)
}

// By default the lamp's PNG is readable: mean 8-bit value above 40 (of 255; at 0 EV it is
// below 10: the floor's luminance, ≈ 46 cd/m², is Y ≈ 6e-4 of the film's scale), and the
// summary says the exposure was chosen and why. `--exposure 0` keeps the physical 0 EV
// (nearly black, mean < 10); `--resolution 48x30` gives a 48×30 PNG; the summary gives the
// lamp's flux in W and lm.
#[test]
fn realistic_lamp_gives_a_readable_png_by_default() {
    let d = dir();
    let scene = lamp_scene(&d, "");
    let (stdout, size, auto) = render(&scene, &d.join("auto.png"), &["--resolution", "48x30"]);
    println!("{stdout}");
    assert_eq!(size, (48, 30));
    assert!(auto > 40.0, "mean 8-bit value {auto}");
    assert!(
        stdout.contains("PNG exposure chosen automatically") && stdout.contains("nearly black"),
        "{stdout}"
    );
    assert!(
        stdout.contains("light \"lamp\"") && stdout.contains("200.0 W, ") && stdout.contains(" lm"),
        "{stdout}"
    );
    let (stdout0, _, zero) = render(
        &scene,
        &d.join("zero.png"),
        &["--resolution", "48x30", "--exposure", "0"],
    );
    assert!(zero < 10.0, "mean 8-bit value at 0 EV {zero}");
    assert!(!stdout0.contains("chosen automatically"), "{stdout0}");
    // The scene's own png_exposure is respected as given (no automatic choice).
    let scene_exposed = lamp_scene(&d, "png_exposure: 1.0");
    let (stdout1, _, given) = render(
        &scene_exposed,
        &d.join("given.png"),
        &["--resolution", "48x30"],
    );
    assert!(!stdout1.contains("chosen automatically") && (given - zero).abs() < 1e-9);
}

// Bad values are refused with the expected form named.
#[test]
fn bad_exposure_and_resolution_are_refused() {
    for (flag, value, says) in [
        ("--exposure", "nan", "EV between -100 and 100"),
        ("--resolution", "640", "WIDTHxHEIGHT"),
        ("--resolution", "0x10", "1..65536"),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_spectrace"))
            .args(["render", "--spp", "1", flag, value])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains(says),
            "{flag} {value}: {err}"
        );
    }
}
