//! Counter-based random numbers: every camera sample owns a generator seeded by hashing
//! `(seed, pixel, sample index)`, so no state is shared between threads and an image is bitwise
//! reproducible whatever the thread count, tile order, slice split or resume.
//!
//! Two kinds of numbers (chosen per render with [`SamplerKind`], `render --sampler`):
//!
//! | kind | first [`LD_DIMENSIONS`] requests of a sample | later requests |
//! |---|---|---|
//! | `sobol` (default) | shuffled, Owen-scrambled Sobol' points ([`PixelSampler`]) | PCG32 ([`SampleRng`]) |
//! | `independent` | PCG32 | PCG32 |
//!
//! An integrator that draws several walks and connections per sample can instead give each a
//! block of dimensions ([`PixelSampler::set_block`]: Sobol' points for the block's first
//! requests, then its own PCG stream), so that each request keeps its dimension whatever the
//! other walks drew (BDPT and light tracing do; the path tracer reads one sequence).
//!
//! The Sobol' part is written here rather than taken from the `sobol_burley` crate because it
//! needs only the first two Sobol' dimensions (each 2D request gets its own shuffle and
//! scramble, Burley's "padding"), about forty lines; the crate's 256-dimension tables and 4D
//! interface would not be used.

use glam::Vec2;

/// Where a random walk or a connection takes its uniform numbers: the pixel's stratified
/// [`PixelSampler`] (BDPT, light tracing) or a plain [`SampleRng`] (estimators without a
/// sample layout). Generic callers are monomorphised per source: no dynamic call per number.
pub trait UniformSource {
    /// One uniform number in [0, 1).
    fn next_1d(&mut self) -> f32;
    /// Two uniform numbers in [0, 1)².
    fn next_2d(&mut self) -> Vec2;
    /// Consume one 1D request without using it, so the requests after it keep their
    /// dimensions whether or not this one was needed.
    #[inline]
    fn skip_1d(&mut self) {
        self.next_1d();
    }
}

impl UniformSource for SampleRng {
    #[inline]
    fn next_1d(&mut self) -> f32 {
        SampleRng::next_1d(self)
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        SampleRng::next_2d(self)
    }
    /// Nothing: independent numbers have no dimensions to keep aligned, and the callers with
    /// a plain stream (estimators, tests) keep the numbers they drew before skips existed.
    #[inline]
    fn skip_1d(&mut self) {}
}

impl UniformSource for PixelSampler {
    #[inline]
    fn next_1d(&mut self) -> f32 {
        PixelSampler::next_1d(self)
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        PixelSampler::next_2d(self)
    }
    #[inline]
    fn skip_1d(&mut self) {
        PixelSampler::skip_1d(self)
    }
}

/// SplitMix64 finaliser: a bijective 64-bit mix with full avalanche (Steele et al. 2014).
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A PCG32 generator (O'Neill 2014: 64-bit LCG state, xorshift-rotate output).
#[derive(Clone, Debug)]
pub struct SampleRng {
    state: u64,
    inc: u64,
}

impl SampleRng {
    /// The generator for sample `sample` of pixel `pixel` under `seed`.
    #[inline]
    pub fn for_sample(seed: u64, pixel: u64, sample: u64) -> Self {
        let a = mix64(seed ^ 0x6A09_E667_F3BC_C909);
        let b = mix64(a ^ pixel.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let state = mix64(b ^ sample.wrapping_mul(0xD1B5_4A32_D192_ED03));
        let inc = (mix64(state ^ 0xBB67_AE85_84CA_A73B) << 1) | 1;
        let mut rng = Self { state: 0, inc };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(state);
        rng.next_u32();
        rng
    }

    /// Next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in [0, 1) with 24 bits (every value exactly representable, never 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Two uniforms in [0, 1).
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_1d(), self.next_1d())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Same inputs → same stream; neighbouring pixels/samples/seeds → different streams; mean of
    /// 10⁵ draws is ½ within 5σ (σ = 1/√(12·10⁵) ≈ 9e-4).
    #[test]
    fn streams_are_reproducible_and_distinct() {
        let mut a = SampleRng::for_sample(1, 2, 3);
        let mut b = SampleRng::for_sample(1, 2, 3);
        let va: Vec<u32> = (0..8).map(|_| a.next_u32()).collect();
        let vb: Vec<u32> = (0..8).map(|_| b.next_u32()).collect();
        assert_eq!(va, vb);
        for (s, p, k) in [(2, 2, 3), (1, 3, 3), (1, 2, 4)] {
            let mut c = SampleRng::for_sample(s, p, k);
            let vc: Vec<u32> = (0..8).map(|_| c.next_u32()).collect();
            assert_ne!(va, vc);
        }
        let mut r = SampleRng::for_sample(7, 0, 0);
        let n = 100_000;
        let mean: f64 = (0..n).map(|_| r.next_1d() as f64).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 5.0 * 9.2e-4, "{mean}");
    }
}

