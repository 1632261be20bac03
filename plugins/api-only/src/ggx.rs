//! The GGX (Trowbridge–Reitz) microfacet distribution, isotropic, in the local frame (+z the
//! macro normal), with Smith's height-correlated masking-shadowing and sampling of the normals
//! visible from a direction (E. Heitz, "Sampling the GGX Distribution of Visible Normals",
//! JCGT 7(4), 2018), as the built-in conductor uses it.
//!
//! | quantity | formula | unit |
//! |---|---|---|
//! | `d(m)` | 1 / (π α² cos⁴θm (1 + tan²θm/α²)²) | 1/sr (∫ D cos θm dωm = 1) |
//! | `lambda(w)` | (√(1 + α² tan²θ) − 1)/2 | — |
//! | `g(wo, wi)` | 1 / (1 + Λ(wo) + Λ(wi)) | — |
//! | `d_visible(w, m)` | G1(w) max(0, w·m) D(m) / cos θw | 1/sr |
//!
//! Conventions shared with the built-in: α is clamped to at least 1e-4, and below
//! [`SMOOTH_ALPHA`] the surface is a perfect mirror (a delta lobe).

use crate::vec::{cross, normalize, scale};
use spectrace_plugin_api::Vec4f;
use std::f32::consts::PI;

/// Below this α the lobe is a delta (D would overflow single precision), as in the built-in.
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// An isotropic GGX distribution of slope-space width `alpha`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    alpha: f32,
}

impl Ggx {
    /// Width `alpha`, clamped to at least 1e-4 so the formulas stay finite.
    pub fn new(alpha: f32) -> Self {
        Self {
            alpha: alpha.max(1e-4),
        }
    }

    /// True when the lobe must be treated as a delta.
    pub fn smooth(&self) -> bool {
        self.alpha < SMOOTH_ALPHA
    }

    /// Normal density D(m), 1/sr.
    #[inline]
    pub fn d(&self, m: Vec4f) -> f32 {
        let cos2 = m.z * m.z;
        if cos2 <= 0.0 {
            return 0.0;
        }
        // D = 1 / (π α² (sin²θ/α² + cos²θ)²), with sin²θ = x² + y²: the usual tan²θ =
        // (1 − cos²θ)/cos²θ cancels in f32 near the normal, which for a narrow lobe (α ≲ 0.01)
        // moved D by percents between two evaluations of nearly the same direction.
        let a2 = self.alpha * self.alpha;
        let s = (m.x * m.x + m.y * m.y) / a2 + cos2;
        1.0 / (PI * a2 * s * s)
    }

    /// Smith's Λ(w).
    #[inline]
    pub fn lambda(&self, w: Vec4f) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 <= 0.0 {
            return f32::INFINITY;
        }
        // tan²θ from sin²θ = x² + y² (no cancellation near the normal).
        let tan2 = (w.x * w.x + w.y * w.y) / cos2;
        ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0) * 0.5
    }

    /// Height-correlated masking-shadowing G2(wo, wi).
    #[inline]
    pub fn g(&self, wo: Vec4f, wi: Vec4f) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of the normals visible from `w` (`w` above the surface), 1/sr.
    #[inline]
    pub fn d_visible(&self, w: Vec4f, m: Vec4f) -> f32 {
        if w.z == 0.0 {
            return 0.0;
        }
        let g1 = 1.0 / (1.0 + self.lambda(w));
        g1 * w.dot(m).max(0.0) * self.d(m) / w.z.abs()
    }

    /// Draw a normal visible from `w` (above the surface) with `u` in [0, 1)²: stretch `w` so
    /// the distribution becomes a hemisphere, pick a point of the projected visible half-disc,
    /// lift it onto the hemisphere and unstretch.
    #[inline]
    pub fn sample_visible(&self, w: Vec4f, u: [f32; 2]) -> Vec4f {
        let a = self.alpha;
        let v = normalize(Vec4f::new(a * w.x, a * w.y, w.z));
        let r2 = v.x * v.x + v.y * v.y;
        let t1 = if r2 > 1e-7 {
            scale(Vec4f::new(-v.y, v.x, 0.0), 1.0 / r2.sqrt())
        } else {
            Vec4f::new(1.0, 0.0, 0.0)
        };
        let t2 = cross(v, t1);
        let r = u[0].sqrt();
        let phi = 2.0 * PI * u[1];
        let p1 = r * phi.cos();
        let blend = 0.5 * (1.0 + v.z);
        let p2 = (1.0 - blend) * (1.0 - p1 * p1).max(0.0).sqrt() + blend * (r * phi.sin());
        let p3 = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
        let h = Vec4f::new(
            t1.x * p1 + t2.x * p2 + v.x * p3,
            t1.y * p1 + t2.y * p2 + v.y * p3,
            t1.z * p1 + t2.z * p2 + v.z * p3,
        );
        normalize(Vec4f::new(a * h.x, a * h.y, h.z.max(1e-6)))
    }
}
