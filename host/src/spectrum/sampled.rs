//! The spectral quantities a path carries: [`LANES`] wavelengths and one value per wavelength.
//!
//! A path is traced for a *hero* wavelength plus `LANES - 1` rotations of it across the sampled
//! range, so one path estimates several wavelengths at once (Wilkie et al. 2014). Each lane keeps
//! its own pdf (1/nm) so estimators divide by the density the wavelength was actually drawn with.

pub use super::lane_mask::LANES;
use super::LaneMask;
use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, MulAssign, Sub};

/// One value per traced wavelength: radiance, throughput, reflectance … (unit depends on use).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SampledSpectrum(pub [f32; LANES]);

impl SampledSpectrum {
    /// Every lane equal to `v`.
    pub const fn splat(v: f32) -> Self {
        Self([v; LANES])
    }

    /// All lanes zero.
    pub const fn zero() -> Self {
        Self([0.0; LANES])
    }

    /// True when every lane is exactly zero (a path that can contribute nothing).
    pub fn is_black(&self) -> bool {
        self.0.iter().all(|&v| v == 0.0)
    }

    /// Largest lane.
    pub fn max_value(&self) -> f32 {
        self.0.iter().copied().fold(f32::MIN, f32::max)
    }

    /// Mean over lanes.
    pub fn average(&self) -> f32 {
        self.0.iter().sum::<f32>() / LANES as f32
    }

    /// Lane-wise `self / rhs`, with 0 where `rhs` is 0 (a zero-pdf lane contributes nothing).
    pub fn safe_div(self, rhs: Self) -> Self {
        Self(std::array::from_fn(|i| {
            if rhs.0[i] != 0.0 {
                self.0[i] / rhs.0[i]
            } else {
                0.0
            }
        }))
    }

    /// Apply `f` to each lane.
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self(self.0.map(f))
    }

    /// True when any lane is NaN or infinite.
    pub fn has_non_finite(&self) -> bool {
        self.0.iter().any(|v| !v.is_finite())
    }
}

impl Index<usize> for SampledSpectrum {
    type Output = f32;
    fn index(&self, i: usize) -> &f32 {
        &self.0[i]
    }
}

impl IndexMut<usize> for SampledSpectrum {
    fn index_mut(&mut self, i: usize) -> &mut f32 {
        &mut self.0[i]
    }
}

macro_rules! lanewise {
    ($trait:ident, $fn:ident, $op:tt) => {
        impl $trait for SampledSpectrum {
            type Output = Self;
            fn $fn(self, rhs: Self) -> Self {
                Self(std::array::from_fn(|i| self.0[i] $op rhs.0[i]))
            }
        }
        impl $trait<f32> for SampledSpectrum {
            type Output = Self;
            fn $fn(self, rhs: f32) -> Self {
                Self(self.0.map(|v| v $op rhs))
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Mul<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    fn mul(self, rhs: SampledSpectrum) -> SampledSpectrum {
        rhs * self
    }
}

impl AddAssign for SampledSpectrum {
    fn add_assign(&mut self, rhs: Self) {
        *self = *self + rhs;
    }
}

impl MulAssign for SampledSpectrum {
    fn mul_assign(&mut self, rhs: Self) {
        *self = *self * rhs;
    }
}

impl MulAssign<f32> for SampledSpectrum {
    fn mul_assign(&mut self, rhs: f32) {
        *self = *self * rhs;
    }
}

/// The wavelengths (nm) one path carries and the density (1/nm) each was drawn with.
/// `#[repr(C)]`: the plugin interface's `LanesF32` has the same fields in the same places
/// (`plugin::layout`), so a plugin built from the host's code reads it in place.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    /// Wavelengths in nm; lane 0 is the hero.
    pub lambda: [f32; LANES],
    /// Sampling density of each lane in 1/nm (0 for a terminated lane, and for a lane on a
    /// delta line, whose weight is a discrete probability).
    pub pdf: [f32; LANES],
    /// Lanes still carrying light; a dispersive event leaves only the hero
    /// ([`terminate_secondary`](Self::terminate_secondary)).
    pub lanes: LaneMask,
}

impl SampledWavelengths {
    /// Hero wavelength drawn uniformly from `[min, max]` nm with `u ∈ [0,1)`, the other lanes
    /// rotated by equal steps and wrapped, so the set stays stratified across the range.
    pub fn sample_uniform(u: f32, min: f32, max: f32) -> Self {
        let span = max - min;
        let hero = min + u * span;
        let delta = span / LANES as f32;
        let lambda = std::array::from_fn(|i| {
            let mut l = hero + delta * i as f32;
            if l > max {
                l -= span;
            }
            l
        });
        Self {
            lambda,
            pdf: [1.0 / span; LANES],
            lanes: LaneMask::ALL,
        }
    }

    /// Drop every lane but the hero, as a wavelength-dependent event (dispersion) demands: the
    /// other lanes would have scattered in other directions. The hero's pdf becomes the average
    /// over the rotations, which is the density with which the hero's wavelength was produced.
    /// The mask records it, so the film and every integrator see the same state.
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        for p in &mut self.pdf[1..] {
            *p = 0.0;
        }
        self.pdf[0] /= LANES as f32;
        self.lanes = self.lanes.terminate_secondary();
    }

    /// True once [`terminate_secondary`](Self::terminate_secondary) has run.
    pub fn secondary_terminated(&self) -> bool {
        self.lanes.count() <= 1
    }
}