/// The Laine–Karras style hash of Burley 2020 ("Practical Hash-based Owen Scrambling", JCGT
/// 9(4)): a permutation of 32-bit values in which each bit depends only on itself and less
/// significant bits. Applied to a bit-reversed value and reversed back it is a nested uniform
/// (Owen) scramble: every output bit depends only on itself and more significant input bits.
/// The callers keep values bit-reversed between steps, so no reversal is undone by the next.
#[inline]
fn laine_karras(mut v: u32, seed: u32) -> u32 {
    v = v.wrapping_add(seed);
    v ^= v.wrapping_mul(0x6c50_b47c);
    v ^= v.wrapping_mul(0xb82f_1e52);
    v ^= v.wrapping_mul(0xc7af_e638);
    v ^= v.wrapping_mul(0x8d22_f6e6);
    v
}

/// Direction numbers of the second Sobol' dimension (the first is the bit-reversed index):
/// `v₀ = 2³¹`, `vₖ₊₁ = vₖ ⊕ (vₖ ≫ 1)`, folded into four byte tables for bit-reversed input and
/// output: the high half of `T_b[x]` is the XOR over the set bits `j` of byte `b` of
/// `reverse(v₃₁₋₈ᵦ₋ⱼ)`, so that `sobol_dim1_reversed(reverse(i)) = reverse(sobol_dim1(i))`
/// costs four lookups instead of 32 steps and two bit reversals. The low half is byte `b`'s
/// bits reversed into place: the same four lookups also give `reverse(j)`, which the first
/// dimension needs (x86 has no bit-reversal instruction; a reversal costs about twenty).
const REVERSE_AND_SOBOL1_TABLES: [[u64; 256]; 4] = {
    let mut v = [0u32; 32];
    v[0] = 1 << 31;
    let mut k = 1;
    while k < 32 {
        v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        k += 1;
    }
    let mut t = [[0u64; 256]; 4];
    let mut b = 0;
    while b < 4 {
        let mut x = 0;
        while x < 256 {
            let mut r = 0u32;
            let mut j = 0;
            while j < 8 {
                if x & (1 << j) != 0 {
                    r ^= v[31 - (8 * b + j)].reverse_bits();
                }
                j += 1;
            }
            let reversed = ((x as u32) << (8 * b)).reverse_bits();
            t[b][x] = (r as u64) << 32 | reversed as u64;
            x += 1;
        }
        b += 1;
    }
    t
};

/// `reverse(j)` in the low 32 bits and the second Sobol' dimension in bit-reversed form,
/// `reverse(sobol_dim1(reverse(j)))`, in the high 32 bits.
#[inline]
fn reverse_and_sobol1(j: u32) -> u64 {
    REVERSE_AND_SOBOL1_TABLES[0][(j & 0xFF) as usize]
        ^ REVERSE_AND_SOBOL1_TABLES[1][((j >> 8) & 0xFF) as usize]
        ^ REVERSE_AND_SOBOL1_TABLES[2][((j >> 16) & 0xFF) as usize]
        ^ REVERSE_AND_SOBOL1_TABLES[3][(j >> 24) as usize]
}

/// `reverse(x)` with its lowest eight bits cleared, which is all of it that [`to_unit`] reads:
/// three byte lookups of the tables' low halves (the fourth byte lands in the cleared bits).
/// Used for a point's last reversal instead of `reverse_bits`: a chain of about four steps
/// instead of ten (a shift-and-mask reversal, x86 having no bit-reversal instruction), on the
/// path from a sample's number to the ray that waits for it, and each coordinate on its own.
#[inline]
fn reverse_top24(x: u32) -> u32 {
    (REVERSE_AND_SOBOL1_TABLES[0][(x & 0xFF) as usize]
        ^ REVERSE_AND_SOBOL1_TABLES[1][((x >> 8) & 0xFF) as usize]
        ^ REVERSE_AND_SOBOL1_TABLES[2][((x >> 16) & 0xFF) as usize]) as u32
}

/// Second Sobol' dimension in bit-reversed form: `reverse(sobol_dim1(reverse(j)))`.
#[cfg(test)]
fn sobol_dim1_reversed(j: u32) -> u32 {
    (reverse_and_sobol1(j) >> 32) as u32
}

#[inline]
fn to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// How many 1D/2D requests per camera sample get low-discrepancy values before any
/// [`PixelSampler::set_block`]; later requests (deep bounces, where stratification no longer
/// helps) come from [`SampleRng`].
pub const LD_DIMENSIONS: u32 = 48;

/// Which numbers a render's samples use (`render --sampler sobol|independent`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SamplerKind {
    /// Shuffled, Owen-scrambled Sobol' points for the first [`LD_DIMENSIONS`] requests of every
    /// sample: lower error per sample (every power-of-two prefix of a pixel's samples is
    /// stratified in each 2D request).
    #[default]
    Sobol,
    /// Independent uniform numbers (PCG32) for every request: the baseline, and what Mitsuba's
    /// `independent` sampler does.
    Independent,
}

