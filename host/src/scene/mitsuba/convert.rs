//! From the expanded Mitsuba element tree ([`super::xml`]) to a spectrace [`SceneDescription`],
//! with a note for everything changed, approximated or dropped (one note per kind of element or
//! parameter, naming the elements it concerns). The table of what maps to what is in
//! `docs/mitsuba-import.md`.

use super::spectra;
use super::xml::Element;
use crate::scene::SceneError;
use crate::scene_file::description::{
    ItemDescription, ObjectDescription, OutputDescription, SceneDescription, TransformStep,
};
use glam::{DMat4, DVec3};
use ron::Value;
use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

/// A converted scene and what the conversion changed.
#[derive(Debug)]
pub struct Conversion {
    /// The spectrace scene. Relative file paths in it resolve against the XML file's directory.
    pub desc: SceneDescription,
    /// One line per kind of change, approximation or dropped element.
    pub notes: Vec<String>,
}

/// Segments of the polygons that stand in for Mitsuba's analytic disks and cylinders (their
/// area is then 1 − 2.5e-4 of the true one).
pub const ROUND_SEGMENTS: usize = 128;

// ---------------------------------------------------------------- RON value helpers

pub(crate) fn num(x: f64) -> Value {
    Value::Number(ron::Number::from(x))
}
fn text(s: &str) -> Value {
    Value::String(s.to_string())
}
fn seq(items: Vec<Value>) -> Value {
    Value::Seq(items)
}
fn v3(v: DVec3) -> Value {
    seq(vec![num(v.x), num(v.y), num(v.z)])
}
fn map(entries: Vec<(&str, Value)>) -> Value {
    let mut m = ron::Map::new();
    for (k, v) in entries {
        m.insert(text(k), v);
    }
    Value::Map(m)
}
fn table(t: &[(f64, f64)]) -> Value {
    seq(t.iter().map(|&(l, v)| seq(vec![num(l), num(v)])).collect())
}

/// Numbers in a Mitsuba attribute: separated by commas and/or white space.
/// The RGB triple of a converted reflectance: a number (grey) or `(rgb: [r, g, b])`.
fn rgb_of(v: &Value) -> Option<[f64; 3]> {
    let n = |v: &Value| match v {
        Value::Number(x) => Some(x.into_f64()),
        _ => None,
    };
    match v {
        Value::Number(_) => n(v).map(|g| [g; 3]),
        Value::Map(m) if m.len() == 1 => match m.iter().next() {
            Some((Value::String(k), Value::Seq(s))) if k == "rgb" && s.len() == 3 => {
                Some([n(&s[0])?, n(&s[1])?, n(&s[2])?])
            }
            _ => None,
        },
        _ => None,
    }
}

pub fn numbers(s: &str) -> Option<Vec<f64>> {
    s.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| t.parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect()
}

// ---------------------------------------------------------------- properties of one element

const PROPERTY_TAGS: &[&str] = &[
    "float",
    "integer",
    "boolean",
    "string",
    "rgb",
    "spectrum",
    "point",
    "vector",
    "transform",
    "texture",
    "ref",
    "bsdf",
    "emitter",
    "sensor",
    "film",
    "sampler",
    "rfilter",
    "shape",
    "integrator",
    "medium",
    "phase",
    "volume",
];

/// The children of one element, with a record of which were read (the rest is reported).
struct Props<'a> {
    el: &'a Element,
    used: RefCell<HashSet<usize>>,
}

impl<'a> Props<'a> {
    fn new(el: &'a Element) -> Self {
        Self {
            el,
            used: RefCell::new(HashSet::new()),
        }
    }

    /// The named property child (any tag).
    fn get(&self, name: &str) -> Option<&'a Element> {
        let (i, c) = self
            .el
            .children
            .iter()
            .enumerate()
            .find(|(_, c)| c.attr("name") == Some(name))?;
        self.used.borrow_mut().insert(i);
        Some(c)
    }

    fn has(&self, name: &str) -> bool {
        self.el
            .children
            .iter()
            .any(|c| c.attr("name") == Some(name))
    }

    fn value_of(&self, name: &str) -> Option<(&'a Element, &'a str)> {
        let c = self.get(name)?;
        Some((c, c.attr("value").unwrap_or("")))
    }

    fn float(&self, name: &str) -> Result<Option<f64>, SceneError> {
        match self.value_of(name) {
            None => Ok(None),
            Some((c, v)) => match c.tag.as_str() {
                "float" | "integer" => v
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .map(Some)
                    .ok_or_else(|| c.error(format!("`{name}`: `{v}` is not a finite number"))),
                _ => Err(c.error(format!("`{name}` should be a <float>"))),
            },
        }
    }

    fn float_or(&self, name: &str, default: f64) -> Result<f64, SceneError> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    fn int(&self, name: &str) -> Result<Option<i64>, SceneError> {
        match self.value_of(name) {
            None => Ok(None),
            Some((c, v)) => v
                .trim()
                .parse::<i64>()
                .map(Some)
                .map_err(|_| c.error(format!("`{name}`: `{v}` is not an integer"))),
        }
    }

    fn bool(&self, name: &str) -> Result<Option<bool>, SceneError> {
        match self.value_of(name) {
            None => Ok(None),
            Some((c, v)) => match v.trim() {
                "true" => Ok(Some(true)),
                "false" => Ok(Some(false)),
                _ => Err(c.error(format!("`{name}`: `{v}` is neither true nor false"))),
            },
        }
    }

    fn string(&self, name: &str) -> Option<&'a str> {
        self.value_of(name).map(|(_, v)| v)
    }

    fn point(&self, name: &str) -> Result<Option<DVec3>, SceneError> {
        let Some(c) = self.get(name) else {
            return Ok(None);
        };
        point_of(c).map(Some)
    }

    /// Unnamed (or any) nested objects with `tag`, `ref`s included.
    fn nested(&self, tag: &str) -> Vec<(usize, &'a Element)> {
        self.el
            .children
            .iter()
            .enumerate()
            .filter(|(_, c)| c.tag == tag || (c.tag == "ref" && tag == "ref"))
            .collect()
    }

    fn mark(&self, i: usize) {
        self.used.borrow_mut().insert(i);
    }

    /// Names of the children nobody read.
    fn unused(&self) -> Vec<String> {
        let used = self.used.borrow();
        self.el
            .children
            .iter()
            .enumerate()
            .filter(|(i, _)| !used.contains(i))
            .map(|(_, c)| match c.attr("name") {
                Some(n) => n.to_string(),
                None => format!(
                    "<{}{}>",
                    c.tag,
                    c.attr("type")
                        .map(|t| format!(" type={t}"))
                        .unwrap_or_default()
                ),
            })
            .collect()
    }
}

fn point_of(c: &Element) -> Result<DVec3, SceneError> {
    if let Some(v) = c.attr("value") {
        let n = numbers(v).ok_or_else(|| c.error(format!("`{v}` is not a list of numbers")))?;
        return match n.as_slice() {
            [x] => Ok(DVec3::splat(*x)),
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => Err(c.error(format!("`{v}`: expected 1 or 3 numbers"))),
        };
    }
    let f = |k: &str| -> Result<f64, SceneError> {
        match c.attr(k) {
            None => Ok(0.0),
            Some(s) => s
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| c.error(format!("`{k}`: `{s}` is not a number"))),
        }
    };
    Ok(DVec3::new(f("x")?, f("y")?, f("z")?))
}

// ---------------------------------------------------------------- transforms

/// A `<transform>` element as a matrix acting on column vectors; each operation is applied
/// after the ones before it (Mitsuba's order).
pub fn transform_of(t: &Element) -> Result<DMat4, SceneError> {
    let mut m = DMat4::IDENTITY;
    for op in &t.children {
        let attr3 = |default: f64| -> Result<DVec3, SceneError> {
            if let Some(v) = op.attr("value") {
                let n = numbers(v)
                    .ok_or_else(|| op.error(format!("`{v}` is not a list of numbers")))?;
                return match n.as_slice() {
                    [x] => Ok(DVec3::splat(*x)),
                    [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
                    _ => Err(op.error(format!("`{v}`: expected 1 or 3 numbers"))),
                };
            }
            let f = |k: &str| -> Result<f64, SceneError> {
                match op.attr(k) {
                    None => Ok(default),
                    Some(s) => s
                        .trim()
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| op.error(format!("`{k}`: `{s}` is not a number"))),
                }
            };
            Ok(DVec3::new(f("x")?, f("y")?, f("z")?))
        };
        let vec_attr = |k: &str| -> Result<Option<DVec3>, SceneError> {
            match op.attr(k) {
                None => Ok(None),
                Some(s) => match numbers(s).as_deref() {
                    Some([x, y, z]) => Ok(Some(DVec3::new(*x, *y, *z))),
                    _ => Err(op.error(format!("`{k}`: `{s}` is not three numbers"))),
                },
            }
        };
        let step = match op.tag.as_str() {
            "translate" => DMat4::from_translation(attr3(0.0)?),
            "scale" => {
                let s = attr3(1.0)?;
                if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 {
                    return Err(op.error("a scale by 0 flattens the shape"));
                }
                DMat4::from_scale(s)
            }
            "rotate" => {
                let axis = attr3(0.0)?;
                let angle: f64 = op
                    .attr("angle")
                    .and_then(|a| a.trim().parse().ok())
                    .ok_or_else(|| op.error("needs a numeric `angle` (degrees)"))?;
                if axis.length_squared() == 0.0 {
                    return Err(op.error("rotation axis is (0, 0, 0)"));
                }
                DMat4::from_axis_angle(axis.normalize(), angle.to_radians())
            }
            "matrix" => {
                let v = op.attr("value").unwrap_or("");
                let n = numbers(v)
                    .ok_or_else(|| op.error(format!("`{v}` is not a list of numbers")))?;
                match n.len() {
                    16 => DMat4::from_cols_slice(&n).transpose(),
                    9 => {
                        let r = |i: usize, j: usize| n[3 * i + j];
                        DMat4::from_cols_array_2d(&[
                            [r(0, 0), r(1, 0), r(2, 0), 0.0],
                            [r(0, 1), r(1, 1), r(2, 1), 0.0],
                            [r(0, 2), r(1, 2), r(2, 2), 0.0],
                            [0.0, 0.0, 0.0, 1.0],
                        ])
                    }
                    k => return Err(op.error(format!("a matrix has 16 (or 9) numbers, not {k}"))),
                }
            }
            "lookat" => {
                let origin = vec_attr("origin")?.ok_or_else(|| op.error("needs `origin`"))?;
                let target = vec_attr("target")?.ok_or_else(|| op.error("needs `target`"))?;
                let dir = (target - origin)
                    .try_normalize()
                    .ok_or_else(|| op.error("origin and target coincide"))?;
                let up = match vec_attr("up")? {
                    Some(u) => u,
                    None => dir.any_orthonormal_vector(),
                };
                let left = up
                    .cross(dir)
                    .try_normalize()
                    .ok_or_else(|| op.error("`up` is parallel to the view direction"))?;
                let new_up = dir.cross(left);
                DMat4::from_cols(
                    left.extend(0.0),
                    new_up.extend(0.0),
                    dir.extend(0.0),
                    origin.extend(1.0),
                )
            }
            other => return Err(op.error(format!("unknown transform operation <{other}>"))),
        };
        m = step * m;
    }
    if !m.is_finite() || m.determinant() == 0.0 {
        return Err(t.error("the transform is singular or not finite"));
    }
    Ok(m)
}

