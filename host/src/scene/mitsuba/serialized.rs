//! Mitsuba's `serialized` mesh format, read by hand (no crate reads it; the layout is the one
//! Mitsuba's plugin documentation gives):
//!
//! | field | type | meaning |
//! |---|---|---|
//! | format id | u16 LE | `0x041C` |
//! | version | u16 LE | 3 or 4 |
//! | (the rest of the mesh is one zlib stream) | | |
//! | flags | u32 | 0x1 vertex normals, 0x2 uvs, 0x8 vertex colours, 0x10 face normals, 0x1000 f32, 0x2000 f64 |
//! | name | UTF-8, NUL-terminated | version 4 only |
//! | vertex count, triangle count | u64, u64 | |
//! | positions, normals?, uvs?, colours? | 3, 3, 2, 3 floats per vertex | f32 or f64 per the flags |
//! | indices | 3 per triangle | u32, or u64 when there are more than 2³² vertices |
//!
//! A file may hold several meshes: it then ends with the byte offsets of every mesh (u64 in
//! version 4, u32 in version 3) followed by their number (u32); `shape_index` picks one.
//! Counts are checked against the file's length and the triangle limit before anything is
//! allocated, and the zlib stream is read only as far as the counts say.

use crate::geometry::TriangleMesh;
use glam::{Vec2, Vec3A};
use std::io::Read;

const FORMAT_ID: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x1;
const HAS_UVS: u32 = 0x2;
const HAS_COLORS: u32 = 0x8;
/// Mitsuba's flag for "use face normals" (the vertex normals are then ignored).
pub const FACE_NORMALS: u32 = 0x10;
const SINGLE: u32 = 0x1000;
const DOUBLE: u32 = 0x2000;

/// One mesh read from a serialized file.
#[derive(Debug)]
pub struct SerializedMesh {
    /// The mesh's name (version 4; empty otherwise).
    pub name: String,
    /// The flags word.
    pub flags: u32,
    /// The mesh (normals dropped when the file asks for face normals).
    pub mesh: TriangleMesh,
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(b.get(at..at + 2)?.try_into().ok()?))
}
fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
}
fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

/// Number of meshes in the file and the byte offset of mesh `index`.
fn mesh_offset(bytes: &[u8], index: usize) -> Result<usize, String> {
    let version = u16_at(bytes, 2).ok_or("file shorter than its 4-byte header")?;
    let n = bytes.len();
    let count = u32_at(bytes, n.saturating_sub(4)).unwrap_or(0) as usize;
    let entry = if version >= 4 { 8 } else { 4 };
    // A file with one mesh may have no table: then its last word is zlib data, not a count.
    let table_fits = count >= 1 && count.checked_mul(entry).is_some_and(|t| t + 4 + 4 <= n);
    if index == 0 && !table_fits {
        return Ok(0);
    }
    if !table_fits {
        return Err(format!(
            "shape_index {index} asked for, but the file has no table of several meshes"
        ));
    }
    if index >= count {
        return Err(format!(
            "shape_index {index} asked for, but the file holds {count} meshes"
        ));
    }
    let table = n - 4 - count * entry;
    let off = if version >= 4 {
        u64_at(bytes, table + index * 8).map(|v| v as usize)
    } else {
        u32_at(bytes, table + index * 4).map(|v| v as usize)
    }
    .ok_or("truncated mesh table")?;
    // `off` is the file's word: up to 2^64 − 1, so no `off + 4` (it overflowed, found by the
    // `mitsuba_serialized` fuzz target).
    if off > table || table - off < 4 {
        return Err(format!("mesh {index}'s offset {off} lies outside the file"));
    }
    Ok(off)
}

/// Read mesh `index` of a serialized file's bytes.
pub fn parse_serialized(bytes: &[u8], index: usize) -> Result<SerializedMesh, String> {
    let off = mesh_offset(bytes, index)?;
    let id = u16_at(bytes, off).ok_or("truncated header")?;
    if id != FORMAT_ID {
        return Err(format!(
            "not a Mitsuba serialized mesh (format id {id:#06x} at byte {off}, expected 0x041c)"
        ));
    }
    let version = u16_at(bytes, off + 2).ok_or("truncated header")?;
    if !(3..=4).contains(&version) {
        return Err(format!(
            "serialized format version {version} (3 and 4 are read)"
        ));
    }
    let mut z = Compressed(flate2::read::ZlibDecoder::new(&bytes[off + 4..]));
    let flags = u32::from_le_bytes(z.read(4)?.try_into().unwrap_or_default());
    let name = if version >= 4 {
        z.name()?
    } else {
        String::new()
    };
    let (nv, nt) = z.counts()?;
    let double = if flags & DOUBLE != 0 {
        true
    } else if flags & SINGLE != 0 {
        false
    } else {
        return Err(format!(
            "flags {flags:#x} name neither single (0x1000) nor double (0x2000) precision"
        ));
    };
    let positions = z.vec3s(nv, double)?;
    let normals = if flags & HAS_NORMALS != 0 {
        Some(z.vec3s(nv, double)?)
    } else {
        None
    };
    let uvs = if flags & HAS_UVS != 0 {
        let t = z.floats(nv * 2, double)?;
        Some(
            t.chunks_exact(2)
                .map(|c| Vec2::new(c[0], c[1]))
                .collect::<Vec<_>>(),
        )
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        z.floats(nv * 3, double)?;
    }
    let indices = z.indices(nv, nt)?;
    let mesh = TriangleMesh {
        positions,
        normals: if flags & FACE_NORMALS != 0 {
            None
        } else {
            normals
        },
        uvs,
        indices,
    };
    mesh.validate().map_err(|e| e.to_string())?;
    Ok(SerializedMesh { name, flags, mesh })
}

