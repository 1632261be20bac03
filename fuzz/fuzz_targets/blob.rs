//! The blob reader: any bytes give a blob or an error, never a panic.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = spectrace::plugin::blob::Blob::decode(data);
});
