//! What the host accepts from a plugin call: values it checks before they reach the renderer.
//! A plugin that returns NaN or negative densities or values, non-unit directions or
//! wavelengths out of range gets that result dropped (as "no contribution") and
//! counted per plugin object and reason; the render completes and its summary reports the counts
//! (see `adapter::PluginFaults`). Each check returns the reason it failed.

use spectrace_plugin_api::{Beam, EmittedRay, Incident, Scatter, Vec3, Vec4f, WavelengthSample};

/// Largest accepted deviation of a "unit" direction's length from 1. Plugins compute in f64;
/// 1e-3 leaves room for single-precision plugin arithmetic and still catches unnormalised
/// vectors, which would silently scale every cosine.
pub const UNIT_TOLERANCE: f64 = 1e-3;

/// Why a result was refused.
pub type Reason = &'static str;

fn unit(v: Vec3) -> Result<(), Reason> {
    if v.is_finite() && (v.length() - 1.0).abs() <= UNIT_TOLERANCE {
        Ok(())
    } else {
        Err(BAD_DIRECTION)
    }
}

fn finite_point(p: Vec3) -> Result<(), Reason> {
    if p.is_finite() {
        Ok(())
    } else {
        Err("position not finite")
    }
}

/// A density (1/sr, 1/m², 1/nm): finite and ≥ 0.
pub fn density(p: f64) -> Result<(), Reason> {
    if p.is_finite() && p >= 0.0 {
        Ok(())
    } else {
        Err(BAD_DENSITY)
    }
}

/// The reason [`density`] gives.
pub const BAD_DENSITY: Reason = "pdf NaN, infinite or negative";

/// The reason [`values`] gives.
pub const BAD_VALUE: Reason = "value NaN, infinite or negative";

/// The reason a direction that is not a finite unit vector is refused for.
pub const BAD_DIRECTION: Reason = "direction not a finite unit vector";

/// A plain value (an SPD's value, a power in W): finite and ≥ 0.
pub fn scalar(v: f64) -> Result<(), Reason> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(BAD_VALUE)
    }
}

/// Colour-matching values: finite (sensor curves may dip below 0).
pub fn finite(v: [f64; 3]) -> Result<(), Reason> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err("value NaN or infinite")
    }
}

/// Accepted wavelengths, nm: anything a spectrum could hold. Light outside the observers'
/// 360–830 nm is legitimate (bundled SPDs start at 300 nm) and simply not seen; a wavelength
/// that is zero, negative, NaN or beyond 0.1 mm is a plugin bug (a sign error, a unit mix-up).
pub const WAVELENGTH_RANGE_NM: (f64, f64) = (1.0, 1e5);

/// A wavelength inside [`WAVELENGTH_RANGE_NM`].
pub fn wavelength(nm: f64) -> Result<(), Reason> {
    if (WAVELENGTH_RANGE_NM.0..=WAVELENGTH_RANGE_NM.1).contains(&nm) {
        Ok(())
    } else {
        Err("wavelength not finite or outside 1 nm – 0.1 mm")
    }
}

/// A beam: finite origin, unit direction, wavelength in range, power finite and ≥ 0.
pub fn beam(b: &Beam) -> Result<(), Reason> {
    finite_point(b.origin)?;
    unit(b.direction)?;
    wavelength(b.wavelength_nm)?;
    if b.power_w.is_finite() && b.power_w >= 0.0 {
        Ok(())
    } else {
        Err("beam power NaN, infinite or negative")
    }
}

/// A drawn wavelength: in range, density finite and ≥ 0.
pub fn wavelength_sample(s: &WavelengthSample) -> Result<(), Reason> {
    wavelength(s.nm)?;
    density(s.pdf)
}

// The rules for the single-precision results of the per-sample calls, written
// to cost a few instructions: four lanes compared at once (SIMD, glam's `Vec4`), a NaN failing
// every comparison, single values and squared lengths compared as bit patterns (see
// `non_negative_finite`, `unit_squared`), and every rule of a result combined before one
// branch. Only a refused result takes the slower path that names the rule.

/// `[(1 − UNIT_TOLERANCE)², (1 + UNIT_TOLERANCE)²]`: the squared lengths of an accepted unit
/// vector (the same set as `|length − 1| ≤ UNIT_TOLERANCE`).
const UNIT_SQUARED: (f32, f32) = (
    ((1.0 - UNIT_TOLERANCE) * (1.0 - UNIT_TOLERANCE)) as f32,
    ((1.0 + UNIT_TOLERANCE) * (1.0 + UNIT_TOLERANCE)) as f32,
);

/// True when every lane of `v` is finite and ≥ 0 (NaN fails both comparisons).
#[inline]
fn all_non_negative_finite(v: glam::Vec4) -> bool {
    (v.cmpge(glam::Vec4::ZERO) & v.cmplt(glam::Vec4::INFINITY)).all()
}

