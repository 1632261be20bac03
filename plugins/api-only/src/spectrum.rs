//! The spot light's emission spectrum: an SPD the host resolved from the scene's spec
//! ([`Host::spd`](spectrace_plugin_api::Host::spd)), read per sample from a table held here.
//!
//! Each value of an SPD the host lends is a call through the plugin boundary; a light sample
//! needs four. So the light tabulates the SPD once, on a uniform grid of 0.25 nm over its range,
//! and keeps the table only if linear interpolation in it reproduces the host's values
//! everywhere it was checked (4,096 points spread over the range and 1 nm beyond each end,
//! every node and half-way point; differences ≤ 1e-6 of the SPD's peak, a few f32 roundings): true of the
//! host's own tables (blackbodies at 0.25 nm, bundled illuminants, CSV files on a grid of
//! 0.25 nm multiples). Otherwise, and for SPDs with spectral lines, every value is asked of the
//! host.

use spectrace_plugin_api::{PluginResult, Spd, SpdHandle};

/// Grid step of the table, nm.
const STEP_NM: f64 = 0.25;

/// An SPD lent by the host, with a table of it where the table is exact.
#[derive(Clone)]
pub struct EmissionSpd {
    handle: SpdHandle,
    table: Option<Table>,
}

#[derive(Clone, Debug)]
struct Table {
    lo: f32,
    hi: f32,
    inv_step: f32,
    values: Vec<f32>,
}

impl Table {
    #[inline]
    fn at(&self, nm: f32) -> f32 {
        if !(nm >= self.lo && nm <= self.hi) {
            return 0.0;
        }
        let x = (nm - self.lo) * self.inv_step;
        let i = (x as usize).min(self.values.len() - 2);
        let t = x - i as f32;
        let (a, b) = (self.values[i], self.values[i + 1]);
        a + t * (b - a)
    }
}

impl EmissionSpd {
    /// Wrap `handle`, tabulating it where the table is exact (see the module docs).
    pub fn new(handle: SpdHandle) -> PluginResult<Self> {
        let table = if handle.lines().is_empty() {
            Self::tabulate(&handle)?
        } else {
            None
        };
        Ok(Self { handle, table })
    }

    /// Whether values come from the table (for tests and the docs' claims).
    pub fn tabulated(&self) -> bool {
        self.table.is_some()
    }

    /// The host's SPD.
    pub fn handle(&self) -> &SpdHandle {
        &self.handle
    }

    fn tabulate(h: &SpdHandle) -> PluginResult<Option<Table>> {
        let r = h.range_nm();
        let (lo, hi) = (r.min_nm, r.max_nm);
        let cells = ((hi - lo) / STEP_NM).round();
        // The grid must end on the range's end and stay small.
        if !((1.0..=1e6).contains(&cells) && (lo + cells * STEP_NM - hi).abs() < 1e-9) {
            return Ok(None);
        }
        let cells = cells as usize;
        let mut values = Vec::with_capacity(cells + 1);
        for i in 0..=cells {
            values.push(h.value(lo + i as f64 * STEP_NM)? as f32);
        }
        let table = Table {
            lo: lo as f32,
            hi: hi as f32,
            inv_step: (1.0 / STEP_NM) as f32,
            values,
        };
        let peak = table.values.iter().fold(0.0f32, |m, &v| m.max(v));
        let tol = 1e-6 * peak as f64;
        let n = 4096;
        let probes = (0..n)
            .map(|i| lo - 1.0 + (hi - lo + 2.0) * (i as f64 + 0.37) / n as f64)
            .chain((0..=cells).map(|i| lo + i as f64 * STEP_NM))
            .chain((0..cells).map(|i| lo + (i as f64 + 0.5) * STEP_NM));
        for nm in probes {
            // The light reads the SPD at the f32 wavelengths of the host's lanes.
            let nm = nm as f32;
            let want = h.value(nm as f64)?;
            if (table.at(nm) as f64 - want).abs() > tol {
                return Ok(None);
            }
        }
        Ok(Some(table))
    }

    /// The normalised value (1/nm) at each lane's wavelength; on a spectral line, the line's
    /// share (as the host weighs a lane drawn on a line).
    #[inline]
    pub fn lanes(&self, nm: &[f32; 4]) -> PluginResult<[f32; 4]> {
        match &self.table {
            Some(t) => Ok(nm.map(|l| t.at(l))),
            None => {
                let mut out = [0.0; 4];
                for (o, &l) in out.iter_mut().zip(nm) {
                    *o = self.handle.value(l as f64)? as f32;
                }
                Ok(out)
            }
        }
    }
}
