//! BVH scaling: generated meshes of about 1k, 100k, 1M and 5M triangles (bumpy icosphere, 3, 6,
//! 8 and 9 subdivisions; 10 subdivisions, 21M triangles, with `SPECTRACE_SCALING_MAX=10`):
//! build time on one and two threads, BVH memory per triangle, and closest-hit rays per second
//! (camera rays and random rays, 262,144 of each) on one and two threads.
//!
//! Embree 3 is the hardware anchor: where `cc` and Debian's `libembree-dev` are present, the
//! harness `scripts/embree/embree_rays.c` is compiled into the target directory and traces the
//! same triangles and the same random rays (single rays, `rtcIntersect1`) on one and two
//! threads; elsewhere the table says it was skipped. It is never part of the workspace build.
//! The `obvhs` crate (compressed eight-wide BVH, PLOC builder) is the other comparison: its
//! harness `scripts/obvhs` (a separate Cargo project with its own target directory, since it
//! needs another glam) is built with cargo and given the same input file; it prints its build
//! time on one and two threads and its closest-hit rays per second with its own triangle test
//! and with spectrace's watertight one.
//!
//! A plain timing program, not criterion: each figure is the best of three runs, so that a
//! shared machine's interruptions count less. Run:
//! `cargo bench -p spectrace --bench scaling` (prints a Markdown table for docs/performance.md).
//!
//! `SPECTRACE_SCALING_SIZES=8,9,9x2` picks the meshes by subdivision count instead; `9x2` is
//! two 9-subdivision spheres side by side in one mesh (10.5 M triangles, half the memory of
//! the 21 M sphere). `SPECTRACE_SCALING_BUILDS=<repetitions>` times only the builds of those
//! sizes (default 8), one and two threads interleaved, and prints each run, the median and
//! range, the peak resident memory and the tree's fingerprint on both thread counts.

use std::time::Instant;

use glam::Vec3A;
use rayon::prelude::*;
use spectrace::geometry::generate::icosphere;
use spectrace::geometry::{
    Aabb, Bvh, Geometry, NodeLayout, Ray, Shape, ShapeDesc, Transform, TraversalKernel,
    TriangleMesh,
};

const RAYS: usize = 262_144;
const RUNS: usize = 3;

fn bumpy_sphere(subdivisions: u32) -> TriangleMesh {
    let mut m = icosphere(subdivisions);
    for p in &mut m.positions {
        let bump = 0.05 * (13.0 * p.x).sin() * (11.0 * p.y).sin() * (17.0 * p.z).sin()
            + 0.02 * (41.0 * p.x + 37.0 * p.z).sin();
        *p *= 1.0 + bump;
    }
    m.normals = None;
    m
}

/// A generated test mesh: `copies` (1 or 2) bumpy spheres of `subdivisions`.
#[derive(Clone, Copy)]
struct Size {
    subdivisions: u32,
    copies: u32,
}

impl Size {
    /// `"9"` or `"9x2"`.
    fn parse(s: &str) -> Option<Size> {
        let (sub, copies) = s.trim().split_once('x').unwrap_or((s.trim(), "1"));
        let size = Size {
            subdivisions: sub.parse().ok()?,
            copies: copies.parse().ok()?,
        };
        (size.subdivisions <= 10 && (1..=2).contains(&size.copies)).then_some(size)
    }

    /// The mesh: one sphere, or two of radius 0.55 centred at x = ±0.6 (inside the random
    /// rays' cube and the camera's view) merged into one mesh.
    fn mesh(self) -> TriangleMesh {
        let one = bumpy_sphere(self.subdivisions);
        if self.copies == 1 {
            return one;
        }
        let mut m = TriangleMesh {
            positions: Vec::with_capacity(2 * one.positions.len()),
            normals: None,
            uvs: None,
            indices: Vec::with_capacity(2 * one.indices.len()),
        };
        for x in [-0.6f32, 0.6] {
            let base = m.positions.len() as u32;
            let shift = Vec3A::new(x, 0.0, 0.0);
            m.positions
                .extend(one.positions.iter().map(|&p| p * 0.55 + shift));
            m.indices
                .extend(one.indices.iter().map(|t| t.map(|i| i + base)));
        }
        m
    }
}

