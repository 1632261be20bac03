//! The few single-precision vector operations the material needs, on the API's [`Vec4f`]
//! (x, y, z; `w` unused). Written here because the plugin links nothing but the API; single
//! precision because the host's records are, so values agree with the built-ins to f32 rounding.

use spectrace_plugin_api::Vec4f;

/// `a + b`.
#[inline]
pub fn add(a: Vec4f, b: Vec4f) -> Vec4f {
    Vec4f::new(a.x + b.x, a.y + b.y, a.z + b.z)
}

/// `v · s`.
#[inline]
pub fn scale(v: Vec4f, s: f32) -> Vec4f {
    Vec4f::new(v.x * s, v.y * s, v.z * s)
}

/// `a × b`.
#[inline]
pub fn cross(a: Vec4f, b: Vec4f) -> Vec4f {
    Vec4f::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

/// Squared length.
#[inline]
pub fn length2(v: Vec4f) -> f32 {
    v.dot(v)
}

/// `v` scaled to unit length.
#[inline]
pub fn normalize(v: Vec4f) -> Vec4f {
    scale(v, 1.0 / length2(v).sqrt())
}

/// The mirror direction of `w` about the unit normal `n`: `2 (w·n) n − w`.
#[inline]
pub fn reflect(w: Vec4f, n: Vec4f) -> Vec4f {
    let d = 2.0 * w.dot(n);
    Vec4f::new(d * n.x - w.x, d * n.y - w.y, d * n.z - w.z)
}

/// `v` with its `w` set to 0 (a host may lend vectors with anything in `w`).
#[inline]
pub fn xyz(v: &Vec4f) -> Vec4f {
    Vec4f::new(v.x, v.y, v.z)
}
