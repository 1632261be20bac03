//! Mitsuba emitters as spectrace lights.

use super::converter::Converter;
use super::props::{transform_of, Props};
use super::values::{map, num, seq, table, text, v3};
use crate::scene::mitsuba::spectra;
use crate::scene::mitsuba::xml::Element;
use crate::scene::SceneError;
use crate::scene_file::description::ItemDescription;
use glam::{DMat4, DVec3};

impl<'a> Converter<'a> {
    pub(super) fn emitter(&mut self, el: &'a Element) -> Result<(), SceneError> {
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
                p.mark_named();
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
}