impl std::str::FromStr for SamplerKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "sobol" => Ok(Self::Sobol),
            "independent" => Ok(Self::Independent),
            other => Err(format!(
                "unknown sampler {other:?}: expected sobol or independent"
            )),
        }
    }
}

impl std::fmt::Display for SamplerKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Sobol => "sobol",
            Self::Independent => "independent",
        })
    }
}

/// Salt of the independent sampler's stream, so it never equals the [`SampleRng`] an
/// integrator opens for the same `(seed, pixel, sample)` next to its [`PixelSampler`].
const INDEPENDENT_SALT: u64 = 0x3C6E_F372_FE94_F82B;

/// Salt of light path sequences ([`PixelSampler::for_light_path`]), apart from every pixel's.
const LIGHT_PATH_SALT: u64 = 0xA54F_F53A_5F1D_36F1;

/// The sampler of one camera sample (or one light path): shuffled, Owen-scrambled Sobol'
/// points (Burley 2020) for the first [`LD_DIMENSIONS`] requests, then PCG; with
/// [`SamplerKind::Independent`] PCG throughout. Each 1D or 2D request uses its own dimension's
/// scramble and its own index shuffle, so dimensions are decorrelated while every power-of-two
/// prefix of a pixel's samples stays stratified in each 2D projection. Everything is a pure
/// function of (seed, pixel, sample index, request number): deterministic in any thread order.
#[derive(Clone, Debug)]
pub struct PixelSampler {
    /// The render's seed hashed once: `pixel_seed` is it hashed with the pixel.
    seed_hash: u64,
    pixel_seed: u64,
    /// The sample index, bit-reversed (what the shuffle scrambles).
    index_reversed: u32,
    dimension: u32,
    /// Requests below this number are Sobol' points: [`LD_DIMENSIONS`], or 0 when independent.
    ld_end: u32,
    /// `(seed, pixel, sample)` of the PCG stream for the requests past `ld_end`.
    rng_key: (u64, u64, u64),
    /// That stream, opened at the first such request: most camera samples of a short path
    /// never reach it, and seeding it costs four hashes.
    rng: Option<SampleRng>,
    /// Whether the first [`LD_DIMENSIONS`] requests are Sobol' points (kind `sobol`).
    sobol: bool,
    /// The block of dimensions being drawn ([`set_block`](Self::set_block)): its start keys
    /// the PCG stream of its requests past `ld_end`; 0 before any block is set.
    block: u32,
    /// The pixel's scramble seeds kept across its samples ([`memoised`](Self::memoised));
    /// `None`: every request hashes its seeds.
    memo: Option<Box<SeedMemo>>,
}

/// Dimensions whose scramble seeds a `SeedMemo` keeps: every Sobol' request of a sample
/// without blocks ([`LD_DIMENSIONS`]) and then some; later ones are hashed per request.
const MEMO_DIMENSIONS: usize = 64;

/// The Owen-scramble and shuffle seeds of one pixel's dimensions, filled as requests first need
/// them. A seed depends on the pixel and the dimension, not on the sample, so the samples of a
/// pixel after its first read them instead of hashing three SplitMix64 finalisers per 2D
/// request (two per 1D): the same numbers, about a third of a request's instructions.
#[derive(Clone, Debug)]
struct SeedMemo {
    /// The seeds of 1D requests (salts 1, 2).
    one: SeedTable<2>,
    /// The seeds of 2D requests (salts 3, 4, 5).
    two: SeedTable<3>,
}

/// `N` seeds per dimension for the first [`MEMO_DIMENSIONS`] dimensions, each hashed once.
#[derive(Clone, Debug)]
struct SeedTable<const N: usize> {
    /// Bit `d`: `seeds[d]` holds dimension `d`'s seeds.
    known: u64,
    seeds: [[u32; N]; MEMO_DIMENSIONS],
}

impl<const N: usize> SeedTable<N> {
    const EMPTY: Self = Self {
        known: 0,
        seeds: [[0; N]; MEMO_DIMENSIONS],
    };

    /// Dimension `d`'s seeds (`d < MEMO_DIMENSIONS`), from `hash` the first time.
    #[inline]
    fn get(&mut self, d: u32, hash: impl FnOnce() -> [u32; N]) -> [u32; N] {
        let bit = 1u64 << d;
        if self.known & bit == 0 {
            self.seeds[d as usize] = hash();
            self.known |= bit;
        }
        self.seeds[d as usize]
    }
}

