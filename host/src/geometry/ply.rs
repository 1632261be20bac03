//! PLY loader (Stanford polygon format): `ascii 1.0` and `binary_little_endian 1.0`.
//!
//! Reads element `vertex` (`x y z`, optional `nx ny nz`, optional `u v` / `s t` /
//! `texture_u texture_v`) and element `face` (`vertex_indices` or `vertex_index`, a list of any
//! integer type; polygons are triangulated by [`super::polygon`]). Other elements and properties are skipped.
//! Counts in the header are untrusted: before anything is allocated they are checked against
//! the bytes (binary) or lines (ascii) actually left in the file.

use std::path::Path;

use glam::{Vec2, Vec3A};

use super::{GeometryError, TriangleMesh};

/// Reads and parses a PLY file.
pub fn load_ply(path: &Path) -> Result<TriangleMesh, GeometryError> {
    let limit = crate::limits::mesh_file_max_bytes();
    let bytes = crate::limits::read_limited(path, limit, "mesh file").map_err(|source| {
        GeometryError::Io {
            path: path.to_path_buf(),
            source,
        }
    })?;
    parse_ply(&bytes, path)
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Clone, Debug)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

impl Property {
    fn name(&self) -> &str {
        match self {
            Property::Scalar(n, _) | Property::List(n, _, _) => n,
        }
    }
    /// Fewest bytes one value can take in binary (a list with zero items).
    fn min_size(&self) -> usize {
        match self {
            Property::Scalar(_, s) | Property::List(_, s, _) => s.size(),
        }
    }
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

/// Where values come from: whitespace-separated text records or little-endian bytes.
trait Source {
    fn begin_record(&mut self) -> Result<(), GeometryError>;
    fn read(&mut self, s: Scalar) -> Result<f64, GeometryError>;
    fn error(&self, message: String) -> GeometryError;
}

struct AsciiSource<'a> {
    path: &'a Path,
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    line_offset: usize,
    line: usize,
    tokens: Vec<&'a str>,
    next: usize,
}

impl Source for AsciiSource<'_> {
    fn begin_record(&mut self) -> Result<(), GeometryError> {
        loop {
            let Some((i, l)) = self.lines.next() else {
                return Err(GeometryError::ParseLine {
                    path: self.path.to_path_buf(),
                    line: self.line + 1,
                    message: "unexpected end of file: fewer elements than the header declares"
                        .into(),
                });
            };
            self.line = self.line_offset + i + 1;
            self.tokens = l.split_whitespace().collect();
            self.next = 0;
            if !self.tokens.is_empty() {
                return Ok(());
            }
        }
    }

    fn read(&mut self, s: Scalar) -> Result<f64, GeometryError> {
        let Some(tok) = self.tokens.get(self.next) else {
            return Err(self.error("too few values on the line".into()));
        };
        self.next += 1;
        let v: f64 = tok
            .parse()
            .map_err(|_| self.error(format!("`{tok}` is not a number")))?;
        if !v.is_finite() || (s.is_integer() && v.fract() != 0.0) {
            return Err(self.error(format!("`{tok}` is not a valid {s:?}")));
        }
        Ok(v)
    }

    fn error(&self, message: String) -> GeometryError {
        GeometryError::ParseLine {
            path: self.path.to_path_buf(),
            line: self.line,
            message,
        }
    }
}

struct BinarySource<'a> {
    path: &'a Path,
    data: &'a [u8],
    pos: usize,
}

impl Source for BinarySource<'_> {
    fn begin_record(&mut self) -> Result<(), GeometryError> {
        Ok(())
    }

    fn read(&mut self, s: Scalar) -> Result<f64, GeometryError> {
        let n = s.size();
        let Some(b) = self.data.get(self.pos..self.pos + n) else {
            return Err(self.error(format!(
                "unexpected end of file reading a {n}-byte value (file is {} bytes)",
                self.data.len()
            )));
        };
        let v = match s {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b.try_into().expect("8 bytes")),
        };
        if !v.is_finite() {
            return Err(self.error("value is NaN or infinite".into()));
        }
        self.pos += n;
        Ok(v)
    }

    fn error(&self, message: String) -> GeometryError {
        GeometryError::ParseByte {
            path: self.path.to_path_buf(),
            offset: self.pos,
            message,
        }
    }
}

