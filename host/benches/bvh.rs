//! BVH benchmark on a generated ~1.3M-triangle mesh (icosphere subdivided 8 times, radially
//! displaced by a sum of sines so the surface is bumpy and triangle sizes vary):
//! - `bvh/build`: `Geometry::build` time (binned SAH, rayon for large subtrees);
//! - `bvh/coherent`: closest-hit rays from a pinhole camera, 256×256 image, one thread;
//! - `bvh/incoherent`: rays from random points in the bounding box in random directions;
//! - `bvh/occluded_incoherent`: the same rays with the any-hit query.
//!
//! Peak resident memory (VmHWM from /proc/self/status) is printed after mesh generation and
//! after the first build. Run: `cargo bench -p spectrace --bench bvh`.

use std::time::Instant;

use criterion::{black_box, BatchSize, Criterion, Throughput};
use glam::Vec3A;
use spectrace::geometry::generate::icosphere;
use spectrace::geometry::{Geometry, Ray, Shape, ShapeDesc, Transform, TriangleMesh};

const SUBDIVISIONS: u32 = 8;
const RAYS: usize = 65_536;

fn displaced_sphere() -> TriangleMesh {
    let mut m = icosphere(SUBDIVISIONS);
    for p in &mut m.positions {
        let bump = 0.05 * (13.0 * p.x).sin() * (11.0 * p.y).sin() * (17.0 * p.z).sin()
            + 0.02 * (41.0 * p.x + 37.0 * p.z).sin();
        *p *= 1.0 + bump;
    }
    m.normals = None;
    m
}

/// Peak resident set size in MiB, or `None` where /proc is unavailable.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

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

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let t = Instant::now();
    let mesh = displaced_sphere();
    println!(
        "mesh: {} triangles, {} vertices, generated in {:.2} s; peak RSS {:.0} MiB",
        mesh.indices.len(),
        mesh.positions.len(),
        t.elapsed().as_secs_f64(),
        peak_rss_mib().unwrap_or(f64::NAN)
    );
    let desc = || {
        vec![ShapeDesc {
            shape: Shape::Mesh(mesh.clone()),
            transform: Transform::IDENTITY,
        }]
    };
    let t = Instant::now();
    let geometry = Geometry::build(desc()).expect("valid mesh");
    println!(
        "first build: {:.2} s; BVH + primitive list {:.0} MiB; peak RSS after build {:.0} MiB",
        t.elapsed().as_secs_f64(),
        geometry.bvh_memory_bytes() as f64 / (1024.0 * 1024.0),
        peak_rss_mib().unwrap_or(f64::NAN)
    );

    let mut g = c.benchmark_group("bvh");
    g.sample_size(10);
    g.throughput(Throughput::Elements(mesh.indices.len() as u64));
    g.bench_function("build", |b| {
        b.iter_batched(
            desc,
            |d| Geometry::build(d).unwrap(),
            BatchSize::PerIteration,
        )
    });

    let coherent = camera_rays();
    let incoherent = random_rays();
    let hits = coherent
        .iter()
        .filter(|r| geometry.intersect(r, f32::INFINITY).is_some())
        .count();
    println!("coherent rays hitting: {hits} of {}", coherent.len());
    g.throughput(Throughput::Elements(coherent.len() as u64));
    g.bench_function("coherent", |b| {
        b.iter(|| {
            let mut n = 0u32;
            for r in &coherent {
                n += geometry.intersect(black_box(r), f32::INFINITY).is_some() as u32;
            }
            n
        })
    });
    g.throughput(Throughput::Elements(incoherent.len() as u64));
    g.bench_function("incoherent", |b| {
        b.iter(|| {
            let mut n = 0u32;
            for r in &incoherent {
                n += geometry.intersect(black_box(r), f32::INFINITY).is_some() as u32;
            }
            n
        })
    });
    g.bench_function("occluded_incoherent", |b| {
        b.iter(|| {
            let mut n = 0u32;
            for r in &incoherent {
                n += geometry.occluded(black_box(r), f32::INFINITY) as u32;
            }
            n
        })
    });
    g.finish();
    c.final_summary();
}
