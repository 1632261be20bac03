//! Wavefront OBJ loader: `v`, `vt`, `vn` and `f` (polygons triangulated by [`super::polygon`]; `v`, `v/vt`,
//! `v//vn`, `v/vt/vn`; negative indices count back from the latest element). Other statements
//! (`o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, ...) are ignored.
//!
//! OBJ indexes positions, uvs and normals separately; vertices are merged per distinct
//! `(v, vt, vn)` triple. Normals (uvs) are kept only if *every* face corner has one; a file that
//! mixes corners with and without is loaded without them rather than with made-up values.

use std::collections::HashMap;
use std::path::Path;

use glam::{Vec2, Vec3A};

use super::{GeometryError, TriangleMesh};

/// Reads and parses an OBJ file.
pub fn load_obj(path: &Path) -> Result<TriangleMesh, GeometryError> {
    let limit = crate::limits::mesh_file_max_bytes();
    let bytes = crate::limits::read_limited(path, limit, "mesh file").map_err(|source| {
        GeometryError::Io {
            path: path.to_path_buf(),
            source,
        }
    })?;
    let text = String::from_utf8_lossy(&bytes);
    parse_obj(&text, path)
}

/// Parses OBJ text; `path` is only used in error messages.
pub fn parse_obj(text: &str, path: &Path) -> Result<TriangleMesh, GeometryError> {
    let err = |line: usize, message: String| GeometryError::ParseLine {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut v: Vec<Vec3A> = Vec::new();
    let mut vt: Vec<Vec2> = Vec::new();
    let mut vn: Vec<Vec3A> = Vec::new();
    let mut mesh = TriangleMesh::default();
    let mut corner_uvs: Vec<Vec2> = Vec::new();
    let mut corner_normals: Vec<Vec3A> = Vec::new();
    let mut all_uv = true;
    let mut all_n = true;
    let mut merge: HashMap<(u32, u32, u32), u32> = HashMap::new();
    let max_triangles = crate::limits::max_triangles();

    let mut lines = text.lines().enumerate().peekable();
    while let Some((ln0, raw)) = lines.next() {
        let mut line_no = ln0 + 1;
        // Backslash continuation joins the next line.
        let mut line = raw.to_string();
        while line.ends_with('\\') {
            line.pop();
            match lines.next() {
                Some((n, next)) => {
                    line.push(' ');
                    line.push_str(next);
                    line_no = n + 1;
                }
                None => break,
            }
        }
        let line = line.split('#').next().unwrap_or("");
        let mut parts = line.split_whitespace();
        let Some(kw) = parts.next() else { continue };
        match kw {
            "v" | "vn" => {
                let nums = parse_floats(parts, 3, line_no, kw, &err)?;
                let p = Vec3A::new(nums[0], nums[1], nums[2]);
                if kw == "v" {
                    v.push(p)
                } else {
                    vn.push(p)
                }
            }
            "vt" => {
                let nums = parse_floats(parts, 2, line_no, kw, &err)?;
                vt.push(Vec2::new(nums[0], nums[1]));
            }
            "f" => {
                let mut face: Vec<u32> = Vec::new();
                for tok in parts {
                    let mut fields = tok.split('/');
                    let vi = resolve(fields.next(), v.len(), "position", line_no, &err)?
                        .ok_or_else(|| {
                            err(
                                line_no,
                                format!("face corner `{tok}` has no position index"),
                            )
                        })?;
                    let ti = resolve(fields.next(), vt.len(), "texture coordinate", line_no, &err)?;
                    let ni = resolve(fields.next(), vn.len(), "normal", line_no, &err)?;
                    if fields.next().is_some() {
                        return Err(err(
                            line_no,
                            format!("face corner `{tok}` has more than 3 fields"),
                        ));
                    }
                    all_uv &= ti.is_some();
                    all_n &= ni.is_some();
                    let key = (vi, ti.map_or(u32::MAX, |x| x), ni.map_or(u32::MAX, |x| x));
                    let next = mesh.positions.len() as u32;
                    let id = *merge.entry(key).or_insert_with(|| {
                        mesh.positions.push(v[vi as usize]);
                        corner_uvs.push(ti.map_or(Vec2::ZERO, |i| vt[i as usize]));
                        corner_normals.push(ni.map_or(Vec3A::ZERO, |i| vn[i as usize]));
                        next
                    });
                    face.push(id);
                }
                if face.len() < 3 {
                    return Err(err(
                        line_no,
                        format!("face has {} corners, needs at least 3", face.len()),
                    ));
                }
                super::polygon::triangulate_convex(&face, &mut mesh.indices);
                if mesh.indices.len() as u64 > max_triangles {
                    return Err(err(
                        line_no,
                        format!(
                            "more than {max_triangles} triangles, the limit for one mesh on \
                             this machine (its available memory at {} bytes a triangle)",
                            crate::limits::BYTES_PER_TRIANGLE
                        ),
                    ));
                }
            }
            _ => {}
        }
    }
    if mesh.indices.is_empty() {
        return Err(GeometryError::File {
            path: path.to_path_buf(),
            message: "no faces (`f` lines) found".into(),
        });
    }
    if all_n {
        mesh.normals = Some(corner_normals);
    }
    if all_uv {
        mesh.uvs = Some(corner_uvs);
    }
    mesh.validate().map_err(|e| GeometryError::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok(mesh)
}

fn parse_floats<'a, E: Fn(usize, String) -> GeometryError>(
    parts: impl Iterator<Item = &'a str>,
    needed: usize,
    line: usize,
    kw: &str,
    err: &E,
) -> Result<[f32; 3], GeometryError> {
    let mut out = [0.0f32; 3];
    let mut n = 0;
    for tok in parts {
        if n < needed {
            let x: f32 = tok
                .parse()
                .map_err(|_| err(line, format!("`{kw}`: `{tok}` is not a number")))?;
            if !x.is_finite() {
                return Err(err(line, format!("`{kw}`: `{tok}` is not finite")));
            }
            out[n] = x;
        }
        n += 1;
    }
    if n < needed {
        return Err(err(
            line,
            format!("`{kw}` needs {needed} numbers, found {n}"),
        ));
    }
    Ok(out)
}

/// Resolves a 1-based (or negative, relative) OBJ index against `count` elements seen so far.
/// Empty field → `None`.
fn resolve<E: Fn(usize, String) -> GeometryError>(
    field: Option<&str>,
    count: usize,
    what: &str,
    line: usize,
    err: &E,
) -> Result<Option<u32>, GeometryError> {
    let Some(f) = field.filter(|f| !f.is_empty()) else {
        return Ok(None);
    };
    let i: i64 = f
        .parse()
        .map_err(|_| err(line, format!("{what} index `{f}` is not an integer")))?;
    let idx = if i > 0 {
        i - 1
    } else if i < 0 {
        count as i64 + i
    } else {
        return Err(err(
            line,
            format!("{what} index 0 is invalid (OBJ indices start at 1)"),
        ));
    };
    if idx < 0 || idx >= count as i64 {
        return Err(err(
            line,
            format!("{what} index {i} is out of range (only {count} defined so far)"),
        ));
    }
    Ok(Some(idx as u32))
}