fn matrix_step(m: &DMat4) -> TransformStep {
    let r = m.transpose().to_cols_array_2d();
    TransformStep::Matrix(r)
}

// ---------------------------------------------------------------- the converter

#[derive(Default)]
struct Note {
    message: String,
    items: Vec<String>,
}

struct Converter<'a> {
    dir: PathBuf,
    /// Folders from `<path value>` elements, the last one first (Mitsuba prepends them).
    search: Vec<PathBuf>,
    ids: HashMap<&'a str, &'a Element>,
    desc: SceneDescription,
    notes: BTreeMap<String, Note>,
    used_names: HashSet<String>,
    /// Material already made for a bsdf element (by its address) or emitter key.
    made: HashMap<usize, String>,
    default_material: Option<String>,
}

impl<'a> Converter<'a> {
    fn note(&mut self, key: &str, message: impl Into<String>, item: impl Into<String>) {
        let n = self.notes.entry(key.to_string()).or_default();
        if n.message.is_empty() {
            n.message = message.into();
        }
        let item = item.into();
        if !item.is_empty() && !n.items.contains(&item) {
            n.items.push(item);
        }
    }

    fn finish(&mut self, p: &Props, what: &str, item: &str) {
        for name in p.unused() {
            self.note(
                &format!("{what}: parameter `{name}` ignored"),
                "spectrace has no equivalent; the parameter is dropped",
                item,
            );
        }
    }

    fn unique(&mut self, base: &str) -> String {
        let base = if base.is_empty() { "item" } else { base };
        let mut name = base.to_string();
        let mut k = 1;
        while !self.used_names.insert(name.clone()) {
            k += 1;
            name = format!("{base}.{k}");
        }
        name
    }

    fn resolve(&self, r: &'a Element) -> Result<&'a Element, SceneError> {
        if r.tag != "ref" {
            return Ok(r);
        }
        let id = r.attr("id").ok_or_else(|| r.error("<ref> needs `id`"))?;
        self.ids
            .get(id)
            .copied()
            .ok_or_else(|| r.error(format!("no element has id \"{id}\"")))
    }

    /// A file named in the scene: relative to the element's file, else to the `<path>` folders
    /// (the last declared first), else to the main scene's directory (Mitsuba's resolver);
    /// returned relative to the main directory when inside it.
    fn file(&self, el: &Element, name: &str) -> Result<String, SceneError> {
        let here = el.file.parent().unwrap_or(Path::new("."));
        let first = here.join(name);
        let candidates = std::iter::once(first.clone())
            .chain(self.search.iter().map(|d| d.join(name)))
            .chain(std::iter::once(self.dir.join(name)));
        let Some(p) = candidates.into_iter().find(|c| c.exists()) else {
            let tried: Vec<String> = self
                .search
                .iter()
                .chain(std::iter::once(&self.dir))
                .map(|d| d.join(name).display().to_string())
                .collect();
            return Err(el.error(format!(
                "file not found: {} (nor {})",
                first.display(),
                tried.join(", ")
            )));
        };
        Ok(match p.strip_prefix(&self.dir) {
            Ok(rel) => rel.to_string_lossy().into_owned(),
            Err(_) => p.to_string_lossy().into_owned(),
        })
    }

    // ------------------------------------------------------------ spectra

    /// A reflectance-like (unitless) colour parameter as a spectrace spectral value.
    fn reflectance(
        &mut self,
        p: &Props<'a>,
        name: &str,
        default: f64,
        item: &str,
    ) -> Result<Value, SceneError> {
        let Some(c) = p.get(name) else {
            return Ok(num(default));
        };
        let c = self.resolve(c)?;
        match c.tag.as_str() {
            "float" | "integer" => {
                let v = c
                    .attr("value")
                    .and_then(|v| v.trim().parse::<f64>().ok())
                    .ok_or_else(|| c.error("not a number"))?;
                Ok(num(v))
            }
            "rgb" => {
                let v = c
                    .attr("value")
                    .and_then(numbers)
                    .ok_or_else(|| c.error("not a list of numbers"))?;
                let rgb = match v.as_slice() {
                    [g] => [*g; 3],
                    [r, g, b] => [*r, *g, *b],
                    _ => return Err(c.error("an rgb value has 1 or 3 numbers")),
                };
                if rgb.iter().any(|&x| !(0.0..=1.0).contains(&x)) && name != "eta" && name != "k" {
                    self.note(
                        "rgb reflectance outside [0, 1]",
                        "clamped to [0, 1] by the uplift (Mitsuba keeps it)",
                        item,
                    );
                }
                Ok(map(vec![(
                    "rgb",
                    seq(rgb.iter().map(|&x| num(x)).collect()),
                )]))
            }
            "spectrum" => {
                let t = self.spectrum_pairs(c)?;
                match t {
                    SpectrumValue::Uniform(v) => Ok(num(v)),
                    SpectrumValue::Pairs(t) => Ok(table(&t)),
                }
            }
            "texture" => self.texture(c, item),
            other => Err(c.error(format!("`{name}` cannot be a <{other}>"))),
        }
    }

    fn texture(&mut self, c: &'a Element, item: &str) -> Result<Value, SceneError> {
        let p = Props::new(c);
        match c.attr("type").unwrap_or("") {
            "bitmap" => {
                let file = p
                    .string("filename")
                    .ok_or_else(|| c.error("bitmap needs `filename`"))?;
                let file = self.file(c, file)?;
                let raw = p.bool("raw")?.unwrap_or(false);
                let filter = match p.string("filter_type").unwrap_or("bilinear") {
                    "nearest" => "nearest",
                    _ => "bilinear",
                };
                let mut entries = vec![("file", text(&file)), ("filter", text(filter))];
                let lower = file.to_ascii_lowercase();
                let hdr = lower.ends_with(".exr") || lower.ends_with(".hdr");
                if raw && !hdr {
                    entries.push(("encoding", text("linear")));
                }
                if let Some(t) = p.get("to_uv") {
                    let m = transform_of(t)?;
                    if m.x_axis.y.abs() > 1e-12 || m.y_axis.x.abs() > 1e-12 {
                        self.note(
                            "texture to_uv rotation",
                            "only the scale and offset of `to_uv` are kept",
                            item,
                        );
                    }
                    // Mitsuba: row from the top = s_v·v + o_v, with v flipped on loading
                    // as above; spectrace: row from the top = 1 − (s_v·v' + o_v') with
                    // v' = 1 − v, so o_v' = 1 − s_v − o_v (s_v unchanged).
                    let (sv, ov) = (m.y_axis.y, m.w_axis.y);
                    entries.push(("uv_scale", seq(vec![num(m.x_axis.x), num(sv)])));
                    entries.push(("uv_offset", seq(vec![num(m.w_axis.x), num(1.0 - sv - ov)])));
                }
                if let Some(w) = p.string("wrap_mode") {
                    if w != "repeat" {
                        self.note("texture wrap_mode", format!("`{w}` becomes repeat"), item);
                    }
                }
                self.finish(&p, "texture bitmap", item);
                Ok(map(vec![("texture", map(entries))]))
            }
            "checkerboard" => {
                let a = self.reflectance(&p, "color0", 0.4, item)?;
                let b = self.reflectance(&p, "color1", 0.2, item)?;
                // The two colours cover equal areas: their mean keeps the surface's mean
                // reflectance (what an image's mean depends on) where color0 alone would not.
                match (rgb_of(&a), rgb_of(&b)) {
                    (Some(x), Some(y)) => {
                        self.note(
                            "texture checkerboard",
                            "not supported: the mean of color0 and color1 is used as a constant",
                            item,
                        );
                        let m: Vec<Value> = (0..3).map(|i| num(0.5 * (x[i] + y[i]))).collect();
                        Ok(if m[0] == m[1] && m[1] == m[2] {
                            m[0].clone()
                        } else {
                            map(vec![("rgb", seq(m))])
                        })
                    }
                    _ => {
                        self.note(
                            "texture checkerboard",
                            "not supported: its color0 is used as a constant (color1 is a spectrum or texture)",
                            item,
                        );
                        Ok(a)
                    }
                }
            }
            other => {
                self.note(
                    &format!("texture {other}"),
                    "not supported: a constant 0.5 stands in",
                    item,
                );
                Ok(num(0.5))
            }
        }
    }

    fn spectrum_pairs(&mut self, c: &Element) -> Result<SpectrumValue, SceneError> {
        if let Some(f) = c.attr("filename") {
            let path = self.file(c, f)?;
            let full = if Path::new(&path).is_absolute() {
                PathBuf::from(&path)
            } else {
                self.dir.join(&path)
            };
            let text = crate::limits::read_text_limited(
                &full,
                crate::limits::TABLE_FILE_MAX_BYTES,
                "spectrum file",
            )
            .map_err(|e| c.error(format!("{}: {e}", full.display())))?;
            let mut t = Vec::new();
            for (i, line) in text.lines().enumerate() {
                let line = line.trim();
                if line.is_empty() || line.starts_with('#') {
                    continue;
                }
                match numbers(line).as_deref() {
                    Some([l, v]) => t.push((*l, *v)),
                    _ => {
                        return Err(c.error(format!(
                            "{} line {}: expected `wavelength value`",
                            full.display(),
                            i + 1
                        )))
                    }
                }
            }
            return pairs_checked(c, t);
        }
        if let Some(kind) = c.attr("type") {
            let p = Props::new(c);
            return match kind {
                "blackbody" => {
                    let t = p
                        .float("temperature")?
                        .ok_or_else(|| c.error("blackbody needs `temperature`"))?;
                    if !(t > 0.0) {
                        return Err(c.error("temperature must be > 0 K"));
                    }
                    Ok(SpectrumValue::Pairs(
                        spectra::grid()
                            .map(|l| (l, spectra::planck(t, l)))
                            .collect(),
                    ))
                }
                "d65" => Ok(SpectrumValue::Pairs(
                    spectra::grid().map(|l| (l, spectra::d65_unit(l))).collect(),
                )),
                other => Err(c.error(format!(
                    "spectrum type `{other}` is not supported (blackbody, d65 are)"
                ))),
            };
        }
        let v = c
            .attr("value")
            .ok_or_else(|| c.error("<spectrum> needs `value` or `filename`"))?;
        if !v.contains(':') {
            let x = v
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| c.error(format!("`{v}` is not a number")))?;
            return Ok(SpectrumValue::Uniform(x));
        }
        let mut t = Vec::new();
        for part in v.split(',') {
            let part = part.trim();
            if part.is_empty() {
                continue;
            }
            let (l, x) = part
                .split_once(':')
                .ok_or_else(|| c.error(format!("`{part}` is not `wavelength:value`")))?;
            let l = l.trim().parse::<f64>().ok().filter(|x| x.is_finite());
            let x = x.trim().parse::<f64>().ok().filter(|x| x.is_finite());
            match (l, x) {
                (Some(l), Some(x)) => t.push((l, x)),
                _ => return Err(c.error(format!("`{part}` is not `wavelength:value`"))),
            }
        }
        pairs_checked(c, t)
    }

