//! `spectrace render --sensors-out DIR --luminance-out F.csv` through the real binary: the
//! files and their columns, the estimator named at run time, and bad sensor items refused with
//! the item and the parameter named.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A point light over a grey floor with a 4×3 sensor grid and a 4×4 camera: renders in
/// milliseconds.
const SCENE: &str = r#"(
    materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
    objects: [(name: "floor", type: "quad", material: "grey",
               params: (corner: (-5, 0, 5), edge0: (10, 0, 0), edge1: (0, 0, -10)))],
    lights: [(name: "p", type: "point", params: (position: (0, 2, 0), power: 100, spd: "e"))],
    cameras: [(name: "c", type: "pinhole",
               params: (position: (0, 1, 4), look_at: (0, 0, 0), resolution: (4, 4)))],
    sensors: [SENSORS],
)"#;

const GRID: &str = r#"(name: "floor", type: "illuminance_grid",
    params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -3), resolution: (4, 3), samples: 64))"#;

fn tmp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "spectrace-sensor-cli-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn scene(dir: &Path, sensors: &str) -> PathBuf {
    let p = dir.join("s.ron");
    std::fs::write(&p, SCENE.replace("SENSORS", sensors)).unwrap();
    p
}

fn spectrace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spectrace"))
        .args(args)
        .output()
        .expect("run spectrace")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Each integrator names its estimator; the CSV has the header `x,y,z,lux,stderr` and one row
/// per point with finite positive lux (a lit floor) and the PNG is a PNG; the luminance CSV has
/// one row per pixel.
#[test]
fn sensors_out_writes_csv_and_map() {
    let dir = tmp_dir("out");
    let s = scene(&dir, GRID);
    for (integrator, says) in [
        ("pt", "sensor path tracing"),
        ("bdpt", "sensor path tracing"),
        ("lt", "light tracing"),
    ] {
        let out = dir.join(integrator);
        let lum = dir.join(format!("{integrator}-lum.csv"));
        let o = spectrace(&[
            "render",
            s.to_str().unwrap(),
            "-o",
            dir.join("img.exr").to_str().unwrap(),
            "--spp",
            "2",
            "--quiet",
            "--integrator",
            integrator,
            "--sensors-out",
            out.to_str().unwrap(),
            "--luminance-out",
            lum.to_str().unwrap(),
        ]);
        let t = text(&o);
        assert!(o.status.success(), "{t}");
        assert!(t.contains(&format!("sensors ({integrator}: {says}")), "{t}");
        let csv = std::fs::read_to_string(out.join("floor.csv")).unwrap();
        let mut lines = csv.lines();
        assert_eq!(lines.next(), Some("x,y,z,lux,stderr"));
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 12);
        for r in &rows {
            assert_eq!(r.len(), 5);
            assert!(r[3] > 0.0 && r[3].is_finite() && r[4] >= 0.0, "{r:?}");
        }
        let png = std::fs::read(out.join("floor.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let lum = std::fs::read_to_string(&lum).unwrap();
        assert_eq!(lum.lines().next(), Some("x,y,cd_m2"));
        assert_eq!(lum.lines().count(), 1 + 16);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Bad sensor items: an unknown type, a duplicate name, a name unfit for a file, parallel
/// edges, a zero resolution: each refused before rendering, naming the sensor and what is
/// wrong.
#[test]
fn bad_sensors_are_refused_by_name() {
    let dir = tmp_dir("bad");
    let cases = [
        (
            r#"(name: "a", type: "lux_meter", params: ())"#,
            "unknown sensor type `lux_meter`",
        ),
        (&format!("{GRID}, {GRID}"), "duplicate sensor name"),
        (
            r#"(name: "../x", type: "illuminance_grid", params: (corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (0, 0, -1), resolution: (1, 1)))"#,
            "output file name",
        ),
        (
            r#"(name: "a", type: "illuminance_grid", params: (corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (2, 0, 0), resolution: (1, 1)))"#,
            "parallel",
        ),
        (
            r#"(name: "a", type: "illuminance_grid", params: (corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (0, 0, -1), resolution: (0, 1)))"#,
            "resolution",
        ),
    ];
    for (sensors, says) in cases {
        let s = scene(&dir, sensors);
        let o = spectrace(&[
            "render",
            s.to_str().unwrap(),
            "-o",
            dir.join("img.exr").to_str().unwrap(),
            "--spp",
            "1",
            "--quiet",
        ]);
        let t = text(&o);
        assert!(!o.status.success(), "{sensors}: {t}");
        assert!(t.contains("sensor") && t.contains(says), "{sensors}: {t}");
        assert!(!t.contains("panicked"), "{t}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A grid that no light reaches (above the lamp, facing the empty sky) reads 0 lx and says so,
/// naming its normal.
#[test]
fn sensor_facing_away_is_warned() {
    let dir = tmp_dir("away");
    let s = scene(
        &dir,
        r#"(name: "sky", type: "illuminance_grid", params: (corner: (-2, 3, 2), edge0: (4, 0, 0), edge1: (0, 0, -3), resolution: (2, 2), samples: 16))"#,
    );
    let o = spectrace(&[
        "render",
        s.to_str().unwrap(),
        "-o",
        dir.join("img.exr").to_str().unwrap(),
        "--spp",
        "1",
        "--quiet",
        "--integrator",
        "pt",
    ]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(
        t.contains("sensor \"sky\" reads 0 lx everywhere") && t.contains("(0.000, 1.000, 0.000)"),
        "{t}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
