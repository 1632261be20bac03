//! First derivatives of a surface point and its unit shading normal with respect to the
//! shape's own parameters `(u, v)`: what a specular-chain (manifold) solve needs to move a
//! vertex along its surface and to know how the normal turns as it moves (Jakob & Marschner
//! 2012, "Manifold Exploration", §4; Hanika, Droske & Fascione 2015, "Manifold Next Event
//! Estimation").
//!
//! | field  | unit                 | meaning                                        |
//! |--------|----------------------|------------------------------------------------|
//! | `dpdu` | scene units per `u`  | ∂p/∂u, tangent to the (geometric) surface      |
//! | `dpdv` | scene units per `v`  | ∂p/∂v                                          |
//! | `dndu` | 1 per `u`            | ∂n/∂u of the unit shading normal (⊥ n)         |
//! | `dndv` | 1 per `v`            | ∂n/∂v                                          |
//!
//! The parameters are each shape's own: `(φ/2π, θ/π)` on spheres, `(s, t)` along the edges on
//! quads, the barycentrics `(b1, b2)` on triangles. Callers that need an orthonormal chart build
//! it from these (see `integrator::connect::specular_chain`).

use glam::Vec3A;

/// ∂p/∂(u, v) and ∂n/∂(u, v) at one surface point (world space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivatives {
    /// ∂p/∂u (scene units per unit of u).
    pub dpdu: Vec3A,
    /// ∂p/∂v (scene units per unit of v).
    pub dpdv: Vec3A,
    /// ∂n/∂u of the unit shading normal.
    pub dndu: Vec3A,
    /// ∂n/∂v of the unit shading normal.
    pub dndv: Vec3A,
}

impl SurfaceDerivatives {
    /// A flat patch spanned by `dpdu`, `dpdv`: the normal does not turn.
    pub fn flat(dpdu: Vec3A, dpdv: Vec3A) -> Self {
        Self {
            dpdu,
            dpdv,
            dndu: Vec3A::ZERO,
            dndv: Vec3A::ZERO,
        }
    }
}
