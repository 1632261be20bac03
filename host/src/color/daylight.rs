//! CIE daylight (D-series) spectra at any correlated colour temperature, from the daylight
//! components S0, S1, S2 (CIE 15:2004 Table T.2, `host/data/cie/d_series_components.csv`) and
//! the daylight locus x_D(T), y_D(x_D) of CIE 15:2004 section 3.1. Used as the reference
//! illuminant of colour rendering above 5000 K.

/// The components as `(nm, S0, S1, S2)` rows, 5 nm steps.
fn components() -> &'static [(f64, f64, f64, f64)] {
    static TABLE: std::sync::OnceLock<Vec<(f64, f64, f64, f64)>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        // S1 and S2 are negative in places, which the spectral CSV reader rightly refuses for
        // spectra, so this small signed table is read here.
        include_str!("../../data/cie/d_series_components.csv")
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("wavelength"))
            .filter_map(|l| {
                let f: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
                (f.len() == 4).then(|| (f[0], f[1], f[2], f[3]))
            })
            .collect()
    })
}

/// Chromaticity (x, y) of CIE daylight at `kelvin` (valid 4000–25000 K; clamped to it).
pub fn daylight_xy(kelvin: f64) -> (f64, f64) {
    let t = kelvin.clamp(4000.0, 25_000.0);
    let x = if t <= 7000.0 {
        -4.6070e9 / t.powi(3) + 2.9678e6 / t.powi(2) + 0.09911e3 / t + 0.244063
    } else {
        -2.0064e9 / t.powi(3) + 1.9018e6 / t.powi(2) + 0.24748e3 / t + 0.237040
    };
    (x, -3.000 * x * x + 2.870 * x - 0.275)
}

/// Relative spectral power of CIE daylight at `kelvin`, at `lambda_nm` (linear between the
/// 5 nm rows, 0 outside 300–830 nm). M1 and M2 are not rounded (CIE 15 rounds them only for
/// the tabulated standard illuminants).
pub fn daylight_spd(kelvin: f64) -> impl Fn(f64) -> f64 {
    let (x, y) = daylight_xy(kelvin);
    let m = 0.0241 + 0.2562 * x - 0.7341 * y;
    let m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m;
    let m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m;
    move |l: f64| {
        let rows = components();
        let value = |r: &(f64, f64, f64, f64)| r.1 + m1 * r.2 + m2 * r.3;
        let i = rows.partition_point(|r| r.0 <= l);
        if i == 0 || i == rows.len() && l > rows[rows.len() - 1].0 {
            return 0.0;
        }
        if i == rows.len() {
            return value(&rows[i - 1]);
        }
        let (a, b) = (&rows[i - 1], &rows[i]);
        let t = (l - a.0) / (b.0 - a.0);
        value(a) + (value(b) - value(a)) * t
    }
}
