//! Mesh files that used to make a scene unusable: one huge polygon face.

use std::path::Path;

use spectrace::geometry::parse_obj;

/// One OBJ face of `n` corners on the unit circle.
fn circle_face(n: usize) -> String {
    let mut s = String::with_capacity(n * 40);
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        s.push_str(&format!("v {} {} 0\n", a.cos(), a.sin()));
    }
    s.push('f');
    for k in 1..=n {
        s.push_str(&format!(" {k}"));
    }
    s.push('\n');
    s
}

/// A fan of a 20,000-corner face is 19,998 slivers reaching from corner 0 across the disc: the
/// sum of their bounding-box areas was 4,054× the disc's area (every ray crosses the boxes of a
/// large share of them; a 600,000-corner face made tracing ~2,000× slower). The balanced split
/// keeps the sum within a small multiple of the area: measured 3.58×; the bound 10× leaves room
/// for other balanced schemes and is 400× below the fan's.
#[test]
fn a_huge_face_is_not_split_into_slivers() {
    let n = 20_000;
    let mesh = parse_obj(&circle_face(n), Path::new("disc.obj")).unwrap();
    assert_eq!(mesh.indices.len(), n - 2);
    let mut box_area = 0.0f64;
    let mut area = 0.0f64;
    for t in &mesh.indices {
        let p = t.map(|i| mesh.positions[i as usize]);
        let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
        box_area += f64::from((hi.x - lo.x) * (hi.y - lo.y));
        area += 0.5 * f64::from((p[1] - p[0]).cross(p[2] - p[0]).z);
    }
    let disc = std::f64::consts::PI;
    println!(
        "sum of triangle box areas / disc area = {:.2}",
        box_area / disc
    );
    assert!(
        (area - disc).abs() < 1e-3,
        "the triangles tile the disc: {area}"
    );
    assert!(
        box_area / disc < 10.0,
        "box area {box_area:.1} against disc {disc:.3}"
    );
}
