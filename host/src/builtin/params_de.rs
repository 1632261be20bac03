//! Reading a scene item's `params` (a `ron::Value`) into a type's serde parameter struct, with
//! errors that name the parameter (`parameter `ior.cauchy`: expected ...`).
//!
//! Written by hand because `ron::Value`'s own deserializer (ron 0.8) neither reads a bare
//! number into an `Option` field (the scene syntax `scale: 2` for `Option<f64>`) nor `()` as an
//! empty struct, and serde's errors do not say which field they came from.

use ron::Value;
use serde::de::{self, DeserializeOwned, DeserializeSeed, IntoDeserializer, Visitor};
use std::fmt;

/// A parameter error with the path of the offending parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamsError {
    /// Outermost first: `["ior", "cauchy"]`.
    pub path: Vec<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ParamsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "params: {}", self.message)
        } else {
            write!(f, "parameter `{}`: {}", self.path.join("."), self.message)
        }
    }
}

impl std::error::Error for ParamsError {}

impl ParamsError {
    /// An error about parameter `name`.
    pub fn at(name: &str, message: impl fmt::Display) -> Self {
        Self {
            path: vec![name.to_string()],
            message: message.to_string(),
        }
    }

    fn within(mut self, key: String) -> Self {
        self.path.insert(0, key);
        self
    }
}

impl de::Error for ParamsError {
    fn custom<T: fmt::Display>(msg: T) -> Self {
        Self {
            path: Vec::new(),
            message: msg.to_string(),
        }
    }

    fn unknown_field(field: &str, expected: &'static [&'static str]) -> Self {
        Self::at(
            field,
            format!(
                "unknown parameter; expected one of: {}",
                expected.join(", ")
            ),
        )
    }

    fn missing_field(field: &'static str) -> Self {
        Self::at(field, "missing")
    }

    fn invalid_type(unexp: de::Unexpected<'_>, exp: &dyn de::Expected) -> Self {
        Self::custom(format_args!("expected {exp}, got {}", describe(unexp)))
    }
}

fn describe(u: de::Unexpected<'_>) -> String {
    match u {
        de::Unexpected::Bool(b) => format!("a bool ({b})"),
        de::Unexpected::Map => "a struct/map".into(),
        de::Unexpected::Seq => "a list".into(),
        de::Unexpected::Unit => "()".into(),
        other => other.to_string(),
    }
}

/// Read `value` into `T`.
pub fn from_value<T: DeserializeOwned>(value: &Value) -> Result<T, ParamsError> {
    T::deserialize(ValueDe(value.clone()))
}

/// A `ron::Value` as a serde deserializer (human readable: the scene's syntax).
pub struct ValueDe(pub Value);