/// A mesh's zlib stream, read field by field.
struct Compressed<'a>(flate2::read::ZlibDecoder<&'a [u8]>);

impl Compressed<'_> {
    /// The next `n` bytes.
    fn read(&mut self, n: usize) -> Result<Vec<u8>, String> {
        let mut buf = vec![0u8; n];
        self.0
            .read_exact(&mut buf)
            .map_err(|e| format!("compressed mesh data ends early or is corrupt ({e})"))?;
        Ok(buf)
    }

    /// The mesh's name (version 4): bytes up to a 0, at most 4096.
    fn name(&mut self) -> Result<String, String> {
        let mut raw = Vec::new();
        loop {
            let b = self.read(1)?[0];
            if b == 0 {
                break;
            }
            if raw.len() >= 4096 {
                return Err("mesh name longer than 4096 bytes".into());
            }
            raw.push(b);
        }
        Ok(String::from_utf8_lossy(&raw).into_owned())
    }

    /// The vertex and triangle counts. The decompressed mesh cannot be larger than the triangle
    /// limit allows; a zlib stream claiming more is cut off there and reported as truncated.
    fn counts(&mut self) -> Result<(usize, usize), String> {
        let max_tris = crate::limits::max_triangles();
        let head = self.read(16)?;
        let nv = u64::from_le_bytes(head[0..8].try_into().unwrap_or_default());
        let nt = u64::from_le_bytes(head[8..16].try_into().unwrap_or_default());
        if nt > max_tris || nv > 3 * max_tris.max(1) {
            return Err(format!(
                "{nv} vertices and {nt} triangles: over the limit of {max_tris} triangles for this machine's memory"
            ));
        }
        Ok((nv as usize, nt as usize))
    }

    /// `count` floats stored in double or single precision.
    fn floats(&mut self, count: usize, double: bool) -> Result<Vec<f32>, String> {
        let raw = self.read(count * if double { 8 } else { 4 })?;
        Ok(if double {
            raw.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap_or_default()) as f32)
                .collect()
        } else {
            raw.chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap_or_default()))
                .collect()
        })
    }

    /// `n` 3-vectors (positions or normals).
    fn vec3s(&mut self, n: usize, double: bool) -> Result<Vec<Vec3A>, String> {
        let p = self.floats(n * 3, double)?;
        Ok(p.chunks_exact(3)
            .map(|c| Vec3A::new(c[0], c[1], c[2]))
            .collect())
    }

    /// `nt` triangles' vertex indices (64-bit when `nv` needs it).
    fn indices(&mut self, nv: usize, nt: usize) -> Result<Vec<[u32; 3]>, String> {
        let wide = nv > u32::MAX as usize;
        let raw = self.read(nt * 3 * if wide { 8 } else { 4 })?;
        let mut idx = Vec::with_capacity(nt * 3);
        if wide {
            for c in raw.chunks_exact(8) {
                let v = u64::from_le_bytes(c.try_into().unwrap_or_default());
                idx.push(u32::try_from(v).map_err(|_| format!("vertex index {v} beyond u32"))?);
            }
        } else {
            for c in raw.chunks_exact(4) {
                idx.push(u32::from_le_bytes(c.try_into().unwrap_or_default()));
            }
        }
        Ok(idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    }
}