    /// An emission parameter as an absolute `(nm, value)` table (see [`spectra`]).
    fn emission(
        &mut self,
        p: &Props<'a>,
        name: &str,
        item: &str,
    ) -> Result<Vec<(f64, f64)>, SceneError> {
        let Some(c) = p.get(name) else {
            // Mitsuba's default emission is 1 (a D65' spectrum in the spectral variants).
            return Ok(spectra::grid().map(|l| (l, spectra::d65_unit(l))).collect());
        };
        let c = self.resolve(c)?;
        let t: Vec<(f64, f64)> = match c.tag.as_str() {
            "float" | "integer" => {
                let v = c
                    .attr("value")
                    .and_then(|v| v.trim().parse::<f64>().ok())
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| c.error("not a number"))?;
                spectra::grid()
                    .map(|l| (l, v * spectra::d65_unit(l)))
                    .collect()
            }
            "rgb" => {
                let v = c
                    .attr("value")
                    .and_then(numbers)
                    .ok_or_else(|| c.error("not a list of numbers"))?;
                let rgb = match v.as_slice() {
                    [g] => [*g; 3],
                    [r, g, b] => [*r, *g, *b],
                    _ => return Err(c.error("an rgb value has 1 or 3 numbers")),
                };
                if rgb.iter().any(|&x| x < 0.0) {
                    return Err(c.error("negative emission"));
                }
                spectra::rgb_emission_table(rgb)
            }
            "spectrum" => match self.spectrum_pairs(c)? {
                SpectrumValue::Uniform(v) => spectra::grid().map(|l| (l, v)).collect(),
                SpectrumValue::Pairs(t) => spectra::grid()
                    .map(|l| (l, spectra::interpolate(&t, l)))
                    .collect(),
            },
            "texture" => {
                self.note(
                    "textured emission",
                    "not supported: a uniform radiance of 1 (D65') stands in",
                    item,
                );
                spectra::grid().map(|l| (l, spectra::d65_unit(l))).collect()
            }
            other => return Err(c.error(format!("`{name}` cannot be a <{other}>"))),
        };
        if t.iter().any(|(_, v)| *v < 0.0) {
            return Err(c.error(format!("`{name}` is negative somewhere")));
        }
        Ok(t)
    }

    // ------------------------------------------------------------ BSDFs

    /// The material for a bsdf element (made once per element); None for `null`.
    fn material(&mut self, el: &'a Element, suggested: &str) -> Result<Option<String>, SceneError> {
        let el = self.resolve(el)?;
        let key = el as *const Element as usize;
        if let Some(n) = self.made.get(&key) {
            return Ok(Some(n.clone()));
        }
        let base = el.attr("id").unwrap_or(suggested).to_string();
        let Some((type_name, params)) = self.bsdf(el, &base)? else {
            return Ok(None);
        };
        let name = self.unique(&base);
        self.desc.materials.push(ItemDescription {
            name: name.clone(),
            type_name,
            params,
        });
        self.made.insert(key, name.clone());
        Ok(Some(name))
    }

    fn default_material(&mut self) -> String {
        if let Some(n) = &self.default_material {
            return n.clone();
        }
        let name = self.unique("mitsuba-default-diffuse");
        self.desc.materials.push(ItemDescription {
            name: name.clone(),
            type_name: "lambertian".into(),
            params: map(vec![("reflectance", num(0.5))]),
        });
        self.default_material = Some(name.clone());
        name
    }

    fn ior(&mut self, p: &Props<'a>, name: &str, default: f64) -> Result<f64, SceneError> {
        let Some(c) = p.get(name) else {
            return Ok(default);
        };
        let v = c.attr("value").unwrap_or("");
        if c.tag == "float" || c.tag == "integer" {
            return v
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x > 0.0)
                .ok_or_else(|| c.error(format!("`{name}`: `{v}` is not a positive number")));
        }
        named_ior(v).ok_or_else(|| {
            c.error(format!(
                "`{name}`: unknown material `{v}` (Mitsuba's names: {})",
                IOR_TABLE
                    .iter()
                    .map(|(n, _)| *n)
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
    }

    fn alpha(&mut self, p: &Props<'a>, kind: &str, item: &str) -> Result<f64, SceneError> {
        let dist = p.string("distribution").unwrap_or("beckmann");
        if dist != "ggx" {
            self.note(
                &format!("{kind}: {dist} distribution"),
                "spectrace's microfacets are GGX: the same α is used with GGX",
                item,
            );
        }
        self.roughness_alpha(p, kind, item)
    }

    /// The isotropic α of a rough BSDF (`alpha`, or `alpha_u`, `alpha_v`; Mitsuba's default 0.1).
    fn roughness_alpha(
        &mut self,
        p: &Props<'a>,
        kind: &str,
        item: &str,
    ) -> Result<f64, SceneError> {
        let a = p.float("alpha")?;
        let au = p.float("alpha_u")?;
        let av = p.float("alpha_v")?;
        // Sampling visible normals is how Mitsuba samples, not what it renders.
        let _ = p.get("sample_visible");
        Ok(match (a, au, av) {
            (Some(a), _, _) => a,
            (None, Some(u), Some(v)) => {
                if (u - v).abs() > 1e-9 {
                    self.note(
                        &format!("{kind}: anisotropic roughness"),
                        "α_u ≠ α_v: the isotropic α = √(α_u·α_v) is used",
                        item,
                    );
                }
                (u * v).sqrt()
            }
            _ => 0.1,
        })
    }

    fn conductor_params(
        &mut self,
        p: &Props<'a>,
        kind: &str,
        item: &str,
    ) -> Result<Option<Vec<(&'static str, Value)>>, SceneError> {
        if p.has("eta") || p.has("k") {
            let eta = self.reflectance(p, "eta", 0.0, item)?;
            let k = self.reflectance(p, "k", 1.0, item)?;
            let as_table = |v: &Value| -> Option<Value> {
                match v {
                    Value::Number(n) => {
                        let x = n.into_f64();
                        Some(table(&[(360.0, x), (830.0, x)]))
                    }
                    Value::Seq(_) => Some(v.clone()),
                    // An rgb η or k: its three values placed at the sRGB primaries' dominant
                    // wavelengths (blue 465, green 550, red 610 nm), flat beyond them.
                    Value::Map(m) => {
                        let Some((_, Value::Seq(c))) = m.iter().find(|(k, _)| **k == text("rgb"))
                        else {
                            return None;
                        };
                        let c: Vec<f64> = c
                            .iter()
                            .filter_map(|x| {
                                if let Value::Number(n) = x {
                                    Some(n.into_f64())
                                } else {
                                    None
                                }
                            })
                            .collect();
                        (c.len() == 3).then(|| {
                            table(&[
                                (360.0, c[2]),
                                (465.0, c[2]),
                                (550.0, c[1]),
                                (610.0, c[0]),
                                (830.0, c[0]),
                            ])
                        })
                    }
                    _ => None,
                }
            };
            if p.get("eta").is_some_and(|e| e.tag == "rgb")
                || p.get("k").is_some_and(|e| e.tag == "rgb")
            {
                self.note(&format!("{kind}: rgb eta/k"), "its three values are placed at 465, 550 and 610 nm and interpolated (Mitsuba uplifts them to smooth spectra)", item);
            }
            match (as_table(&eta), as_table(&k)) {
                (Some(e), Some(k)) => return Ok(Some(vec![("n", e), ("k", k)])),
                _ => {
                    self.note(
                        &format!("{kind}: rgb eta/k"),
                        "an rgb η or k is not supported: aluminium stands in",
                        item,
                    );
                    return Ok(Some(vec![("metal", text("aluminium"))]));
                }
            }
        }
        let m = p.string("material").unwrap_or("none");
        let metal = match m {
            "Au" => "gold",
            "Ag" => "silver",
            "Cu" => "copper",
            "Al" => "aluminium",
            "none" => return Ok(None),
            other => {
                self.note(&format!("{kind}: metal {other}"), format!("spectrace has measured gold, silver, copper and aluminium: aluminium stands in for `{other}`"), item);
                "aluminium"
            }
        };
        Ok(Some(vec![("metal", text(metal))]))
    }

    fn bsdf(&mut self, el: &'a Element, item: &str) -> Result<Option<(String, Value)>, SceneError> {
        let kind = el.attr("type").unwrap_or("");
        let p = Props::new(el);
        let nested = |this: &mut Self, p: &Props<'a>| -> Result<Option<&'a Element>, SceneError> {
            let list = p
                .nested("bsdf")
                .into_iter()
                .chain(p.nested("ref"))
                .collect::<Vec<_>>();
            let mut found = None;
            for (i, c) in list {
                let r = this.resolve(c)?;
                if r.tag == "bsdf" {
                    p.mark(i);
                    if found.is_none() {
                        found = Some(r);
                    }
                }
            }
            Ok(found)
        };
        let out = match kind {
            "diffuse" => {
                let r = self.reflectance(&p, "reflectance", 0.5, item)?;
                ("lambertian".to_string(), map(vec![("reflectance", r)]))
            }
            "dielectric" | "thindielectric" | "roughdielectric" => {
                let int = self.ior(&p, "int_ior", 1.5046)?;
                let ext = self.ior(&p, "ext_ior", 1.000277)?;
                for s in ["specular_reflectance", "specular_transmittance"] {
                    if p.get(s).is_some() {
                        self.note(
                            &format!("{kind}: {s}"),
                            "dropped (spectrace's dielectrics follow Fresnel only)",
                            item,
                        );
                    }
                }
                let eta = int / ext;
                match kind {
                    "dielectric" => ("dielectric".into(), map(vec![("ior", num(eta))])),
                    "thindielectric" => {
                        self.note("thindielectric", "a free thin_film of the same index, 0.1 mm thick: its fringes are far finer than a wavelength sample, so the image equals the incoherent thin sheet's", item);
                        (
                            "thin_film".into(),
                            map(vec![
                                ("thickness_nm", num(100_000.0)),
                                ("film", num(eta)),
                                ("base", num(1.0)),
                            ]),
                        )
                    }
                    _ => {
                        let a = self.alpha(&p, kind, item)?;
                        (
                            "rough_dielectric".into(),
                            map(vec![("ior", num(eta)), ("alpha", num(a))]),
                        )
                    }
                }
            }
            "conductor" | "roughconductor" => {
                if p.get("specular_reflectance").is_some() {
                    self.note(&format!("{kind}: specular_reflectance"), "dropped", item);
                }
                let a = if kind == "roughconductor" {
                    self.alpha(&p, kind, item)?
                } else {
                    0.0
                };
                match self.conductor_params(&p, kind, item)? {
                    None if a == 0.0 => ("mirror".into(), map(vec![("reflectance", num(1.0))])),
                    None => (
                        "conductor".into(),
                        map(vec![
                            ("n", table(&[(360.0, 0.0), (830.0, 0.0)])),
                            ("k", table(&[(360.0, 1.0), (830.0, 1.0)])),
                            ("alpha", num(a)),
                        ]),
                    ),
                    Some(mut e) => {
                        e.push(("alpha", num(a)));
                        ("conductor".into(), map(e))
                    }
                }
            }
            "plastic" | "roughplastic" => {
                let r = self.reflectance(&p, "diffuse_reflectance", 0.5, item)?;
                // Mitsuba's defaults: polypropylene in air.
                let int = self.ior(&p, "int_ior", 1.49)?;
                let ext = self.ior(&p, "ext_ior", 1.000277)?;
                let mut e = vec![
                    ("diffuse_reflectance", r),
                    ("int_ior", num(int)),
                    ("ext_ior", num(ext)),
                ];
                if p.has("specular_reflectance") {
                    let s = self.reflectance(&p, "specular_reflectance", 1.0, item)?;
                    e.push(("specular_reflectance", s));
                }
                if let Some(b) = p.bool("nonlinear")? {
                    e.push(("nonlinear", Value::Bool(b)));
                }
                if kind == "plastic" {
                    ("plastic".into(), map(e))
                } else {
                    // spectrace's rough_plastic has both of Mitsuba's distributions.
                    let dist = match p.string("distribution").unwrap_or("beckmann") {
                        "ggx" => "ggx",
                        "beckmann" => "beckmann",
                        other => return Err(el.error(format!("unknown distribution `{other}`"))),
                    };
                    e.push(("alpha", num(self.roughness_alpha(&p, kind, item)?)));
                    e.push(("distribution", text(dist)));
                    ("rough_plastic".into(), map(e))
                }
            }
            "principled" | "principledthin" => {
                let r = self.reflectance(&p, "base_color", 0.5, item)?;
                for c in &el.children {
                    if let Some(n) = c.attr("name") {
                        let _ = p.get(n);
                    }
                }
                self.note(kind, "not supported: a lambertian of its base_color", item);
                ("lambertian".into(), map(vec![("reflectance", r)]))
            }
            "twosided" => {
                let list: Vec<_> = p
                    .nested("bsdf")
                    .into_iter()
                    .chain(p.nested("ref"))
                    .collect();
                if list.len() > 1 {
                    self.note(
                        "twosided with two different bsdfs",
                        "the front one is used on both sides",
                        item,
                    );
                }
                let inner =
                    nested(self, &p)?.ok_or_else(|| el.error("twosided needs a nested bsdf"))?;
                if !matches!(inner.attr("type"), Some("diffuse")) {
                    self.note(
                        "twosided",
                        "spectrace's surfaces are all two-sided already: the nested bsdf is used",
                        item,
                    );
                }
                self.finish(&p, "bsdf twosided", item);
                return self.bsdf(inner, item);
            }
            "mask" | "bumpmap" | "normalmap" | "blendbsdf" => {
                let what = match kind {
                    "mask" => "opacity masks are not supported: the surface is fully opaque (the nested bsdf)",
                    "bumpmap" => "bump mapping is dropped: the nested bsdf on the flat surface",
                    "normalmap" => "normal mapping is dropped: the nested bsdf on the mesh's own normals",
                    _ => "blending is not supported: the first nested bsdf is used",
                };
                for c in &el.children {
                    if let Some(n) = c.attr("name") {
                        let _ = p.get(n);
                    }
                    if c.tag == "texture" {
                        if let Some(i) = el.children.iter().position(|x| std::ptr::eq(x, c)) {
                            p.mark(i);
                        }
                    }
                }
                self.note(kind, what, item);
                let inner = nested(self, &p)?
                    .ok_or_else(|| el.error(format!("{kind} needs a nested bsdf")))?;
                self.finish(&p, &format!("bsdf {kind}"), item);
                return self.bsdf(inner, item);
            }
            "null" => {
                self.note(
                    "bsdf null",
                    "an invisible surface (a medium boundary): the shape is left out",
                    item,
                );
                return Ok(None);
            }
            other => {
                for c in &el.children {
                    if let Some(n) = c.attr("name") {
                        let _ = p.get(n);
                    }
                }
                self.note(
                    &format!("bsdf {other}"),
                    "not supported: a lambertian of reflectance 0.5 stands in",
                    item,
                );
                ("lambertian".into(), map(vec![("reflectance", num(0.5))]))
            }
        };
        self.finish(&p, &format!("bsdf {kind}"), item);
        Ok(Some(out))
    }

    // ------------------------------------------------------------ shapes

    fn shape(&mut self, el: &'a Element, parent: &DMat4, prefix: &str) -> Result<(), SceneError> {
        let kind = el.attr("type").unwrap_or("");
        let p = Props::new(el);
        let base = format!("{prefix}{}", el.attr("id").unwrap_or(kind));
        let m_local = match p.get("to_world") {
            Some(t) => transform_of(t)?,
            None => DMat4::IDENTITY,
        };
        let m = *parent * m_local;
        if kind == "shapegroup" {
            if prefix.is_empty() && el.attr("id").is_none() {
                return Err(el.error("a shapegroup needs an `id`"));
            }
            // Emitted by the instances that refer to it.
            return Ok(());
        }
        if kind == "instance" {
            return self.instance(el, &p, &m, &base);
        }
        let Some((type_name, params)) = self.shape_geometry(el, &p, kind, &base)? else {
            return Ok(());
        };
        let Some(material) = self.shape_material(&p, &base)? else {
            self.finish(&p, &format!("shape {kind}"), &base);
            return Ok(());
        };
        let flip = p.bool("flip_normals")?.unwrap_or(false);
        let own_material = !p.nested("emitter").is_empty();
        let (type_name, params, material) = self.analytic_uvs(
            (kind, flip),
            (type_name, params),
            material,
            own_material,
            &base,
        )?;
        self.drop_media(el, &p, &base);
        self.finish(&p, &format!("shape {kind}"), &base);
        let name = self.unique(&base);
        let transform = if m == DMat4::IDENTITY {
            vec![]
        } else {
            vec![matrix_step(&m)]
        };
        self.desc.objects.push(ObjectDescription {
            name,
            type_name,
            material,
            params,
            transform,
        });
        Ok(())
    }

    /// A shape instance: the shapegroup it refers to, flattened with the transform `m`.
    fn instance(
        &mut self,
        el: &'a Element,
        p: &Props<'a>,
        m: &DMat4,
        base: &str,
    ) -> Result<(), SceneError> {
        let group = p
            .nested("ref")
            .first()
            .map(|(i, r)| {
                p.mark(*i);
                *r
            })
            .or_else(|| {
                p.nested("shape").first().map(|(i, r)| {
                    p.mark(*i);
                    *r
                })
            })
            .ok_or_else(|| el.error("an instance needs a <ref> to a shapegroup"))?;
        let group = self.resolve(group)?;
        if group.attr("type") != Some("shapegroup") {
            return Err(el.error("an instance refers to a shapegroup"));
        }
        self.finish(p, "shape instance", base);
        self.note(
            "shape instance",
            "flattened: each instance's shapes are copied with the instance's transform",
            base,
        );
        for c in group.children.iter().filter(|c| c.tag == "shape") {
            self.shape(c, m, &format!("{base}/"))?;
        }
        Ok(())
    }

    /// The spectrace shape type and parameters of shape `kind`; `None` when spectrace has no
    /// equivalent (noted and left out).
    fn shape_geometry(
        &mut self,
        el: &'a Element,
        p: &Props<'a>,
        kind: &str,
        base: &str,
    ) -> Result<Option<(String, Value)>, SceneError> {
        let flip = p.bool("flip_normals")?.unwrap_or(false);
        Ok(Some(match kind {
            "obj" | "ply" => self.mesh_file(el, p, kind, flip, base)?,
            "serialized" => self.serialized(el, p, flip)?,
            "rectangle" => {
                // (s, t) = ((x + 1)/2, (y + 1)/2) as Mitsuba's uv; flipped: (s, 1 − t), the
                // normal −z (see `analytic_uvs`).
                let (c, e1) = if flip {
                    (DVec3::new(-1.0, 1.0, 0.0), DVec3::Y * -2.0)
                } else {
                    (DVec3::new(-1.0, -1.0, 0.0), DVec3::Y * 2.0)
                };
                (
                    "quad".into(),
                    map(vec![
                        ("corner", v3(c)),
                        ("edge0", v3(DVec3::X * 2.0)),
                        ("edge1", v3(e1)),
                    ]),
                )
            }
            "cube" => ("mesh".into(), mesh_value(&cube_mesh(flip))),
            "sphere" => {
                let c = p.point("center")?.unwrap_or(DVec3::ZERO);
                let r = p.float_or("radius", 1.0)?;
                if !(r > 0.0) {
                    return Err(el.error("sphere radius must be > 0"));
                }
                if flip {
                    self.note(
                        "shape sphere flip_normals",
                        "dropped: spectrace's sphere normals point outwards",
                        base,
                    );
                }
                (
                    "sphere".into(),
                    map(vec![("center", v3(c)), ("radius", num(r))]),
                )
            }
            "disk" => {
                self.note(
                    "shape disk",
                    format!(
                        "tessellated into a {ROUND_SEGMENTS}-gon of 16 rings (area 2.5e-4 smaller)"
                    ),
                    base,
                );
                ("mesh".into(), mesh_value(&disk_mesh(flip)))
            }
            "cylinder" => {
                let p0 = p.point("p0")?.unwrap_or(DVec3::ZERO);
                let p1 = p.point("p1")?.unwrap_or(DVec3::Z);
                let r = p.float_or("radius", 1.0)?;
                if !(r > 0.0) || p0 == p1 {
                    return Err(el.error("cylinder needs radius > 0 and p0 ≠ p1"));
                }
                self.note(
                    "shape cylinder",
                    format!("tessellated into {ROUND_SEGMENTS} flat sides with smooth normals"),
                    base,
                );
                ("mesh".into(), mesh_value(&cylinder_mesh(p0, p1, r, flip)))
            }
            other => {
                for c in &el.children {
                    if let Some(n) = c.attr("name") {
                        let _ = p.get(n);
                    }
                }
                self.note(&format!("shape {other}"), "not supported: left out", base);
                return Ok(None);
            }
        }))
    }

    /// An `obj` or `ply` shape: the file, read by spectrace's own loader.
    fn mesh_file(
        &mut self,
        el: &'a Element,
        p: &Props<'a>,
        kind: &str,
        flip: bool,
        base: &str,
    ) -> Result<(String, Value), SceneError> {
        let f = p
            .string("filename")
            .ok_or_else(|| el.error(format!("{kind} needs `filename`")))?;
        let f = self.file(el, f)?;
        if p.bool("face_normals")?.unwrap_or(false) {
            self.note("shape face_normals", "the file's vertex normals are used anyway (spectrace interpolates them when the file has them)", base);
        }
        // Mitsuba's bitmap puts v = 0 at the image's top row and reads a file's uvs as
        // stored, except OBJ's, which it flips (`flip_tex_coords`, default true);
        // spectrace puts v = 0 at the bottom row. So a PLY, or an OBJ read unflipped,
        // gets `flip_v`.
        let flip_v = kind == "ply" || !p.bool("flip_tex_coords")?.unwrap_or(true);
        if flip {
            self.note(
                "shape flip_normals on obj/ply",
                "dropped: the file's winding is kept (it matters for one-sided emitters)",
                base,
            );
        }
        let mut entries = vec![("file", text(&f))];
        if flip_v {
            entries.push(("flip_v", Value::Bool(true)));
        }
        Ok((kind.to_string(), map(entries)))
    }

    /// A `serialized` shape: the mesh is read here and written into the scene.
    fn serialized(
        &mut self,
        el: &'a Element,
        p: &Props<'a>,
        flip: bool,
    ) -> Result<(String, Value), SceneError> {
        let f = p
            .string("filename")
            .ok_or_else(|| el.error("serialized needs `filename`"))?;
        let rel = self.file(el, f)?;
        let full = if Path::new(&rel).is_absolute() {
            PathBuf::from(&rel)
        } else {
            self.dir.join(&rel)
        };
        let index = p.int("shape_index")?.unwrap_or(0);
        if index < 0 {
            return Err(el.error("shape_index < 0"));
        }
        let max = crate::limits::mesh_file_max_bytes();
        let bytes = crate::limits::read_limited(&full, max, "mesh file")
            .map_err(|e| el.error(format!("{}: {e}", full.display())))?;
        let s = super::serialized::parse_serialized(&bytes, index as usize)
            .map_err(|e| el.error(format!("{}: {e}", full.display())))?;
        let mut mesh = s.mesh;
        // Mitsuba reads serialized uvs with v = 0 at the image's top row; spectrace's
        // v = 0 is the bottom row.
        if let Some(uvs) = &mut mesh.uvs {
            for t in uvs {
                t.y = 1.0 - t.y;
            }
        }
        if p.bool("face_normals")?.unwrap_or(false) {
            mesh.normals = None;
        }
        if flip {
            for t in &mut mesh.indices {
                t.swap(1, 2);
            }
            if let Some(n) = &mut mesh.normals {
                for v in n {
                    *v = -*v;
                }
            }
        }
        Ok(("mesh".into(), mesh_value(&mesh)))
    }

    /// The shape's material: its area emitter if it has one (an emitter wins: spectrace's
    /// emissive surfaces do not reflect), else its bsdf, else the default material. `None`
    /// when its bsdf has no spectrace equivalent (the shape is then left out).
    fn shape_material(&mut self, p: &Props<'a>, base: &str) -> Result<Option<String>, SceneError> {
        let mut bsdf_el = None;
        for (i, c) in p.nested("bsdf").into_iter().chain(p.nested("ref")) {
            let r = self.resolve(c)?;
            if r.tag == "bsdf" {
                p.mark(i);
                bsdf_el = Some(r);
            }
        }
        let emitters = p.nested("emitter");
        let material = if let Some((i, em)) = emitters.first() {
            p.mark(*i);
            Some(self.area_emitter(em, bsdf_el.is_some(), base)?)
        } else if let Some(b) = bsdf_el {
            match self.material(b, &format!("{base}.bsdf"))? {
                Some(n) => Some(n),
                None => return Ok(None),
            }
        } else {
            None
        };
        Ok(Some(match material {
            Some(m) => m,
            None => self.default_material(),
        }))
    }

    /// The emissive material of an `area` emitter attached to a shape (`has_bsdf`: the shape
    /// also has a bsdf, which is dropped with a note).
    fn area_emitter(
        &mut self,
        em: &'a Element,
        has_bsdf: bool,
        base: &str,
    ) -> Result<String, SceneError> {
        if em.attr("type") != Some("area") {
            return Err(em.error("only an `area` emitter can be attached to a shape"));
        }
        let ep = Props::new(em);
        // A bitmap radiance becomes an emission texture (RGB by the illuminant method, as
        // Mitsuba 3's spectral variants read it); anything else a uniform spectrum.
        let textured = match ep.get("radiance") {
            Some(c) => {
                let c = self.resolve(c)?;
                (c.tag == "texture" && c.attr("type") == Some("bitmap")).then_some(c)
            }
            None => None,
        };
        let radiance = match textured {
            Some(c) => self.texture(c, base)?,
            None => table(&self.emission(&ep, "radiance", base)?),
        };
        self.finish(&ep, "emitter area", base);
        let name = self.unique(&format!("{base}.emitter"));
        self.desc.materials.push(ItemDescription {
            name: name.clone(),
            type_name: "emissive".into(),
            params: map(vec![
                ("radiance", radiance),
                ("two_sided", Value::Bool(false)),
            ]),
        });
        if has_bsdf {
            self.note(
                "bsdf of an emitting shape",
                "dropped: spectrace's emissive surfaces emit and do not reflect",
                base,
            );
        }
        Ok(name)
    }

    /// Participating media (nested, or `interior`/`exterior` refs) are dropped with a note.
    fn drop_media(&mut self, el: &'a Element, p: &Props<'a>, base: &str) {
        for (i, c) in el.children.iter().enumerate() {
            if c.tag == "medium"
                || (c.tag == "ref" && matches!(c.attr("name"), Some("interior") | Some("exterior")))
            {
                p.mark(i);
                self.note(
                    "media",
                    "participating media are not supported: dropped",
                    base,
                );
            }
        }
    }

    /// Texture coordinates of Mitsuba's analytic shapes where a texture shows them
    /// (docs/mitsuba-import.md, "Texture coordinates"): Mitsuba's `rectangle` has uv
    /// `((x + 1)/2, (y + 1)/2)`, which the quad's `(s, t)` already is, but its bitmap reads v = 0
    /// on the image's top row: the quad's textures get v flipped (`flip_texture_v`), in a copy
    /// of a shared material (a rectangle with `flip_normals` runs its `t` the other way, which
    /// is the flip already). Mitsuba's `sphere` has `u = φ/2π` (φ = atan2(y, x)) and `v = θ/π`
    /// (θ from its local +z), which spectrace's sphere (pole +y) cannot carry: a sphere whose
    /// material has a texture becomes a mesh with those uvs (`uv_sphere_mesh`). `cube` and
    /// `disk` are meshes with Mitsuba's uvs already (`cube_mesh`, `disk_mesh`).
    fn analytic_uvs(
        &mut self,
        (kind, flip): (&str, bool),
        (type_name, params): (String, Value),
        material: String,
        own_material: bool,
        item: &str,
    ) -> Result<(String, Value, String), SceneError> {
        let textured = self
            .desc
            .materials
            .iter()
            .any(|m| m.name == material && has_texture(&m.params));
        if !textured {
            return Ok((type_name, params, material));
        }
        match kind {
            "rectangle" if !flip => {
                let material = if own_material {
                    if let Some(m) = self.desc.materials.iter_mut().find(|m| m.name == material) {
                        flip_texture_v(&mut m.params);
                    }
                    material
                } else {
                    let name = format!("{material}.rectangle_uv");
                    let exists = self.desc.materials.iter().any(|m| m.name == name);
                    let original = self.desc.materials.iter().find(|m| m.name == material);
                    if let (false, Some(original)) = (exists, original) {
                        let mut copy = original.clone();
                        copy.name = name.clone();
                        flip_texture_v(&mut copy.params);
                        self.desc.materials.push(copy);
                    }
                    name
                };
                Ok((type_name, params, material))
            }
            "sphere" => {
                let centre: Option<DVec3> = match value_at(&params, "center") {
                    Some(Value::Seq(c)) => {
                        let x: Vec<f64> = c.iter().filter_map(number).collect();
                        (x.len() == 3).then(|| DVec3::new(x[0], x[1], x[2]))
                    }
                    _ => Some(DVec3::ZERO),
                };
                let r = value_at(&params, "radius").and_then(number);
                let (Some(centre), Some(r)) = (centre, r) else {
                    return Ok((type_name, params, material));
                };
                self.note(
                    "shape sphere with a texture",
                    format!(
                        "tessellated into {ROUND_SEGMENTS} × {} quads with Mitsuba's sphere uvs \
                         and smooth normals (spectrace's sphere lays a texture out about +y)",
                        ROUND_SEGMENTS / 2
                    ),
                    item,
                );
                let mesh = uv_sphere_mesh(centre, r);
                Ok(("mesh".into(), mesh_value(&mesh), material))
            }
            _ => Ok((type_name, params, material)),
        }
    }

    // ------------------------------------------------------------ emitters

    fn emitter(&mut self, el: &'a Element) -> Result<(), SceneError> {
        let kind = el.attr("type").unwrap_or("");
        let p = Props::new(el);
        let base = el.attr("id").unwrap_or(kind).to_string();
        let m = match p.get("to_world") {
            Some(t) => transform_of(t)?,
            None => DMat4::IDENTITY,
        };
        let item = match kind {
            "point" => {
                let pos = match p.point("position")? {
                    Some(x) => x,
                    None => m.transform_point3(DVec3::ZERO),
                };
                let t = self.emission(&p, "intensity", &base)?;
                let power = 4.0 * std::f64::consts::PI * spectra::integral(&t);
                Some((
                    "point",
                    map(vec![
                        ("position", v3(pos)),
                        ("power", num(power)),
                        ("spd", table(&t)),
                    ]),
                ))
            }
            "spot" => {
                let t = self.emission(&p, "intensity", &base)?;
                let cutoff = p.float_or("cutoff_angle", 20.0)?;
                let beam = p.float_or("beam_width", cutoff * 0.75)?;
                if !(cutoff > 0.0 && cutoff <= 90.0 && beam >= 0.0 && beam <= cutoff) {
                    return Err(el.error(
                        "spot needs 0 < cutoff_angle ≤ 90 and 0 ≤ beam_width ≤ cutoff_angle",
                    ));
                }
                if p.get("texture").is_some() {
                    self.note(
                        "spot texture",
                        "projected textures are not supported: dropped",
                        &base,
                    );
                }
                let pos = m.transform_point3(DVec3::ZERO);
                let target = m.transform_point3(DVec3::Z);
                let omega = crate::light::spot::falloff_solid_angle_sr(beam, cutoff);
                let power = omega * spectra::integral(&t);
                self.note("emitter spot", "spectrace's falloff between beam_width and cutoff_angle replaces Mitsuba's (linear in angle); the peak intensity is kept", &base);
                Some((
                    "spot",
                    map(vec![
                        ("position", v3(pos)),
                        ("target", v3(target)),
                        ("inner_angle", num(beam)),
                        ("outer_angle", num(cutoff)),
                        ("power", num(power)),
                        ("spd", table(&t)),
                    ]),
                ))
            }
            "directional" => {
                let t = self.emission(&p, "irradiance", &base)?;
                let dir = match p.point("direction")? {
                    Some(d) => d,
                    None => m.transform_vector3(DVec3::Z),
                };
                if dir.length_squared() == 0.0 {
                    return Err(el.error("direction is (0, 0, 0)"));
                }
                Some((
                    "directional",
                    map(vec![
                        ("direction", v3(dir.normalize())),
                        ("irradiance", num(spectra::integral(&t))),
                        ("spd", table(&t)),
                    ]),
                ))
            }
            "constant" => {
                let t = self.emission(&p, "radiance", &base)?;
                Some(("environment", map(vec![("radiance", table(&t))])))
            }
            "envmap" => {
                let f = p
                    .string("filename")
                    .ok_or_else(|| el.error("envmap needs `filename`"))?;
                let f = self.file(el, f)?;
                let scale = p.float_or("scale", 1.0)?;
                let r = m.transpose().to_cols_array_2d();
                let rows = seq(r
                    .iter()
                    .map(|row| seq(row.iter().map(|&x| num(x)).collect()))
                    .collect());
                Some((
                    "envmap",
                    map(vec![
                        ("file", text(&f)),
                        ("scale", num(scale)),
                        ("transform", rows),
                    ]),
                ))
            }
            "area" => return Err(el.error("an area emitter belongs inside a <shape>")),
            other => {
                for c in &el.children {
                    if let Some(n) = c.attr("name") {
                        let _ = p.get(n);
                    }
                }
                self.note(
                    &format!("emitter {other}"),
                    "not supported: left out",
                    &base,
                );
                None
            }
        };
        if let Some((type_name, params)) = item {
            self.finish(&p, &format!("emitter {kind}"), &base);
            let name = self.unique(&base);
            self.desc.lights.push(ItemDescription {
                name,
                type_name: type_name.into(),
                params,
            });
        }
        Ok(())
    }

    // ------------------------------------------------------------ sensor, film, sampler, integrator

    fn sensor(&mut self, el: &'a Element) -> Result<(), SceneError> {
        let kind = el.attr("type").unwrap_or("");
        let p = Props::new(el);
        let base = el.attr("id").unwrap_or("camera").to_string();
        if !matches!(kind, "perspective" | "thinlens") {
            for c in &el.children {
                if let Some(n) = c.attr("name") {
                    let _ = p.get(n);
                }
            }
            self.note(&format!("sensor {kind}"), "not supported: left out", &base);
            return Ok(());
        }
        let (pos, fwd, up) = self.sensor_frame(&p, &base)?;
        // Film first: the aspect ratio converts fov axes.
        let (w, h, filter) = self.film(&p, &base)?;
        self.sampler(&p, &base)?;
        let (fov, axis) = Self::field_of_view(el, &p, w, h)?;
        if let Some(n) = p.float("near_clip")? {
            if n > 1e-2 {
                self.note("sensor near_clip", "not supported: spectrace has no clipping planes (geometry nearer than near_clip is rendered)", &base);
            }
        }
        let _ = p.float("far_clip")?;
        let mut params = vec![
            ("position", v3(pos)),
            ("look_at", v3(pos + fwd)),
            ("up", v3(up)),
            ("fov", num(fov)),
            ("fov_axis", text(&axis)),
            ("resolution", seq(vec![num(w as f64), num(h as f64)])),
            ("filter", filter),
        ];
        let type_name = if kind == "thinlens" {
            let r = p.float_or("aperture_radius", 0.1)?;
            let d = p.float_or("focus_distance", 1.0)?;
            params.push(("lens_radius", num(r)));
            params.push(("focus_distance", num(d)));
            "perspective"
        } else {
            let _ = p.get("focus_distance");
            "pinhole"
        };
        if p.get("principal_point_offset_x").is_some()
            || p.get("principal_point_offset_y").is_some()
        {
            self.note(
                "sensor principal point offset",
                "not supported: dropped",
                &base,
            );
        }
        let _ = p.get("shutter_open");
        let _ = p.get("shutter_close");
        self.finish(&p, &format!("sensor {kind}"), &base);
        let name = self.unique(&base);
        self.desc.cameras.push(ItemDescription {
            name,
            type_name: type_name.into(),
            params: map(params),
        });
        Ok(())
    }

    /// The sensor's position, forward and up directions from its `to_world`; a mirroring
    /// transform is noted (spectrace renders the image unmirrored).
    fn sensor_frame(
        &mut self,
        p: &Props<'a>,
        base: &str,
    ) -> Result<(DVec3, DVec3, DVec3), SceneError> {
        let m = match p.get("to_world") {
            Some(t) => transform_of(t)?,
            None => DMat4::IDENTITY,
        };
        let pos = m.transform_point3(DVec3::ZERO);
        let fwd = m.transform_vector3(DVec3::Z).normalize();
        let up = m.transform_vector3(DVec3::Y).normalize();
        let left = m.transform_vector3(DVec3::X);
        // Mitsuba's image x runs along −(local x); spectrace's image right is forward × up.
        if fwd.cross(up).dot(-left) < 0.0 {
            self.note(
                "sensor mirrored to_world",
                "the camera transform mirrors the image: spectrace renders it unmirrored",
                base,
            );
        }
        Ok((pos, fwd, up))
    }

    /// The sensor's film: width, height (Mitsuba's defaults 768 × 576) and pixel filter
    /// (Mitsuba's default a Gaussian of σ 0.5); what spectrace has no equivalent for is noted.
    fn film(&mut self, p: &Props<'a>, base: &str) -> Result<(i64, i64, Value), SceneError> {
        let (mut w, mut h) = (768i64, 576i64);
        let mut filter = map(vec![
            ("type", text("gaussian")),
            ("sigma", num(0.5)),
            ("radius", num(2.0)),
        ]);
        for (i, f) in p.nested("film") {
            p.mark(i);
            let fp = Props::new(f);
            w = fp.int("width")?.unwrap_or(768);
            h = fp.int("height")?.unwrap_or(576);
            if !(1..=65536).contains(&w) || !(1..=65536).contains(&h) {
                return Err(f.error(format!("film size {w}×{h}: each side must be 1..65536")));
            }
            if fp.has("crop_width")
                || fp.has("crop_height")
                || fp.has("crop_offset_x")
                || fp.has("crop_offset_y")
            {
                for n in [
                    "crop_width",
                    "crop_height",
                    "crop_offset_x",
                    "crop_offset_y",
                ] {
                    let _ = fp.get(n);
                }
                self.note(
                    "film crop",
                    "not supported: the whole image is rendered",
                    base,
                );
            }
            for n in [
                "pixel_format",
                "component_format",
                "file_format",
                "banner",
                "high_quality_edges",
                "sample_border",
                "compensate",
            ] {
                if fp.get(n).is_some() {
                    self.note("film output format", "ignored: spectrace writes an OpenEXR (linear, the scene's RGB space) and a PNG", base);
                }
            }
            for (j, r) in fp.nested("rfilter") {
                fp.mark(j);
                filter = self.rfilter(r, filter, base)?;
            }
            self.finish(&fp, "film", base);
        }
        Ok((w, h, filter))
    }

    /// spectrace's pixel filter for the film's `rfilter` `r`; `current` stays when spectrace has
    /// none like it.
    fn rfilter(&mut self, r: &'a Element, current: Value, base: &str) -> Result<Value, SceneError> {
        let rp = Props::new(r);
        let filter = match r.attr("type").unwrap_or("") {
            "box" => text("box"),
            "gaussian" => {
                let s = rp.float_or("stddev", 0.5)?;
                map(vec![
                    ("type", text("gaussian")),
                    ("sigma", num(s)),
                    ("radius", num(4.0 * s)),
                ])
            }
            "tent" => {
                let r0 = rp.float_or("radius", 1.0)?;
                self.note(
                    "rfilter tent",
                    "a Gaussian of the same variance (σ = r/√6, radius r) stands in",
                    base,
                );
                map(vec![
                    ("type", text("gaussian")),
                    ("sigma", num(r0 / 6f64.sqrt())),
                    ("radius", num(r0)),
                ])
            }
            other => {
                self.note(
                    &format!("rfilter {other}"),
                    "not supported: spectrace's Gaussian (σ 0.5) stands in",
                    base,
                );
                current
            }
        };
        self.finish(&rp, "rfilter", base);
        Ok(filter)
    }

    /// The sensor's sampler: only the sample count is kept (as the scene's spp unless set).
    fn sampler(&mut self, p: &Props<'a>, base: &str) -> Result<(), SceneError> {
        for (i, s) in p.nested("sampler") {
            p.mark(i);
            let sp = Props::new(s);
            if let Some(n) = sp.int("sample_count")? {
                if !(1..=crate::limits::MAX_SPP as i64).contains(&n) {
                    return Err(s.error(format!(
                        "sample_count {n} outside 1..{}",
                        crate::limits::MAX_SPP
                    )));
                }
                self.desc.output.spp.get_or_insert(n as u32);
            }
            for n in ["seed", "jitter", "scramble_seed", "dimension"] {
                let _ = sp.get(n);
            }
            self.note(
                "sampler",
                "only sample_count is kept: spectrace uses its own sample sequence",
                base,
            );
            self.finish(&sp, "sampler", base);
        }
        Ok(())
    }

    /// A sensor's field of view (degrees) and the image axis it spans (`x` or `y`), from `fov` and
    /// `fov_axis` or a 35 mm `focal_length`, on a `w` × `h` film.
    fn field_of_view(el: &Element, p: &Props, w: i64, h: i64) -> Result<(f64, String), SceneError> {
        let aspect = w as f64 / h as f64;
        let (mut fov, mut axis) = match (p.float("fov")?, p.value_of("focal_length")) {
            (Some(f), _) => (f, p.string("fov_axis").unwrap_or("x").to_string()),
            (None, Some((c, v))) => {
                let mm: f64 = v
                    .trim()
                    .trim_end_matches("mm")
                    .parse()
                    .map_err(|_| c.error(format!("focal_length `{v}`")))?;
                // Mitsuba: a 35 mm film (36 × 24 mm), the focal length giving the diagonal fov.
                let diag = 2.0 * (36f64.hypot(24.0) / (2.0 * mm)).atan().to_degrees();
                (diag, "diagonal".to_string())
            }
            (None, None) => (
                p.float_or("fov", 45.0)?,
                p.string("fov_axis").unwrap_or("x").to_string(),
            ),
        };
        if p.string("fov_axis").is_some() {
            let _ = p.get("fov_axis");
        }
        let tan = (fov.to_radians() / 2.0).tan();
        match axis.as_str() {
            "x" | "y" => {}
            "diagonal" => {
                // tan of the x half-angle from the diagonal's.
                let tx = tan * aspect / (1.0 + aspect * aspect).sqrt();
                fov = 2.0 * tx.atan().to_degrees();
                axis = "x".into();
            }
            "smaller" => axis = if w <= h { "x".into() } else { "y".into() },
            "larger" => axis = if w >= h { "x".into() } else { "y".into() },
            other => {
                return Err(el.error(format!(
                    "fov_axis `{other}` (x, y, diagonal, smaller, larger)"
                )))
            }
        }
        if !(fov > 0.0 && fov < 180.0) {
            return Err(el.error(format!("fov {fov}° outside (0, 180)")));
        }
        Ok((fov, axis))
    }

    fn integrator(&mut self, el: &'a Element) -> Result<(), SceneError> {
        let kind = el.attr("type").unwrap_or("");
        let p = Props::new(el);
        match kind {
            "path" | "volpath" | "volpathmis" | "prb" | "direct" | "ptracer" => {
                let d = if kind == "direct" {
                    Some(2)
                } else {
                    p.int("max_depth")?
                };
                match d {
                    None | Some(-1) => {}
                    Some(d) if d >= 1 => {
                        // Mitsuba counts path segments (1: only emitters seen directly);
                        // spectrace counts scattering events.
                        self.desc.output.max_depth = Some((d - 1).min(1024) as u32);
                    }
                    Some(d) => return Err(el.error(format!("max_depth {d} (-1 or ≥ 1)"))),
                }
                if d == Some(-1) {
                    self.note("integrator max_depth -1", "unbounded paths: spectrace's limit of 1024 scattering events with Russian roulette", "");
                    self.desc.output.max_depth = Some(1024);
                }
                for n in ["rr_depth", "hide_emitters"] {
                    if p.get(n).is_some() {
                        self.note(&format!("integrator {n}"), "ignored (spectrace's Russian roulette is its own; emitters are always visible)", "");
                    }
                }
                if kind != "path" {
                    self.note(&format!("integrator {kind}"), "rendered with the integrator `render --integrator` chooses (default pt), max_depth kept", "");
                }
            }
            "aov" | "moment" => {
                for (i, c) in p.nested("integrator") {
                    p.mark(i);
                    self.integrator(c)?;
                }
                for c in &el.children {
                    if let Some(n) = c.attr("name") {
                        let _ = p.get(n);
                    }
                }
                self.note(&format!("integrator {kind}"), "its extra channels are not produced: the nested integrator's settings are used", "");
            }
            other => {
                for c in &el.children {
                    if let Some(n) = c.attr("name") {
                        let _ = p.get(n);
                    }
                }
                self.note(
                    &format!("integrator {other}"),
                    "not supported: spectrace's own (render --integrator) is used",
                    "",
                );
            }
        }
        self.finish(&p, &format!("integrator {kind}"), "");
        Ok(())
    }
}

enum SpectrumValue {
    Uniform(f64),
    Pairs(Vec<(f64, f64)>),
}

fn pairs_checked(c: &Element, t: Vec<(f64, f64)>) -> Result<SpectrumValue, SceneError> {
    if t.is_empty() {
        return Err(c.error("an empty spectrum"));
    }
    if t.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(c.error("spectrum wavelengths must increase"));
    }
    Ok(SpectrumValue::Pairs(t))
}

/// Mitsuba's named indices of refraction (its documentation's table, at 589 nm).
pub const IOR_TABLE: &[(&str, f64)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

fn named_ior(name: &str) -> Option<f64> {
    let n = name.trim().to_ascii_lowercase();
    if let Ok(x) = n.parse::<f64>() {
        return Some(x).filter(|x| x.is_finite() && *x > 0.0);
    }
    IOR_TABLE.iter().find(|(k, _)| *k == n).map(|(_, v)| *v)
}

// ---------------------------------------------------------------- meshes of analytic shapes

fn mesh_value(m: &crate::geometry::TriangleMesh) -> Value {
    let mut e = vec![
        (
            "positions",
            seq(m
                .positions
                .iter()
                .map(|p| seq(vec![num(p.x as f64), num(p.y as f64), num(p.z as f64)]))
                .collect()),
        ),
        (
            "indices",
            seq(m
                .indices
                .iter()
                .map(|t| {
                    seq(t
                        .iter()
                        .map(|&i| Value::Number(ron::Number::from(i as i64)))
                        .collect())
                })
                .collect()),
        ),
    ];
    if let Some(n) = &m.normals {
        e.push((
            "normals",
            seq(n
                .iter()
                .map(|p| seq(vec![num(p.x as f64), num(p.y as f64), num(p.z as f64)]))
                .collect()),
        ));
    }
    if let Some(t) = &m.uvs {
        e.push((
            "uvs",
            seq(t
                .iter()
                .map(|p| seq(vec![num(p.x as f64), num(p.y as f64)]))
                .collect()),
        ));
    }
    map(e)
}

/// The value of key `k` in a RON map.
fn value_at<'v>(v: &'v Value, k: &str) -> Option<&'v Value> {
    match v {
        Value::Map(m) => m
            .iter()
            .find(|(key, _)| matches!(key, Value::String(s) if s == k))
            .map(|(_, v)| v),
        _ => None,
    }
}

fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Number(x) => Some(x.into_f64()),
        _ => None,
    }
}

/// True when a material's parameters hold an image texture anywhere.
fn has_texture(v: &Value) -> bool {
    match v {
        Value::Map(m) => m.iter().any(|(k, v)| {
            (matches!(k, Value::String(s) if s == "texture") && matches!(v, Value::Map(_)))
                || has_texture(v)
        }),
        Value::Seq(items) => items.iter().any(has_texture),
        _ => false,
    }
}

/// Every image texture in a material's parameters reads its image with v flipped
/// (`v → 1 − v` before its `uv_scale` and `uv_offset`): `(s_v, o_v)` becomes
/// `(−s_v, o_v + s_v)`. For a shape whose uvs are Mitsuba's unflipped (the rectangle).
fn flip_texture_v(v: &mut Value) {
    let pair = |t: &Value, k: &str, default: f64| -> [f64; 2] {
        match value_at(t, k) {
            Some(Value::Seq(p)) if p.len() == 2 => [
                number(&p[0]).unwrap_or(default),
                number(&p[1]).unwrap_or(default),
            ],
            _ => [default; 2],
        }
    };
    match v {
        Value::Map(m) => {
            for (k, v) in m.iter_mut() {
                let is_texture = matches!(k, Value::String(s) if s == "texture");
                match v {
                    Value::Map(t) if is_texture => {
                        let tv = Value::Map(t.clone());
                        let sc = pair(&tv, "uv_scale", 1.0);
                        let of = pair(&tv, "uv_offset", 0.0);
                        t.insert(text("uv_scale"), seq(vec![num(sc[0]), num(-sc[1])]));
                        t.insert(text("uv_offset"), seq(vec![num(of[0]), num(of[1] + sc[1])]));
                    }
                    _ => flip_texture_v(v),
                }
            }
        }
        Value::Seq(items) => items.iter_mut().for_each(flip_texture_v),
        _ => {}
    }
}

