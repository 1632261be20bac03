//! Bit flags describing the kind of a light.

use std::ops::BitOr;

/// A set of light properties.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub struct LightFlags(pub u32);

impl LightFlags {
    /// All light leaves one point (point, spot): cannot be hit by rays.
    pub const DELTA_POSITION: Self = Self(1);
    /// All light travels in one direction (directional): cannot be hit by rays.
    pub const DELTA_DIRECTION: Self = Self(1 << 1);
    /// Emits from a surface that rays can hit.
    pub const AREA: Self = Self(1 << 2);
    /// Only generates beams (the seed's `next_beam` / `number_of_beams`), cannot be evaluated:
    /// handled by light tracing alone.
    pub const BEAMS_ONLY: Self = Self(1 << 3);
    /// Seen by rays that leave the scene (an environment): radiance on escape.
    pub const ENVIRONMENT: Self = Self(1 << 4);

    /// True when every bit of `other` is set.
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// True for point-like or directional lights (pdfs are discrete, MIS must not weight them).
    pub fn is_delta(self) -> bool {
        self.0 & (Self::DELTA_POSITION.0 | Self::DELTA_DIRECTION.0) != 0
    }

    /// True when a ray can find the light: a surface in the scene ([`AREA`](Self::AREA)) or
    /// the environment. Only then do BSDF-sampled hits (PT) and camera paths ending on the light
    /// (BDPT's s = 0) exist as strategies; for every other light, next-event estimation and the
    /// light-subpath strategies are all there is, and MIS must give them the whole weight (a
    /// connectable plugin light without a delta bit and without a surface is such a light).
    pub fn can_be_hit(self) -> bool {
        self.0 & (Self::AREA.0 | Self::ENVIRONMENT.0) != 0
    }
}

impl BitOr for LightFlags {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        Self(self.0 | rhs.0)
    }
}