/// Write one mesh in the serialized format (version 4, single precision): the inverse of
/// [`parse_serialized`], for tests and the fuzz seeds.
pub fn write_serialized(mesh: &TriangleMesh, name: &str) -> Vec<u8> {
    use std::io::Write;
    let mut flags = SINGLE;
    if mesh.normals.is_some() {
        flags |= HAS_NORMALS;
    }
    if mesh.uvs.is_some() {
        flags |= HAS_UVS;
    }
    let mut body = Vec::new();
    body.extend(flags.to_le_bytes());
    body.extend(name.as_bytes());
    body.push(0);
    body.extend((mesh.positions.len() as u64).to_le_bytes());
    body.extend((mesh.indices.len() as u64).to_le_bytes());
    for p in &mesh.positions {
        for v in p.to_array() {
            body.extend(v.to_le_bytes());
        }
    }
    if let Some(n) = &mesh.normals {
        for p in n {
            for v in p.to_array() {
                body.extend(v.to_le_bytes());
            }
        }
    }
    if let Some(t) = &mesh.uvs {
        for p in t {
            for v in p.to_array() {
                body.extend(v.to_le_bytes());
            }
        }
    }
    for t in &mesh.indices {
        for v in t {
            body.extend(v.to_le_bytes());
        }
    }
    let mut out = Vec::new();
    out.extend(FORMAT_ID.to_le_bytes());
    out.extend(4u16.to_le_bytes());
    let mut enc = flate2::write::ZlibEncoder::new(out, flate2::Compression::default());
    enc.write_all(&body).expect("writing to a Vec cannot fail");
    enc.finish().expect("writing to a Vec cannot fail")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (fuzz target `mitsuba_serialized`, 2026-12-07): a one-mesh table whose offset
    /// is 0xffff_ffff_ffff_fffc made `off + 4` overflow (a panic with overflow checks on, as in
    /// debug builds; a wrapped comparison otherwise). Now an error naming the offset.
    #[test]
    fn offset_near_u64_max_is_an_error() {
        let bytes = [
            0x1c, 0x04, 0x04, 0x00, 0x78, 0x9c, 0x63, 0x16, 0x60, 0x60, 0x28, 0x2e, 0x2c, 0x4d,
            0x4c, 0x95, 0x8d, 0xc6, 0xc7, 0xa7, 0x96, 0x58, 0x36, 0x2e, 0xb9, 0x10, 0x9a, 0x11,
            0xc9, 0x3d, 0x20, 0x9a, 0x19, 0x88, 0x01, 0xed, 0xa9, 0x0a, 0xc1, 0x00, 0x00, 0x00,
            0x00, 0x14, 0x19, 0x88, 0x01, 0xed, 0xa9, 0x0a, 0xc1, 0xfc, 0xff, 0xff, 0xff, 0xff,
            0xff, 0xff, 0xff, 0x01, 0x00, 0x00, 0x00,
        ];
        for index in 0..2 {
            if let Err(e) = parse_serialized(&bytes, index) {
                assert!(!e.is_empty());
            }
        }
        let Err(e) = parse_serialized(&bytes, 0) else {
            panic!("mesh 0's offset is outside the file")
        };
        assert!(e.contains("outside the file"), "{e}");
    }

    fn quad() -> TriangleMesh {
        TriangleMesh {
            positions: vec![
                Vec3A::new(0.0, 0.0, 0.0),
                Vec3A::new(1.0, 0.0, 0.0),
                Vec3A::new(1.0, 1.0, 0.0),
                Vec3A::new(0.0, 1.0, 0.0),
            ],
            normals: Some(vec![Vec3A::Z; 4]),
            uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]),
            indices: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    // Round trip through the writer: every field back bit for bit.
    #[test]
    fn round_trip() {
        let m = quad();
        let back = parse_serialized(&write_serialized(&m, "quad"), 0).unwrap();
        assert_eq!(back.name, "quad");
        assert_eq!(back.mesh.positions, m.positions);
        assert_eq!(back.mesh.normals, m.normals);
        assert_eq!(back.mesh.uvs, m.uvs);
        assert_eq!(back.mesh.indices, m.indices);
    }

    // Two meshes with the version-4 offset table: shape_index picks each; a third is an error.
    #[test]
    fn several_meshes() {
        let a = write_serialized(&quad(), "a");
        let mut m2 = quad();
        m2.indices.pop();
        let b = write_serialized(&m2, "b");
        let mut file = a.clone();
        file.extend(&b);
        file.extend(0u64.to_le_bytes());
        file.extend((a.len() as u64).to_le_bytes());
        file.extend(2u32.to_le_bytes());
        assert_eq!(parse_serialized(&file, 0).unwrap().name, "a");
        let second = parse_serialized(&file, 1).unwrap();
        assert_eq!(second.name, "b");
        assert_eq!(second.mesh.indices.len(), 1);
        assert!(parse_serialized(&file, 2)
            .unwrap_err()
            .contains("holds 2 meshes"));
    }

    // Broken input: errors, never a panic or a huge allocation.
    #[test]
    fn bad_input() {
        assert!(parse_serialized(&[], 0).is_err());
        assert!(parse_serialized(&[0x1c, 0x04, 4, 0, 1, 2, 3], 0).is_err());
        let mut good = write_serialized(&quad(), "q");
        good.truncate(good.len() - 6);
        assert!(parse_serialized(&good, 0)
            .unwrap_err()
            .contains("ends early"));
        // A header claiming 2^40 triangles is refused before allocating.
        let mut body = Vec::new();
        body.extend(SINGLE.to_le_bytes());
        body.push(0);
        body.extend(3u64.to_le_bytes());
        body.extend((1u64 << 40).to_le_bytes());
        let mut out = vec![0x1c, 0x04, 4, 0];
        let mut enc = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        std::io::Write::write_all(&mut enc, &body).unwrap();
        out.extend(enc.finish().unwrap());
        assert!(parse_serialized(&out, 0)
            .unwrap_err()
            .contains("over the limit"));
        // An index past the vertices is caught by the mesh check.
        let mut m = quad();
        m.indices[0][2] = 9;
        assert!(parse_serialized(&write_serialized(&m, ""), 0).is_err());
    }
}