/// A sphere of radius `r` at `centre` with Mitsuba's sphere uvs: `u = φ/2π` (φ = atan2(y, x)
/// in [0, 2π)), `v = θ/π` (θ from +z), stored with v flipped (spectrace's v = 0 is an image's
/// bottom row, Mitsuba's its top row). [`ROUND_SEGMENTS`] sectors × half as many rings; the
/// seam's vertices are doubled (u = 0 and 1) and each pole has a vertex per sector (its u at
/// the sector's middle), so no triangle interpolates across the seam. Smooth normals.
pub fn uv_sphere_mesh(centre: DVec3, r: f64) -> crate::geometry::TriangleMesh {
    use glam::{Vec2, Vec3A};
    let (np, nt) = (ROUND_SEGMENTS, ROUND_SEGMENTS / 2);
    let (mut positions, mut normals, mut uvs, mut indices) = (vec![], vec![], vec![], vec![]);
    for k in 0..=nt {
        let theta = std::f64::consts::PI * k as f64 / nt as f64;
        for j in 0..=np {
            // At the poles, u in the middle of the sector below (or above) the vertex.
            let uj = if k == 0 || k == nt {
                (j as f64 + 0.5) / np as f64
            } else {
                j as f64 / np as f64
            };
            let phi = std::f64::consts::TAU * j as f64 / np as f64;
            let n = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let p = centre + n * r;
            positions.push(Vec3A::new(p.x as f32, p.y as f32, p.z as f32));
            normals.push(Vec3A::new(n.x as f32, n.y as f32, n.z as f32));
            uvs.push(Vec2::new(uj as f32, (1.0 - k as f64 / nt as f64) as f32));
        }
    }
    let at = |k: usize, j: usize| (k * (np + 1) + j) as u32;
    for k in 0..nt {
        for j in 0..np {
            let (a, b, c, d) = (at(k, j), at(k + 1, j), at(k + 1, j + 1), at(k, j + 1));
            if k == 0 {
                // a is the north pole's vertex of sector j.
                indices.push([a, b, c]);
            } else if k + 1 == nt {
                // b is the south pole's vertex of sector j.
                indices.push([a, b, d]);
            } else {
                indices.push([a, b, c]);
                indices.push([a, c, d]);
            }
        }
    }
    crate::geometry::TriangleMesh {
        positions,
        normals: Some(normals),
        uvs: Some(uvs),
        indices,
    }
}

