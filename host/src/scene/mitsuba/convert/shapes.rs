//! Mitsuba shapes as spectrace objects: meshes, analytic shapes, instances, their materials
//! and area emitters.

use super::converter::Converter;
use super::meshes::{
    cube_mesh, cylinder_mesh, disk_mesh, mesh_value, uv_sphere_mesh, ROUND_SEGMENTS,
};
use super::props::{matrix_step, transform_of, Props};
use super::values::{flip_texture_v, has_texture, map, num, number, table, text, v3, value_at};
use crate::scene::mitsuba::xml::Element;
use crate::scene::SceneError;
use crate::scene_file::description::{ItemDescription, ObjectDescription};
use glam::{DMat4, DVec3};
use ron::Value;
use std::path::{Path, PathBuf};

impl<'a> Converter<'a> {
    pub(super) fn shape(
        &mut self,
        el: &'a Element,
        parent: &DMat4,
        prefix: &str,
    ) -> Result<(), SceneError> {
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
    pub(super) fn instance(
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
    pub(super) fn shape_geometry(
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
                p.mark_named();
                self.note(&format!("shape {other}"), "not supported: left out", base);
                return Ok(None);
            }
        }))
    }

    /// An `obj` or `ply` shape: the file, read by spectrace's own loader.
    pub(super) fn mesh_file(
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
    pub(super) fn serialized(
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
        let s = crate::scene::mitsuba::serialized::parse_serialized(&bytes, index as usize)
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
    pub(super) fn shape_material(
        &mut self,
        p: &Props<'a>,
        base: &str,
    ) -> Result<Option<String>, SceneError> {
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
    pub(super) fn area_emitter(
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
    pub(super) fn drop_media(&mut self, el: &'a Element, p: &Props<'a>, base: &str) {
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
    pub(super) fn analytic_uvs(
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
}
