//! IES LM-63-2019 writer: a [`Luminaire`] as an `.ies` file that this crate's reader (and any
//! LM-63 reader) reads back to the same table.
//!
//! | field | written as |
//! |---|---|
//! | keywords | `[TEST]`, `[TESTLAB]`, `[ISSUEDATE]`, `[MANUFAC]` (required by LM-63-2019), then each header line of the source as `[OTHER]` |
//! | `TILT=` | `NONE`, or `INCLUDE` with the source's tilt table |
//! | lamps | number of lamps of set 1; lumens per lamp = rated lumens / lamps, or −1 for absolute photometry |
//! | candela multiplier, ballast factor | 1: the table already includes every multiplier |
//! | file generation type | 1.00001 (undefined) |
//! | units | 2 (metres) |
//! | angles, candela | the stored table, in the shortest decimal form that reads back to the same `f64` |

use super::luminaire::{Luminaire, PhotometricType};
use std::fmt::Write as _;

/// The LM-63-2019 text of `lum`; `source` names where it came from (written to `[TEST]`).
pub fn write_ies_2019(lum: &Luminaire, source: &str) -> String {
    let mut s = String::new();
    let line = |s: &mut String, t: &str| {
        s.push_str(t);
        s.push_str("\r\n");
    };
    line(&mut s, "IES:LM-63-2019");
    line(
        &mut s,
        &format!("[TEST] exported by spectrace from {source}"),
    );
    line(&mut s, "[TESTLAB] unknown (exported)");
    line(&mut s, "[ISSUEDATE] unknown (exported)");
    line(&mut s, "[MANUFAC] unknown (exported)");
    for h in &lum.header {
        line(&mut s, &format!("[OTHER] {h}"));
    }
    match &lum.tilt {
        None => line(&mut s, "TILT=NONE"),
        Some(t) => {
            line(&mut s, "TILT=INCLUDE");
            line(&mut s, &t.geometry.to_string());
            line(&mut s, &t.angles_deg.len().to_string());
            write_values(&mut s, &t.angles_deg);
            write_values(&mut s, &t.factors);
        }
    }
    let lamps = lum.lamps.first().map_or(1, |l| l.count.abs().max(1));
    let lumens = match lum.rated_lamp_lumens {
        Some(r) if !lum.absolute => r / lamps as f64,
        _ => -1.0,
    };
    let ptype = match lum.photometric_type {
        PhotometricType::C => 1,
        PhotometricType::B => 2,
        PhotometricType::A => 3,
    };
    let [w, l, h] = lum.size_m;
    line(
        &mut s,
        &format!(
            "{lamps} {lumens} 1 {} {} {ptype} 2 {w} {l} {h}",
            lum.v_deg.len(),
            lum.h_deg.len()
        ),
    );
    let watts = lum.lamps.iter().filter_map(|l| l.watts).sum::<f64>();
    line(&mut s, &format!("1 1.00001 {watts}"));
    write_values(&mut s, &lum.v_deg);
    write_values(&mut s, &lum.h_deg);
    for row in lum.candela.chunks(lum.v_deg.len()) {
        write_values(&mut s, row);
    }
    s
}

/// Values 10 to a line, shortest round-trip form.
pub(crate) fn write_values(s: &mut String, values: &[f64]) {
    for chunk in values.chunks(10) {
        let parts: Vec<String> = chunk.iter().map(|v| format!("{v}")).collect();
        let _ = write!(s, "{}\r\n", parts.join(" "));
    }
}
