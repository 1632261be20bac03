//! Colour observers: x̄ȳz̄ colour-matching functions. The [`Observer`] trait lets a plugin supply
//! other sensitivities (a camera's sensor curves); [`CieObserver`] holds the four CIE tables.

use std::sync::OnceLock;

use crate::spectrum::csv_table::parse_csv_table;

/// Colour-matching functions of wavelength (nm), dimensionless.
pub trait Observer: Send + Sync + std::fmt::Debug {
    /// Short identifier, e.g. `cie1931-2`.
    fn name(&self) -> &str;
    /// `(min, max)` nm outside which all three functions are 0.
    fn range(&self) -> (f64, f64);
    /// `[x̄, ȳ, z̄]` at `lambda_nm`, 0 outside the range.
    fn xyz_bar(&self, lambda_nm: f64) -> [f64; 3];
    /// `Σ ȳ(λ)` over the integration grid (integer nm inside the range, Δλ = 1 nm): the Y of
    /// the equal-energy spectrum with value 1/nm.
    fn integral_y(&self) -> f64 {
        integration_grid(self).map(|l| self.xyz_bar(l)[1]).sum()
    }
}

/// The wavelengths (nm) XYZ integration sums over: every integer nm inside the observer's range.
pub fn integration_grid<O: Observer + ?Sized>(obs: &O) -> impl Iterator<Item = f64> {
    let (lo, hi) = obs.range();
    let (lo, hi) = (lo.ceil() as i64, hi.floor() as i64);
    (lo..=hi).map(|l| l as f64)
}

/// Which CIE standard observer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CieObserverKind {
    /// CIE 1931 2°.
    Cie1931_2,
    /// CIE 1964 10°.
    Cie1964_10,
    /// CIE 2015 2° (cone-fundamental based).
    Cie2015_2,
    /// CIE 2015 10° (cone-fundamental based).
    Cie2015_10,
}

impl CieObserverKind {
    /// All four, in the order above.
    pub const ALL: [Self; 4] = [
        Self::Cie1931_2,
        Self::Cie1964_10,
        Self::Cie2015_2,
        Self::Cie2015_10,
    ];

    /// CLI/scene name: `cie1931-2`, `cie1964-10`, `cie2015-2`, `cie2015-10`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Cie1931_2 => "cie1931-2",
            Self::Cie1964_10 => "cie1964-10",
            Self::Cie2015_2 => "cie2015-2",
            Self::Cie2015_10 => "cie2015-10",
        }
    }

    /// Look up by [`name`](Self::name) (case-insensitive).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(name.trim()))
    }

    /// `(data file, CSV text)`. CIE tables as published by the CIE, 1 nm, via colour-science
    /// 0.4.7 (host/data/cie).
    fn data(self) -> (&'static str, &'static str) {
        match self {
            Self::Cie1931_2 => (
                "cie/cie1931_2deg.csv",
                include_str!("../../data/cie/cie1931_2deg.csv"),
            ),
            Self::Cie1964_10 => (
                "cie/cie1964_10deg.csv",
                include_str!("../../data/cie/cie1964_10deg.csv"),
            ),
            Self::Cie2015_2 => (
                "cie/cie2015_2deg.csv",
                include_str!("../../data/cie/cie2015_2deg.csv"),
            ),
            Self::Cie2015_10 => (
                "cie/cie2015_10deg.csv",
                include_str!("../../data/cie/cie2015_10deg.csv"),
            ),
        }
    }

    /// The observer, parsed once and shared.
    pub fn get(self) -> &'static CieObserver {
        static CELLS: [OnceLock<CieObserver>; 4] = [
            OnceLock::new(),
            OnceLock::new(),
            OnceLock::new(),
            OnceLock::new(),
        ];
        let idx = Self::ALL.iter().position(|&k| k == self).unwrap_or(0);
        CELLS[idx].get_or_init(|| CieObserver::load(self))
    }
}

