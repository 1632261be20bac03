//! The kit's random numbers: SplitMix64 (Steele, Lea and Flood, 2014), seeded per check.
//!
//! Written here rather than taken from a crate because the checks must draw the very same
//! numbers in every version of the kit (a verdict may not change with a dependency's update),
//! and the generator is a dozen lines.

/// A SplitMix64 stream.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A stream for `seed`; different seeds give unrelated streams.
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9E37_79B9_7F4A_7C15)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1), 53 bits.
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in [0, 1), 24 bits (every value exactly representable, never 1).
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u32 << 24) as f32)
    }
    /// A unit vector, uniform on the sphere.
    pub fn sphere(&mut self) -> [f64; 3] {
        let z = 1.0 - 2.0 * self.f64();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f64::consts::PI * self.f64();
        [r * phi.cos(), r * phi.sin(), z]
    }
}
