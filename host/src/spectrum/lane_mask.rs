//! Which wavelength lanes of a path still carry light.
//!
//! A path starts with every lane live. A wavelength-dependent (dispersive) scattering event
//! sends each wavelength in its own direction, so only the hero lane (lane 0), whose wavelength
//! chose the direction, stays valid; the event terminates the other lanes. The mask travels with
//! the wavelengths ([`SampledWavelengths::lanes`](super::SampledWavelengths)) and with every
//! subpath vertex, and the film weighting reads it: a lane outside the mask contributes nothing,
//! and the estimate becomes the mean over the live lanes only (for the hero alone:
//! `L(λ₀)/pdf(λ₀)`, i.e. the hero's pdf becomes the single-lane pdf).

/// Number of wavelengths traced together along one path.
pub const LANES: usize = 4;

/// A set of live lanes, one bit per lane (bit `i` = lane `i`; lane 0 is the hero).
/// `#[repr(transparent)]`: one byte, the plugin interface's live-lane bits (`plugin::layout`).
#[repr(transparent)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LaneMask(u8);

const _: () = assert!(LANES <= 8, "LaneMask stores one bit per lane in a u8");

impl LaneMask {
    /// Every lane live (no wavelength-dependent event yet).
    pub const ALL: Self = Self(((1u16 << LANES) - 1) as u8);
    /// Only the hero lane live (after a dispersive event).
    pub const HERO: Self = Self(1);
    /// No lane live.
    pub const NONE: Self = Self(0);

    /// The lanes as bits (bit `i` = lane `i`), e.g. for the plugin interface.
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// The lanes of `bits` (bit `i` = lane `i`); bits beyond [`LANES`] are dropped.
    pub const fn from_bits(bits: u8) -> Self {
        Self(bits & Self::ALL.0)
    }

    /// True when lane `i` is live.
    #[inline]
    pub fn contains(self, i: usize) -> bool {
        i < LANES && self.0 & (1 << i) != 0
    }

    /// Number of live lanes.
    #[inline]
    pub fn count(self) -> u32 {
        self.0.count_ones()
    }

    /// True when every lane is live.
    #[inline]
    pub fn is_all(self) -> bool {
        self == Self::ALL
    }

    /// Lanes live in both (a BDPT connection joins two subpaths: a lane is valid only if it is
    /// valid on both).
    #[inline]
    pub fn intersect(self, other: Self) -> Self {
        Self(self.0 & other.0)
    }

    /// Lanes live in either (bdpt: the lanes a fluorescent shift moved on either subpath).
    #[inline]
    pub fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// This mask with lane `i` added (ignored for `i ≥ LANES`).
    #[inline]
    pub fn with(self, i: usize) -> Self {
        if i < LANES {
            Self(self.0 | (1 << i))
        } else {
            self
        }
    }

    /// The mask after a dispersive event: the hero alone, if it was live.
    #[inline]
    pub fn terminate_secondary(self) -> Self {
        self.intersect(Self::HERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_compose() {
        assert_eq!(LaneMask::ALL.count(), LANES as u32);
        assert!(LaneMask::ALL.is_all());
        assert_eq!(LaneMask::ALL.terminate_secondary(), LaneMask::HERO);
        assert_eq!(LaneMask::NONE.terminate_secondary(), LaneMask::NONE);
        assert_eq!(LaneMask::ALL.intersect(LaneMask::HERO), LaneMask::HERO);
        assert!(LaneMask::HERO.contains(0) && !LaneMask::HERO.contains(1));
        assert!(!LaneMask::ALL.contains(LANES));
    }
}
