//! The scene's length unit (`units: "m" | "cm" | "mm" | "in" | "ft"`, default metres) and its
//! conversion to metres, done once when the scene is built.
//!
//! Design: the renderer works in metres only. Every length a scene file gives in its own unit
//! is multiplied by [`LengthUnit::metres`] before anything is built from it, so no area, squared
//! distance, area-measure density, camera importance, beam origin or light footprint ever sees
//! another unit:
//! - objects: a uniform scale is appended to each object's transform (inline meshes, spheres,
//!   quads and mesh files alike);
//! - lights and cameras: every parameter whose documented unit is `scene units` (for
//!   built-in types and plugin types alike — the unit column of their parameter tables) is
//!   scaled, and so is its documented default when the parameter is left out;
//! - what is not a length (W, W/sr, W/m², W/(m²·sr·nm), degrees, nm) is never touched, so a
//!   point light of 100 W is 100 W in any unit, and an emissive surface's radiance is the same.
//!
//! A plugin light type that declares its own beam representation (`metres_per_unit`, see
//! `plugin::representation`) converts its own lengths; its parameters are taken in its unit.

use super::type_doc::ParamDoc;
use ron::{Number, Value};

/// The unit a parameter table gives for lengths in the scene's unit.
pub const SCENE_UNITS: &str = "scene units";

/// A scene's length unit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LengthUnit {
    /// Metres (the default, and the renderer's own unit).
    #[default]
    Metre,
    /// Centimetres.
    Centimetre,
    /// Millimetres.
    Millimetre,
    /// International inches (25.4 mm exactly).
    Inch,
    /// International feet (0.3048 m exactly).
    Foot,
}

impl LengthUnit {
    /// Every unit, in the order of the scene-file names.
    pub const ALL: [Self; 5] = [
        Self::Metre,
        Self::Centimetre,
        Self::Millimetre,
        Self::Inch,
        Self::Foot,
    ];

    /// Scene-file name: `m`, `cm`, `mm`, `in`, `ft`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Metre => "m",
            Self::Centimetre => "cm",
            Self::Millimetre => "mm",
            Self::Inch => "in",
            Self::Foot => "ft",
        }
    }

    /// Metres per unit (exact definitions: 1 in = 0.0254 m, 1 ft = 0.3048 m).
    pub fn metres(self) -> f64 {
        match self {
            Self::Metre => 1.0,
            Self::Centimetre => 0.01,
            Self::Millimetre => 0.001,
            Self::Inch => 0.0254,
            Self::Foot => 0.3048,
        }
    }

    /// The unit named `name`; the error lists the known names.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|u| u.name() == name.trim())
            .ok_or_else(|| {
                format!(
                    "unknown length unit `{name}`; known: {}",
                    Self::ALL.map(|u| u.name()).join(", ")
                )
            })
    }
}

impl std::fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// `v` with every number in it (a number, or lists of numbers at any depth) multiplied by `s`;
/// `None` when `v` holds anything else (left for the type's own check to report).
fn scaled(v: &Value, s: f64) -> Option<Value> {
    match v {
        Value::Number(n) => Some(Value::Number(Number::new(n.into_f64() * s))),
        Value::Seq(items) => items
            .iter()
            .map(|x| scaled(x, s))
            .collect::<Option<Vec<_>>>()
            .map(Value::Seq),
        Value::Option(Some(inner)) => scaled(inner, s).map(|x| Value::Option(Some(Box::new(x)))),
        _ => None,
    }
}

/// An item's `params` with its lengths in metres: every parameter `docs` gives in
/// [`SCENE_UNITS`] is multiplied by `metres_per_unit`; one left out whose documented default
/// is a number (or list of numbers) gets that default, converted. Unchanged when
/// `metres_per_unit` is 1 (bit for bit: a metre scene renders exactly as before).
pub fn params_in_metres(params: &Value, docs: &[ParamDoc], metres_per_unit: f64) -> Value {
    if metres_per_unit == 1.0 {
        return params.clone();
    }
    let mut map = match params {
        Value::Map(m) => m.clone(),
        Value::Unit => ron::Map::new(),
        other => return other.clone(),
    };
    for doc in docs.iter().filter(|d| d.unit == SCENE_UNITS) {
        let key = Value::String(doc.name.clone());
        let present = map.iter().find(|(k, _)| **k == key).map(|(_, v)| v.clone());
        match present {
            Some(v) => {
                let v = &v;
                if let Some(x) = scaled(v, metres_per_unit) {
                    map.insert(key, x);
                }
            }
            None => {
                let default = doc
                    .default
                    .as_deref()
                    .and_then(|d| ron::from_str::<Value>(d).ok())
                    .and_then(|d| scaled(&d, metres_per_unit));
                if let Some(x) = default {
                    map.insert(key, x);
                }
            }
        }
    }
    Value::Map(map)
}

