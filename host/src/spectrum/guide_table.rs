//! A guide table for searching a sorted table of `f64`s (a tabulated spectrum's wavelengths, its
//! CDF): `partition_point(|v| v <= t)` in expected O(1) instead of a binary search.
//!
//! The range `[values₀, values_{n−1}]` is cut into `n` equal bins; each bin stores where the
//! search answer for its lower end lies. A query starts at its bin's entry and walks to the
//! answer, which for a sorted table is unique, so the result is exactly the binary search's
//! (the walk goes both ways, so rounding in the bin computation cannot make it wrong, only
//! longer). For a uniform query over the range (a CDF searched with a uniform number, a grid of
//! wavelengths) the walk passes about one entry. Tables of at most [`MIN_GUIDED`] entries are
//! searched by bisection (a few steps, cheaper than the bin computation; the Cornell box light
//! has four). This is the "cutpoint" or guide-table method
//! of inverse-transform sampling (Chen & Asau 1974); written here because it is a dozen lines
//! around the table it serves.
//!
//! | field | meaning |
//! |---|---|
//! | `lo` | first table value |
//! | `bins_per_unit` | bins per unit of the table's values (0 for a table of one value) |
//! | `start` | per bin, the search answer for the bin's lower end (empty: bisection) |

/// Tables up to this many entries are searched by bisection.
pub const MIN_GUIDED: usize = 16;

/// Starting points for searches in one sorted table (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct GuideTable {
    lo: f64,
    bins_per_unit: f64,
    start: Vec<u32>,
}

impl GuideTable {
    /// The guide of `values` (sorted, non-decreasing, finite, at most `u32::MAX` entries).
    pub fn new(values: &[f64]) -> Self {
        let n = values.len();
        if n <= MIN_GUIDED {
            return Self {
                lo: 0.0,
                bins_per_unit: 0.0,
                start: Vec::new(),
            };
        }
        let (lo, hi) = (values[0], values[n - 1]);
        let bins_per_unit = if hi > lo { n as f64 / (hi - lo) } else { 0.0 };
        let start = (0..n)
            .map(|k| {
                let lower = lo + k as f64 / bins_per_unit.max(f64::MIN_POSITIVE);
                values.partition_point(|&v| v <= lower) as u32
            })
            .collect();
        Self {
            lo,
            bins_per_unit,
            start,
        }
    }

    /// `values.partition_point(|&v| v <= t)` (the number of entries at most `t`), exactly;
    /// `values` must be the table this guide was made for.
    #[inline]
    pub fn partition_point(&self, values: &[f64], t: f64) -> usize {
        if self.start.is_empty() {
            return values.partition_point(|&v| v <= t);
        }
        // A saturating conversion (NaN → 0), clamped into the bins.
        let bin = (((t - self.lo) * self.bins_per_unit) as i32).max(0) as usize;
        let mut p = (self.start[bin.min(self.start.len() - 1)] as usize).min(values.len());
        while p > 0 && !(values[p - 1] <= t) {
            p -= 1;
        }
        while p < values.len() && values[p] <= t {
            p += 1;
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quantity: the guided search against the binary search on tables that are uniform,
    /// strongly non-uniform (values clustered at both ends), with runs of equal values (a CDF
    /// over zero-valued stretches), of one and two entries, for queries below, inside, at every
    /// entry, above, ±∞ and NaN. Tolerance: equality, since for a sorted table the answer is
    /// unique and both must find it.
    #[test]
    fn guided_search_equals_binary_search() {
        let uniform: Vec<f64> = (0..531).map(|i| 300.0 + i as f64).collect();
        let clustered: Vec<f64> = (0..200)
            .map(|i| {
                let u = i as f64 / 199.0;
                (u * std::f64::consts::PI).cos() * -0.5 + 0.5
            })
            .map(|v| v * v * v)
            .collect();
        let mut runs = vec![0.0; 40];
        runs.extend((1..60).map(|i| i as f64 * 0.01));
        runs.extend(std::iter::repeat_n(0.59, 30));
        runs.extend((0..20).map(|i| 0.6 + i as f64));
        let equal = vec![4.0; 40];
        for table in [uniform, clustered, runs, equal, vec![2.5], vec![1.0, 3.0]] {
            let guide = GuideTable::new(&table);
            let (lo, hi) = (table[0], table[table.len() - 1]);
            let mut queries = vec![
                lo - 1.0,
                hi + 1.0,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NAN,
            ];
            queries.extend(table.iter().copied());
            queries.extend((0..5000).map(|k| lo + (hi - lo) * (k as f64 / 4999.0)));
            for t in queries {
                assert_eq!(
                    guide.partition_point(&table, t),
                    table.partition_point(|&v| v <= t),
                    "t = {t}, table of {}",
                    table.len()
                );
            }
        }
    }
}
