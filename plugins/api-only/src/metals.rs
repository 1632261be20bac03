//! Measured complex indices of refraction `n + i·k` of four metals, and the table type a scene's
//! own `(nm, n)`, `(nm, k)` pairs make. Interpolated linearly in wavelength and held at the end
//! values outside the table, as the built-in conductor does.
//!
//! | metal (names) | file | source |
//! |---|---|---|
//! | gold (`gold`, `au`) | `data/metals/au.csv` | Johnson & Christy 1972, via refractiveindex.info (CC0) |
//! | silver (`silver`, `ag`) | `data/metals/ag.csv` | Johnson & Christy 1972, via refractiveindex.info (CC0) |
//! | copper (`copper`, `cu`) | `data/metals/cu.csv` | Johnson & Christy 1972, via refractiveindex.info (CC0) |
//! | aluminium (`aluminium`, `aluminum`, `al`) | `data/metals/al.csv` | Rakić 1995, via refractiveindex.info (CC0) |
//!
//! Each file's header gives the full reference; the tables are the host's
//! (`host/data/metals/`), copied into this crate so that it stands alone.

const AU: &str = include_str!("../data/metals/au.csv");
const AG: &str = include_str!("../data/metals/ag.csv");
const CU: &str = include_str!("../data/metals/cu.csv");
const AL: &str = include_str!("../data/metals/al.csv");

/// `n` and `k` over wavelength (nm), rows sorted by wavelength.
#[derive(Clone, Debug, PartialEq)]
pub struct ComplexIor {
    nm: Vec<f32>,
    n: Vec<f32>,
    k: Vec<f32>,
}

impl ComplexIor {
    /// From `(nm, n, k)` rows: at least two, wavelengths increasing, n > 0, k ≥ 0.
    pub fn from_rows(rows: &[(f32, f32, f32)]) -> Result<Self, String> {
        if rows.len() < 2 {
            return Err("a complex IOR table needs at least two rows".into());
        }
        if let Some(w) = rows.windows(2).find(|w| !(w[1].0 > w[0].0)) {
            return Err(format!("wavelengths not increasing at {} nm", w[1].0));
        }
        if let Some(r) = rows.iter().find(|r| !(r.1 > 0.0 && r.2 >= 0.0)) {
            return Err(format!("invalid n, k at {} nm", r.0));
        }
        Ok(Self {
            nm: rows.iter().map(|r| r.0).collect(),
            n: rows.iter().map(|r| r.1).collect(),
            k: rows.iter().map(|r| r.2).collect(),
        })
    }

    /// A bundled metal by name (case-insensitive): gold/au, silver/ag, copper/cu,
    /// aluminium/aluminum/al.
    pub fn metal(name: &str) -> Result<Self, String> {
        let (file, text) = match name.to_ascii_lowercase().as_str() {
            "gold" | "au" => ("au.csv", AU),
            "silver" | "ag" => ("ag.csv", AG),
            "copper" | "cu" => ("cu.csv", CU),
            "aluminium" | "aluminum" | "al" => ("al.csv", AL),
            other => {
                return Err(format!(
                    "unknown metal {other:?}; bundled metals: gold, silver, copper, aluminium"
                ))
            }
        };
        let mut rows = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') || line.starts_with("wavelength") {
                continue;
            }
            let cols: Result<Vec<f32>, _> = line.split(',').map(|s| s.trim().parse()).collect();
            match cols {
                Ok(c) if c.len() == 3 => rows.push((c[0], c[1], c[2])),
                _ => return Err(format!("data/metals/{file} line {}: not nm,n,k", i + 1)),
            }
        }
        Self::from_rows(&rows).map_err(|e| format!("data/metals/{file}: {e}"))
    }

    /// `(n, k)` at `nm`, linear between rows, the end rows' values beyond them.
    #[inline]
    pub fn at(&self, nm: f32) -> (f32, f32) {
        let last = self.nm.len() - 1;
        let l = nm.clamp(self.nm[0], self.nm[last]);
        // The first row above `l` (l lies within the table, so 1 ≤ i ≤ last unless l is the
        // last row itself).
        let i = self.nm.partition_point(|&x| x <= l);
        if i > last {
            return (self.n[last], self.k[last]);
        }
        let i = i.max(1);
        let (x0, x1) = (self.nm[i - 1], self.nm[i]);
        let t = (l - x0) / (x1 - x0);
        (
            self.n[i - 1] + t * (self.n[i] - self.n[i - 1]),
            self.k[i - 1] + t * (self.k[i] - self.k[i - 1]),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bundled tables load; values at a row are the row's, half-way between two rows their
    /// mean, and beyond the ends the end rows' (1e-6: f32 rounding).
    #[test]
    fn tables_interpolate_and_clamp() {
        for m in ["gold", "Ag", "copper", "aluminum"] {
            ComplexIor::metal(m).unwrap();
        }
        assert!(ComplexIor::metal("mithril").is_err());
        let t = ComplexIor::from_rows(&[(400.0, 1.0, 2.0), (500.0, 3.0, 4.0)]).unwrap();
        assert_eq!(t.at(400.0), (1.0, 2.0));
        assert_eq!(t.at(300.0), (1.0, 2.0));
        assert_eq!(t.at(900.0), (3.0, 4.0));
        let (n, k) = t.at(450.0);
        assert!((n - 2.0).abs() < 1e-6 && (k - 3.0).abs() < 1e-6);
    }
}
