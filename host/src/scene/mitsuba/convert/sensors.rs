//! Mitsuba sensors, films, filters, samplers and integrators as spectrace cameras and output
//! settings.

use super::converter::Converter;
use super::props::{transform_of, Props};
use super::values::{map, num, seq, text, v3};
use crate::scene::mitsuba::xml::Element;
use crate::scene::SceneError;
use crate::scene_file::description::ItemDescription;
use glam::{DMat4, DVec3};
use ron::Value;

impl<'a> Converter<'a> {
    pub(super) fn sensor(&mut self, el: &'a Element) -> Result<(), SceneError> {
        let kind = el.attr("type").unwrap_or("");
        let p = Props::new(el);
        let base = el.attr("id").unwrap_or("camera").to_string();
        if !matches!(kind, "perspective" | "thinlens") {
            p.mark_named();
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
    pub(super) fn sensor_frame(
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
    pub(super) fn film(
        &mut self,
        p: &Props<'a>,
        base: &str,
    ) -> Result<(i64, i64, Value), SceneError> {
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
    pub(super) fn rfilter(
        &mut self,
        r: &'a Element,
        current: Value,
        base: &str,
    ) -> Result<Value, SceneError> {
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
    pub(super) fn sampler(&mut self, p: &Props<'a>, base: &str) -> Result<(), SceneError> {
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
    pub(super) fn field_of_view(
        el: &Element,
        p: &Props,
        w: i64,
        h: i64,
    ) -> Result<(f64, String), SceneError> {
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

    pub(super) fn integrator(&mut self, el: &'a Element) -> Result<(), SceneError> {
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
                p.mark_named();
                self.note(&format!("integrator {kind}"), "its extra channels are not produced: the nested integrator's settings are used", "");
            }
            other => {
                p.mark_named();
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