/// Sizes from `SPECTRACE_SCALING_SIZES` (comma-separated, e.g. `8,9,9x2`), else `default`.
fn sizes_from_env(default: &[Size]) -> Vec<Size> {
    match std::env::var("SPECTRACE_SCALING_SIZES") {
        Ok(list) => list
            .split(',')
            .map(|s| {
                Size::parse(s).unwrap_or_else(|| {
                    panic!("SPECTRACE_SCALING_SIZES: `{s}` is not `<subdivisions ≤ 10>[x2]`")
                })
            })
            .collect(),
        Err(_) => default.to_vec(),
    }
}

/// Peak resident memory of this process so far (bytes), from `/proc/self/status`.
fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn scene(mesh: &TriangleMesh) -> Vec<ShapeDesc> {
    vec![ShapeDesc {
        shape: Shape::Mesh(mesh.clone()),
        transform: Transform::IDENTITY,
    }]
}

/// `SPECTRACE_SCALING_BUILDS=<repetitions>`: builds of each size on one and two threads,
/// interleaved (1, 2, 1, 2, …) so that a shared machine's load falls on both alike; each run,
/// then the median and range per thread count and the fingerprints of the BVH built on one
/// and on two threads (they must be equal).
fn builds_run(reps: usize) {
    let sizes = sizes_from_env(&[Size {
        subdivisions: 8,
        copies: 1,
    }]);
    for size in sizes {
        let mesh = size.mesh();
        let tris = mesh.indices.len();
        let mut times = [Vec::new(), Vec::new()];
        let mut fingerprints = [0u64; 2];
        let mut bvh_bytes = 0;
        for rep in 0..reps {
            for threads in [1, 2] {
                let d = scene(&mesh);
                let p = pool(threads);
                let t = Instant::now();
                let g = p.install(|| Geometry::build(d).expect("valid mesh"));
                let s = t.elapsed().as_secs_f64();
                println!("{tris} triangles, run {rep}, {threads} thread(s): {s:.3} s");
                times[threads - 1].push(s);
                bvh_bytes = g.bvh_memory_bytes();
            }
        }
        let bounds: Vec<Aabb> = mesh
            .indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                Aabb::from_point(a).grow(b).grow(c)
            })
            .collect();
        for threads in [1, 2] {
            fingerprints[threads - 1] = pool(threads).install(|| Bvh::build(&bounds).fingerprint());
        }
        let stats = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            (v[v.len() / 2], v[0], v[v.len() - 1])
        };
        let (m1, lo1, hi1) = stats(&mut times[0]);
        let (m2, lo2, hi2) = stats(&mut times[1]);
        println!(
            "{tris} triangles, {reps} interleaved runs: 1 thread median {m1:.3} s \
             ({lo1:.3}–{hi1:.3}), 2 threads median {m2:.3} s ({lo2:.3}–{hi2:.3}), \
             speed-up of medians {:.3}; BVH {:.1} bytes/triangle; peak resident {} \
             bytes/triangle; fingerprint {:016x} (1 thread) {:016x} (2 threads)",
            m1 / m2,
            bvh_bytes as f64 / tris as f64,
            peak_rss_bytes().map_or("?".into(), |b| format!("{:.0}", b as f64 / tris as f64)),
            fingerprints[0],
            fingerprints[1],
        );
    }
}

/// SplitMix64 → uniform f32 in [0, 1).
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// A 512×512 pinhole camera looking at the sphere from z = 3.
fn camera_rays() -> Vec<Ray> {
    let n = (RAYS as f64).sqrt() as usize;
    let origin = Vec3A::new(0.0, 0.0, 3.0);
    (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f32 + 0.5, (i / n) as f32 + 0.5);
            let d = Vec3A::new(x / n as f32 - 0.5, 0.5 - y / n as f32, -1.0);
            Ray::new(origin, d.normalize())
        })
        .collect()
}