/// The scramble seed of request `dimension` under `salt` (1, 2: a 1D request's shuffle and
/// scramble; 3, 4, 5: a 2D request's shuffle and its two coordinates' scrambles).
#[inline]
fn dim_seed(pixel_seed: u64, dimension: u32, salt: u64) -> u32 {
    mix64(pixel_seed ^ (dimension as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt) as u32
}

impl PixelSampler {
    /// The Sobol' sampler for sample `sample` of pixel `pixel` under `seed`.
    #[inline]
    pub fn new(seed: u64, pixel: u64, sample: u32) -> Self {
        Self::with_kind(SamplerKind::Sobol, seed, pixel, sample)
    }

    /// The sampler of kind `kind` for sample `sample` of pixel `pixel` under `seed`.
    #[inline]
    pub fn with_kind(kind: SamplerKind, seed: u64, pixel: u64, sample: u32) -> Self {
        let seed_hash = mix64(seed ^ 0x5851_F42D_4C95_7F2D);
        let pixel_seed = mix64(seed_hash ^ pixel);
        match kind {
            SamplerKind::Sobol => Self {
                seed_hash,
                pixel_seed,
                index_reversed: sample.reverse_bits(),
                dimension: 0,
                ld_end: LD_DIMENSIONS,
                rng_key: (seed, pixel, sample as u64),
                rng: None,
                sobol: true,
                block: 0,
                memo: None,
            },
            SamplerKind::Independent => Self {
                seed_hash,
                pixel_seed,
                index_reversed: sample.reverse_bits(),
                dimension: 0,
                ld_end: 0,
                rng_key: (mix64(seed ^ INDEPENDENT_SALT), pixel, sample as u64),
                rng: None,
                sobol: false,
                block: 0,
                memo: None,
            },
        }
    }

    /// [`with_kind`](Self::with_kind) that keeps each dimension's scramble seeds once hashed,
    /// for a caller that draws many samples of a pixel in a row and moves between them with
    /// [`restart`](Self::restart): the same numbers, fewer hashes per request.
    pub fn memoised(kind: SamplerKind, seed: u64, pixel: u64, sample: u32) -> Self {
        let mut s = Self::with_kind(kind, seed, pixel, sample);
        s.memo = Some(Box::new(SeedMemo {
            one: SeedTable::EMPTY,
            two: SeedTable::EMPTY,
        }));
        s
    }

    /// Become the sampler of sample `sample` of pixel `pixel` with this sampler's kind and
    /// seed: exactly the numbers of `with_kind(kind, seed, pixel, sample)`. The memo of
    /// scramble seeds ([`memoised`](Self::memoised)) is kept while the pixel stays the same.
    #[inline]
    pub fn restart(&mut self, pixel: u64, sample: u32) {
        let (rng_seed, old_pixel, _) = self.rng_key;
        if pixel != old_pixel {
            self.pixel_seed = mix64(self.seed_hash ^ pixel);
            if let Some(m) = self.memo.as_deref_mut() {
                m.one.known = 0;
                m.two.known = 0;
            }
        }
        self.index_reversed = sample.reverse_bits();
        self.dimension = 0;
        self.ld_end = if self.sobol { LD_DIMENSIONS } else { 0 };
        self.rng_key = (rng_seed, pixel, sample as u64);
        self.rng = None;
        self.block = 0;
    }

    /// The sampler of light path `k` of a light-tracing render under `seed`: all light paths
    /// of a render form one sequence (index `k`), so every power-of-two prefix of them is
    /// stratified in the light's first dimensions; beyond 2³² paths a new scramble begins.
    #[inline]
    pub fn for_light_path(kind: SamplerKind, seed: u64, k: u64) -> Self {
        Self::with_kind(
            kind,
            mix64(seed ^ LIGHT_PATH_SALT),
            k >> 32,
            (k & 0xFFFF_FFFF) as u32,
        )
    }

    /// Continue at dimension `start`, with Sobol' points for the `len` requests from there
    /// (independent numbers with kind `independent`) and a PCG stream of this block's own after
    /// them. An integrator with several walks and connections per sample gives each a fixed
    /// block, so that request `k` of a walk lands on the same dimension in every sample of the
    /// pixel however long the other walks were (BDPT's layout: `integrator/bdpt/dimensions.rs`).
    /// Blocks must not overlap; two blocks with different starts never share PCG numbers.
    #[inline]
    pub fn set_block(&mut self, start: u32, len: u32) {
        self.dimension = start;
        self.ld_end = if self.sobol {
            start.saturating_add(len)
        } else {
            0
        };
        self.block = start;
        self.rng = None;
    }

    /// The PCG stream of the requests past `ld_end` (the same numbers whenever it is opened).
    #[inline]
    fn rng(&mut self) -> &mut SampleRng {
        let (seed, pixel, sample) = self.rng_key;
        // Block 0 (no block set) keeps the plain per-sample stream; the sample index fits in
        // 32 bits, so the block start in the upper bits gives every block its own stream.
        let key = sample ^ ((self.block as u64) << 32);
        self.rng
            .get_or_insert_with(|| SampleRng::for_sample(seed, pixel, key))
    }

    /// The seeds (salts 1, 2) of the current dimension as a 1D request.
    #[inline]
    fn seeds_1d(&mut self) -> [u32; 2] {
        let (p, d) = (self.pixel_seed, self.dimension);
        let hash = || [dim_seed(p, d, 1), dim_seed(p, d, 2)];
        match self.memo.as_deref_mut() {
            Some(m) if (d as usize) < MEMO_DIMENSIONS => m.one.get(d, hash),
            _ => hash(),
        }
    }

    /// The seeds (salts 3, 4, 5) of the current dimension as a 2D request.
    #[inline]
    fn seeds_2d(&mut self) -> [u32; 3] {
        let (p, d) = (self.pixel_seed, self.dimension);
        let hash = || [dim_seed(p, d, 3), dim_seed(p, d, 4), dim_seed(p, d, 5)];
        match self.memo.as_deref_mut() {
            Some(m) if (d as usize) < MEMO_DIMENSIONS => m.two.get(d, hash),
            _ => hash(),
        }
    }

    /// One uniform number in [0, 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        if self.dimension >= self.ld_end {
            return self.rng().next_1d();
        }
        // The shuffled index is `i = reverse(j)` (the index Owen-scrambled); its dimension-0
        // Sobol' point `reverse(i)`, reversed for scrambling, is `i` itself.
        let [s1, s2] = self.seeds_1d();
        let j = laine_karras(self.index_reversed, s1);
        let x = reverse_top24(laine_karras(reverse_and_sobol1(j) as u32, s2));
        self.dimension += 1;
        to_unit(x)
    }

    /// Consumes the next 1D request without computing it: what [`next_1d`](Self::next_1d)
    /// would do to the sampler's state, for a caller that knows the number would not be used
    /// (one light to choose from, a material with a single lobe). Every later request then
    /// gets the same number as if it had been drawn, so skipping changes no image; it saves
    /// the two hashes and two scrambles of a Sobol' dimension (about 75 instructions).
    #[inline]
    pub fn skip_1d(&mut self) {
        if self.dimension >= self.ld_end {
            // The PCG stream advances by one draw, as `next_1d` past `ld_end` would.
            self.rng().next_u32();
        } else {
            self.dimension += 1;
        }
    }

    /// Consumes the next 2D request without computing it, as [`skip_1d`](Self::skip_1d)
    /// does for a 1D one (for a caller that knows the numbers would not be used: the lens
    /// sample of a pinhole camera); every later request gets the number it would have had.
    #[inline]
    pub fn skip_2d(&mut self) {
        if self.dimension >= self.ld_end {
            // The PCG stream advances by two draws, as `next_2d` past `ld_end` would.
            let rng = self.rng();
            rng.next_u32();
            rng.next_u32();
        } else {
            self.dimension += 1;
        }
    }

    /// Two uniform numbers in [0, 1)², stratified jointly.
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        if self.dimension >= self.ld_end {
            return self.rng().next_2d();
        }
        let [s3, s4, s5] = self.seeds_2d();
        let j = laine_karras(self.index_reversed, s3);
        let both = reverse_and_sobol1(j);
        let x = laine_karras(both as u32, s4);
        let y = laine_karras((both >> 32) as u32, s5);
        self.dimension += 1;
        Vec2::new(to_unit(reverse_top24(x)), to_unit(reverse_top24(y)))
    }
}