/// Parses PLY bytes; `path` is only used in error messages.
pub fn parse_ply(bytes: &[u8], path: &Path) -> Result<TriangleMesh, GeometryError> {
    let header = read_header(bytes, path)?;
    let (ascii, pos, line_no) = (header.ascii, header.body_start, header.lines);
    let elements = &header.elements;
    let body = &bytes[pos..];
    let ascii_text = if ascii {
        std::str::from_utf8(body).map_err(|e| GeometryError::ParseByte {
            path: path.to_path_buf(),
            offset: pos + e.valid_up_to(),
            message: "ascii body is not UTF-8 text".into(),
        })?
    } else {
        ""
    };
    check_counts(&header, body, ascii_text, path)?;

    let vertex_count = elements
        .iter()
        .find(|e| e.name == "vertex")
        .map_or(0, |e| e.count);
    let mut mesh = TriangleMesh::default();
    if ascii {
        let mut src = AsciiSource {
            path,
            lines: ascii_text.lines().enumerate(),
            line_offset: line_no,
            line: line_no,
            tokens: Vec::new(),
            next: 0,
        };
        read_elements(elements, &mut src, vertex_count, &mut mesh)?;
    } else {
        let mut src = BinarySource {
            path,
            data: bytes,
            pos,
        };
        read_elements(elements, &mut src, vertex_count, &mut mesh)?;
    }
    if mesh.indices.is_empty() {
        return Err(GeometryError::File {
            path: path.to_path_buf(),
            message: "no faces (element `face` missing or empty)".into(),
        });
    }
    mesh.validate().map_err(|e| GeometryError::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    Ok(mesh)
}

/// What the header says.
struct Header {
    /// `format ascii` (else binary little-endian).
    ascii: bool,
    elements: Vec<Element>,
    /// Byte offset of the body (after the `end_header` line).
    body_start: usize,
    /// Number of header lines.
    lines: usize,
}

/// An error in header line `line`.
fn header_error(path: &Path, line: usize, message: String) -> GeometryError {
    GeometryError::ParseLine {
        path: path.to_path_buf(),
        line,
        message,
    }
}

/// The header: text lines up to and including `end_header`.
fn read_header(bytes: &[u8], path: &Path) -> Result<Header, GeometryError> {
    let herr = |line: usize, message: String| header_error(path, line, message);
    let mut pos = 0usize;
    let mut line_no = 0usize;
    let mut format: Option<bool> = None; // Some(true) = ascii
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let rest = &bytes[pos..];
        let Some(nl) = rest.iter().position(|&b| b == b'\n') else {
            return Err(herr(line_no + 1, "header ends before `end_header`".into()));
        };
        line_no += 1;
        let line = std::str::from_utf8(&rest[..nl])
            .map_err(|_| herr(line_no, "header line is not UTF-8 text".into()))?
            .trim_end_matches('\r');
        pos += nl + 1;
        let mut w = line.split_whitespace();
        let kw = w.next().unwrap_or("");
        if line_no == 1 {
            if kw != "ply" {
                return Err(herr(1, "not a PLY file (first line must be `ply`)".into()));
            }
            continue;
        }
        match kw {
            "format" => {
                format = Some(match w.next() {
                    Some("ascii") => true,
                    Some("binary_little_endian") => false,
                    Some(other) => {
                        return Err(herr(
                            line_no,
                            format!(
                                "unsupported format `{other}` (ascii and binary_little_endian are)"
                            ),
                        ))
                    }
                    None => return Err(herr(line_no, "`format` without a value".into())),
                });
            }
            "element" => {
                let name = w
                    .next()
                    .ok_or_else(|| herr(line_no, "`element` without a name".into()))?;
                let count = w
                    .next()
                    .and_then(|c| c.parse::<usize>().ok())
                    .ok_or_else(|| {
                        herr(
                            line_no,
                            format!("element `{name}` needs a non-negative integer count"),
                        )
                    })?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            "property" => {
                let el = elements
                    .last_mut()
                    .ok_or_else(|| herr(line_no, "`property` before any `element`".into()))?;
                el.props.push(parse_property(w, line, line_no, path)?);
            }
            "end_header" => break,
            "comment" | "obj_info" | "" => {}
            other => return Err(herr(line_no, format!("unknown header keyword `{other}`"))),
        }
    }
    let ascii = format.ok_or_else(|| herr(line_no, "header has no `format` line".into()))?;
    Ok(Header {
        ascii,
        elements,
        body_start: pos,
        lines: line_no,
    })
}

/// A `property` line after its keyword (`w`): a scalar `TYPE NAME` or `list COUNT ITEM NAME`.
fn parse_property<'a>(
    mut w: impl Iterator<Item = &'a str>,
    line: &str,
    line_no: usize,
    path: &Path,
) -> Result<Property, GeometryError> {
    let herr = |message: String| header_error(path, line_no, message);
    let t = w.next().unwrap_or("");
    if t == "list" {
        let ct = w.next().and_then(Scalar::parse);
        let it = w.next().and_then(Scalar::parse);
        let name = w.next();
        match (ct, it, name) {
            (Some(c), Some(i), Some(n)) if c.is_integer() => Ok(Property::List(n.into(), c, i)),
            _ => Err(herr(format!("bad list property `{line}`"))),
        }
    } else {
        let s = Scalar::parse(t).ok_or_else(|| herr(format!("unknown property type `{t}`")))?;
        let name = w
            .next()
            .ok_or_else(|| herr("property without a name".into()))?;
        Ok(Property::Scalar(name.into(), s))
    }
}