/// True when `x` is finite and ≥ 0, in one comparison of bits: `x + 0` turns −0 into +0 and
/// leaves everything else as it is (NaN stays NaN), and the bit patterns below infinity's, as
/// an unsigned number, are exactly +0 and the positive finite numbers (a sign bit or a NaN's
/// exponent lies above). The same set as `x >= 0 && x < ∞`, which the compiler turns into a
/// dozen integer instructions.
#[inline]
fn non_negative_finite(x: f32) -> bool {
    (x + 0.0).to_bits() < f32::INFINITY.to_bits()
}

/// True when the squared length `l2` lies in [`UNIT_SQUARED`], in one comparison of bits: a
/// sum of squares is +0, positive or NaN, and for those the bit patterns are ordered as the
/// values are (a NaN's above infinity's, or with its sign bit set, above every number's), so
/// `lo ≤ l2 ≤ hi` is `bits(l2) − bits(lo) ≤ bits(hi) − bits(lo)` in unsigned arithmetic. The
/// same set as `l2 − lo ≥ 0 && hi − l2 ≥ 0`.
#[inline]
fn unit_squared(l2: f32) -> bool {
    let lo = UNIT_SQUARED.0.to_bits();
    l2.to_bits().wrapping_sub(lo) <= UNIT_SQUARED.1.to_bits() - lo
}

/// The squared length of `v`'s `x, y, z` (its `w` is not looked at).
#[inline]
fn length_squared(v: Vec4f) -> f32 {
    v.x * v.x + v.y * v.y + v.z * v.z
}

#[inline]
fn unit_f32(v: Vec4f) -> bool {
    unit_squared(length_squared(v))
}

/// [`density`] in `f32`.
#[inline]
pub fn density_f32(p: f32) -> Result<(), Reason> {
    // The reason as a constant: with `density(p as f64)` here the compiler merged both tests
    // into the dozen instructions `non_negative_finite` avoids.
    if non_negative_finite(p) {
        Ok(())
    } else {
        Err(BAD_DENSITY)
    }
}

/// Spectral values (radiance, BSDF, …): finite and ≥ 0 in every lane.
#[inline]
pub fn values_f32(v: &[f32; 4]) -> Result<(), Reason> {
    if all_non_negative_finite(glam::Vec4::from_array(*v)) {
        Ok(())
    } else {
        Err(BAD_VALUE)
    }
}

/// [`values_f32`] of the values as one vector.
#[inline]
pub fn vector_f32(v: glam::Vec4) -> Result<(), Reason> {
    if all_non_negative_finite(v) {
        Ok(())
    } else {
        Err(BAD_VALUE)
    }
}

/// A BSDF sample: unit direction, density and values finite and ≥ 0.
#[inline]
pub fn scatter_f32(s: &Scatter) -> Result<(), Reason> {
    let ok = all_non_negative_finite(glam::Vec4::from_array(s.value))
        & non_negative_finite(s.pdf)
        & unit_f32(s.wi);
    if ok {
        Ok(())
    } else {
        scatter_f32_reason(s)
    }
}

/// Which rule a refused sample broke.
#[cold]
fn scatter_f32_reason(s: &Scatter) -> Result<(), Reason> {
    if !unit_f32(s.wi) {
        return Err(BAD_DIRECTION);
    }
    density_f32(s.pdf)?;
    values_f32(&s.value)
}

/// `v`'s `x, y, z` with `w` cleared: one AND of the loaded vector with a lane mask, which keeps
/// the three lanes' bits (building `(x, y, z, 0)` lane by lane took half a dozen shuffles).
#[inline]
fn xyz(v: Vec4f) -> glam::Vec4 {
    glam::Vec4::select(
        glam::BVec4A::new(true, true, true, false),
        glam::Vec4::new(v.x, v.y, v.z, v.w),
        glam::Vec4::ZERO,
    )
}

/// True when `x, y, z` of `v` are finite (its `w` is not looked at): their magnitudes, three
/// lanes at once.
#[inline]
fn finite_f32(v: Vec4f) -> bool {
    all_non_negative_finite(xyz(v).abs())
}

/// An incident sample (next-event estimation): finite point, unit direction, density and
/// values finite and ≥ 0, the point's error bound finite and ≥ 0.
#[inline]
pub fn incident_f32(s: &Incident) -> Result<(), Reason> {
    let ok = all_non_negative_finite(glam::Vec4::from_array(s.value))
        & non_negative_finite(s.pdf)
        & unit_f32(s.direction)
        & all_non_negative_finite(xyz(s.point_error))
        & finite_f32(s.point);
    if ok {
        Ok(())
    } else {
        incident_f32_reason(s)
    }
}

