//! Checking a plugin observer's claim that its colour-matching functions ARE a table on a 1 nm
//! grid, interpolated linearly (`ColorObserver::table`), once, when it
//! is built. The host then evaluates its own copy ([`GridObserver`], the CIE tables' code)
//! instead of calling `xyz_bar` per wavelength: bidirectional and light tracing weigh each
//! path's wavelengths with the observer, four calls per sample.
//!
//! A declared table the host used without checking could make a lying plugin's observer
//! render with functions it never evaluates. So the plugin's own `xyz_bar` is asked where a
//! difference would show first, and must give the copy's value to the bit:
//!
//! | probe | where |
//! |---|---|
//! | nodes | every `start + i` nm |
//! | between nodes | every `start + i + ½` nm (the straight line between the nodes) |
//! | outside | ½ nm before the first node and after the last (0) |
//! | range | the observer's `range_nm` equals the table's `[start, start + n − 1]` |
//!
//! About 2n + 2 calls (945 for a 360–830 nm table): nothing next to building a scene. Between
//! the probed points a function that is not that line stays the plugin's responsibility, as
//! the API's documentation says.

use crate::color::{GridObserver, Observer};
use spectrace_plugin_api::{abi::std_types::RResult, ObserverObject, ObserverTable};

/// The host's copy of `table`, the table `observer` declares, after checking the claim;
/// else what is off, as the end of a sentence.
pub fn host_copy(object: &ObserverObject, table: &ObserverTable) -> Result<GridObserver, String> {
    let observer = &object.observer;
    let values: Vec<[f64; 3]> = table.xyz.iter().map(|v| [v.x, v.y, v.z]).collect();
    let copy = GridObserver::new(&object.name, table.start_nm, values)
        .map_err(|e| format!("its table is unusable: {e}"))?;
    let (lo, hi) = copy.range();
    let r = object.range;
    if r.min_nm != lo || r.max_nm != hi {
        return Err(format!(
            "its range_nm is {}..{} nm where its table covers {lo}..{hi} nm",
            r.min_nm, r.max_nm
        ));
    }
    let n = table.xyz.len();
    let probes = (0..n)
        .map(|i| lo + i as f64)
        .chain((0..n - 1).map(|i| lo + i as f64 + 0.5))
        .chain([lo - 0.5, hi + 0.5]);
    for nm in probes {
        let own = match observer.xyz_bar(nm) {
            RResult::ROk(v) => [v.x, v.y, v.z],
            RResult::RErr(e) => return Err(format!("its xyz_bar fails at {nm} nm: {}", e.message)),
        };
        let declared = copy.xyz_bar(nm);
        if own.map(f64::to_bits) != declared.map(f64::to_bits) {
            return Err(format!(
                "at {nm} nm its xyz_bar gives {own:?} where its table gives {declared:?}"
            ));
        }
    }
    Ok(copy)
}