/// Untrusted counts: every record needs at least one line (ascii) or its minimum size in bytes
/// (binary), so a count larger than that is a corrupt/truncated file.
fn check_counts(
    header: &Header,
    body: &[u8],
    ascii_text: &str,
    path: &Path,
) -> Result<(), GeometryError> {
    let ascii = header.ascii;
    let mut needed: usize = 0;
    for e in &header.elements {
        let unit = if ascii {
            1
        } else {
            e.props.iter().map(Property::min_size).sum()
        };
        needed = needed.saturating_add(e.count.saturating_mul(unit));
    }
    let available = if ascii {
        ascii_text.lines().filter(|l| !l.trim().is_empty()).count()
    } else {
        body.len()
    };
    if needed > available {
        return Err(GeometryError::File {
            path: path.to_path_buf(),
            message: format!(
                "header declares more data than the file holds (needs at least {needed} {}, has {available})",
                if ascii { "non-empty lines" } else { "bytes after the header" }
            ),
        });
    }
    Ok(())
}

/// Indices of the named properties in an element, or `None` if any is missing.
fn find3(props: &[Property], names: &[&str]) -> Option<Vec<usize>> {
    names
        .iter()
        .map(|n| {
            props
                .iter()
                .position(|p| p.name() == *n && matches!(p, Property::Scalar(..)))
        })
        .collect()
}

fn read_elements<S: Source>(
    elements: &[Element],
    src: &mut S,
    vertex_count: usize,
    mesh: &mut TriangleMesh,
) -> Result<(), GeometryError> {
    for e in elements {
        if e.props.is_empty() {
            continue; // no data to read, whatever the count
        }
        match e.name.as_str() {
            "vertex" => read_vertices(e, src, mesh)?,
            "face" => read_faces(e, src, vertex_count, mesh)?,
            _ => {
                for _ in 0..e.count {
                    src.begin_record()?;
                    let mut vals = Vec::new();
                    read_record(&e.props, src, &mut vals)?;
                }
            }
        }
    }
    Ok(())
}