/// Rays from random points of the bounding cube in random directions.
fn random_rays() -> Vec<Ray> {
    let mut rng = Rng(42);
    (0..RAYS)
        .map(|_| {
            let o = Vec3A::new(rng.f(), rng.f(), rng.f()) * 2.4 - 1.2;
            let d = loop {
                let v = Vec3A::new(rng.f(), rng.f(), rng.f()) * 2.0 - 1.0;
                if v.length_squared() > 1e-3 && v.length_squared() <= 1.0 {
                    break v.normalize();
                }
            };
            Ray::new(o, d)
        })
        .collect()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

/// `SPECTRACE_SCALING_LAYOUT=float|quantised` forces the BVH node layout (default: the
/// build's choice by scene size).
fn node_layout() -> NodeLayout {
    match std::env::var("SPECTRACE_SCALING_LAYOUT").as_deref() {
        Ok("float") => NodeLayout::Float,
        Ok("quantised") => NodeLayout::Quantised,
        _ => NodeLayout::Auto,
    }
}

fn build_geometry(desc: Vec<ShapeDesc>) -> Geometry {
    Geometry::build_with_node_layout(desc, node_layout()).expect("valid mesh")
}

/// Best of `RUNS` wall-clock seconds of `f`.
fn best_of<T>(mut f: impl FnMut() -> T) -> f64 {
    (0..RUNS)
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(f());
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn rays_per_second(g: &Geometry, rays: &[Ray], threads: usize) -> f64 {
    let p = pool(threads);
    let secs = best_of(|| {
        p.install(|| {
            rays.par_chunks(1024)
                .map(|c| {
                    c.iter()
                        .filter(|r| g.intersect(r, f32::INFINITY).is_some())
                        .count()
                })
                .sum::<usize>()
        })
    });
    rays.len() as f64 / secs
}

/// Compiles the Embree harness next to the bench executable; `Err` says why it cannot run.
fn build_embree_harness() -> Result<std::path::PathBuf, String> {
    let src =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/embree/embree_rays.c");
    let exe = std::env::current_exe()
        .map_err(|e| e.to_string())?
        .with_file_name("embree_rays");
    let out = std::process::Command::new("cc")
        .args(["-O2", "-o"])
        .arg(&exe)
        .arg(&src)
        .args(["-lembree3", "-lpthread", "-lm"])
        .output()
        .map_err(|e| format!("no C compiler ({e})"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!(
            "cannot build the harness (is libembree-dev installed?): {}",
            err.lines().next().unwrap_or("")
        ));
    }
    Ok(exe)
}

/// Builds the obvhs harness (`scripts/obvhs`, its own Cargo project and target directory);
/// `Err` says why it cannot run (e.g. no network for its first build).
fn build_obvhs_harness() -> Result<std::path::PathBuf, String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let target = root.join("target/obvhs");
    let out = std::process::Command::new(env!("CARGO"))
        .args(["build", "--release", "--quiet", "--manifest-path"])
        .arg(root.join("scripts/obvhs/Cargo.toml"))
        .env("CARGO_TARGET_DIR", &target)
        .output()
        .map_err(|e| format!("cannot run cargo ({e})"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!(
            "cannot build the obvhs harness: {}",
            err.lines().next().unwrap_or("")
        ));
    }
    Ok(target.join("release/obvhs-rays"))
}

/// Writes the harnesses' input file (format in `scripts/embree/embree_rays.c`).
fn write_harness_input(
    path: &std::path::Path,
    mesh: &TriangleMesh,
    rays: &[Ray],
) -> Result<(), String> {
    let mut bytes = Vec::new();
    bytes.extend((mesh.positions.len() as u32).to_le_bytes());
    bytes.extend((mesh.indices.len() as u32).to_le_bytes());
    for p in &mesh.positions {
        for c in [p.x, p.y, p.z] {
            bytes.extend(c.to_le_bytes());
        }
    }
    for t in &mesh.indices {
        for i in t {
            bytes.extend(i.to_le_bytes());
        }
    }
    bytes.extend((rays.len() as u32).to_le_bytes());
    for r in rays {
        for c in [
            r.origin.x, r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z,
        ] {
            bytes.extend(c.to_le_bytes());
        }
    }
    std::fs::write(path, bytes).map_err(|e| e.to_string())
}

/// Runs a harness on the input file; its one output line.
fn run_harness(exe: &std::path::Path, input: &std::path::Path) -> Result<String, String> {
    let out = std::process::Command::new(exe)
        .arg(input)
        .output()
        .map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).into_owned());
    }
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// `SPECTRACE_SCALING_PROFILE=<subdivisions>[x2]`: one build and one pass of the random rays on
/// the calling thread, nothing else, for instruction counts under
/// `valgrind --tool=callgrind` (a shared machine's wall times vary too much for small A/B
/// differences). Prints the hit count and the seconds of the closest-hit and the any-hit pass
/// (for interleaved wall-clock A/B runs). `SPECTRACE_SCALING_KERNEL=portable` traces with the
/// portable (SSE) box test instead of AVX2. `SPECTRACE_SCALING_STATS=1` first prints the tree's statistics
/// in the terms of Embree's `verbose=2` build report (`EMBREE_RAYS_CONFIG=threads=2,verbose=2`
/// for the harness) and the nodes, leaves and triangles a random ray visits on average.
/// `SPECTRACE_SCALING_INPUT=<file>` only writes the
/// Embree/obvhs harnesses' input (same triangles and random rays) there, to count their
/// instructions the same way.
fn profile_run(size: Size) {
    let mesh = size.mesh();
    if let Some(path) = std::env::var_os("SPECTRACE_SCALING_INPUT") {
        // Only the harnesses' input, to run them under callgrind too.
        let path = std::path::PathBuf::from(path);
        match write_harness_input(&path, &mesh, &random_rays()) {
            Ok(()) => println!("wrote {}", path.display()),
            Err(e) => eprintln!("cannot write {}: {e}", path.display()),
        }
        return;
    }
    let pool = pool(1);
    let mut g = pool.install(|| {
        build_geometry(vec![ShapeDesc {
            shape: Shape::Mesh(mesh),
            transform: Transform::IDENTITY,
        }])
    });
    if std::env::var("SPECTRACE_SCALING_KERNEL").as_deref() == Ok("portable") {
        g.set_traversal_kernel(TraversalKernel::Portable);
    }
    if std::env::var_os("SPECTRACE_SCALING_BUILD_ONLY").is_some() {
        println!("built {} primitives", g.primitive_count());
        return;
    }
    let rays = random_rays();
    if std::env::var_os("SPECTRACE_SCALING_STATS").is_some() {
        print_tree_statistics(&g, &rays);
    }
    let start = Instant::now();
    let hits = rays
        .iter()
        .filter(|r| g.intersect(r, f32::INFINITY).is_some())
        .count();
    let closest_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let occluded = rays.iter().filter(|r| g.occluded(r, f32::INFINITY)).count();
    let any_s = start.elapsed().as_secs_f64();
    println!(
        "{hits} hits, {occluded} occluded of {} rays in {closest_s:.4} / {any_s:.4} s \
         ({:?} kernel, {:?} nodes, {:.1} BVH bytes/triangle)",
        rays.len(),
        g.traversal_kernel(),
        g.node_layout(),
        g.bvh_memory_bytes() as f64 / g.primitive_count() as f64
    );
}

