//! The render loop's data, in the host's own single-precision layout: what the per-sample calls
//! of [`Material`](crate::Material) and [`LightSource`](crate::LightSource) take and write.
//!
//! Every type here is laid out exactly as the host keeps the same data (16-byte SIMD vectors,
//! four wavelength lanes of `f32`), so the host passes its own records by reference and a plugin
//! writes its answers into the host's records in place: nothing is converted or copied on
//! either side of the boundary.
//!
//! | type | fields | units |
//! |---|---|---|
//! | [`Vec4f`] | `x, y, z` and an unused `w` | scene units, or a unit direction |
//! | [`Surface`] | texture coordinates, position, geometric and shading normal (world) | scene units; normals unit, zero when unknown |
//! | [`Wavelengths`] | wavelength per lane, its sampling density, live-lane bits | nm, 1/nm |
//! | [`Values`] | one value per lane, returned by value | per call |
//! | [`Scatter`] | sampled `wi` (local frame), BSDF value per lane, density, event bits, relative IOR | 1/sr, 1/sr |
//! | [`Receiver`] | the point a light is sampled from: position, its error bound, geometric normal | scene units |
//! | [`Incident`] | radiance per lane, unit direction to the light, density, point on the light, its error bound, light normal | W/(m²·sr·nm), 1/sr, scene units |
//! | [`EmittedRay`] | origin, unit direction, emitted value per lane, densities of origin and direction, normal | scene units, W/(sr·nm) or W/(m²·sr·nm), 1/m², 1/sr |
//! | [`EmissionPdf`] | densities of an emitted ray's origin and direction | 1/m², 1/sr |
//!
//! Vectors the host lends (`wo`, `wi`, the surface, the receiver) may hold anything in `w`:
//! read `x, y, z` only.

use crate::types::{Flags, Vec3, LANES};
use abi_stable::StableAbi;

/// A 3-vector in the host's 16-byte SIMD layout: `x, y, z` and an unused `w`.
#[repr(C, align(16))]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec4f {
    /// x
    pub x: f32,
    /// y
    pub y: f32,
    /// z
    pub z: f32,
    /// Unused; there for the layout. Not to be read.
    pub w: f32,
}

impl Vec4f {
    /// Build from components (`w` = 0).
    #[inline]
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Self { x, y, z, w: 0.0 }
    }
    /// As an `f64` vector (exact).
    #[inline]
    pub fn to_f64(self) -> Vec3 {
        Vec3::new(self.x as f64, self.y as f64, self.z as f64)
    }
    /// From an `f64` vector, rounded to `f32`.
    #[inline]
    pub fn from_f64(v: Vec3) -> Self {
        Self::new(v.x as f32, v.y as f32, v.z as f32)
    }
    /// Dot product of the `x, y, z` parts.
    #[inline]
    pub fn dot(self, o: Self) -> f32 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
}

/// Where on the surface a material is evaluated. The local frame's z axis is the shading normal.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct Surface {
    /// Texture coordinates.
    pub uv: [f32; 2],
    /// World-space position (scene units).
    pub position: Vec4f,
    /// Geometric normal, world space, unit (zero when unknown).
    pub geometric_normal: Vec4f,
    /// Shading normal, world space, unit: the local frame's z axis (zero when unknown).
    pub shading_normal: Vec4f,
}

/// The wavelengths one path carries: nm per lane (lane 0 the hero), each lane's sampling density
/// (1/nm; 0 for a terminated lane or one on a spectral line) and which lanes still carry light
/// (bit i = lane i; the three bytes after `live` are padding, not to be read).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct Wavelengths {
    /// Wavelengths, nm.
    pub nm: [f32; LANES],
    /// Sampling densities, 1/nm.
    pub pdf: [f32; LANES],
    /// Live lanes, one bit per lane.
    pub live: u8,
}

impl Wavelengths {
    /// All four lanes live at the given wavelengths (densities 1/nm each: for tests and tools).
    pub fn at(nm: [f32; LANES]) -> Self {
        Self {
            nm,
            pdf: [1.0; LANES],
            live: (1 << LANES) - 1,
        }
    }
}

