//! The blob reader: any bytes give a blob or an error, never a panic; a blob that decodes is
//! also instantiated (built-in lights; no plugins are loaded), which parses its payload.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(blob) = spectrace::plugin::blob::Blob::decode(data) {
        let factory = spectrace::plugin::factory::RegistryFactory::new(
            std::sync::Arc::new(spectrace::plugin::builtin_registry()),
            spectrace::plugin::adapter::PluginFaults::new(),
        );
        let _ = blob.instantiate(&factory);
    }
});
