//! An exact sum of non-negative finite `f64` values: the film's accumulator.
//!
//! Why exact: integer addition is associative, so the sum is the same bits whatever order the
//! samples arrive in (threads), however they are grouped (passes, slices on different machines,
//! a checkpoint and its resumption), and it can neither saturate nor wrap. A sum of floats in a
//! fixed order is deterministic too, but two slices summed separately and then added differ from
//! one sum in the last bits; fixed point (the previous film) needs a scale chosen in advance and
//! wraps in bright scenes.
//!
//! How: every finite `f64 ≥ 0` is `m·2^(e−1074)` with an integer mantissa `m < 2⁵³` and
//! `0 ≤ e < 2046`. The exact value of a sum is therefore an integer multiple of 2⁻¹⁰⁷⁴, held as
//! base-2⁶⁴ digits: digit `w` weighs `2^(64·w − 1074)`. A sample adds `m << (e mod 64)` (< 2¹¹⁷)
//! to digit `e / 64`. A digit that reaches 2¹²⁶ carries its high part into the next one, so no
//! digit ever overflows its 128 bits. One digit (the window of the first sample, usually the only
//! one a pixel needs) is stored inline; other windows spill to a small heap list. Reading the
//! value first normalises to unique base-2⁶⁴ digits, so equal sums give equal `f64`s.
//!
//! Nothing here is hand-written for lack of a crate: the general arbitrary-precision crates
//! (e.g. `num-bigint`) allocate per number, which for three sums per pixel costs more memory
//! and time than these 32 bytes with an inline digit.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Marks an empty inline digit.
const EMPTY: u16 = u16::MAX;
/// A digit at or above this carries (2¹²⁶; a sample adds < 2¹¹⁷, a merge < 2¹²⁶, so the 128-bit
/// digit never overflows).
const CARRY_AT: u128 = 1 << 126;
/// The highest digit index a finite sum can reach (2046 + 64 carries' worth of bits, / 64).
pub const MAX_WINDOW: u16 = 40;

/// Exact sum of non-negative finite `f64`s (see the module docs). 32 bytes when one window
/// holds all of it.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(into = "Vec<(u16, u64)>", try_from = "Vec<(u16, u64)>")]
pub struct ExactSum {
    /// Window of the inline digit, or [`EMPTY`].
    window: u16,
    /// The inline digit as two little-endian `u64`s (no 16-byte alignment: keeps this 32 bytes).
    main: [u64; 2],
    /// Digits of other windows, unordered. Boxed: 8 bytes inline instead of a `Vec`'s 24, as
    /// most sums never need it.
    #[allow(clippy::box_collection)]
    rest: Option<Box<Vec<(u16, u128)>>>,
}

impl Default for ExactSum {
    fn default() -> Self {
        Self {
            window: EMPTY,
            main: [0, 0],
            rest: None,
        }
    }
}

impl ExactSum {
    /// Add `x`. Only non-negative finite values belong here (the film's guard rejects the rest
    /// before); anything else is ignored, in release builds too.
    #[inline]
    pub fn add(&mut self, x: f64) {
        if !(x > 0.0 && x.is_finite()) {
            return;
        }
        let bits = x.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as u32;
        let frac = bits & ((1u64 << 52) - 1);
        // x = m · 2^(e − 1074), subnormals included.
        let (m, e) = if biased == 0 {
            (frac, 0)
        } else {
            (frac | (1u64 << 52), biased - 1)
        };
        let (w, v) = ((e / 64) as u16, (m as u128) << (e % 64));
        if w == self.window {
            // The common case inline: the sample lands in the inline digit and nothing carries.
            let s = (self.main[0] as u128 | (self.main[1] as u128) << 64) + v;
            if s < CARRY_AT {
                self.main = [s as u64, (s >> 64) as u64];
                return;
            }
        }
        self.add_digit(w, v);
    }

    /// Add `v·2^(64·w − 1074)` (`v` < 2¹²⁷ − 2¹²⁶).
    fn add_digit(&mut self, w: u16, v: u128) {
        if v == 0 {
            return;
        }
        if self.window == EMPTY {
            self.window = w;
        }
        let carry;
        if w == self.window {
            let mut s = (self.main[0] as u128 | (self.main[1] as u128) << 64) + v;
            carry = if s >= CARRY_AT {
                let c = s >> 64;
                s &= u64::MAX as u128;
                c
            } else {
                0
            };
            self.main = [s as u64, (s >> 64) as u64];
        } else {
            let rest = self.rest.get_or_insert_with(Default::default);
            let slot = match rest.iter_mut().find(|(rw, _)| *rw == w) {
                Some((_, d)) => d,
                None => {
                    rest.push((w, 0));
                    &mut rest.last_mut().expect("just pushed").1
                }
            };
            *slot += v;
            carry = if *slot >= CARRY_AT {
                let c = *slot >> 64;
                *slot &= u64::MAX as u128;
                c
            } else {
                0
            };
        }
        if carry != 0 {
            self.add_digit(w + 1, carry);
        }
    }