/// A CIE observer tabulated at 1 nm; evaluation is an index computation and one lerp.
#[derive(Clone, Debug, PartialEq)]
pub struct CieObserver {
    kind: CieObserverKind,
    /// First wavelength of the table, nm.
    start: f64,
    /// `[x̄, ȳ, z̄]` at `start + i` nm.
    table: Vec<[f64; 3]>,
    integral_y: f64,
}

impl CieObserver {
    fn load(kind: CieObserverKind) -> Self {
        let (file, text) = kind.data();
        let t = parse_csv_table(text, file).expect("bundled CIE table is valid (checked by tests)");
        let start = t.wavelengths[0];
        // The bundled tables are on a 1 nm grid; evaluation relies on it.
        assert!(
            t.wavelengths
                .iter()
                .enumerate()
                .all(|(i, &l)| l == start + i as f64),
            "{file}: not a 1 nm grid"
        );
        let table: Vec<[f64; 3]> = (0..t.wavelengths.len())
            .map(|i| [t.columns[0][i], t.columns[1][i], t.columns[2][i]])
            .collect();
        let integral_y = table.iter().map(|v| v[1]).sum();
        Self {
            kind,
            start,
            table,
            integral_y,
        }
    }

    /// Which observer this is.
    pub fn kind(&self) -> CieObserverKind {
        self.kind
    }

    /// The table: the first node's wavelength (nm) and `[x̄, ȳ, z̄]` at every 1 nm from it.
    pub fn grid(&self) -> (f64, &[[f64; 3]]) {
        (self.start, &self.table)
    }
}

/// `[x̄, ȳ, z̄]` at `lambda_nm` of a table with nodes every 1 nm from `start` nm (at least two),
/// interpolated linearly, 0 outside: how [`CieObserver`] and
/// [`GridObserver`](super::GridObserver) evaluate, one code for both so that equal tables give
/// equal bits.
#[inline]
pub fn lerp_1nm(start: f64, table: &[[f64; 3]], lambda_nm: f64) -> [f64; 3] {
    let x = lambda_nm - start;
    let last = (table.len() - 1) as f64;
    if !(x >= 0.0 && x <= last) {
        return [0.0; 3];
    }
    let i = (x as usize).min(table.len() - 2);
    let s = x - i as f64;
    let (a, b) = (table[i], table[i + 1]);
    std::array::from_fn(|c| a[c] + s * (b[c] - a[c]))
}

impl Observer for CieObserver {
    fn name(&self) -> &str {
        self.kind.name()
    }

    fn range(&self) -> (f64, f64) {
        (self.start, self.start + (self.table.len() - 1) as f64)
    }

    fn xyz_bar(&self, lambda_nm: f64) -> [f64; 3] {
        lerp_1nm(self.start, &self.table, lambda_nm)
    }

    fn integral_y(&self) -> f64 {
        self.integral_y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Values at table nodes are the table entries (exact) and between nodes the lerp; peak of
    // CIE 1931 ȳ is 1.0 at 555 nm by definition of the luminous efficiency function.
    #[test]
    fn cie1931_values() {
        let o = CieObserverKind::Cie1931_2.get();
        assert_eq!(o.range(), (360.0, 830.0));
        assert_eq!(o.xyz_bar(555.0)[1], 1.0);
        assert_eq!(o.xyz_bar(359.9), [0.0; 3]);
        assert_eq!(o.xyz_bar(830.0)[0], 1.251141e-06);
        let mid = o.xyz_bar(555.5)[1];
        let expect = 0.5 * (o.xyz_bar(555.0)[1] + o.xyz_bar(556.0)[1]);
        assert!((mid - expect).abs() < 1e-15);
        // Σȳ at 1 nm ≈ 106.857 for CIE 1931 (the well-known normalization constant of the
        // 1 nm table); 1e-3 relative allows for the published rounding.
        assert!(
            (o.integral_y() / 106.857 - 1.0).abs() < 1e-3,
            "{}",
            o.integral_y()
        );
        for k in CieObserverKind::ALL {
            assert_eq!(CieObserverKind::from_name(k.name()), Some(k));
            assert!(k.get().integral_y() > 100.0);
        }
    }
}
