//! Colours of the Mitsuba converter: reflectances, textures, spectra and emission as spectrace
//! spectral values.

use super::converter::Converter;
use super::props::{transform_of, Props};
use super::values::{map, num, numbers, rgb_of, seq, table, text};
use crate::scene::mitsuba::spectra;
use crate::scene::mitsuba::xml::Element;
use crate::scene::SceneError;
use ron::Value;
use std::path::{Path, PathBuf};

impl<'a> Converter<'a> {
    /// A reflectance-like (unitless) colour parameter as a spectrace spectral value.
    pub(super) fn reflectance(
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
                let rgb = rgb_value(c)?;
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

    pub(super) fn texture(&mut self, c: &'a Element, item: &str) -> Result<Value, SceneError> {
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

    pub(super) fn spectrum_pairs(&mut self, c: &Element) -> Result<SpectrumValue, SceneError> {
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
    pub(super) fn emission(
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
                let rgb = rgb_value(c)?;
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
}

pub(super) enum SpectrumValue {
    Uniform(f64),
    Pairs(Vec<(f64, f64)>),
}

pub(super) fn pairs_checked(c: &Element, t: Vec<(f64, f64)>) -> Result<SpectrumValue, SceneError> {
    if t.is_empty() {
        return Err(c.error("an empty spectrum"));
    }
    if t.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(c.error("spectrum wavelengths must increase"));
    }
    Ok(SpectrumValue::Pairs(t))
}

/// An `<rgb value="…">` element's three numbers (one number stands for all three).
fn rgb_value(c: &Element) -> Result<[f64; 3], SceneError> {
    let v = c
        .attr("value")
        .and_then(numbers)
        .ok_or_else(|| c.error("not a list of numbers"))?;
    match v.as_slice() {
        [g] => Ok([*g; 3]),
        [r, g, b] => Ok([*r, *g, *b]),
        _ => Err(c.error("an rgb value has 1 or 3 numbers")),
    }
}