    /// Add another exact sum (exact, so `a + (b + c)` and `(a + b) + c` are the same bits).
    pub fn merge(&mut self, other: &ExactSum) {
        for (w, v) in other.raw_digits() {
            self.add_digit(w, v);
        }
    }

    /// The stored digits, unnormalised.
    fn raw_digits(&self) -> impl Iterator<Item = (u16, u128)> + '_ {
        let main = (self.window != EMPTY).then(|| {
            (
                self.window,
                self.main[0] as u128 | (self.main[1] as u128) << 64,
            )
        });
        main.into_iter()
            .chain(self.rest.iter().flat_map(|r| r.iter().copied()))
    }

    /// The unique base-2⁶⁴ digits of the value, lowest window first, zero digits left out.
    pub fn digits(&self) -> Vec<(u16, u64)> {
        let mut by_window: BTreeMap<u16, u128> = BTreeMap::new();
        for (w, v) in self.raw_digits() {
            *by_window.entry(w).or_insert(0) += v;
        }
        let mut out = Vec::with_capacity(by_window.len());
        let mut carry: u128 = 0;
        let mut next: Option<u16> = None;
        for (w, v) in by_window {
            // Flush a carry into windows between the previous one and this.
            while carry != 0 && next.is_some_and(|n| n < w) {
                let n = next.expect("checked");
                out.push((n, carry as u64));
                carry >>= 64;
                next = Some(n + 1);
            }
            if next != Some(w) {
                carry = 0;
            }
            let t = v + carry;
            out.push((w, t as u64));
            carry = t >> 64;
            next = Some(w + 1);
        }
        while carry != 0 {
            let n = next.expect("a carry follows a digit");
            out.push((n, carry as u64));
            carry >>= 64;
            next = Some(n + 1);
        }
        out.retain(|&(_, d)| d != 0);
        out
    }

    /// The value rounded to `f64` (deterministic: computed from the unique digits, highest
    /// first, so equal sums give equal bits). Beyond the `f64` range it is +∞.
    pub fn value(&self) -> f64 {
        if self.rest.is_none() {
            // One window: its unique digits are the inline digit's two halves (what `digits`
            // returns, without its map and vector), added highest first as below.
            if self.window == EMPTY {
                return 0.0;
            }
            let w = self.window as i32;
            let mut acc = 0.0f64;
            if self.main[1] != 0 {
                acc += scale_pow2(self.main[1] as f64, 64 * (w + 1) - 1074);
            }
            if self.main[0] != 0 {
                acc += scale_pow2(self.main[0] as f64, 64 * w - 1074);
            }
            return acc;
        }
        let mut acc = 0.0f64;
        for (w, d) in self.digits().into_iter().rev() {
            acc += scale_pow2(d as f64, 64 * w as i32 - 1074);
        }
        acc
    }

    /// [`value`](Self::value) through the general path (normalised digits), for tests.
    #[cfg(test)]
    fn value_from_digits(&self) -> f64 {
        let mut acc = 0.0f64;
        for (w, d) in self.digits().into_iter().rev() {
            acc += scale_pow2(d as f64, 64 * w as i32 - 1074);
        }
        acc
    }

    /// True when nothing (or only zeros) was added.
    pub fn is_zero(&self) -> bool {
        self.raw_digits().all(|(_, v)| v == 0)
    }
}

/// `x·2^e` for any `e`, without overflowing the intermediate power of two.
fn scale_pow2(mut x: f64, mut e: i32) -> f64 {
    let step = |k: i32| f64::from_bits(((k + 1023) as u64) << 52);
    while e > 1000 {
        x *= step(1000);
        e -= 1000;
    }
    while e < -1000 {
        x *= step(-1000);
        e += 1000;
    }
    x * step(e)
}

impl PartialEq for ExactSum {
    fn eq(&self, other: &Self) -> bool {
        self.digits() == other.digits()
    }
}