/// Which rule a refused incident sample broke.
#[cold]
fn incident_f32_reason(s: &Incident) -> Result<(), Reason> {
    finite_point(s.point.to_f64())?;
    if !unit_f32(s.direction) {
        return Err(BAD_DIRECTION);
    }
    density_f32(s.pdf)?;
    values_f32(&s.value)?;
    if !all_non_negative_finite(xyz(s.point_error)) {
        return Err("error bound NaN, infinite or negative");
    }
    Ok(())
}

/// An emitted ray (light subpaths): finite origin, unit direction, densities and values finite
/// and ≥ 0.
#[inline]
pub fn emission_f32(s: &EmittedRay) -> Result<(), Reason> {
    let ok = finite_f32(s.origin)
        & unit_f32(s.direction)
        & non_negative_finite(s.pdf_position)
        & non_negative_finite(s.pdf_direction)
        & all_non_negative_finite(glam::Vec4::from_array(s.value));
    if ok {
        Ok(())
    } else {
        emission_f32_reason(s)
    }
}

/// Which rule a refused emitted ray broke.
#[cold]
fn emission_f32_reason(s: &EmittedRay) -> Result<(), Reason> {
    finite_point(s.origin.to_f64())?;
    if !unit_f32(s.direction) {
        return Err(BAD_DIRECTION);
    }
    density_f32(s.pdf_position)?;
    density_f32(s.pdf_direction)?;
    values_f32(&s.value)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Each rule refuses its bad value and accepts the boundary of the good range.
    #[test]
    fn each_rule_refuses_what_it_names() {
        let good = Beam {
            direction: Vec3::new(0.0, 0.0, 1.0),
            wavelength_nm: 550.0,
            power_w: 1.0,
            ..Beam::default()
        };
        assert!(beam(&good).is_ok());
        assert!(beam(&Beam {
            power_w: 0.0,
            ..good
        })
        .is_ok());
        // Outside the observers' 360–830 nm but legitimate (bundled SPDs start at 300 nm).
        for nm in [300.0, 2000.0] {
            assert!(beam(&Beam {
                wavelength_nm: nm,
                ..good
            })
            .is_ok());
        }
        let cases = [
            (
                Beam {
                    power_w: f64::NAN,
                    ..good
                },
                "power",
            ),
            (
                Beam {
                    power_w: -1.0,
                    ..good
                },
                "power",
            ),
            (
                Beam {
                    wavelength_nm: -550.0,
                    ..good
                },
                "wavelength",
            ),
            (
                Beam {
                    wavelength_nm: 2e5,
                    ..good
                },
                "wavelength",
            ),
            (
                Beam {
                    wavelength_nm: f64::NAN,
                    ..good
                },
                "wavelength",
            ),
            (
                Beam {
                    direction: Vec3::new(0.0, 0.0, 2.0),
                    ..good
                },
                "direction",
            ),
            (
                Beam {
                    direction: Vec3::new(f64::NAN, 0.0, 1.0),
                    ..good
                },
                "direction",
            ),
            (
                Beam {
                    origin: Vec3::new(f64::INFINITY, 0.0, 0.0),
                    ..good
                },
                "position",
            ),
        ];
        for (b, what) in cases {
            let e = beam(&b).unwrap_err();
            assert!(e.contains(what), "{b:?}: {e}");
        }
        assert!(density(0.0).is_ok() && density(-1e-30).is_err() && density(f64::NAN).is_err());
        assert!(values_f32(&[0.0; 4]).is_ok());
        assert!(values_f32(&[1.0, -0.5, 0.0, 0.0]).is_err());
    }

    // The comparisons of bits accept exactly what the comparisons of values they replace accept:
    // every sign, exponent and the ends of every mantissa, and a sweep through all bit patterns.
    #[test]
    fn the_bit_comparisons_are_the_value_comparisons() {
        let mut bits: Vec<u32> = (0..=0xffff_ffffu32).step_by(0x3fd).collect();
        for sign in [0, 0x8000_0000u32] {
            for exp in 0..=0xffu32 {
                for mantissa in [0, 1, 2, 0x40_0000, 0x7f_fffe, 0x7f_ffff] {
                    bits.push(sign | exp << 23 | mantissa);
                }
            }
        }
        let (lo, hi) = UNIT_SQUARED;
        bits.extend([lo, hi].iter().flat_map(|b| {
            let b = b.to_bits();
            [b - 1, b, b + 1]
        }));
        for b in bits {
            let x = f32::from_bits(b);
            assert_eq!(
                non_negative_finite(x),
                (0.0..f32::INFINITY).contains(&x),
                "{x:e} ({b:#x})"
            );
            // Squared lengths are +0, positive or NaN (of either sign).
            if x >= 0.0 || x.is_nan() {
                assert_eq!(
                    unit_squared(x),
                    x - lo >= 0.0 && hi - x >= 0.0,
                    "{x:e} ({b:#x})"
                );
            }
        }
    }

    /// Values at the edges of what the checks accept: ±0, the smallest subnormal, the largest
    /// finite, ±∞, NaN and a negative.
    const SPECIAL: [f32; 8] = [
        0.0,
        -0.0,
        f32::from_bits(1),
        f32::MAX,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -1e-30,
    ];

    // `vector_f32` (eval's four values as one vector) accepts and refuses exactly what
    // `values_f32` does, with the same reason: each special value (±0, the smallest subnormal,
    // the largest finite, ±∞, NaN, a negative) in each lane among ordinary values.
    #[test]
    fn the_vector_check_is_the_values_check() {
        for &x in &SPECIAL {
            for lane in 0..4 {
                let mut v = [0.25, 1.0, 3.5, 0.0];
                v[lane] = x;
                assert_eq!(
                    vector_f32(glam::Vec4::from_array(v)).err(),
                    values_f32(&v).err(),
                    "{v:?}"
                );
            }
        }
    }

    // `xyz` (a lane mask) is `(x, y, z, 0)` built lane by lane, bit for bit whatever `w` holds,
    // so the point's and the error bound's checks through it accept and refuse what they did:
    // each special value in each of `x, y, z` and in `w`.
    #[test]
    fn the_lane_mask_is_the_vector_without_w() {
        for &x in &SPECIAL {
            for lane in 0..4 {
                let mut a = [0.25, -1.0, 3.5, 7.0];
                a[lane] = x;
                let v = Vec4f {
                    x: a[0],
                    y: a[1],
                    z: a[2],
                    w: a[3],
                };
                let by_lane = glam::Vec4::new(v.x, v.y, v.z, 0.0);
                let bits = |u: glam::Vec4| u.to_array().map(f32::to_bits);
                assert_eq!(bits(xyz(v)), bits(by_lane), "{a:?}");
                assert_eq!(
                    finite_f32(v),
                    all_non_negative_finite(by_lane.abs()),
                    "{a:?}"
                );
                assert_eq!(
                    all_non_negative_finite(xyz(v)),
                    all_non_negative_finite(by_lane),
                    "{a:?}"
                );
            }
        }
    }

    // The light samples in `f32`: an honest sample passes; each broken field is refused
    // with the reason of its rule (the incident sample's error bound too).
    #[test]
    fn the_v6_light_samples_are_checked_field_by_field() {
        let good = Incident {
            value: [1.0, 2.0, 0.0, 3.0],
            direction: Vec4f::new(0.0, 0.6, 0.8),
            pdf: 1.0,
            point: Vec4f::new(1.0, 2.0, 3.0),
            point_error: Vec4f::new(1e-6, 1e-6, 1e-6),
            normal: Vec4f::default(),
        };
        assert_eq!(incident_f32(&good), Ok(()));
        let bad = [
            (
                Incident {
                    value: [1.0, f32::NAN, 0.0, 0.0],
                    ..good
                },
                "value",
            ),
            (Incident { pdf: -1.0, ..good }, "pdf"),
            (
                Incident {
                    direction: Vec4f::new(0.0, 0.0, 2.0),
                    ..good
                },
                "direction",
            ),
            (
                Incident {
                    point: Vec4f::new(f32::INFINITY, 0.0, 0.0),
                    ..good
                },
                "position",
            ),
            (
                Incident {
                    point_error: Vec4f::new(0.0, -1.0, 0.0),
                    ..good
                },
                "error bound",
            ),
        ];
        for (s, what) in bad {
            let e = incident_f32(&s).unwrap_err();
            assert!(e.contains(what), "{s:?}: {e}");
        }
        let good = EmittedRay {
            origin: Vec4f::new(1.0, 2.0, 3.0),
            direction: Vec4f::new(1.0, 0.0, 0.0),
            value: [1.0; 4],
            pdf_position: 1.0,
            pdf_direction: 0.5,
            normal: Vec4f::default(),
        };
        assert_eq!(emission_f32(&good), Ok(()));
        let bad = [
            (
                EmittedRay {
                    value: [-1.0; 4],
                    ..good
                },
                "value",
            ),
            (
                EmittedRay {
                    pdf_direction: f32::NAN,
                    ..good
                },
                "pdf",
            ),
            (
                EmittedRay {
                    direction: Vec4f::new(0.5, 0.0, 0.0),
                    ..good
                },
                "direction",
            ),
            (
                EmittedRay {
                    origin: Vec4f::new(f32::NAN, 0.0, 0.0),
                    ..good
                },
                "position",
            ),
        ];
        for (s, what) in bad {
            let e = emission_f32(&s).unwrap_err();
            assert!(e.contains(what), "{s:?}: {e}");
        }
    }
}
