//! OBJ and PLY loading: valid files in every supported flavour, and malformed files that must
//! produce an error naming the file and the place, never a panic or a huge allocation.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3A};
use spectrace::geometry::{load_obj, load_ply, parse_obj, parse_ply, GeometryError};

fn obj(text: &str) -> Result<spectrace::geometry::TriangleMesh, GeometryError> {
    parse_obj(text, Path::new("test.obj"))
}

fn ply(bytes: &[u8]) -> Result<spectrace::geometry::TriangleMesh, GeometryError> {
    parse_ply(bytes, Path::new("test.ply"))
}

/// The error's display text, which must name the file.
fn message(e: GeometryError) -> String {
    let s = e.to_string();
    assert!(
        s.contains("test.obj") || s.contains("test.ply"),
        "no file name in `{s}`"
    );
    s
}

// A quad with `v/vt/vn` corners becomes 2 triangles (fan) with 4 merged vertices carrying uvs
// and normals; exact values (they are copied, not computed).
#[test]
fn obj_quad_with_uv_and_normals() {
    let m = obj(
        "# comment\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
                 o thing\ns off\nf 1/1/1 2/2/1 3/3/1 4/4/1\n",
    )
    .unwrap();
    assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(m.positions[2], Vec3A::new(1.0, 1.0, 0.0));
    assert_eq!(m.uvs.as_ref().unwrap()[3], Vec2::new(0.0, 1.0));
    assert_eq!(m.normals.as_ref().unwrap()[1], Vec3A::Z);
}

// Negative (relative) indices and `v//vn` corners; a pentagon gives 3 fan triangles.
#[test]
fn obj_negative_indices_and_normal_only_corners() {
    let m = obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 2 0\nv 0 1 0\nvn 0 0 1\nf -5//-1 -4//-1 -3//-1 -2//-1 -1//-1\n").unwrap();
    assert_eq!(m.indices.len(), 3);
    assert!(m.uvs.is_none());
    assert_eq!(m.normals.as_ref().unwrap().len(), 5);
    assert_eq!(
        m.positions[m.indices[2][2] as usize],
        Vec3A::new(0.0, 1.0, 0.0)
    );
}

// Corners that share a position but differ in normal stay separate vertices; faces mixing
// corners with and without normals drop normals entirely (no invented data).
#[test]
fn obj_vertex_merging_and_mixed_attributes() {
    let m =
        obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 -1\nf 1//1 2//1 3//1\nf 1//2 3//2 2//2\n")
            .unwrap();
    assert_eq!(m.positions.len(), 6);
    let m = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1 3 2\n").unwrap();
    assert!(m.normals.is_none());
    assert_eq!(m.indices.len(), 2);
}

// Malformed OBJ: each error names the file and the 1-based line of the problem.
#[test]
fn obj_errors_name_file_and_line() {
    let cases: &[(&str, &str)] = &[
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "line 4"),
        ("v 0 0 0\nv 1 x 0\n", "line 2"),
        ("v 0 0\n", "line 1"),
        ("v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", "line 4"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/3/4 2 3\n", "line 4"),
        ("v 0 0 0\nv nan 0 0\n", "line 2"),
    ];
    for (text, line) in cases {
        let e = message(obj(text).expect_err(text));
        assert!(e.contains(line), "`{e}` should mention {line}");
    }
    let e = message(obj("v 0 0 0\n").unwrap_err());
    assert!(e.contains("no faces"), "{e}");
}

const PLY_ASCII: &str = "ply\nformat ascii 1.0\ncomment a unit square\nelement vertex 4\n\
property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
property float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n";

// ASCII PLY with normals, s/t uvs and a quad face (fan → 2 triangles); values copied exactly.
#[test]
fn ply_ascii_quad() {
    let m = ply(PLY_ASCII.as_bytes()).unwrap();
    assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(m.normals.as_ref().unwrap()[0], Vec3A::Z);
    assert_eq!(m.uvs.as_ref().unwrap()[2], Vec2::new(1.0, 1.0));
}

/// A binary little-endian PLY with 3 vertices (x y z u v as float, plus an ignored uchar
/// property), one `list uchar uint` face, and an extra element that must be skipped.
fn binary_ply(vertex_count_in_header: &str, face_index: u32) -> Vec<u8> {
    let mut b = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertex_count_in_header}\nproperty float x\n\
