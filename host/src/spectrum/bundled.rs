//! Spectra bundled into the binary, found by name: the CIE standard illuminants and measured
//! lamps from `host/data/`.

use super::csv_table::{parse_csv_table, CsvTable};
use super::error::SpectrumError;
use super::tabulated_spd::{Interpolation, TabulatedSpd};

/// `(name, data file, CSV text)` of every bundled emission spectrum.
///
/// Illuminants: CIE 15:2018 tables, via colour-science 0.4.7 (host/data/illuminants).
/// Lamps: NIST CQS measured lamp spectra at 5 nm, via colour-science 0.4.7 (host/data/lamps).
pub const BUNDLED_SPDS: &[(&str, &str, &str)] = &[
    (
        "a",
        "illuminants/a.csv",
        include_str!("../../data/illuminants/a.csv"),
    ),
    (
        "d50",
        "illuminants/d50.csv",
        include_str!("../../data/illuminants/d50.csv"),
    ),
    (
        "d65",
        "illuminants/d65.csv",
        include_str!("../../data/illuminants/d65.csv"),
    ),
    (
        "e",
        "illuminants/e.csv",
        include_str!("../../data/illuminants/e.csv"),
    ),
    (
        "fl1",
        "illuminants/fl1.csv",
        include_str!("../../data/illuminants/fl1.csv"),
    ),
    (
        "fl10",
        "illuminants/fl10.csv",
        include_str!("../../data/illuminants/fl10.csv"),
    ),
    (
        "fl11",
        "illuminants/fl11.csv",
        include_str!("../../data/illuminants/fl11.csv"),
    ),
    (
        "fl12",
        "illuminants/fl12.csv",
        include_str!("../../data/illuminants/fl12.csv"),
    ),
    (
        "fl2",
        "illuminants/fl2.csv",
        include_str!("../../data/illuminants/fl2.csv"),
    ),
    (
        "fl3",
        "illuminants/fl3.csv",
        include_str!("../../data/illuminants/fl3.csv"),
    ),
    (
        "fl4",
        "illuminants/fl4.csv",
        include_str!("../../data/illuminants/fl4.csv"),
    ),
    (
        "fl5",
        "illuminants/fl5.csv",
        include_str!("../../data/illuminants/fl5.csv"),
    ),
    (
        "fl6",
        "illuminants/fl6.csv",
        include_str!("../../data/illuminants/fl6.csv"),
    ),
    (
        "fl7",
        "illuminants/fl7.csv",
        include_str!("../../data/illuminants/fl7.csv"),
    ),
    (
        "fl8",
        "illuminants/fl8.csv",
        include_str!("../../data/illuminants/fl8.csv"),
    ),
    (
        "fl9",
        "illuminants/fl9.csv",
        include_str!("../../data/illuminants/fl9.csv"),
    ),
    (
        "hp1",
        "illuminants/hp1.csv",
        include_str!("../../data/illuminants/hp1.csv"),
    ),
    (
        "hp5",
        "illuminants/hp5.csv",
        include_str!("../../data/illuminants/hp5.csv"),
    ),
    (
        "led_b1",
        "illuminants/led_b1.csv",
        include_str!("../../data/illuminants/led_b1.csv"),
    ),
    (
        "led_b2",
        "illuminants/led_b2.csv",
        include_str!("../../data/illuminants/led_b2.csv"),
    ),
    (
        "led_b3",
        "illuminants/led_b3.csv",
        include_str!("../../data/illuminants/led_b3.csv"),
    ),
    (
        "led_b4",
        "illuminants/led_b4.csv",
        include_str!("../../data/illuminants/led_b4.csv"),
    ),
    (
        "led_b5",
        "illuminants/led_b5.csv",
        include_str!("../../data/illuminants/led_b5.csv"),
    ),
    (
        "led_bh1",
        "illuminants/led_bh1.csv",
        include_str!("../../data/illuminants/led_bh1.csv"),
    ),
    (
        "led_rgb1",
        "illuminants/led_rgb1.csv",
        include_str!("../../data/illuminants/led_rgb1.csv"),
    ),
    (
        "led_v1",
        "illuminants/led_v1.csv",
        include_str!("../../data/illuminants/led_v1.csv"),
    ),
    (
        "led_v2",
        "illuminants/led_v2.csv",
        include_str!("../../data/illuminants/led_v2.csv"),
    ),
    (
        "high_pressure_sodium",
        "lamps/high_pressure_sodium.csv",
        include_str!("../../data/lamps/high_pressure_sodium.csv"),
    ),
    (
        "incandescent",
        "lamps/incandescent.csv",
        include_str!("../../data/lamps/incandescent.csv"),
    ),
    (
        "low_pressure_sodium",
        "lamps/low_pressure_sodium.csv",
        include_str!("../../data/lamps/low_pressure_sodium.csv"),
    ),
    (
        "mercury",
        "lamps/mercury.csv",
        include_str!("../../data/lamps/mercury.csv"),
    ),
    (
        "metal_halide",
        "lamps/metal_halide.csv",
        include_str!("../../data/lamps/metal_halide.csv"),
    ),
    (
        "phosphor_led_yag",
        "lamps/phosphor_led_yag.csv",
        include_str!("../../data/lamps/phosphor_led_yag.csv"),
    ),
    (
        "rgb_led_457_540_605",
        "lamps/rgb_led_457_540_605.csv",
        include_str!("../../data/lamps/rgb_led_457_540_605.csv"),
    ),
    (
        "triphosphor_fl",
        "lamps/triphosphor_fl.csv",
        include_str!("../../data/lamps/triphosphor_fl.csv"),
    ),
];

