//! Typed access to an item's `params` block (a `ron::Value`), with errors that name the
//! parameter and say what was expected.

use ron::Value;

/// A parameter error: `param` and what was wrong with it.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamError {
    /// Parameter name (dotted for nested values).
    pub param: String,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "parameter `{}`: {}", self.param, self.message)
    }
}

/// A view of a params map.
#[derive(Clone, Copy, Debug)]
pub struct Params<'a> {
    value: &'a Value,
}

/// Short description of a value's kind for messages.
pub fn kind_of(v: &Value) -> &'static str {
    match v {
        Value::Bool(_) => "a bool",
        Value::Char(_) => "a char",
        Value::Map(_) => "a struct/map",
        Value::Number(_) => "a number",
        Value::Option(_) => "an option",
        Value::String(_) => "a string",
        Value::Seq(_) => "a list",
        Value::Unit => "()",
    }
}

/// A number as f64.
pub fn as_f64(v: &Value) -> Option<f64> {
    match v {
        Value::Number(n) => Some(n.into_f64()),
        Value::Option(Some(b)) => as_f64(b),
        _ => None,
    }
}

/// A list of numbers.
pub fn as_f64_list(v: &Value) -> Option<Vec<f64>> {
    match v {
        Value::Seq(s) => s.iter().map(as_f64).collect(),
        _ => None,
    }
}

impl<'a> Params<'a> {
    /// Wrap a params value (`()` or a map).
    pub fn new(value: &'a Value) -> Self {
        Self { value }
    }

    /// The raw value of parameter `name`.
    pub fn get(&self, name: &str) -> Option<&'a Value> {
        match self.value {
            Value::Map(m) => m.iter().find_map(|(k, v)| match k {
                Value::String(s) if s == name => Some(match v {
                    Value::Option(Some(inner)) => inner.as_ref(),
                    other => other,
                }),
                _ => None,
            }),
            _ => None,
        }
    }

    /// Names of all parameters present.
    pub fn keys(&self) -> Vec<String> {
        match self.value {
            Value::Map(m) => m
                .iter()
                .filter_map(|(k, _)| match k {
                    Value::String(s) => Some(s.clone()),
                    _ => None,
                })
                .collect(),
            _ => Vec::new(),
        }
    }

    /// Fail if a parameter not in `known` is present (catches typos).
    pub fn expect_only(&self, known: &[&str]) -> Result<(), ParamError> {
        for k in self.keys() {
            if !known.contains(&k.as_str()) {
                return Err(ParamError {
                    param: k,
                    message: format!("unknown parameter; expected one of: {}", known.join(", ")),
                });
            }
        }
        if !matches!(self.value, Value::Map(_) | Value::Unit) {
            return Err(ParamError {
                param: "params".into(),
                message: format!("expected a struct, got {}", kind_of(self.value)),
            });
        }
        Ok(())
    }

    fn err(name: &str, message: impl Into<String>) -> ParamError {
        ParamError {
            param: name.to_string(),
            message: message.into(),
        }
    }

    /// Required finite number.
    pub fn f64(&self, name: &str) -> Result<f64, ParamError> {
        let v = self.get(name).ok_or_else(|| Self::err(name, "missing"))?;
        let x = as_f64(v)
            .ok_or_else(|| Self::err(name, format!("expected a number, got {}", kind_of(v))))?;
        if !x.is_finite() {
            return Err(Self::err(name, "must be finite"));
        }
        Ok(x)
    }

    /// Optional finite number with a default.
    pub fn f64_or(&self, name: &str, default: f64) -> Result<f64, ParamError> {
        match self.get(name) {
            None => Ok(default),
            Some(_) => self.f64(name),
        }
    }

    /// Required number as f32.
    pub fn f32(&self, name: &str) -> Result<f32, ParamError> {
        self.f64(name).map(|v| v as f32)
    }

    /// Optional f32.
    pub fn f32_or(&self, name: &str, default: f32) -> Result<f32, ParamError> {
        self.f64_or(name, default as f64).map(|v| v as f32)
    }

    /// Required 3-vector `(x, y, z)`.
    pub fn vec3(&self, name: &str) -> Result<glam::Vec3A, ParamError> {
        let v = self.get(name).ok_or_else(|| Self::err(name, "missing"))?;
        let l = as_f64_list(v)
            .filter(|l| l.len() == 3 && l.iter().all(|x| x.is_finite()))
            .ok_or_else(|| Self::err(name, "expected three finite numbers (x, y, z)"))?;
        Ok(glam::Vec3A::new(l[0] as f32, l[1] as f32, l[2] as f32))
    }

    /// Optional 3-vector.
    pub fn vec3_or(&self, name: &str, default: glam::Vec3A) -> Result<glam::Vec3A, ParamError> {
        match self.get(name) {
            None => Ok(default),
            Some(_) => self.vec3(name),
        }
    }

    /// Required string.
    pub fn string(&self, name: &str) -> Result<&'a str, ParamError> {
        match self.get(name) {
            Some(Value::String(s)) => Ok(s),
            Some(v) => Err(Self::err(
                name,
                format!("expected a string, got {}", kind_of(v)),
            )),
            None => Err(Self::err(name, "missing")),
        }
    }

    /// Optional string.
    pub fn string_opt(&self, name: &str) -> Result<Option<&'a str>, ParamError> {
        match self.get(name) {
            None => Ok(None),
            Some(_) => self.string(name).map(Some),
        }
    }

    /// Optional bool.
    pub fn bool_or(&self, name: &str, default: bool) -> Result<bool, ParamError> {
        match self.get(name) {
            None => Ok(default),
            Some(Value::Bool(b)) => Ok(*b),
            Some(v) => Err(Self::err(
                name,
                format!("expected a bool, got {}", kind_of(v)),
            )),
        }
    }

    /// Optional non-negative integer.
    pub fn u32_or(&self, name: &str, default: u32) -> Result<u32, ParamError> {
        match self.get(name) {
            None => Ok(default),
            Some(_) => {
                let x = self.f64(name)?;
                if x < 0.0 || x.fract() != 0.0 || x > u32::MAX as f64 {
                    return Err(Self::err(name, "expected a non-negative integer"));
                }
                Ok(x as u32)
            }
        }
    }
}
