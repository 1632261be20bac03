//! [`GridObserver`]: an observer given as a table on a 1 nm grid, evaluated as the CIE tables
//! are ([`lerp_1nm`]). The host's own copy of a plugin observer that declares its functions
//! to be such a table (extension v7, checked when it is built: `plugin::observer_table`), so
//! that weighing a path's wavelengths costs what it costs with the built-in observers.
//!
//! | field | unit | meaning |
//! |-------|------|---------|
//! | `start` | nm | wavelength of the first node |
//! | `table` | — | `[x̄, ȳ, z̄]` at `start + i` nm |

use super::observer::{lerp_1nm, Observer};

/// Colour-matching functions tabulated every 1 nm, linear between nodes, 0 outside.
#[derive(Clone, Debug, PartialEq)]
pub struct GridObserver {
    name: String,
    start: f64,
    table: Vec<[f64; 3]>,
    /// `Σ ȳ` over the nodes, in order (as [`CieObserver`](super::CieObserver) sums it).
    integral_y: f64,
}

impl GridObserver {
    /// The observer `name` with nodes every 1 nm from `start` nm. An error says what is wrong
    /// with the table: fewer than two nodes, a start that is not a finite positive
    /// wavelength, or a value that is not finite.
    pub fn new(name: &str, start: f64, table: Vec<[f64; 3]>) -> Result<Self, String> {
        if table.len() < 2 {
            return Err(format!("{} node(s); at least 2 are needed", table.len()));
        }
        if !(start.is_finite() && start > 0.0) {
            return Err(format!(
                "first node at {start} nm, not a positive wavelength"
            ));
        }
        if let Some(i) = table.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
            return Err(format!(
                "the value at {} nm is {:?}, not finite",
                start + i as f64,
                table[i]
            ));
        }
        let integral_y = table.iter().map(|v| v[1]).sum();
        Ok(Self {
            name: name.to_string(),
            start,
            table,
            integral_y,
        })
    }
}

impl Observer for GridObserver {
    fn name(&self) -> &str {
        &self.name
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
    use crate::color::{CieObserverKind, Observer};

    // A copy of a CIE table is that observer to the bit (the same evaluation code), at nodes,
    // between them and outside; bad tables are refused with a reason.
    #[test]
    fn a_copy_of_a_cie_table_evaluates_to_the_same_bits() {
        let cie = CieObserverKind::Cie1931_2.get();
        let (start, table) = cie.grid();
        let copy = GridObserver::new("copy", start, table.to_vec()).unwrap();
        assert_eq!(copy.range(), cie.range());
        assert_eq!(copy.integral_y().to_bits(), cie.integral_y().to_bits());
        for i in 0..4000 {
            let nm = 355.0 + i as f64 * 0.1234;
            assert_eq!(copy.xyz_bar(nm), cie.xyz_bar(nm), "{nm} nm");
        }
        assert!(GridObserver::new("one", 400.0, vec![[0.0; 3]]).is_err());
        assert!(GridObserver::new("nan", 400.0, vec![[0.0; 3], [f64::NAN, 0.0, 0.0]]).is_err());
        assert!(GridObserver::new("start", f64::INFINITY, vec![[0.0; 3]; 2]).is_err());
    }
}
