//! Luminous efficacy of a normalised emission spectrum, for lights given in lumens or
//! candelas: K = Km · Σ S(λ) V(λ) over 360, 361, …, 830 nm (Δλ = 1 nm) plus each spectral line's
//! share times V at its wavelength, Km = 683.002 lm/W (CIE 015:2018; the SI's 683 lm/W at
//! 540 THz, 555.016 nm). V(λ) is the CIE 1931 2° ȳ, `data/cie/cie1931_v.csv` (source in its
//! header), linear between its 1 nm rows and 0 outside 360–830 nm. The same rule as the host's
//! own conversion, so a light in lm or cd gets the built-in's power.

use spectrace_plugin_api::{PluginResult, Spd};

/// Maximum luminous efficacy of photopic vision, lm/W.
pub const KM_LM_PER_W: f64 = 683.002;

const V_CSV: &str = include_str!("../data/cie/cie1931_v.csv");

/// V(λ) at 360, 361, …, 830 nm.
fn v_table() -> Vec<f64> {
    V_CSV
        .lines()
        .filter(|l| !(l.starts_with('#') || l.starts_with("wavelength") || l.trim().is_empty()))
        .map(|l| {
            let (_, v) = l
                .split_once(',')
                .expect("data/cie/cie1931_v.csv: nm,y_bar rows");
            v.trim()
                .parse::<f64>()
                .expect("data/cie/cie1931_v.csv: a number")
        })
        .collect()
}

/// V(λ), linear between the table's rows, 0 outside 360–830 nm.
pub fn v(nm: f64) -> f64 {
    let t = v_table();
    if !(360.0..=830.0).contains(&nm) {
        return 0.0;
    }
    let x = nm - 360.0;
    let i = (x.floor() as usize).min(t.len() - 2);
    let f = x - i as f64;
    t[i] + f * (t[i + 1] - t[i])
}

/// Lumens per watt of `spd` (normalised, 1/nm); 0 when it has no visible part.
pub fn efficacy_lm_per_w(spd: &dyn Spd) -> PluginResult<f64> {
    let t = v_table();
    let lines = spd.lines();
    let on_line = |nm: f64| lines.iter().any(|l| l.nm as f32 == nm as f32);
    let mut y = 0.0;
    for (i, &vbar) in t.iter().enumerate() {
        let nm = 360.0 + i as f64;
        // The continuous part: at a wavelength that carries a line the host answers the line's
        // share instead, so read the continuous part just beside it.
        let s = if on_line(nm) {
            0.5 * (spd.value(nm - 1e-3)? + spd.value(nm + 1e-3)?)
        } else {
            spd.value(nm)?
        };
        if s != 0.0 {
            y += s * vbar;
        }
    }
    for l in &lines {
        y += l.weight * v(l.nm);
    }
    Ok(if y.is_finite() && y > 0.0 {
        KM_LM_PER_W * y
    } else {
        0.0
    })
}
