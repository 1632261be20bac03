//! Small traps and resource limits of the command line, run through the real `spectrace`
//! binary: each request that used to overwrite a file, write beside a directory, abort on an
//! allocation or run for minutes is now refused before any work, with the limit and the request.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A lit quad seen by a 4×4 pinhole camera: renders in milliseconds.
const TINY_SCENE: &str = r#"(
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: 0.5)),
        (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 10.0)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-1, -1, 0), edge0: (2, 0, 0), edge1: (0, 2, 0))),
        (name: "lamp", type: "quad", material: "lamp",
         params: (corner: (-0.2, -0.2, 2), edge0: (0, 0.4, 0), edge1: (0.4, 0, 0))),
    ],
    cameras: [(name: "c", type: "pinhole",
               params: (position: (0, 0, 5), look_at: (0, 0, 0), resolution: (RES))) ],
)"#;

fn tmp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "spectrace-robust-cli-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn scene(dir: &Path, resolution: &str) -> PathBuf {
    let p = dir.join("tiny.ron");
    std::fs::write(&p, TINY_SCENE.replace("RES", resolution)).unwrap();
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

/// `-o x.png` wrote the EXR into x.png and then the PNG over it ("wrote x.png" twice). Now the
/// PNG alone is written, once, and it is a PNG.
#[test]
fn png_output_name_writes_one_png() {
    let dir = tmp_dir("png");
    let s = scene(&dir, "4, 4");
    let out = dir.join("x.png");
    let o = spectrace(&[
        "render",
        s.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--spp",
        "1",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let wrote = String::from_utf8_lossy(&o.stdout)
        .lines()
        .filter(|l| l.contains("wrote"))
        .map(str::to_string)
        .collect::<Vec<_>>();
    assert_eq!(wrote.len(), 1, "{wrote:?}");
    assert!(wrote[0].ends_with("x.png"), "{wrote:?}");
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert!(!dir.join("x.exr").exists());
}

/// `-o DIR` wrote DIR.png beside the directory (and the EXR failed into a rescue file). Now it
/// is refused before rendering, naming the directory, and nothing is written.
#[test]
fn directory_output_is_refused() {
    let dir = tmp_dir("dir");
    let s = scene(&dir, "4, 4");
    let target = dir.join("outdir");
    std::fs::create_dir_all(&target).unwrap();
    let o = spectrace(&[
        "render",
        s.to_str().unwrap(),
        "-o",
        target.to_str().unwrap(),
        "--spp",
        "1",
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains(target.to_str().unwrap()) && t.contains("is a directory"),
        "{t}"
    );
    assert!(!dir.join("outdir.png").exists());
}

/// `resolution: (65536, 65536)` passed validation and aborted the process on a 103 GB
/// allocation. Now the scene is refused with the image's need and the memory limit.
#[test]
fn huge_resolution_is_refused_with_the_limit() {
    let dir = tmp_dir("res");
    let s = scene(&dir, "65536, 65536");
    let o = spectrace(&[
        "render",
        s.to_str().unwrap(),
        "-o",
        dir.join("a.exr").to_str().unwrap(),
        "--spp",
        "1",
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("65536×65536") && t.contains("limit") && t.contains("resolution"),
        "{t}"
    );
}

/// `--spp 4294967295` took 1 GB at once for its pass list; `--threads 100000` started threads for
/// minutes. Both are refused by the argument parser (exit code 2) with the limit.
#[test]
fn sample_and_thread_counts_are_bounded() {
    let o = spectrace(&["render", "--spp", "4294967295", "-o", "/nonexistent/a.exr"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("4294967295") && text(&o).contains("16777216"),
        "{}",
        text(&o)
    );
    let o = spectrace(&["render", "--threads", "100000", "-o", "/nonexistent/a.exr"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("100000") && text(&o).contains("limit"),
        "{}",
        text(&o)
    );
    let o = spectrace(&[
        "reference",
        "--pass-spp",
        "4294967295",
        "-o",
        "/nonexistent/a.exr",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

/// `/dev/zero` as a scene was read until memory ran out; now the read stops at the scene-file
/// limit (64 MiB) with an error saying so.
#[test]
#[cfg(unix)]
fn endless_scene_file_is_cut_at_the_limit() {
    let o = spectrace(&["render", "/dev/zero", "-o", "/nonexistent/a.exr"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("/dev/zero") && t.contains("64.00 MiB"), "{t}");
}

/// `/dev/zero` as a luminaire, or named by an IES file's `TILT=` line, was read until memory
/// ran out; now both reads stop at the luminaire-file limit (64 MiB) with an error naming the
/// file and the limit.
#[test]
#[cfg(unix)]
fn endless_luminaire_and_tilt_files_are_cut_at_the_limit() {
    use spectrace::photometry::{ies::parse_ies, load_luminaire};
    let e = load_luminaire(std::path::Path::new("/dev/zero"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("/dev/zero") && e.contains("64.00 MiB"), "{e}");
    let ies =
        b"IES:LM-63-2019\n[TEST] x\nTILT=/dev/zero\n1 1000 1 1 1 1 2 0 0 0\n1 1 10\n0\n0\n100\n";
    let e = parse_ies(ies, std::path::Path::new("/tmp/x.ies"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("/dev/zero") && e.contains("64.00 MiB"), "{e}");
}

/// `spectrace … | head`: output to a pipe whose reader has gone made `println!` panic ("failed
/// printing to stdout: Broken pipe", exit 101, a panic message on stderr). Now the process ends
/// quietly, by SIGPIPE as other command-line tools do. The read end is closed before the child
/// starts, so its first write always meets the broken pipe. Checked for two commands that print
/// with `println!` (a list and a computed table): no panic message, ended by SIGPIPE.
#[test]
#[cfg(unix)]
fn writing_into_a_closed_pipe_ends_quietly() {
    use std::os::unix::process::ExitStatusExt;
    for args in [&["plugins"][..], &["color", "d65"][..]] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = Command::new(env!("CARGO_BIN_EXE_spectrace"))
            .args(args)
            .stdout(writer)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert_eq!(
            o.status.signal(),
            Some(libc::SIGPIPE),
            "{args:?}: {:?} {stderr}",
            o.status
        );
    }
}

/// Light tracing cannot show a specular surface the camera sees directly: on the thin-film
/// scene (specular panels over a black floor) its image is black in every pixel. That used to
/// pass without a word; now the summary says the image is black and why. The same scene with
/// bdpt is not black and gets no such warning (the check looks at the image, not the scene).
#[test]
fn a_black_image_is_said_with_its_likely_reason() {
    let dir = tmp_dir("black");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/thin_film.ron");
    let out = dir.join("tf.exr");
    let out = out.to_str().unwrap();
    let lt = spectrace(&[
        "render",
        scene,
        "--integrator",
        "lt",
        "--spp",
        "1",
        "--resolution",
        "32x20",
        "-o",
        out,
    ]);
    let t = text(&lt);
    assert!(lt.status.success(), "{t}");
    assert!(
        t.contains("warning: the image is black") && t.contains("light tracing cannot show"),
        "{t}"
    );
    let bdpt = spectrace(&[
        "render",
        scene,
        "--integrator",
        "bdpt",
        "--spp",
        "1",
        "--resolution",
        "32x20",
        "-o",
        out,
    ]);
    let t = text(&bdpt);
    assert!(bdpt.status.success(), "{t}");
    assert!(!t.contains("the image is black"), "{t}");
}
