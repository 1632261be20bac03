//! The spatial half of a beam-representation adapter: plugin length units to scene units
//! (metres), left-handed axes to the host's right-handed ones (z negated), and two angles to a
//! unit vector. Each conversion is a pure function, tested on its own below.

use spectrace_plugin_api::{BeamRepresentation, DirectionEncoding, Handedness, Vec3};

/// Metres per unit of the host's world: scenes are converted to metres when built, whatever
/// their `units` (see `scene_file::units`), so a beam's `power_w` and a radiance's m² hold.
pub const SCENE_METRES_PER_UNIT: f64 = 1.0;

/// Converts origins and directions of one declared representation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpatialAdapter {
    /// Scene units per plugin unit.
    scale: f64,
    /// Negate z (left-handed plugin axes).
    flip_z: bool,
    /// Directions come as `[θ, φ, 0]`.
    angles: bool,
}

impl SpatialAdapter {
    /// The adapter for `repr`; an error names a unit that is not finite and positive.
    pub fn new(repr: &BeamRepresentation) -> Result<Self, String> {
        let m = repr.metres_per_unit;
        if !(m.is_finite() && m > 0.0) {
            return Err(format!(
                "declared beam representation: metres_per_unit must be finite and > 0, got {m}"
            ));
        }
        Ok(Self {
            scale: m / SCENE_METRES_PER_UNIT,
            flip_z: repr.handedness == Handedness::Left,
            angles: repr.direction == DirectionEncoding::Angles,
        })
    }

    fn axes(&self, v: Vec3) -> Vec3 {
        if self.flip_z {
            Vec3::new(v.x, v.y, -v.z)
        } else {
            v
        }
    }

    /// A point in plugin units and axes, in scene units and axes.
    pub fn origin(&self, p: Vec3) -> Vec3 {
        self.axes(p * self.scale)
    }

    /// A direction as the plugin writes it, as a host vector (not normalised here: the caller
    /// checks that it is a unit vector). Lengths do not scale.
    pub fn direction(&self, d: [f64; 3]) -> Vec3 {
        let v = if self.angles {
            angles_to_vector(d[0], d[1])
        } else {
            Vec3::new(d[0], d[1], d[2])
        };
        self.axes(v)
    }
}

/// `(sin θ cos φ, cos θ, sin θ sin φ)`: polar angle θ from +y, azimuth φ from +x towards +z.
pub fn angles_to_vector(theta: f64, phi: f64) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * cp, ct, st * sp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use spectrace_plugin_api::ColourEncoding;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn repr(m: f64, h: Handedness, d: DirectionEncoding) -> BeamRepresentation {
        BeamRepresentation {
            metres_per_unit: m,
            handedness: h,
            direction: d,
            colour: ColourEncoding::Spectral,
        }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-12
    }

    // Units: 2500 mm is 2.5 m; directions keep their length (exact up to rounding, 1e-12).
    #[test]
    fn millimetres_become_metres() {
        let a = SpatialAdapter::new(&repr(
            0.001,
            Handedness::Right,
            DirectionEncoding::UnitVector,
        ))
        .unwrap();
        assert!(close(
            a.origin(Vec3::new(2500.0, -40.0, 1.0)),
            Vec3::new(2.5, -0.04, 0.001)
        ));
        assert!(close(
            a.direction([0.0, 0.0, 1.0]),
            Vec3::new(0.0, 0.0, 1.0)
        ));
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e =
                SpatialAdapter::new(&repr(bad, Handedness::Right, DirectionEncoding::UnitVector))
                    .unwrap_err();
            assert!(e.contains("metres_per_unit"), "{e}");
        }
    }

    // Handedness: a left-handed frame has +z away from the viewer, so z of points and directions
    // changes sign and x, y stay; a cross product in the plugin frame maps to minus the host's
    // cross product of the mapped vectors (the orientation really flips).
    #[test]
    fn left_handed_axes_flip_z() {
        let a = SpatialAdapter::new(&repr(1.0, Handedness::Left, DirectionEncoding::UnitVector))
            .unwrap();
        assert!(close(
            a.origin(Vec3::new(1.0, 2.0, 3.0)),
            Vec3::new(1.0, 2.0, -3.0)
        ));
        let (x, y) = (a.direction([1.0, 0.0, 0.0]), a.direction([0.0, 1.0, 0.0]));
        let z_plugin = Vec3::new(1.0, 0.0, 0.0).cross(Vec3::new(0.0, 1.0, 0.0));
        let z_mapped = a.direction([z_plugin.x, z_plugin.y, z_plugin.z]);
        assert!(close(z_mapped, -x.cross(y)));
        let r = SpatialAdapter::new(&repr(1.0, Handedness::Right, DirectionEncoding::UnitVector))
            .unwrap();
        assert!(close(
            r.origin(Vec3::new(1.0, 2.0, 3.0)),
            Vec3::new(1.0, 2.0, 3.0)
        ));
    }

    // Angles: θ from +y, φ from +x towards +z; every output is a unit vector (1e-12) and the
    // axes come out where the convention puts them.
    #[test]
    fn two_angles_become_a_unit_vector() {
        let a =
            SpatialAdapter::new(&repr(1.0, Handedness::Right, DirectionEncoding::Angles)).unwrap();
        assert!(close(
            a.direction([0.0, 1.234, 0.0]),
            Vec3::new(0.0, 1.0, 0.0)
        ));
        assert!(close(
            a.direction([PI, 0.0, 0.0]),
            Vec3::new(0.0, -1.0, 0.0)
        ));
        assert!(close(
            a.direction([FRAC_PI_2, 0.0, 0.0]),
            Vec3::new(1.0, 0.0, 0.0)
        ));
        assert!(close(
            a.direction([FRAC_PI_2, FRAC_PI_2, 0.0]),
            Vec3::new(0.0, 0.0, 1.0)
        ));
        for i in 0..100 {
            let (t, p) = (i as f64 * 0.0317, i as f64 * 0.173 - 3.0);
            assert!((a.direction([t, p, 0.0]).length() - 1.0).abs() < 1e-12);
        }
        // With left-handed axes the same angles point to -z.
        let l =
            SpatialAdapter::new(&repr(1.0, Handedness::Left, DirectionEncoding::Angles)).unwrap();
        assert!(close(
            l.direction([FRAC_PI_2, FRAC_PI_2, 0.0]),
            Vec3::new(0.0, 0.0, -1.0)
        ));
    }
}
