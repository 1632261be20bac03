//! Mitsuba BSDFs as spectrace materials (the table is in `docs/mitsuba-import.md`).

use super::converter::Converter;
use super::props::Props;
use super::values::{map, num, table, text};
use crate::scene::mitsuba::xml::Element;
use crate::scene::SceneError;
use crate::scene_file::description::ItemDescription;
use ron::Value;

impl<'a> Converter<'a> {
    /// The material for a bsdf element (made once per element); None for `null`.
    pub(super) fn material(
        &mut self,
        el: &'a Element,
        suggested: &str,
    ) -> Result<Option<String>, SceneError> {
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

    pub(super) fn default_material(&mut self) -> String {
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

    pub(super) fn ior(
        &mut self,
        p: &Props<'a>,
        name: &str,
        default: f64,
    ) -> Result<f64, SceneError> {
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

    pub(super) fn alpha(
        &mut self,
        p: &Props<'a>,
        kind: &str,
        item: &str,
    ) -> Result<f64, SceneError> {
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
    pub(super) fn roughness_alpha(
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

    pub(super) fn conductor_params(
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

    pub(super) fn bsdf(
        &mut self,
        el: &'a Element,
        item: &str,
    ) -> Result<Option<(String, Value)>, SceneError> {
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
                p.mark_named();
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
                p.mark_named();
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

pub(super) fn named_ior(name: &str) -> Option<f64> {
    let n = name.trim().to_ascii_lowercase();
    if let Ok(x) = n.parse::<f64>() {
        return Some(x).filter(|x| x.is_finite() && *x > 0.0);
    }
    IOR_TABLE.iter().find(|(k, _)| *k == n).map(|(_, v)| *v)
}