/// The tree's node and leaf statistics and its surface-area costs (as Embree reports them:
/// expected node tests and four-triangle leaf passes of a ray through the root's box), then the
/// visits per random ray of a closest-hit and an any-hit query.
fn print_tree_statistics(g: &Geometry, rays: &[Ray]) {
    let s = g.bvh_statistics();
    println!(
        "tree: {} wide nodes ({:.1}% of slots used), {} leaves of {} primitives \
         ({:.2} per leaf; sizes 1..8: {:?}), SAH nodes {:.3} + leaves {:.3} = {:.3}; \
         nodes of 1..8 slots: {:?}, {} with leaf children only",
        s.nodes,
        100.0 * s.children as f64 / (8 * s.nodes.max(1)) as f64,
        s.leaves,
        s.primitives,
        s.primitives as f64 / s.leaves.max(1) as f64,
        s.leaf_sizes,
        s.node_sah,
        s.leaf_sah,
        s.node_sah + s.leaf_sah,
        s.node_slots,
        s.twig_nodes
    );
    for any_hit in [false, true] {
        let mut c = spectrace::geometry::VisitCounts::default();
        for r in rays {
            c += g.count_visits(r, f32::INFINITY, any_hit);
        }
        let n = rays.len() as f64;
        println!(
            "{} per ray: {:.3} wide nodes, {:.3} leaves, {:.3} primitives",
            if any_hit { "any hit" } else { "closest hit" },
            c.nodes as f64 / n,
            c.leaves as f64 / n,
            c.primitives as f64 / n
        );
    }
}