/// Reads one record; scalar values go to `out` by property, lists are returned separately.
fn read_record<S: Source>(
    props: &[Property],
    src: &mut S,
    out: &mut Vec<f64>,
) -> Result<Vec<Vec<f64>>, GeometryError> {
    out.clear();
    let mut lists = Vec::new();
    for p in props {
        match p {
            Property::Scalar(_, s) => out.push(src.read(*s)?),
            Property::List(_, c, i) => {
                let n = src.read(*c)?;
                if n < 0.0 {
                    return Err(src.error(format!("negative list length {n}")));
                }
                // List lengths come from the file: read item by item, never pre-allocate by n.
                let mut items = Vec::new();
                for _ in 0..n as usize {
                    items.push(src.read(*i)?);
                }
                out.push(f64::NAN);
                lists.push(items);
            }
        }
    }
    Ok(lists)
}

fn read_vertices<S: Source>(
    e: &Element,
    src: &mut S,
    mesh: &mut TriangleMesh,
) -> Result<(), GeometryError> {
    let pos = find3(&e.props, &["x", "y", "z"])
        .ok_or_else(|| src.error("element `vertex` lacks scalar properties x, y and z".into()))?;
    let nrm = find3(&e.props, &["nx", "ny", "nz"]);
    let uv = find3(&e.props, &["u", "v"])
        .or_else(|| find3(&e.props, &["s", "t"]))
        .or_else(|| find3(&e.props, &["texture_u", "texture_v"]));
    // The count was checked against the file size already, so this allocation is bounded.
    mesh.positions.reserve(e.count);
    let mut normals = Vec::with_capacity(if nrm.is_some() { e.count } else { 0 });
    let mut uvs = Vec::with_capacity(if uv.is_some() { e.count } else { 0 });
    let mut vals = Vec::new();
    for _ in 0..e.count {
        src.begin_record()?;
        read_record(&e.props, src, &mut vals)?;
        mesh.positions.push(Vec3A::new(
            vals[pos[0]] as f32,
            vals[pos[1]] as f32,
            vals[pos[2]] as f32,
        ));
        if let Some(n) = &nrm {
            normals.push(Vec3A::new(
                vals[n[0]] as f32,
                vals[n[1]] as f32,
                vals[n[2]] as f32,
            ));
        }
        if let Some(t) = &uv {
            uvs.push(Vec2::new(vals[t[0]] as f32, vals[t[1]] as f32));
        }
        if !mesh.positions.last().is_some_and(|p| p.is_finite()) {
            return Err(src.error("vertex position overflows f32".into()));
        }
    }
    if nrm.is_some() {
        mesh.normals = Some(normals);
    }
    if uv.is_some() {
        mesh.uvs = Some(uvs);
    }
    Ok(())
}

fn read_faces<S: Source>(
    e: &Element,
    src: &mut S,
    vertex_count: usize,
    mesh: &mut TriangleMesh,
) -> Result<(), GeometryError> {
    let list_index = e
        .props
        .iter()
        .filter(|p| matches!(p, Property::List(..)))
        .position(|p| p.name() == "vertex_indices" || p.name() == "vertex_index")
        .ok_or_else(|| src.error("element `face` has no list property `vertex_indices`".into()))?;
    mesh.indices.reserve(e.count);
    let max_triangles = crate::limits::max_triangles();
    let mut vals = Vec::new();
    for _ in 0..e.count {
        src.begin_record()?;
        let lists = read_record(&e.props, src, &mut vals)?;
        let face = &lists[list_index];
        if face.len() < 3 {
            return Err(src.error(format!(
                "face has {} vertices, needs at least 3",
                face.len()
            )));
        }
        let mut idx = Vec::with_capacity(face.len());
        for &f in face {
            if f < 0.0 || f >= vertex_count as f64 {
                return Err(src.error(format!(
                    "face uses vertex {f} but there are only {vertex_count}"
                )));
            }
            idx.push(f as u32);
        }
        super::polygon::triangulate_convex(&idx, &mut mesh.indices);
        if mesh.indices.len() as u64 > max_triangles {
            return Err(src.error(format!(
                "more than {max_triangles} triangles, the limit for one mesh on this machine \
                 (its available memory at {} bytes a triangle)",
                crate::limits::BYTES_PER_TRIANGLE
            )));
        }
    }
    Ok(())
}