#[cfg(test)]
mod ld_tests {
    use super::*;

    /// The first 16 samples of a pixel put exactly one point in each cell of the 4×4 grid for
    /// every 2D request, and exactly one in each of 16 1D strata (a (0,4,2)-net after scrambling
    /// and shuffling); this is what makes the sampler better than independent random numbers.
    #[test]
    fn prefixes_are_stratified() {
        for pixel in [0u64, 17, 12345] {
            let mut grids = [[0u8; 16]; 6];
            let mut strata = [[0u8; 16]; 6];
            for s in 0..16 {
                let mut p = PixelSampler::new(9, pixel, s);
                for d in 0..6 {
                    let v = p.next_2d();
                    let cell = (v.x * 4.0) as usize + 4 * (v.y * 4.0) as usize;
                    grids[d][cell] += 1;
                    let u = p.next_1d();
                    strata[d][(u * 16.0) as usize] += 1;
                }
            }
            for d in 0..6 {
                assert!(
                    grids[d].iter().all(|&c| c == 1),
                    "pixel {pixel} dim {d}: {:?}",
                    grids[d]
                );
                assert!(
                    strata[d].iter().all(|&c| c == 1),
                    "pixel {pixel} dim {d}: {:?}",
                    strata[d]
                );
            }
        }
    }