impl<'de> de::Deserializer<'de> for ValueDe {
    type Error = ParamsError;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, ParamsError> {
        match self.0 {
            Value::Bool(b) => visitor.visit_bool(b),
            Value::Char(c) => visitor.visit_char(c),
            Value::Map(m) => {
                let items: Vec<(Value, Value)> = m.into_iter().collect();
                visitor.visit_map(MapAcc {
                    items: items.into_iter(),
                    key: None,
                    value: None,
                })
            }
            Value::Number(ron::Number::Float(f)) => visitor.visit_f64(f.get()),
            Value::Number(ron::Number::Integer(i)) => visitor.visit_i64(i),
            Value::Option(Some(v)) => visitor.visit_some(ValueDe(*v)),
            Value::Option(None) => visitor.visit_none(),
            Value::String(s) => visitor.visit_string(s),
            Value::Seq(s) => visitor.visit_seq(SeqAcc {
                items: s.into_iter(),
                index: 0,
            }),
            Value::Unit => visitor.visit_unit(),
        }
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, ParamsError> {
        match self.0 {
            Value::Option(None) | Value::Unit => visitor.visit_none(),
            Value::Option(Some(v)) => visitor.visit_some(ValueDe(*v)),
            other => visitor.visit_some(ValueDe(other)),
        }
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, ParamsError> {
        match self.0 {
            // `params: ()` or no params at all: every field takes its default.
            Value::Unit => visitor.visit_map(MapAcc {
                items: Vec::new().into_iter(),
                key: None,
                value: None,
            }),
            Value::Map(_) => self.deserialize_any(visitor),
            Value::Option(Some(v)) => ValueDe(*v).deserialize_struct(_name, _fields, visitor),
            other => Err(de::Error::custom(format_args!(
                "expected a struct `(name: value, …)`, got {}",
                crate::scene_file::params::kind_of(&other)
            ))),
        }
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, ParamsError> {
        visitor.visit_newtype_struct(self)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, ParamsError> {
        match self.0 {
            // Unit variants are written as strings: `fov_axis: "x"`.
            Value::String(s) => visitor.visit_enum(s.into_deserializer()),
            other => Err(de::Error::custom(format_args!(
                "expected a name string, got {}",
                crate::scene_file::params::kind_of(&other)
            ))),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf unit unit_struct seq tuple
        tuple_struct map identifier ignored_any
    }
}

struct MapAcc {
    items: std::vec::IntoIter<(Value, Value)>,
    key: Option<String>,
    value: Option<Value>,
}

impl<'de> de::MapAccess<'de> for MapAcc {
    type Error = ParamsError;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, ParamsError> {
        let Some((k, v)) = self.items.next() else {
            return Ok(None);
        };
        self.key = Some(match &k {
            Value::String(s) => s.clone(),
            other => format!("{other:?}"),
        });
        self.value = Some(v);
        seed.deserialize(ValueDe(k)).map(Some)
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(
        &mut self,
        seed: V,
    ) -> Result<V::Value, ParamsError> {
        let key = self.key.take().unwrap_or_default();
        let value = self.value.take().unwrap_or(Value::Unit);
        seed.deserialize(ValueDe(value)).map_err(|e| e.within(key))
    }
}

struct SeqAcc {
    items: std::vec::IntoIter<Value>,
    index: usize,
}

impl<'de> de::SeqAccess<'de> for SeqAcc {
    type Error = ParamsError;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, ParamsError> {
        let Some(v) = self.items.next() else {
            return Ok(None);
        };
        let i = self.index;
        self.index += 1;
        seed.deserialize(ValueDe(v)).map(Some).map_err(|mut e| {
            e.message = format!("entry {i}: {}", e.message);
            e
        })
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.items.len())
    }
}

impl From<ParamsError> for crate::scene_file::FactoryError {
    fn from(e: ParamsError) -> Self {
        crate::scene_file::FactoryError::Param(e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Deserialize, Debug, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct P {
        a: f64,
        #[serde(default)]
        b: Option<f64>,
        #[serde(default)]
        c: Option<Inner>,
    }

    #[derive(Deserialize, Debug, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct Inner {
        x: [f64; 2],
    }

    fn read(text: &str) -> Result<P, ParamsError> {
        from_value(&ron::from_str::<Value>(text).unwrap())
    }

    /// Bare numbers fill `Option` fields, nested errors carry the dotted path, unknown and
    /// missing fields are named.
    #[test]
    fn scene_syntax_and_error_paths() {
        assert_eq!(
            read("(a: 1, b: 2.5)").unwrap(),
            P {
                a: 1.0,
                b: Some(2.5),
                c: None
            }
        );
        let e = read("(a: 1, c: (x: (1, true)))").unwrap_err().to_string();
        assert!(
            e.starts_with("parameter `c.x`") && e.contains("bool"),
            "{e}"
        );
        let e = read("(a: 1, d: 3)").unwrap_err().to_string();
        assert!(e.contains("`d`") && e.contains("unknown parameter"), "{e}");
        let e = read("()").unwrap_err().to_string();
        assert_eq!(e, "parameter `a`: missing");
    }
}