fn flip_winding(m: &mut crate::geometry::TriangleMesh) {
    for t in &mut m.indices {
        t.swap(1, 2);
    }
    if let Some(n) = &mut m.normals {
        for v in n {
            *v = -*v;
        }
    }
}

/// Mitsuba 3's uv on its `cube` at point `p` of the face whose outward normal is `s` along
/// axis `a` (0, 1, 2 = x, y, z), as Mitsuba 3.9.1 reports it (`si.uv` of rays hitting each
/// face, `scripts/mitsuba_import/uv_probe.py`): affine in the face's two other coordinates.
fn mitsuba_cube_uv(a: usize, s: f32, p: glam::Vec3A) -> (f32, f32) {
    let h = |x: f32| (x + 1.0) / 2.0;
    let g = |x: f32| (1.0 - x) / 2.0;
    match (a, s > 0.0) {
        (0, false) => (h(p.y), h(p.z)),
        (0, true) => (h(p.y), g(p.z)),
        (1, false) => (h(p.z), h(p.x)),
        (1, true) => (g(p.x), g(p.z)),
        (2, false) => (g(p.y), h(p.x)),
        _ => (h(p.y), h(p.x)),
    }
}

/// Mitsuba's `cube`: [−1, 1]³, outward faces, four vertices per face, with Mitsuba's uvs
/// (`mitsuba_cube_uv`) stored with v flipped (spectrace's v = 0 is an image's bottom row).
pub fn cube_mesh(flip: bool) -> crate::geometry::TriangleMesh {
    use glam::{Vec2, Vec3A};
    let mut m = crate::geometry::TriangleMesh {
        positions: vec![],
        normals: None,
        uvs: Some(vec![]),
        indices: vec![],
    };
    let axes = [Vec3A::X, Vec3A::Y, Vec3A::Z];
    for a in 0..3 {
        for s in [-1.0f32, 1.0] {
            let n = axes[a] * s;
            let u = axes[(a + 1) % 3];
            let v = n.cross(u);
            let k = m.positions.len() as u32;
            for (du, dv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = n + u * du + v * dv;
                m.positions.push(p);
                if let Some(t) = &mut m.uvs {
                    let (mu, mv) = mitsuba_cube_uv(a, s, p);
                    t.push(Vec2::new(mu, 1.0 - mv));
                }
            }
            m.indices.push([k, k + 1, k + 2]);
            m.indices.push([k, k + 2, k + 3]);
        }
    }
    if flip {
        flip_winding(&mut m);
    }
    m
}

