//! Bit flags describing what a material (or one sampled lobe of it) does.

use std::ops::{BitAnd, BitOr, BitOrAssign};

/// A set of material properties. The integrator only asks questions such as "is this a delta
/// lobe?" or "did this event depend on wavelength?"; it never asks which material it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub struct MaterialFlags(pub u32);

impl MaterialFlags {
    /// Nothing.
    pub const NONE: Self = Self(0);
    /// Scatters into the hemisphere of the incident light.
    pub const REFLECTION: Self = Self(1);
    /// Scatters through the surface.
    pub const TRANSMISSION: Self = Self(1 << 1);
    /// Lambertian-like lobe.
    pub const DIFFUSE: Self = Self(1 << 2);
    /// Rough but directional lobe (microfacets).
    pub const GLOSSY: Self = Self(1 << 3);
    /// Dirac delta lobe (mirror, smooth glass): cannot be evaluated, only sampled.
    pub const SPECULAR: Self = Self(1 << 4);
    /// Wavelength-dependent scattering direction: the integrator must keep only the hero lane
    /// (`SampledWavelengths::terminate_secondary`).
    pub const DISPERSIVE: Self = Self(1 << 5);
    /// Emits light (an area light's surface).
    pub const EMISSIVE: Self = Self(1 << 6);
    /// Re-emits light at other (longer) wavelengths: the path's wavelength changes at a
    /// scattering event (see `spectrum::reradiation`).
    pub const FLUORESCENT: Self = Self(1 << 7);
    /// Reflectance varies quickly with wavelength and angle through thin-film interference
    /// (no change of direction, so not dispersive; per-lane weights differ strongly).
    pub const THIN_FILM: Self = Self(1 << 8);

    /// True when every bit of `other` is set.
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// True when any bit of `other` is set.
    pub fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }

    /// True when the material has a lobe that can be evaluated (not only delta lobes), i.e. when
    /// next-event estimation makes sense.
    pub fn has_non_specular(self) -> bool {
        self.intersects(Self::DIFFUSE | Self::GLOSSY)
    }

    /// True for a delta lobe.
    pub fn is_specular(self) -> bool {
        self.contains(Self::SPECULAR)
    }
}

impl BitOr for MaterialFlags {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        Self(self.0 | rhs.0)
    }
}

impl BitOrAssign for MaterialFlags {
    fn bitor_assign(&mut self, rhs: Self) {
        self.0 |= rhs.0;
    }
}

impl BitAnd for MaterialFlags {
    type Output = Self;
    fn bitand(self, rhs: Self) -> Self {
        Self(self.0 & rhs.0)
    }
}