    /// `skip_1d` leaves the sampler exactly where `next_1d` would, and `skip_2d` where
    /// `next_2d` would: for both kinds, at every position of a request sequence that crosses
    /// [`LD_DIMENSIONS`] (into the PCG stream), the requests after a skip equal those after a
    /// draw, bit for bit.
    #[test]
    fn skipping_a_request_matches_drawing_it() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            for skip_at in [
                0u32,
                1,
                7,
                LD_DIMENSIONS - 1,
                LD_DIMENSIONS,
                LD_DIMENSIONS + 3,
            ] {
                let mut drawn = PixelSampler::with_kind(kind, 5, 321, 9);
                let mut skipped = drawn.clone();
                for k in 0..LD_DIMENSIONS + 8 {
                    if k == skip_at {
                        drawn.next_1d();
                        skipped.skip_1d();
                        continue;
                    }
                    if k == skip_at + 2 {
                        drawn.next_2d();
                        skipped.skip_2d();
                        continue;
                    }
                    if k % 2 == 0 {
                        assert_eq!(drawn.next_1d().to_bits(), skipped.next_1d().to_bits());
                    } else {
                        let (a, b) = (drawn.next_2d(), skipped.next_2d());
                        assert_eq!(
                            (a.x.to_bits(), a.y.to_bits()),
                            (b.x.to_bits(), b.y.to_bits())
                        );
                    }
                }
            }
        }
    }

    /// Quantity: requests after [`PixelSampler::set_block`]. (1) A block's numbers do not
    /// depend on what was drawn before it (alignment across samples of different path
    /// lengths); (2) the first 16 samples of a pixel are stratified (one per 1/16) in a block's
    /// Sobol' requests; (3) the requests past a block's Sobol' length, and every request of an
    /// independent block, are PCG numbers that differ between blocks and from the unblocked
    /// stream. Tolerance: bit equality for (1), exact counts for (2), all distinct for (3).
    #[test]
    fn blocks_are_aligned_stratified_and_distinct() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            let mut a = PixelSampler::with_kind(kind, 3, 77, 5);
            let mut b = a.clone();
            for _ in 0..7 {
                b.next_2d();
            }
            a.set_block(30, 2);
            b.set_block(30, 2);
            for _ in 0..5 {
                assert_eq!(a.next_2d(), b.next_2d(), "{kind}");
            }
        }
        let mut strata = [0u8; 16];
        for s in 0..16 {
            let mut p = PixelSampler::new(3, 77, s);
            p.next_1d();
            p.set_block(100, 1);
            strata[(p.next_1d() * 16.0) as usize] += 1;
        }
        assert!(strata.iter().all(|&c| c == 1), "{strata:?}");
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            let mut seen = Vec::new();
            for start in [0u32, 1, 2, 1 << 24] {
                let mut p = PixelSampler::with_kind(kind, 3, 77, 5);
                if start > 0 {
                    p.set_block(start, 0);
                } else {
                    for _ in 0..LD_DIMENSIONS {
                        p.skip_1d();
                    }
                }
                let v = (p.next_2d(), p.next_2d());
                assert!(!seen.contains(&v), "{kind} block {start}");
                seen.push(v);
            }
        }
    }

    /// The byte tables reproduce the bit-serial definition of the second Sobol' dimension
    /// (bit-reversed in and out) and `u32::reverse_bits` (and `reverse_top24` its top 24 bits);
    /// exact equality on 10⁴ scattered indices and the byte boundaries.
    #[test]
    fn sobol_tables_match_definition() {
        let serial = |mut i: u32| {
            let (mut v, mut r) = (1u32 << 31, 0u32);
            while i != 0 {
                if i & 1 != 0 {
                    r ^= v;
                }
                i >>= 1;
                v ^= v >> 1;
            }
            r
        };
        for k in 0..10_000u32 {
            let i = k.wrapping_mul(0x9E37_79B9);
            assert_eq!(
                sobol_dim1_reversed(i.reverse_bits()),
                serial(i).reverse_bits()
            );
            assert_eq!(reverse_and_sobol1(i) as u32, i.reverse_bits());
            assert_eq!(reverse_top24(i), i.reverse_bits() & !0xFF);
        }
        for i in [0, 1, 0xFF, 0x100, 0xFF_FFFF, 0x100_0000, u32::MAX] {
            assert_eq!(reverse_top24(i), i.reverse_bits() & !0xFF);
        }
    }

    /// True when the 2^k points put exactly one point in every elementary interval of area
    /// 2^-k (all 2^a × 2^b grids with a + b = k): the (0, k, 2)-net property.
    fn is_net(points: &[Vec2], k: u32) -> bool {
        (0..=k).all(|a| {
            let (nx, ny) = (1usize << a, 1usize << (k - a));
            let mut cells = vec![0u8; nx * ny];
            for p in points {
                cells[(p.x * nx as f32) as usize + nx * (p.y * ny as f32) as usize] += 1;
            }
            cells.iter().all(|&c| c == 1)
        })
    }

    /// Quantity: for every power-of-two prefix (1 … 256 samples) of one pixel's samples, each
    /// of the first 8 2D requests is a (0, k, 2)-net (exactly one point per elementary
    /// interval of every shape) and each 1D request has exactly one point per 1/2^k stratum;
    /// the same for the first 2^k light paths of a light-tracing sequence. Tolerance: exact
    /// counts, since the shuffle maps a prefix onto an aligned block of Sobol' indices and
    /// Owen scrambling keeps the net property. Independent numbers fail this almost surely.
    #[test]
    fn every_power_of_two_prefix_is_stratified() {
        let draw = |make: &dyn Fn(u32) -> PixelSampler, n: u32| {
            let mut d2 = vec![Vec::new(); 8];
            let mut d1 = vec![Vec::new(); 8];
            for s in 0..n {
                let mut p = make(s);
                for d in 0..8 {
                    d2[d].push(p.next_2d());
                    d1[d].push(p.next_1d());
                }
            }
            (d2, d1)
        };
        let pixel = |s| PixelSampler::new(11, 4242, s);
        let light = |s| PixelSampler::for_light_path(SamplerKind::Sobol, 11, s as u64);
        for (name, make) in [
            ("pixel", &pixel as &dyn Fn(u32) -> PixelSampler),
            ("light", &light),
        ] {
            let (d2, d1) = draw(make, 256);
            for k in 0..=8u32 {
                let n = 1usize << k;
                for d in 0..8 {
                    assert!(
                        is_net(&d2[d][..n], k),
                        "{name}: 2D request {d}, {n} samples"
                    );
                    let mut strata = vec![0u8; n];
                    for u in &d1[d][..n] {
                        strata[(u * n as f32) as usize] += 1;
                    }
                    assert!(
                        strata.iter().all(|&c| c == 1),
                        "{name}: 1D request {d}, {n} samples"
                    );
                }
            }
        }
        // The independent sampler is not stratified: 64 uniform points make a (0,6,2)-net with
        // negligible probability.
        let (d2, _) = draw(
            &|s| PixelSampler::with_kind(SamplerKind::Independent, 11, 4242, s),
            64,
        );
        assert!(!is_net(&d2[0], 6));
    }

    /// Quantity: the first 2D point of the same (pixel, sample) under different seeds, pixels,
    /// samples and request numbers, and under the two sampler kinds; tolerance: all distinct
    /// (the scrambles are seeded by hashes of all of these, so a collision of two 48-bit
    /// points has probability ~2⁻⁴⁸). Also: the independent sampler's stream is not the
    /// [`SampleRng`] an integrator opens next to it for the same sample.
    #[test]
    fn seeds_pixels_samples_and_dimensions_differ() {
        let first = |seed, pixel, sample, skip: usize, kind| {
            let mut p = PixelSampler::with_kind(kind, seed, pixel, sample);
            for _ in 0..skip {
                p.next_2d();
            }
            p.next_2d()
        };
        let mut seen = Vec::new();
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            for (seed, pixel, sample, skip) in [
                (1, 2, 3, 0),
                (2, 2, 3, 0),
                (1, 3, 3, 0),
                (1, 2, 4, 0),
                (1, 2, 3, 1),
            ] {
                let v = first(seed, pixel, sample, skip, kind);
                assert!(
                    !seen.contains(&v),
                    "{kind} {seed} {pixel} {sample} {skip}: {v}"
                );
                seen.push(v);
            }
        }
        let mut a = PixelSampler::for_light_path(SamplerKind::Sobol, 1, 5);
        let mut b = PixelSampler::for_light_path(SamplerKind::Sobol, 2, 5);
        assert_ne!(a.next_2d(), b.next_2d());
        let mut ind = PixelSampler::with_kind(SamplerKind::Independent, 1, 2, 3);
        let mut rng = SampleRng::for_sample(1, 2, 3);
        assert_ne!(ind.next_1d(), rng.next_1d());
    }

    /// Quantity: the independent sampler's 10⁵ draws have mean ½ within 5σ
    /// (σ = 1/√(12·10⁵) ≈ 9.2e-4), and the names parse and print back.
    #[test]
    fn independent_kind_is_uniform_and_named() {
        let n = 100_000u32;
        let mean: f64 = (0..n)
            .map(|s| PixelSampler::with_kind(SamplerKind::Independent, 3, 1, s).next_1d() as f64)
            .sum::<f64>()
            / n as f64;
        assert!((mean - 0.5).abs() < 5.0 * 9.2e-4, "{mean}");
        for k in [SamplerKind::Sobol, SamplerKind::Independent] {
            assert_eq!(k.to_string().parse::<SamplerKind>(), Ok(k));
        }
        assert!("halton".parse::<SamplerKind>().is_err());
    }

    /// Quantity: every value of 64 mixed 1D/2D requests (past [`LD_DIMENSIONS`], so the PCG
    /// tail is included) for several seeds, pixels, samples and both kinds, against the
    /// sampler's definition written out plainly (shuffle, Sobol' dimensions 0 and 1, Owen
    /// scramble, one bit reversal per coordinate, PCG opened with the sample). Tolerance: bit
    /// equality, since the fast path (one 64-bit reversal for both coordinates, the PCG stream
    /// opened lazily) only reorders the same integer operations; images depend on it.
    #[test]
    fn fast_paths_equal_the_definition() {
        struct Plain {
            pixel_seed: u64,
            index_reversed: u32,
            dimension: u32,
            ld_end: u32,
            rng: SampleRng,
        }
        impl Plain {
            fn seed(&self, salt: u64) -> u32 {
                mix64(
                    self.pixel_seed
                        ^ (self.dimension as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
                        ^ salt,
                ) as u32
            }
            fn next_1d(&mut self) -> f32 {
                if self.dimension >= self.ld_end {
                    return self.rng.next_1d();
                }
                let j = laine_karras(self.index_reversed, self.seed(1));
                let x = laine_karras(j.reverse_bits(), self.seed(2)).reverse_bits();
                self.dimension += 1;
                to_unit(x)
            }
            fn next_2d(&mut self) -> Vec2 {
                if self.dimension >= self.ld_end {
                    return self.rng.next_2d();
                }
                let j = laine_karras(self.index_reversed, self.seed(3));
                let x = laine_karras(j.reverse_bits(), self.seed(4)).reverse_bits();
                let y = laine_karras(sobol_dim1_reversed(j), self.seed(5)).reverse_bits();
                self.dimension += 1;
                Vec2::new(to_unit(x), to_unit(y))
            }
        }
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            for (seed, pixel, sample) in [(0u64, 0u64, 0u32), (3, 17, 5), (99, 65_535, 1 << 20)] {
                let rng_seed = match kind {
                    SamplerKind::Sobol => seed,
                    SamplerKind::Independent => mix64(seed ^ INDEPENDENT_SALT),
                };
                let mut plain = Plain {
                    pixel_seed: mix64(mix64(seed ^ 0x5851_F42D_4C95_7F2D) ^ pixel),
                    index_reversed: sample.reverse_bits(),
                    dimension: 0,
                    ld_end: if kind == SamplerKind::Sobol {
                        LD_DIMENSIONS
                    } else {
                        0
                    },
                    rng: SampleRng::for_sample(rng_seed, pixel, sample as u64),
                };
                let mut fast = PixelSampler::with_kind(kind, seed, pixel, sample);
                for r in 0..64 {
                    if r % 3 == 1 {
                        assert_eq!(fast.next_1d().to_bits(), plain.next_1d().to_bits());
                    } else {
                        let (a, b) = (fast.next_2d(), plain.next_2d());
                        assert_eq!(
                            (a.x.to_bits(), a.y.to_bits()),
                            (b.x.to_bits(), b.y.to_bits()),
                            "{kind} seed {seed} pixel {pixel} sample {sample} request {r}"
                        );
                    }
                }
            }
        }
    }

    /// Quantity: every value of the requests of one memoised sampler restarted through the
    /// samples of several pixels (back to an earlier pixel too, as a tile's rows do), against a
    /// new [`PixelSampler::with_kind`] per sample; the requests mix 1D, 2D, skips, a block
    /// past the memo's dimensions and the PCG tail past [`LD_DIMENSIONS`], in an order that
    /// depends on the sample, so the memo is filled by one pattern and read by another.
    /// Tolerance: bit equality (the memo stores the seeds the hashes give; images depend on it).
    #[test]
    fn memoised_restarts_equal_fresh_samplers() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            let mut memo = PixelSampler::memoised(kind, 13, 0, 0);
            for (pixel, sample) in [
                (5u64, 0u32),
                (5, 1),
                (5, 7),
                (6, 0),
                (6, 3),
                (5, 2),
                (9, 1 << 20),
            ] {
                let mut fresh = PixelSampler::with_kind(kind, 13, pixel, sample);
                memo.restart(pixel, sample);
                let pattern = sample as usize + pixel as usize;
                for r in 0..(LD_DIMENSIONS as usize + 10) {
                    if r == 40 && pattern.is_multiple_of(2) {
                        fresh.set_block(70, 4);
                        memo.set_block(70, 4);
                    }
                    match (r + pattern) % 4 {
                        0 => assert_eq!(fresh.next_1d().to_bits(), memo.next_1d().to_bits()),
                        1 => {
                            fresh.skip_1d();
                            memo.skip_1d();
                        }
                        _ => {
                            let (a, b) = (fresh.next_2d(), memo.next_2d());
                            assert_eq!(
                                (a.x.to_bits(), a.y.to_bits()),
                                (b.x.to_bits(), b.y.to_bits()),
                                "{kind} pixel {pixel} sample {sample} request {r}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// Different pixels get different point sets; values stay in [0, 1).
    #[test]
    fn pixels_are_decorrelated() {
        let a = PixelSampler::new(1, 5, 3).next_2d();
        let b = PixelSampler::new(1, 6, 3).next_2d();
        assert_ne!(a, b);
        let mut p = PixelSampler::new(1, 5, 3);
        for _ in 0..200 {
            let v = p.next_1d();
            assert!((0.0..1.0).contains(&v));
        }
    }
}
