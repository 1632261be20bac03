//! Optional parameters written bare in a scene (`roughness: 0.3`, not `Some(0.3)`).
//!
//! The API hands a type its parameters as a RON value converted with serde
//! ([`parse_params`](spectrace_plugin_api::export::parse_params)), and a RON value asked for an
//! `Option` answers with the bare value, which serde's own `Option` refuses ("expected option").
//! [`bare`] reads either form: the bare value as `Some`, `None`/`Some(x)` as themselves, and the
//! tagged form of saved state (bincode). Use it as
//! `#[serde(default, deserialize_with = "crate::params::bare")]`.

use serde::de::{self, value, Deserialize, Deserializer, IntoDeserializer, Visitor};
use std::fmt;
use std::marker::PhantomData;

/// Deserialise an `Option<T>` from a bare `T`, `None`, `Some(T)` or bincode's tagged option.
pub fn bare<'de, D, T>(d: D) -> Result<Option<T>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    d.deserialize_option(Bare(PhantomData))
}

struct Bare<T>(PhantomData<T>);

macro_rules! scalar {
    ($($visit:ident: $t:ty),*) => {
        $(fn $visit<E: de::Error>(self, v: $t) -> Result<Self::Value, E> {
            T::deserialize(v.into_deserializer()).map(Some)
        })*
    };
}

impl<'de, T: Deserialize<'de>> Visitor<'de> for Bare<T> {
    type Value = Option<T>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a value, or None / Some(value)")
    }
    fn visit_none<E: de::Error>(self) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_unit<E: de::Error>(self) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_some<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        T::deserialize(d).map(Some)
    }
    scalar!(visit_bool: bool, visit_i64: i64, visit_u64: u64, visit_f64: f64, visit_char: char,
        visit_string: String);
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
        T::deserialize(value::StrDeserializer::<E>::new(v)).map(Some)
    }
    fn visit_seq<A: de::SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
        T::deserialize(value::SeqAccessDeserializer::new(seq)).map(Some)
    }
    fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
        T::deserialize(value::MapAccessDeserializer::new(map)).map(Some)
    }
}

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct P {
        #[serde(default, deserialize_with = "super::bare")]
        a: Option<f64>,
        #[serde(default, deserialize_with = "super::bare")]
        s: Option<String>,
        #[serde(default, deserialize_with = "super::bare")]
        v: Option<Vec<(f64, f64)>>,
    }

    /// Bare values, `Some(..)`, absent fields, and the bincode state round trip.
    #[test]
    fn bare_and_tagged_forms() {
        let parse = |t: &str| -> P { spectrace_plugin_api::export::parse_params("t", t).unwrap() };
        let want = P {
            a: Some(0.5),
            s: Some("gold".into()),
            v: Some(vec![(400.0, 1.0), (500.0, 2.0)]),
        };
        assert_eq!(
            parse("(a: 0.5, s: \"gold\", v: [(400, 1), (500, 2)])"),
            want
        );
        assert_eq!(
            parse("{\"a\": 0.5, \"s\": \"gold\", \"v\": [[400, 1], [500, 2]]}"),
            want
        );
        assert_eq!(
            parse("(a: Some(0.5), s: Some(\"gold\"), v: Some([(400, 1), (500, 2)]))"),
            want
        );
        assert_eq!(
            parse("()"),
            P {
                a: None,
                s: None,
                v: None
            }
        );
        let bytes = spectrace_plugin_api::export::encode_state(&want).unwrap();
        let back: P = spectrace_plugin_api::export::decode_state("t", &bytes).unwrap();
        assert_eq!(back, want);
    }
}