/// Mitsuba's `disk`: the unit disk in z = 0, normal +z, with Mitsuba's polar uvs, `u = r`,
/// `v = φ/2π` (φ = atan2(y, x) in [0, 2π)), stored with v flipped: [`ROUND_SEGMENTS`] sectors
/// by 16 rings (a fan in the innermost), so that interpolating the uvs linearly inside each
/// triangle stays within 10⁻³ of the polar coordinates except within 1/16 of the centre, where
/// the fan's v may be off by up to half a sector (1/256). The seam's vertices are doubled (v = 0
/// and 1) and the centre has a vertex per sector (v at the sector's middle), so no triangle
/// interpolates across the seam.
pub fn disk_mesh(flip: bool) -> crate::geometry::TriangleMesh {
    use glam::{Vec2, Vec3A};
    const RINGS: usize = 16;
    let n = ROUND_SEGMENTS;
    let (mut positions, mut uvs, mut indices) = (vec![], vec![], vec![]);
    for i in 0..n {
        positions.push(Vec3A::ZERO);
        uvs.push(Vec2::new(0.0, (1.0 - (i as f64 + 0.5) / n as f64) as f32));
    }
    // Ring k (1…RINGS) at radius k/RINGS, vertex i at φ = 2πi/n (i = n doubles i = 0).
    let ring = |k: usize, i: usize| (n + (k - 1) * (n + 1) + i) as u32;
    for k in 1..=RINGS {
        let r = k as f64 / RINGS as f64;
        for i in 0..=n {
            let phi = std::f64::consts::TAU * i as f64 / n as f64;
            let (s, c) = phi.sin_cos();
            positions.push(Vec3A::new((r * c) as f32, (r * s) as f32, 0.0));
            uvs.push(Vec2::new(r as f32, (1.0 - i as f64 / n as f64) as f32));
        }
    }
    for i in 0..n {
        indices.push([i as u32, ring(1, i), ring(1, i + 1)]);
        for k in 1..RINGS {
            let (a, b, c, d) = (
                ring(k, i),
                ring(k + 1, i),
                ring(k + 1, i + 1),
                ring(k, i + 1),
            );
            indices.push([a, b, c]);
            indices.push([a, c, d]);
        }
    }
    let mut m = crate::geometry::TriangleMesh {
        positions,
        normals: None,
        uvs: Some(uvs),
        indices,
    };
    if flip {
        flip_winding(&mut m);
    }
    m
}

