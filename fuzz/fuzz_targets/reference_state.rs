//! The reference-render state reader: any bytes give a state or an error, never a panic.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = spectrace::analysis::reference_state::ReferenceState::from_bytes(
        data,
        std::path::Path::new("fuzz.state"),
    );
});