/// Largest extent (m) of a scene that does not declare `units` before a warning asks whether
/// its lengths are millimetres: rooms, buildings and streets fit; a Cornell box written in mm
/// (556 "m" across) does not.
pub const UNDECLARED_EXTENT_WARNING_M: f64 = 200.0;

/// A warning for a scene that declares no unit but is `extent_m` metres across: probably
/// written in millimetres or centimetres, which makes every point, spot and plugin light 10⁴–10⁶×
/// too dark against emissive surfaces.
pub fn undeclared_unit_warning(declared: bool, extent_m: f64) -> Option<String> {
    (!declared && extent_m > UNDECLARED_EXTENT_WARNING_M).then(|| {
        format!(
            "the scene declares no `units`, so its lengths are metres, and it is {extent_m:.0} m              across; if they are millimetres or centimetres, add `units: \"mm\"` (or \"cm\")"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(name: &str, unit: &str, default: Option<&str>) -> ParamDoc {
        ParamDoc {
            name: name.into(),
            unit: unit.into(),
            default: default.map(String::from),
            description: String::new(),
        }
    }

    // The warning comes only for undeclared units and more than 200 m.
    #[test]
    fn large_scene_without_units_is_warned() {
        assert!(undeclared_unit_warning(false, 560.0)
            .unwrap()
            .contains("units: \"mm\""));
        assert_eq!(undeclared_unit_warning(true, 560.0), None);
        assert_eq!(undeclared_unit_warning(false, 150.0), None);
    }

    // Every name parses to its unit and back; factors are the exact definitions.
    #[test]
    fn names_and_factors() {
        for u in LengthUnit::ALL {
            assert_eq!(LengthUnit::parse(u.name()), Ok(u));
        }
        assert_eq!(LengthUnit::Inch.metres(), 0.0254);
        assert!((LengthUnit::Foot.metres() - 12.0 * 0.0254).abs() < 1e-16);
        let e = LengthUnit::parse("yd").unwrap_err();
        assert!(e.contains("`yd`") && e.contains("m, cm, mm, in, ft"), "{e}");
    }

    // Only parameters documented in scene units change (lists at any depth, and defaults when
    // left out); W, degrees and unitless values keep their value; metres change nothing.
    #[test]
    fn only_lengths_are_scaled() {
        let docs = [
            doc("position", SCENE_UNITS, None),
            doc("focus_distance", SCENE_UNITS, Some("1")),
            doc("power", "W", None),
            doc("fov", "degrees", Some("40")),
        ];
        let p: Value =
            ron::from_str("{\"position\": (1000, -250, 2.5), \"power\": 100, \"spd\": \"a\"}")
                .unwrap();
        let m = params_in_metres(&p, &docs, 0.001);
        let expect: Value = ron::from_str(
            "{\"position\": (1.0, -0.25, 0.0025), \"power\": 100, \"spd\": \"a\", \"focus_distance\": 0.001}",
        )
        .unwrap();
        let Value::Map(m) = m else { panic!() };
        let Value::Map(e) = expect else { panic!() };
        for (k, v) in e.iter() {
            let got = m.iter().find(|(x, _)| *x == k).unwrap().1;
            match (got, v) {
                (Value::Number(a), Value::Number(b)) => {
                    assert!((a.into_f64() - b.into_f64()).abs() < 1e-15)
                }
                (Value::Seq(a), Value::Seq(b)) => {
                    for (x, y) in a.iter().zip(b) {
                        let (Value::Number(x), Value::Number(y)) = (x, y) else {
                            panic!()
                        };
                        assert!((x.into_f64() - y.into_f64()).abs() < 1e-15);
                    }
                }
                (a, b) => assert_eq!(a, b),
            }
        }
        assert!(!m.keys().any(|k| *k == Value::String("fov".into())));
        assert_eq!(params_in_metres(&p, &docs, 1.0), p);
    }
}