/// One value per wavelength lane, returned by value (two SIMD registers on x86-64). All lanes NaN
/// means the call failed (see [`status`]).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct Values {
    /// The value of each lane.
    pub v: [f32; LANES],
}

impl Values {
    /// Every lane zero.
    pub const ZERO: Self = Self { v: [0.0; LANES] };
    /// What a failed call answers: NaN in every lane.
    pub const FAILED: Self = Self {
        v: [f32::NAN; LANES],
    };
}

/// A sampled scattering direction, written by [`Material::sample`](crate::Material::sample) into
/// the host's record.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct Scatter {
    /// Incident direction (local frame, away from the surface), unit.
    pub wi: Vec4f,
    /// BSDF value per lane (1/sr); for delta lobes the delta's weight divided by |cos θi|, so
    /// that `value·|cos θi|/pdf` is the throughput factor in every case.
    pub value: [f32; LANES],
    /// Solid-angle density of `wi` (1/sr); for delta lobes the discrete lobe probability.
    pub pdf: f32,
    /// Bits of this event ([`material_flags`](crate::material_flags): DIFFUSE, GLOSSY,
    /// SPECULAR, TRANSMISSION, DISPERSIVE).
    pub flags: Flags,
    /// Relative index of refraction across the surface for transmission, else 1.
    pub eta: f32,
}

/// The point a light is sampled from, lent by the host.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct Receiver {
    /// The point being lit (world, scene units).
    pub p: Vec4f,
    /// Its floating-point error bound per axis (scene units; 0 when unknown).
    pub p_error: Vec4f,
    /// Its geometric normal (world, unit; zero for points in media).
    pub n: Vec4f,
}

/// A point on a light chosen as seen from a receiver, written by
/// [`LightSource::sample_toward`](crate::LightSource::sample_toward) into the host's record. No
/// distance: the host measures it from the two points.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct Incident {
    /// Radiance arriving at the receiver per lane, W/(m²·sr·nm) (for delta lights `I/d²`).
    pub value: [f32; LANES],
    /// Unit direction from the receiver towards the light.
    pub direction: Vec4f,
    /// Solid-angle density of `direction` (1/sr), or 1 for delta lights; 0: no sample.
    pub pdf: f32,
    /// The point on the light (scene units).
    pub point: Vec4f,
    /// Its floating-point error bound per axis (0 when exact).
    pub point_error: Vec4f,
    /// Light surface normal at `point`; zero when the light has no surface.
    pub normal: Vec4f,
}

/// A ray leaving a light, written by
/// [`LightSource::sample_emission`](crate::LightSource::sample_emission).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct EmittedRay {
    /// Start point (scene units).
    pub origin: Vec4f,
    /// Unit direction of travel.
    pub direction: Vec4f,
    /// Emitted value per lane: intensity W/(sr·nm) for point-like sources, radiance
    /// W/(m²·sr·nm) for surfaces.
    pub value: [f32; LANES],
    /// Density of `origin`: per area (1/m²), or 1 for a delta position; 0: no sample.
    pub pdf_position: f32,
    /// Density of `direction`: per solid angle (1/sr), or 1 for a delta direction; 0: no sample.
    pub pdf_direction: f32,
    /// Surface normal at `origin`; zero for lights without a surface.
    pub normal: Vec4f,
}

impl EmittedRay {
    /// The beam this emission sample stands for, for a light that implements
    /// [`next_beam`](crate::LightSource::next_beam) by sampling its own emission: draw the
    /// wavelength from the emission spectrum (`wavelength_nm`, with density `wavelength_pdf`:
    /// 1/nm, or the discrete probability of a spectral line), fill this ray for it in lane 0
    /// (as [`sample_emission`](crate::LightSource::sample_emission) does), then
    ///
    /// `power_w = value[0] · |cos θ| / (pdf_position · pdf_direction · wavelength_pdf)` W,
    ///
    /// the one-sample estimate of the whole light's radiant flux, which is what a
    /// [`Beam`](crate::Beam) carries (θ between `normal` and `direction`; |cos θ| = 1 when
    /// `normal` is zero, as for point-like lights; a delta position or direction has density 1).
    /// `None` when a density is not positive or the power is not finite and ≥ 0: no beam.
    pub fn to_beam(&self, wavelength_nm: f64, wavelength_pdf: f64) -> Option<crate::Beam> {
        let (pos, dir) = (self.pdf_position as f64, self.pdf_direction as f64);
        if !(pos > 0.0 && dir > 0.0 && wavelength_pdf > 0.0) {
            return None;
        }
        let (d, n) = (self.direction.to_f64(), self.normal.to_f64());
        let cos = if n == Vec3::default() {
            1.0
        } else {
            n.dot(d).abs()
        };
        let power_w = self.value[0] as f64 * cos / (pos * dir * wavelength_pdf);
        if !(power_w.is_finite() && power_w >= 0.0) {
            return None;
        }
        Some(crate::Beam {
            origin: self.origin.to_f64(),
            direction: d,
            wavelength_nm,
            power_w,
            source_id: 0,
        })
    }
}

