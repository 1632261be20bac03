//! A Mitsuba element's properties (`<float name=…>`, `<rgb>`, `<transform>`, …) read with their
//! types checked, every one used or noted, and the transforms they describe.

use super::values::numbers;
use crate::scene::mitsuba::xml::Element;
use crate::scene::SceneError;
use crate::scene_file::description::TransformStep;
use glam::{DMat4, DVec3};
use std::cell::RefCell;
use std::collections::HashSet;

pub(super) const PROPERTY_TAGS: &[&str] = &[
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
pub(super) struct Props<'a> {
    el: &'a Element,
    used: RefCell<HashSet<usize>>,
}

impl<'a> Props<'a> {
    pub(super) fn new(el: &'a Element) -> Self {
        Self {
            el,
            used: RefCell::new(HashSet::new()),
        }
    }

    /// The named property child (any tag).
    pub(super) fn get(&self, name: &str) -> Option<&'a Element> {
        let (i, c) = self
            .el
            .children
            .iter()
            .enumerate()
            .find(|(_, c)| c.attr("name") == Some(name))?;
        self.used.borrow_mut().insert(i);
        Some(c)
    }

    /// Marks every named child used (what [`get`](Self::get) of each name marks): for an
    /// element left out as a whole, whose parameters are not noted one by one.
    pub(super) fn mark_named(&self) {
        for c in &self.el.children {
            if let Some(n) = c.attr("name") {
                let _ = self.get(n);
            }
        }
    }

    pub(super) fn has(&self, name: &str) -> bool {
        self.el
            .children
            .iter()
            .any(|c| c.attr("name") == Some(name))
    }

    pub(super) fn value_of(&self, name: &str) -> Option<(&'a Element, &'a str)> {
        let c = self.get(name)?;
        Some((c, c.attr("value").unwrap_or("")))
    }

    pub(super) fn float(&self, name: &str) -> Result<Option<f64>, SceneError> {
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

    pub(super) fn float_or(&self, name: &str, default: f64) -> Result<f64, SceneError> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    pub(super) fn int(&self, name: &str) -> Result<Option<i64>, SceneError> {
        match self.value_of(name) {
            None => Ok(None),
            Some((c, v)) => v
                .trim()
                .parse::<i64>()
                .map(Some)
                .map_err(|_| c.error(format!("`{name}`: `{v}` is not an integer"))),
        }
    }

    pub(super) fn bool(&self, name: &str) -> Result<Option<bool>, SceneError> {
        match self.value_of(name) {
            None => Ok(None),
            Some((c, v)) => match v.trim() {
                "true" => Ok(Some(true)),
                "false" => Ok(Some(false)),
                _ => Err(c.error(format!("`{name}`: `{v}` is neither true nor false"))),
            },
        }
    }

    pub(super) fn string(&self, name: &str) -> Option<&'a str> {
        self.value_of(name).map(|(_, v)| v)
    }

    pub(super) fn point(&self, name: &str) -> Result<Option<DVec3>, SceneError> {
        let Some(c) = self.get(name) else {
            return Ok(None);
        };
        point_of(c).map(Some)
    }

    /// Unnamed (or any) nested objects with `tag`, `ref`s included.
    pub(super) fn nested(&self, tag: &str) -> Vec<(usize, &'a Element)> {
        self.el
            .children
            .iter()
            .enumerate()
            .filter(|(_, c)| c.tag == tag || (c.tag == "ref" && tag == "ref"))
            .collect()
    }

    pub(super) fn mark(&self, i: usize) {
        self.used.borrow_mut().insert(i);
    }

    /// Names of the children nobody read.
    pub(super) fn unused(&self) -> Vec<String> {
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

pub(super) fn point_of(c: &Element) -> Result<DVec3, SceneError> {
    vector_of(c, 0.0)
}

/// An element's vector: its `value` (one number for all three, or three), else its `x`, `y`,
/// `z` attributes, each `default` where absent.
fn vector_of(c: &Element, default: f64) -> Result<DVec3, SceneError> {
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
            None => Ok(default),
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
        let attr3 = |default: f64| vector_of(op, default);
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

pub(super) fn matrix_step(m: &DMat4) -> TransformStep {
    let r = m.transpose().to_cols_array_2d();
    TransformStep::Matrix(r)
}