impl From<ExactSum> for Vec<(u16, u64)> {
    fn from(s: ExactSum) -> Self {
        s.digits()
    }
}

impl TryFrom<Vec<(u16, u64)>> for ExactSum {
    type Error = String;
    fn try_from(d: Vec<(u16, u64)>) -> Result<Self, String> {
        let mut s = ExactSum::default();
        for (w, v) in d {
            if w > MAX_WINDOW {
                return Err(format!(
                    "digit window {w} is beyond the largest finite sum (window {MAX_WINDOW})"
                ));
            }
            s.add_digit(w, v as u128);
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// 1e8 samples of 0.1 (the double 0.1000000000000000055…) sum to 10⁷ + 5.6·10⁻¹⁰, whose
    /// nearest double is 10⁷ exactly (spacing 1.9·10⁻⁹); a float running sum ends at
    /// 9999999.98 instead (error 2·10⁻⁹ relative). Tolerance 0: the sum is exact.
    #[test]
    fn many_small_samples_sum_exactly() {
        let mut s = ExactSum::default();
        for _ in 0..100_000_000u32 {
            s.add(0.1);
        }
        assert_eq!(s.value(), 1e7);
    }

    /// Values across the whole f64 range (subnormals up to 1e308) sum to the correctly
    /// rounded total of a few exactly known cases, and a sum beyond f64 gives +∞, not a wrap.
    #[test]
    fn extremes() {
        let mut s = ExactSum::default();
        s.add(f64::from_bits(1)); // smallest subnormal
        s.add(1.0);
        assert_eq!(s.value(), 1.0);
        let mut t = ExactSum::default();
        for _ in 0..4 {
            t.add(f64::MAX);
        }
        assert_eq!(t.value(), f64::INFINITY);
        let mut u = ExactSum::default();
        u.add(1e300);
        u.add(1e-300);
        u.add(3.0);
        assert_eq!(u.value(), 1e300);
        u.add(f64::NAN);
        u.add(-1.0);
        u.add(f64::INFINITY);
        assert_eq!(u.value(), 1e300);
        let mut z = ExactSum::default();
        z.add(0.0);
        assert!(z.is_zero());
        assert_eq!(z.value(), 0.0);
    }

    proptest! {
        /// Any order and any grouping give the same digits (associativity and commutativity),
        /// and the digits round-trip through their serialised form.
        #[test]
        fn order_and_grouping_do_not_matter(
            xs in proptest::collection::vec(
                prop_oneof![0.0..1e-300f64, 0.0..1.0f64, 0.0..1e300f64, 1e-320..1e-310f64],
                0..60,
            ),
            split in 0usize..60,
        ) {
            let mut a = ExactSum::default();
            for &x in &xs { a.add(x); }
            let mut b = ExactSum::default();
            for &x in xs.iter().rev() { b.add(x); }
            let k = split.min(xs.len());
            let (mut c1, mut c2) = (ExactSum::default(), ExactSum::default());
            for &x in &xs[..k] { c1.add(x); }
            for &x in &xs[k..] { c2.add(x); }
            c2.merge(&c1);
            prop_assert_eq!(a.digits(), b.digits());
            prop_assert_eq!(a.digits(), c2.digits());
            prop_assert_eq!(a.value().to_bits(), c2.value().to_bits());
            prop_assert_eq!(a.value().to_bits(), a.value_from_digits().to_bits());
            prop_assert_eq!(c2.value().to_bits(), c2.value_from_digits().to_bits());
            let back = ExactSum::try_from(a.digits()).unwrap();
            prop_assert_eq!(back.digits(), a.digits());
            // Within rounding of a compensated float sum.
            let mut f = 0.0f64; let mut comp = 0.0f64;
            for &x in &xs { let y = x - comp; let t = f + y; comp = (t - f) - y; f = t; }
            prop_assert!((a.value() - f).abs() <= 1e-12 * f.abs());
        }
    }

    /// Digits that would carry past 128 bits carry instead: 2¹⁰ additions of a digit just
    /// below the carry threshold stay exact.
    #[test]
    fn carries_keep_exactness() {
        let mut s = ExactSum::default();
        let x = 2f64.powi(63) * (1.0 + f64::EPSILON); // mantissa fills the window's top bits
        for _ in 0..1024 {
            s.add(x);
        }
        assert_eq!(s.value(), 1024.0 * x);
        assert!(std::mem::size_of::<ExactSum>() <= 32);
    }
}