/// Mitsuba's `cylinder` (open tube from p0 to p1), outward normals.
pub fn cylinder_mesh(p0: DVec3, p1: DVec3, r: f64, flip: bool) -> crate::geometry::TriangleMesh {
    use glam::Vec3A;
    let axis = (p1 - p0).normalize();
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let n = ROUND_SEGMENTS;
    let (mut positions, mut normals, mut indices) = (vec![], vec![], vec![]);
    for i in 0..n {
        let phi = std::f64::consts::TAU * i as f64 / n as f64;
        let d = u * phi.cos() + v * phi.sin();
        for base in [p0, p1] {
            let q = base + d * r;
            positions.push(Vec3A::new(q.x as f32, q.y as f32, q.z as f32));
            normals.push(Vec3A::new(d.x as f32, d.y as f32, d.z as f32));
        }
        let a = 2 * i as u32;
        let b = 2 * ((i + 1) % n) as u32;
        indices.push([a, b, b + 1]);
        indices.push([a, b + 1, a + 1]);
    }
    let mut m = crate::geometry::TriangleMesh {
        positions,
        normals: Some(normals),
        uvs: None,
        indices,
    };
    if flip {
        flip_winding(&mut m);
    }
    m
}

// ---------------------------------------------------------------- entry point

/// Convert an expanded scene tree; `dir` is the main scene file's directory.
pub fn convert_tree(root: &Element, dir: &Path) -> Result<Conversion, SceneError> {
    let mut ids: HashMap<&str, &Element> = HashMap::new();
    fn collect<'a>(
        e: &'a Element,
        ids: &mut HashMap<&'a str, &'a Element>,
    ) -> Result<(), SceneError> {
        for c in &e.children {
            if c.tag != "ref" {
                if let Some(id) = c.attr("id") {
                    if let Some(prev) = ids.insert(id, c) {
                        return Err(c.error(format!(
                            "id \"{id}\" is used twice (first at {})",
                            prev.at()
                        )));
                    }
                }
            }
            collect(c, ids)?;
        }
        Ok(())
    }
    collect(root, &mut ids)?;
    // `<path>` folders anywhere at scene level (includes are already expanded), last first.
    let search: Vec<PathBuf> = root
        .children
        .iter()
        .rev()
        .filter(|c| c.tag == "path")
        .filter_map(|c| c.attr("value").map(PathBuf::from))
        .collect();
    let mut cv = Converter {
        dir: dir.to_path_buf(),
        search,
        ids,
        desc: SceneDescription {
            units: Some("m".into()),
            emission_units: None,
            observer: Some("cie1931-2".into()),
            output: OutputDescription {
                rgb_space: Some("srgb".into()),
                ..Default::default()
            },
            materials: vec![],
            objects: vec![],
            lights: vec![],
            cameras: vec![],
            sensors: vec![],
            plugins: vec![],
        },
        notes: BTreeMap::new(),
        used_names: HashSet::new(),
        made: HashMap::new(),
        default_material: None,
    };
    let version = root.attr("version").unwrap_or("3.0.0");
    if !version.starts_with('3') && !version.starts_with('2') {
        cv.note(
            "scene version",
            format!("a Mitsuba {version} file: parameter names upgraded as Mitsuba 3 does (camelCase → snake_case)"),
            "",
        );
    }
    for c in &root.children {
        match c.tag.as_str() {
            "shape" => cv.shape(c, &DMat4::IDENTITY, "")?,
            "emitter" => cv.emitter(c)?,
            "sensor" => cv.sensor(c)?,
            "integrator" => cv.integrator(c)?,
            "bsdf" => {
                // Made when a shape refers to it; one nobody uses is noted.
                let used = root_refers(root, c.attr("id"));
                if !used {
                    cv.note(
                        "unused bsdf",
                        "declared but used by no shape: left out",
                        c.attr("id").unwrap_or(""),
                    );
                }
            }
            "texture" | "spectrum" | "rgb" | "float" | "path" => {}
            "medium" | "phase" | "volume" => cv.note(
                "media",
                "participating media are not supported: dropped",
                c.attr("id").unwrap_or(""),
            ),
            other if PROPERTY_TAGS.contains(&other) => cv.note(
                &format!("<{other}> at scene level"),
                "ignored",
                c.attr("id").unwrap_or(""),
            ),
            other => return Err(c.error(format!("unknown element <{other}>"))),
        }
    }
    if cv.desc.cameras.is_empty() {
        cv.note(
            "no sensor",
            "Mitsuba's default camera is not made: add a <sensor>",
            "",
        );
    }
    let notes = cv
        .notes
        .iter()
        .map(|(k, n)| {
            if n.items.is_empty() {
                format!("{k}: {}", n.message)
            } else {
                let shown: Vec<&str> = n.items.iter().take(6).map(|s| s.as_str()).collect();
                let more = if n.items.len() > 6 {
                    format!(" and {} more", n.items.len() - 6)
                } else {
                    String::new()
                };
                format!("{k}: {} ({}{more})", n.message, shown.join(", "))
            }
        })
        .collect();
    Ok(Conversion {
        desc: cv.desc,
        notes,
    })
}

fn root_refers(root: &Element, id: Option<&str>) -> bool {
    let Some(id) = id else { return false };
    fn walk(e: &Element, id: &str) -> bool {
        e.children
            .iter()
            .any(|c| (c.tag == "ref" && c.attr("id") == Some(id)) || walk(c, id))
    }
    walk(root, id)
}
