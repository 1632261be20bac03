//! RON value helpers of the Mitsuba converter: numbers, sequences and maps as the scene
//! description holds them, and the lookups and edits of material parameters.

use glam::DVec3;
use ron::Value;

pub(crate) fn num(x: f64) -> Value {
    Value::Number(ron::Number::from(x))
}
pub(super) fn text(s: &str) -> Value {
    Value::String(s.to_string())
}
pub(super) fn seq(items: Vec<Value>) -> Value {
    Value::Seq(items)
}
pub(super) fn v3(v: DVec3) -> Value {
    seq(vec![num(v.x), num(v.y), num(v.z)])
}
pub(super) fn map(entries: Vec<(&str, Value)>) -> Value {
    let mut m = ron::Map::new();
    for (k, v) in entries {
        m.insert(text(k), v);
    }
    Value::Map(m)
}
pub(super) fn table(t: &[(f64, f64)]) -> Value {
    seq(t.iter().map(|&(l, v)| seq(vec![num(l), num(v)])).collect())
}

/// Numbers in a Mitsuba attribute: separated by commas and/or white space.
/// The RGB triple of a converted reflectance: a number (grey) or `(rgb: [r, g, b])`.
pub(super) fn rgb_of(v: &Value) -> Option<[f64; 3]> {
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

/// The value of key `k` in a RON map.
pub(super) fn value_at<'v>(v: &'v Value, k: &str) -> Option<&'v Value> {
    match v {
        Value::Map(m) => m
            .iter()
            .find(|(key, _)| matches!(key, Value::String(s) if s == k))
            .map(|(_, v)| v),
        _ => None,
    }
}

pub(super) fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Number(x) => Some(x.into_f64()),
        _ => None,
    }
}

/// True when a material's parameters hold an image texture anywhere.
pub(super) fn has_texture(v: &Value) -> bool {
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
pub(super) fn flip_texture_v(v: &mut Value) {
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