/// The densities with which [`LightSource::sample_emission`](crate::LightSource::sample_emission)
/// would produce a given ray, returned by value (NaN in both: the call failed).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct EmissionPdf {
    /// Per area (1/m²), or 1 for a delta position.
    pub position: f32,
    /// Per solid angle (1/sr), or 1 for a delta direction.
    pub direction: f32,
}

/// What a per-sample call that writes a record answers, as one word. A plain `u32` rather than an
/// enum so that any value a plugin returns is a valid one; the host treats every other value as
/// an error of the plugin. Calls that return values instead ([`Values`], `f32`,
/// [`EmissionPdf`]) answer NaN when they fail. Either way the error itself is kept on the
/// plugin's side of the calling thread and taken by the host through the root module's
/// `take_error` (see [`crate::guard`]): a call that succeeds carries nothing for it.
pub mod status {
    /// Nothing sampled (absorbed, or no light towards the receiver); the record is untouched.
    pub const NONE: u32 = 0;
    /// The record was written.
    pub const WRITTEN: u32 = 1;
    /// The call failed (an error, or a panic caught on the plugin's side): its error is kept
    /// for `take_error`; the record is not to be read.
    pub const ERROR: u32 = 2;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `to_beam` against the formula worked by hand: value 2 W/(m²·sr·nm), densities 0.5 /m²,
    /// 0.25 /sr and 0.01 /nm, the normal at 60° to the direction (|cos θ| = 1/2):
    /// 2 · 0.5 / (0.5 · 0.25 · 0.01) = 800 W. Tolerance 1e-12 relative: cos θ is the
    /// direction's y, 0.5 exactly, so only the f64 division rounds.
    #[test]
    fn to_beam_is_the_one_sample_flux_estimate() {
        let c = 0.5f32;
        let s = (0.75f32).sqrt();
        let ray = EmittedRay {
            origin: Vec4f::new(1.0, 2.0, 3.0),
            direction: Vec4f::new(s, c, 0.0),
            value: [2.0, 9.0, 9.0, 9.0],
            pdf_position: 0.5,
            pdf_direction: 0.25,
            normal: Vec4f::new(0.0, 1.0, 0.0),
        };
        let b = ray.to_beam(550.0, 0.01).expect("a beam");
        assert!((b.power_w / 800.0 - 1.0).abs() < 1e-12, "{}", b.power_w);
        assert_eq!(b.wavelength_nm, 550.0);
        assert_eq!(b.origin, Vec3::new(1.0, 2.0, 3.0));
        // No surface: |cos θ| = 1.
        let point = EmittedRay {
            normal: Vec4f::default(),
            ..ray
        };
        let b = point.to_beam(550.0, 0.01).expect("a beam");
        assert!((b.power_w / 1600.0 - 1.0).abs() < 1e-12, "{}", b.power_w);
        // No sample: a density of 0 anywhere, or a power that is not finite and ≥ 0.
        for bad in [
            EmittedRay {
                pdf_position: 0.0,
                ..ray
            },
            EmittedRay {
                pdf_direction: 0.0,
                ..ray
            },
            EmittedRay {
                value: [-1.0; LANES],
                ..ray
            },
            EmittedRay {
                value: [f32::NAN; LANES],
                ..ray
            },
        ] {
            assert_eq!(bad.to_beam(550.0, 0.01), None);
        }
        assert_eq!(ray.to_beam(550.0, 0.0), None);
    }
}
