//! Writing a `ron::Value` back in the scene's own syntax: structs as `(key: value)`, lists as
//! `(a, b, c)`. `ron::to_string` writes maps as `{"key": value}`, which plugins accept but people
//! should not have to read.

use ron::Value;

/// `value` in scene syntax, one field per line at the top level.
pub fn to_scene_syntax(value: &Value) -> String {
    match value {
        Value::Map(m) if m.iter().all(|(k, _)| matches!(k, Value::String(_))) && !m.is_empty() => {
            let mut out = String::from("(\n");
            for (k, v) in m.iter() {
                if let Value::String(k) = k {
                    out.push_str(&format!("    {k}: {},\n", inline(v)));
                }
            }
            out.push(')');
            out
        }
        other => inline(other),
    }
}

fn inline(value: &Value) -> String {
    match value {
        Value::Map(m) if m.iter().all(|(k, _)| matches!(k, Value::String(_))) => {
            let fields: Vec<String> = m
                .iter()
                .map(|(k, v)| match k {
                    Value::String(k) => format!("{k}: {}", inline(v)),
                    _ => unreachable!("checked above"),
                })
                .collect();
            format!("({})", fields.join(", "))
        }
        Value::Seq(items) => {
            let items: Vec<String> = items.iter().map(inline).collect();
            format!("({})", items.join(", "))
        }
        Value::Option(None) => "None".into(),
        Value::Option(Some(v)) => format!("Some({})", inline(v)),
        other => ron::to_string(other).unwrap_or_else(|_| format!("{other:?}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_back_to_the_same_value() {
        let text = r#"(position: (1, 2.5, -3), spd: "d65", nested: (a: [1, 2]), on: true)"#;
        let v: Value = ron::from_str(text).unwrap();
        let back: Value = ron::from_str(&to_scene_syntax(&v)).unwrap();
        assert_eq!(v, back);
        assert!(to_scene_syntax(&v).contains("position: (1, 2.5, -3)"));
    }
}
