//! The SPD CSV reader: any text gives a table or an error, never a panic.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = spectrace::spectrum::csv_table::parse_csv_table(text, "fuzz.csv");
    }
});