property float y\nproperty float z\nproperty uchar flags\nproperty float u\nproperty float v\n\
element face 1\nproperty list uchar uint vertex_indices\nelement extra 1\nproperty list int short junk\nend_header\n"
    )
    .into_bytes();
    for (x, y) in [(0.0f32, 0.0f32), (2.0, 0.0), (0.0, 2.0)] {
        for f in [x, y, 0.5] {
            b.extend_from_slice(&f.to_le_bytes());
        }
        b.push(7);
        b.extend_from_slice(&(x / 2.0).to_le_bytes());
        b.extend_from_slice(&(y / 2.0).to_le_bytes());
    }
    b.push(3);
    for i in [0u32, 1, face_index] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b.extend_from_slice(&2i32.to_le_bytes());
    b.extend_from_slice(&5i16.to_le_bytes());
    b.extend_from_slice(&6i16.to_le_bytes());
    b
}

// Binary little-endian PLY: positions and u/v read exactly, extra element skipped.
#[test]
fn ply_binary_little_endian() {
    let m = ply(&binary_ply("3", 2)).unwrap();
    assert_eq!(m.indices, vec![[0, 1, 2]]);
    assert_eq!(m.positions[1], Vec3A::new(2.0, 0.0, 0.5));
    assert_eq!(m.uvs.as_ref().unwrap()[2], Vec2::new(0.0, 1.0));
    assert!(m.normals.is_none());
}

// Malformed binary PLY: truncation names a byte offset; a bad index names the offset; a huge
// vertex count is rejected by comparing with the file size before allocating anything.
#[test]
fn ply_binary_errors() {
    let full = binary_ply("3", 2);
    for cut in [full.len() - 1, full.len() - 9, full.len() - 40] {
        let e = message(ply(&full[..cut]).unwrap_err());
        assert!(
            e.contains("byte") || e.contains("more data than the file holds"),
            "{e}"
        );
    }
    let e = message(ply(&binary_ply("3", 3)).unwrap_err());
    assert!(e.contains("byte") && e.contains("vertex 3"), "{e}");
    let e = message(ply(&binary_ply("1000000000000", 2)).unwrap_err());
    assert!(e.contains("more data than the file holds"), "{e}");
    let e = message(ply(&binary_ply("18446744073709551615", 2)).unwrap_err());
    assert!(e.contains("more data"), "{e}");
}

// Malformed headers and ASCII bodies: errors carry the line number.
#[test]
fn ply_header_and_ascii_errors() {
    let e = message(ply(b"plx\n").unwrap_err());
    assert!(e.contains("line 1"), "{e}");
    let e = message(ply(b"ply\nformat binary_big_endian 1.0\nend_header\n").unwrap_err());
    assert!(
        e.contains("line 2") && e.contains("binary_big_endian"),
        "{e}"
    );
    let e = message(ply(b"ply\nformat ascii 1.0\nelement vertex 3\n").unwrap_err());
    assert!(e.contains("end_header"), "{e}");
    let e = message(
        ply(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty blob x\nend_header\n").unwrap_err(),
    );
    assert!(e.contains("line 4"), "{e}");
    // Vertex line 17 has a missing value; face line 21 has an out-of-range index.
    let short = PLY_ASCII.replace("1 0 0 0 0 1 1 0\n", "1 0 0 0 0 1 1\n");
    let e = message(ply(short.as_bytes()).unwrap_err());
    assert!(e.contains("line 17"), "{e}");
    let bad = PLY_ASCII.replace("4 0 1 2 3\n", "4 0 1 2 9\n");
    let e = message(ply(bad.as_bytes()).unwrap_err());
    assert!(e.contains("line 20"), "{e}");
    let e = message(
        ply(PLY_ASCII
            .replace("element vertex 4", "element vertex 4000000")
            .as_bytes())
        .unwrap_err(),
    );
    assert!(e.contains("more data"), "{e}");
}

// Files on disk: load_* read them; a missing file is an Io error naming the path.
#[test]
fn load_from_disk_and_missing_file() {
    let dir: PathBuf =
        std::env::temp_dir().join(format!("spectrace-geometry-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("tri.obj");
    std::fs::write(&p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_eq!(load_obj(&p).unwrap().indices.len(), 1);
    let q = dir.join("sq.ply");
    std::fs::write(&q, PLY_ASCII).unwrap();
    assert_eq!(load_ply(&q).unwrap().indices.len(), 2);
    let missing = dir.join("missing.ply");
    let e = load_ply(&missing).unwrap_err();
    assert!(matches!(e, GeometryError::Io { .. }) && e.to_string().contains("missing.ply"));
    std::fs::remove_dir_all(&dir).ok();
}