/// The ColorChecker Classic reflectances, 24 patches, 380–730 nm at 10 nm.
/// Source: BabelColor average, via colour-science 0.4.7 (host/data/reflectance).
pub const COLORCHECKER_CSV: &str =
    include_str!("../../data/reflectance/colorchecker_babelcolor_average.csv");

/// Names accepted by [`bundled_spd`], in table order.
pub fn bundled_names() -> impl Iterator<Item = &'static str> {
    BUNDLED_SPDS.iter().map(|(n, _, _)| *n)
}

/// Normalize a user-given name: case-insensitive, `-`/space as `_`, optional `illuminant_`
/// prefix, so `D65`, `illuminant-a` and `LED-B1` all work.
fn canonical(name: &str) -> String {
    let n = name.trim().to_ascii_lowercase().replace(['-', ' '], "_");
    n.strip_prefix("illuminant_")
        .map(str::to_string)
        .unwrap_or(n)
}

/// The raw table of the bundled spectrum `name`, with its data-file label.
pub fn bundled_table(name: &str) -> Option<Result<(CsvTable, &'static str), SpectrumError>> {
    let key = canonical(name);
    let (_, file, text) = BUNDLED_SPDS.iter().find(|(n, _, _)| *n == key)?;
    Some(parse_csv_table(text, file).map(|t| (t, *file)))
}

/// The bundled spectrum `name` as a normalized SPD, or `None` if there is no such name.
pub fn bundled_spd(name: &str) -> Option<Result<TabulatedSpd, SpectrumError>> {
    Some(bundled_table(name)?.and_then(|(t, file)| {
        TabulatedSpd::new(file, &t.wavelengths, &t.columns[0], Interpolation::Linear)
    }))
}

/// The ColorChecker table (patch names in the header).
pub fn colorchecker_table() -> CsvTable {
    parse_csv_table(
        COLORCHECKER_CSV,
        "reflectance/colorchecker_babelcolor_average.csv",
    )
    .expect("bundled ColorChecker table is valid (checked by tests)")
}

#[cfg(test)]
mod tests {
    use super::*;

    // Every bundled file must parse and normalize; structural check, no tolerance involved.
    #[test]
    fn all_bundled_spectra_load() {
        for name in bundled_names() {
            let spd = bundled_spd(name).unwrap().unwrap();
            assert!(spd.raw_integral() > 0.0, "{name}");
        }
        assert!(bundled_spd("D65").is_some());
        assert!(bundled_spd("Illuminant-A").is_some());
        assert!(bundled_spd("LED-B1").is_some());
        assert!(bundled_spd("nope").is_none());
        let cc = colorchecker_table();
        assert_eq!(cc.columns.len(), 24);
        assert_eq!(cc.wavelengths.len(), 36);
    }
}
