//! Malformed spectral CSV input: every error names the file, the line and the cause.

use spectrace::spectrum::csv_table::{parse_csv_table, read_csv_table};
use spectrace::spectrum::{parse_spd_spec, SpectrumError};

/// Parse `text` and return (line, message); panics if it unexpectedly parses.
fn fail(text: &str) -> (usize, String) {
    match parse_csv_table(text, "bad.csv") {
        Err(e @ SpectrumError::Parse { line, .. }) => (line, e.to_string()),
        other => panic!("expected a parse error for {text:?}, got {other:?}"),
    }
}

// Each case: the exact line number (counting comments and the header) and a word from the
// cause. Exact line numbers because an off-by-one sends the user to the wrong row.
#[test]
fn each_defect_is_reported_with_line_and_cause() {
    let cases: &[(&str, usize, &str)] = &[
        ("# c\nwavelength_nm,v\n400,1\n390,1\n", 4, "not sorted"),
        ("400,1\n410,1\n410,2\n", 3, "duplicate"),
        ("400,1\n410,-0.5\n", 2, "negative"),
        ("400,1\n410,NaN\n", 2, "not finite"),
        ("400,1\n410,inf\n", 2, "not finite"),
        ("400,1\ninf,1\n", 2, "finite and positive"),
        ("400,1\n410,abc\n", 2, "not a number"),
        ("400,1\nxyz,1\n", 2, "not a number"),
        ("400,1\n410\n", 2, "wavelength_nm,value"),
        ("400,1,2\n410,1\n", 2, "columns"),
        ("# only\n400,1\n", 2, "at least 2 data rows"),
        ("", 1, "at least 2 data rows"),
        ("-5,1\n410,1\n", 1, "positive"),
    ];
    for &(text, line, cause) in cases {
        let (l, msg) = fail(text);
        assert_eq!(l, line, "{text:?}: {msg}");
        assert!(msg.contains(cause), "{text:?}: `{msg}` lacks `{cause}`");
        assert!(msg.starts_with(&format!("bad.csv:{line}:")), "{msg}");
    }
}

// Through a real file and the spec parser: the message names the path and the line; an
// all-zero table is rejected as a whole (it cannot be normalized); a missing file names itself.
#[test]
fn file_errors_name_the_path() {
    let dir = std::env::temp_dir().join(format!("spectra_csv_errors_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("unsorted.csv");
    std::fs::write(&bad, "wavelength_nm,value\n500,1\n450,2\n").unwrap();
    let msg = parse_spd_spec(bad.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("unsorted.csv:3:") && msg.contains("not sorted"),
        "{msg}"
    );

    let zero = dir.join("zero.csv");
    std::fs::write(&zero, "400,0\n500,0\n").unwrap();
    let msg = parse_spd_spec(zero.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("zero.csv") && msg.contains("not all zero"),
        "{msg}"
    );

    let multi = dir.join("multi.csv");
    std::fs::write(&multi, "wavelength_nm,a,b\n400,1,2\n500,1,0\n").unwrap();
    let msg = parse_spd_spec(multi.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(msg.contains("2 value columns"), "{msg}");
    assert!(parse_spd_spec(&format!("{}#b", multi.display())).is_ok());

    let missing = dir.join("missing.csv");
    let msg = read_csv_table(&missing).unwrap_err().to_string();
    assert!(
        msg.contains("missing.csv") && msg.contains("cannot read"),
        "{msg}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