fn main() {
    if let Some(s) = std::env::var("SPECTRACE_SCALING_PROFILE")
        .ok()
        .and_then(|v| Size::parse(&v))
    {
        profile_run(s);
        return;
    }
    if let Some(reps) = std::env::var("SPECTRACE_SCALING_BUILDS")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        builds_run(reps);
        return;
    }
    let max: u32 = std::env::var("SPECTRACE_SCALING_MAX")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(9)
        .min(10);
    let camera = camera_rays();
    let random = random_rays();
    let harness = build_embree_harness();
    let obvhs = build_obvhs_harness();
    let mut embree_lines = Vec::new();
    println!(
        "| triangles | build 1 thread (s) | build 2 threads (s) | build speed-up | BVH bytes/triangle \
         | camera Mrays/s 1 thr | 2 thr | speed-up | random Mrays/s 1 thr | 2 thr | speed-up |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let default: Vec<Size> = [3u32, 6, 8, 9, 10]
        .into_iter()
        .filter(|&s| s <= max)
        .map(|subdivisions| Size {
            subdivisions,
            copies: 1,
        })
        .collect();
    for size in sizes_from_env(&default) {
        let mesh = size.mesh();
        let tris = mesh.indices.len();
        let desc = || scene(&mesh);
        let build = |threads: usize| {
            let p = pool(threads);
            (0..RUNS)
                .map(|_| {
                    let d = desc();
                    let t = Instant::now();
                    let g = p.install(|| build_geometry(d));
                    let s = t.elapsed().as_secs_f64();
                    drop(g);
                    s
                })
                .fold(f64::INFINITY, f64::min)
        };
        let (b1, b2) = (build(1), build(2));
        let g = build_geometry(desc());
        let bytes = g.bvh_memory_bytes() as f64 / tris as f64;
        let (c1, c2) = (
            rays_per_second(&g, &camera, 1),
            rays_per_second(&g, &camera, 2),
        );
        let (r1, r2) = (
            rays_per_second(&g, &random, 1),
            rays_per_second(&g, &random, 2),
        );
        println!(
            "| {tris} | {b1:.3} | {b2:.3} | {:.2} | {bytes:.0} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
            b1 / b2,
            c1 / 1e6,
            c2 / 1e6,
            c2 / c1,
            r1 / 1e6,
            r2 / 1e6,
            r2 / r1
        );
        let hits = random
            .iter()
            .filter(|r| g.intersect(r, f32::INFINITY).is_some())
            .count();
        let input = std::env::current_exe()
            .expect("bench executable path")
            .with_file_name("scaling_rays_input.bin");
        let written = write_harness_input(&input, &mesh, &random);
        let ours = format!(
            "{tris} triangles, random rays: spectrace {:.3} / {:.3} Mrays/s (1 / 2 threads), \
             {hits} hits, build {b1:.3} / {b2:.3} s",
            r1 / 1e6,
            r2 / 1e6
        );
        embree_lines.push(ours);
        for (name, exe) in [("Embree", &harness), ("obvhs", &obvhs)] {
            embree_lines.push(match (exe, &written) {
                (Ok(exe), Ok(())) => match run_harness(exe, &input) {
                    Ok(line) => format!("  {name}: {line}"),
                    Err(e) => format!("  {name} failed: {e}"),
                },
                (Err(why), _) | (_, Err(why)) => format!("  {name} skipped: {why}"),
            });
        }
        let _ = std::fs::remove_file(&input);
    }
    println!();
    for l in embree_lines {
        println!("{l}");
    }
}
