//! Serialized objects ("blobs"): a material, light, SPD or observer — built in or from a
//! plugin — saved to a file, to be loaded later by whichever host has its type. bincode is not
//! self-describing, so the header says exactly what the payload is and who can read it.
//!
//! Layout (all integers little-endian):
//!
//! | offset | size | field                                                                |
//! |--------|------|----------------------------------------------------------------------|
//! | 0      | 8    | magic `SPECBLOB`                                                     |
//! | 8      | 2    | format version, currently 2                                          |
//! | 10     | 1    | kind: 0 light, 1 spd, 2 observer, 3 material                         |
//! | 11     | 1    | reserved, 0                                                          |
//! | 12     | 4    | type version (the plugin type's state schema)                        |
//! | 16     | 2+n  | plugin name: u16 length, UTF-8 (`builtin` for built-in types)        |
//! | …      | 2+n  | plugin version: u16 length, UTF-8                                    |
//! | …      | 2+n  | type name: u16 length, UTF-8                                         |
//! | …      | 8    | payload length in bytes                                              |
//! | …      | 4    | CRC-32 (IEEE) of all preceding bytes followed by the payload         |
//! | …      | len  | payload: bincode 2 (standard config) of the type's parameters        |
//!
//! Names are at most [`MAX_NAME`] bytes, payloads at most [`MAX_PAYLOAD`] and never longer than
//! what the file holds: a corrupted length can neither cause a huge allocation nor a panic.
//! Nothing may follow the payload.
//!
//! For plugin types the payload is the plugin's saved state. For built-in types (plugin name
//! `builtin`) it is the type's parameter struct (`host/src/builtin/…`) in bincode, with the data
//! of every file it reads (CSV spectra) embedded at pack time, so the blob loads to the same
//! object after it is moved and its source files are gone. Format 1 stored built-in parameters
//! as RON text with file references; such files are refused with a message to re-pack them.

use spectrace_plugin_api::ObjectKind;
use std::fmt;
use std::path::{Path, PathBuf};

/// The 8 bytes every blob starts with.
pub const MAGIC: &[u8; 8] = b"SPECBLOB";
/// The format version this host writes and reads.
pub const FORMAT_VERSION: u16 = 2;
/// Longest name field, bytes.
pub const MAX_NAME: usize = 255;
/// Largest payload, bytes (the same bound plugins use when decoding state).
pub const MAX_PAYLOAD: u64 = spectrace_plugin_api::export::MAX_STATE_BYTES as u64;
/// Plugin name recorded for built-in types.
pub const BUILTIN_PLUGIN: &str = "builtin";

/// A decoded blob.
#[derive(Clone, Debug, PartialEq)]
pub struct Blob {
    /// Object kind.
    pub kind: ObjectKind,
    /// Plugin that provides the type (`builtin` for built-ins).
    pub plugin: String,
    /// Version of that plugin when the blob was written.
    pub plugin_version: String,
    /// Type name.
    pub type_name: String,
    /// State schema version of the type.
    pub type_version: u32,
    /// The state bytes.
    pub payload: Vec<u8>,
}

/// What is wrong with a blob's bytes.
#[derive(Clone, Debug, PartialEq)]
pub enum BlobError {
    /// Fewer bytes than the fixed header.
    TooShort(usize),
    /// Not a blob at all.
    BadMagic,
    /// Written by a newer (or unknown) format.
    UnsupportedFormat(u16),
    /// Kind byte out of range.
    UnknownKind(u8),
    /// The file ends inside a header field.
    Truncated {
        /// Field being read.
        field: &'static str,
        /// Bytes needed.
        needed: u64,
        /// Bytes left.
        left: u64,
    },
    /// A name is longer than allowed or not UTF-8.
    BadName {
        /// Which name.
        field: &'static str,
        /// What is wrong.
        what: String,
    },
    /// Payload length beyond the sane limit.
    PayloadTooLarge(u64),
    /// Payload length beyond what the file holds.
    PayloadBeyondFile {
        /// Declared length.
        declared: u64,
        /// Bytes present.
        present: u64,
    },
    /// Bytes after the payload.
    TrailingBytes(u64),
    /// Stored and computed checksums differ: the file was altered or damaged.
    Checksum {
        /// From the header.
        stored: u32,
        /// Over the bytes present.
        computed: u32,
    },
}

impl fmt::Display for BlobError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BlobError::TooShort(n) => write!(f, "truncated: {n} bytes is shorter than a blob header"),
            BlobError::BadMagic => write!(f, "not a spectrace blob (bad magic; expected `SPECBLOB`)"),
            BlobError::UnsupportedFormat(1) => write!(
                f,
                "blob format version 1 (older spectrace; built-in types as RON text with file references) is no longer read (this host reads version {FORMAT_VERSION}); pack the object again with `spectrace blob pack`"
            ),
            BlobError::UnsupportedFormat(v) => write!(
                f,
                "blob format version {v} is not supported (this host reads version {FORMAT_VERSION})"
            ),
            BlobError::UnknownKind(k) => write!(f, "unknown object kind byte {k} (corrupted header?)"),
            BlobError::Truncated {
                field,
                needed,
                left,
            } => write!(f, "truncated in the {field}: needs {needed} bytes, {left} left"),
            BlobError::BadName { field, what } => write!(f, "bad {field}: {what}"),
            BlobError::PayloadTooLarge(n) => write!(
                f,
                "payload length {n} bytes exceeds the limit of {MAX_PAYLOAD} bytes (corrupted length?)"
            ),
            BlobError::PayloadBeyondFile { declared, present } => write!(
                f,
                "truncated: header declares a {declared}-byte payload but only {present} bytes follow"
            ),
            BlobError::TrailingBytes(n) => write!(f, "{n} unexpected bytes after the payload"),
            BlobError::Checksum { stored, computed } => write!(
                f,
                "checksum mismatch (stored {stored:08x}, computed {computed:08x}): the blob is corrupted"
            ),
        }
    }
}

impl std::error::Error for BlobError {}

/// A blob error with the file it came from.
#[derive(Debug)]
pub struct BlobFileError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong (an I/O message or a [`BlobError`]).
    pub message: String,
}

impl fmt::Display for BlobFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for BlobFileError {}

fn kind_byte(kind: ObjectKind) -> u8 {
    match kind {
        ObjectKind::Light => 0,
        ObjectKind::Spd => 1,
        ObjectKind::Observer => 2,
        ObjectKind::Material => 3,
    }
}

fn byte_kind(b: u8) -> Option<ObjectKind> {
    Some(match b {
        0 => ObjectKind::Light,
        1 => ObjectKind::Spd,
        2 => ObjectKind::Observer,
        3 => ObjectKind::Material,
        _ => return None,
    })
}

impl Blob {
    /// Serialize to bytes. Fails only if a name is too long.
    pub fn encode(&self) -> Result<Vec<u8>, BlobError> {
        let mut out = Vec::with_capacity(64 + self.payload.len());
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.push(kind_byte(self.kind));
        out.push(0);
        out.extend_from_slice(&self.type_version.to_le_bytes());
        for (field, name) in [
            ("plugin name", &self.plugin),
            ("plugin version", &self.plugin_version),
            ("type name", &self.type_name),
        ] {
            if name.len() > MAX_NAME {
                return Err(BlobError::BadName {
                    field,
                    what: format!("{} bytes, at most {MAX_NAME} allowed", name.len()),
                });
            }
            out.extend_from_slice(&(name.len() as u16).to_le_bytes());
            out.extend_from_slice(name.as_bytes());
        }
        if self.payload.len() as u64 > MAX_PAYLOAD {
            return Err(BlobError::PayloadTooLarge(self.payload.len() as u64));
        }
        out.extend_from_slice(&(self.payload.len() as u64).to_le_bytes());
        let mut hasher = crc32fast::Hasher::new();
        hasher.update(&out);
        hasher.update(&self.payload);
        out.extend_from_slice(&hasher.finalize().to_le_bytes());
        out.extend_from_slice(&self.payload);
        Ok(out)
    }

    /// Parse bytes, checking every length against what is present before using it.
    pub fn decode(bytes: &[u8]) -> Result<Blob, BlobError> {
        const FIXED: usize = 16;
        if bytes.len() < 8 || &bytes[..8] != MAGIC {
            return Err(if bytes.len() < 8 && MAGIC.starts_with(bytes) {
                BlobError::TooShort(bytes.len())
            } else {
                BlobError::BadMagic
            });
        }
        if bytes.len() < FIXED {
            return Err(BlobError::TooShort(bytes.len()));
        }
        let format = u16::from_le_bytes([bytes[8], bytes[9]]);
        if format != FORMAT_VERSION {
            return Err(BlobError::UnsupportedFormat(format));
        }
        let kind = byte_kind(bytes[10]).ok_or(BlobError::UnknownKind(bytes[10]))?;
        let type_version = u32::from_le_bytes(bytes[12..16].try_into().expect("4 bytes"));
        let mut r = Reader { bytes, pos: FIXED };
        let plugin = r.name("plugin name")?;
        let plugin_version = r.name("plugin version")?;
        let type_name = r.name("type name")?;
        let len = u64::from_le_bytes(r.take("payload length", 8)?.try_into().expect("8 bytes"));
        let header_end = r.pos;
        let stored = u32::from_le_bytes(r.take("checksum", 4)?.try_into().expect("4 bytes"));
        if len > MAX_PAYLOAD {
            return Err(BlobError::PayloadTooLarge(len));
        }
        let present = (bytes.len() - r.pos) as u64;
        if len > present {
            return Err(BlobError::PayloadBeyondFile {
                declared: len,
                present,
            });
        }
        let payload = &bytes[r.pos..r.pos + len as usize];
        let mut hasher = crc32fast::Hasher::new();
        hasher.update(&bytes[..header_end]);
        hasher.update(payload);
        let computed = hasher.finalize();
        if computed != stored {
            return Err(BlobError::Checksum { stored, computed });
        }
        if present > len {
            return Err(BlobError::TrailingBytes(present - len));
        }
        Ok(Blob {
            kind,
            plugin,
            plugin_version,
            type_name,
            type_version,
            payload: payload.to_vec(),
        })
    }

    /// Read and decode a file; the file size is checked before anything is read into memory.
    pub fn read_file(path: &Path) -> Result<Blob, BlobFileError> {
        let err = |message: String| BlobFileError {
            path: path.to_path_buf(),
            message,
        };
        let meta = std::fs::metadata(path).map_err(|e| err(format!("cannot read: {e}")))?;
        let limit = MAX_PAYLOAD + 4 * 1024;
        if meta.len() > limit {
            return Err(err(format!(
                "{} bytes is larger than any valid blob ({limit} bytes at most)",
                meta.len()
            )));
        }
        // Not only the size above: a device or pipe (`/dev/zero`) has none and may never end.
        let bytes = crate::limits::read_limited(path, limit, "blob")
            .map_err(|e| err(format!("cannot read: {e}")))?;
        Blob::decode(&bytes).map_err(|e| err(e.to_string()))
    }

    /// Encode and write to a file.
    pub fn write_file(&self, path: &Path) -> Result<(), BlobFileError> {
        let err = |message: String| BlobFileError {
            path: path.to_path_buf(),
            message,
        };
        let bytes = self.encode().map_err(|e| err(e.to_string()))?;
        std::fs::write(path, bytes).map_err(|e| err(format!("cannot write: {e}")))
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, field: &'static str, n: usize) -> Result<&'a [u8], BlobError> {
        let left = self.bytes.len() - self.pos;
        if n > left {
            return Err(BlobError::Truncated {
                field,
                needed: n as u64,
                left: left as u64,
            });
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn name(&mut self, field: &'static str) -> Result<String, BlobError> {
        let len = u16::from_le_bytes(self.take(field, 2)?.try_into().expect("2 bytes")) as usize;
        if len > MAX_NAME {
            return Err(BlobError::BadName {
                field,
                what: format!("length {len} exceeds {MAX_NAME} bytes (corrupted header?)"),
            });
        }
        let raw = self.take(field, len)?;
        String::from_utf8(raw.to_vec()).map_err(|_| BlobError::BadName {
            field,
            what: "not valid UTF-8".to_string(),
        })
    }
}

/// Why a blob could not become an object.
#[derive(Debug)]
pub enum BlobLoadError {
    /// The blob names a plugin that is not loaded.
    MissingPlugin {
        /// Plugin name.
        plugin: String,
        /// Version that wrote the blob.
        version: String,
        /// Kind of the object.
        kind: ObjectKind,
        /// Type name.
        type_name: String,
    },
    /// The plugin is loaded but refused the state, or the type is unknown.
    Registry(super::RegistryError),
}

impl fmt::Display for BlobLoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BlobLoadError::MissingPlugin {
                plugin,
                version,
                kind,
                type_name,
            } => write!(
                f,
                "needs plugin `{plugin}` (version {version}, providing {kind} type `{type_name}`), \
                 which is not loaded; pass it with --plugin PATH or --plugins DIR"
            ),
            BlobLoadError::Registry(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for BlobLoadError {}

impl Blob {
    /// Save a plugin object of `kind` built from `params_ron` as a blob: its plugin's state.
    pub fn pack_plugin(
        registry: &super::Registry,
        kind: ObjectKind,
        type_name: &str,
        params_ron: &str,
    ) -> Result<Blob, super::RegistryError> {
        use spectrace_plugin_api::abi::std_types::RStr;
        use spectrace_plugin_api::module::ObjectSource;
        let entry = registry.lookup(kind, type_name)?.clone();
        let Some(plugin) = registry.plugin_for(kind, type_name)? else {
            return Err(super::RegistryError::Construct {
                kind: kind.into(),
                name: type_name.to_string(),
                provider: "built-in".into(),
                error: spectrace_plugin_api::PluginError::unsupported(
                    "a built-in type is packed with Blob::pack_item",
                ),
            });
        };
        let source = || ObjectSource::Params(RStr::from_str(params_ron));
        let payload = match kind {
            ObjectKind::Light => registry
                .create_plugin_light(type_name, source())?
                .light
                .save_state(),
            ObjectKind::Material => registry
                .create_plugin_material(type_name, source())?
                .material
                .save_state(),
            ObjectKind::Spd => registry
                .create_plugin_spd(type_name, source())?
                .spd
                .save_state(),
            ObjectKind::Observer => registry
                .create_plugin_observer(type_name, source())?
                .observer
                .save_state(),
        }
        .into_result()
        .map_err(|error| super::RegistryError::Construct {
            kind: kind.into(),
            name: type_name.to_string(),
            provider: entry.provider.describe(),
            error,
        })?;
        Ok(Blob {
            kind,
            plugin: plugin.info.name.to_string(),
            plugin_version: plugin.info.version.to_string(),
            type_name: type_name.to_string(),
            type_version: entry.info.version,
            payload: payload.into_vec(),
        })
    }

    /// Save a plugin light built from `params_ron` as a blob.
    pub fn pack_plugin_light(
        registry: &super::Registry,
        type_name: &str,
        params_ron: &str,
    ) -> Result<Blob, super::RegistryError> {
        Self::pack_plugin(registry, ObjectKind::Light, type_name, params_ron)
    }

    /// The plugin that wrote this blob is loaded in `registry` (built-in blobs need none).
    pub fn check_plugin(&self, registry: &super::Registry) -> Result<(), BlobLoadError> {
        let loaded = registry
            .plugins()
            .iter()
            .any(|p| p.info.name.as_str() == self.plugin);
        if !loaded {
            return Err(BlobLoadError::MissingPlugin {
                plugin: self.plugin.clone(),
                version: self.plugin_version.clone(),
                kind: self.kind,
                type_name: self.type_name.clone(),
            });
        }
        Ok(())
    }

    /// Rebuild the light this blob holds, through the plugin that wrote it.
    pub fn load_plugin_light(
        &self,
        registry: &super::Registry,
    ) -> Result<spectrace_plugin_api::LightObject, BlobLoadError> {
        use spectrace_plugin_api::abi::std_types::RSlice;
        use spectrace_plugin_api::module::ObjectSource;
        self.check_plugin(registry)?;
        registry
            .create_plugin_light(
                &self.type_name,
                ObjectSource::State {
                    type_version: self.type_version,
                    bytes: RSlice::from_slice(&self.payload),
                },
            )
            .map_err(BlobLoadError::Registry)
    }

    /// The built-in type this blob holds, if it was written for one.
    pub fn builtin_type(&self) -> Result<&'static crate::builtin::BuiltinType, String> {
        let ty = crate::builtin::find(self.kind.into(), &self.type_name).ok_or_else(|| {
            format!(
                "written by the host for built-in {} type `{}`, which this host does not have",
                self.kind, self.type_name
            )
        })?;
        if self.type_version != ty.version {
            return Err(format!(
                "built-in {} `{}`: saved with type version {}, this host reads version {}",
                self.kind, self.type_name, self.type_version, ty.version
            ));
        }
        Ok(ty)
    }

    /// A built-in blob's parameters in scene syntax (decoded from its bincode payload).
    pub fn builtin_params(&self) -> Result<String, String> {
        let ty = self.builtin_type()?;
        let state = ty
            .state
            .ok_or_else(|| format!("a {} cannot be a blob", self.kind))?;
        (state.load)(&self.payload).map_err(|e| e.to_string())
    }

    /// The payload decoded into parameters (RON), by the host or the plugin that wrote it.
    pub fn describe(&self, registry: &super::Registry) -> Result<String, BlobLoadError> {
        if self.plugin == BUILTIN_PLUGIN {
            let text = self.builtin_params().map_err(|e| {
                BlobLoadError::Registry(super::RegistryError::Construct {
                    kind: self.kind.into(),
                    name: self.type_name.clone(),
                    provider: "built-in".into(),
                    error: spectrace_plugin_api::PluginError::invalid_parameter(e),
                })
            })?;
            return Ok(match ron::from_str::<ron::Value>(&text) {
                Ok(v) => super::ron_text::to_scene_syntax(&shortened(v)),
                Err(_) => text,
            });
        }
        self.check_plugin(registry)?;
        registry
            .describe_plugin_state(self.kind, &self.type_name, self.type_version, &self.payload)
            .map_err(BlobLoadError::Registry)
    }

    /// The header as `key: value` lines.
    pub fn header_text(&self) -> String {
        format!(
            "format: SPECBLOB version {FORMAT_VERSION}\nkind: {}\nplugin: {} {}\ntype: {} (state version {})\npayload: {} bytes",
            self.kind, self.plugin, self.plugin_version, self.type_name, self.type_version,
            self.payload.len()
        )
    }
}

/// `v` with every string longer than 256 characters cut to its first 64 and a count (embedded
/// data, such as a ray file's base64, is not for reading on a terminal).
fn shortened(v: ron::Value) -> ron::Value {
    use ron::Value;
    match v {
        Value::String(s) if s.chars().count() > 256 => {
            let head: String = s.chars().take(64).collect();
            Value::String(format!("{head}… ({} characters in all)", s.chars().count()))
        }
        Value::Seq(items) => Value::Seq(items.into_iter().map(shortened).collect()),
        Value::Option(Some(inner)) => Value::Option(Some(Box::new(shortened(*inner)))),
        Value::Map(m) => Value::Map(m.into_iter().map(|(k, v)| (k, shortened(v))).collect()),
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Blob {
        Blob {
            kind: ObjectKind::Light,
            plugin: "point-light".into(),
            plugin_version: "0.1.0".into(),
            type_name: "point".into(),
            type_version: 1,
            payload: vec![1, 2, 3, 4, 5],
        }
    }

    #[test]
    fn round_trip_is_identity() {
        let b = sample();
        assert_eq!(Blob::decode(&b.encode().unwrap()).unwrap(), b);
    }

    #[test]
    fn every_truncation_is_an_error_not_a_panic() {
        let bytes = sample().encode().unwrap();
        for n in 0..bytes.len() {
            let e = Blob::decode(&bytes[..n]).unwrap_err();
            let msg = e.to_string();
            assert!(
                msg.contains("truncated") || msg.contains("shorter") || msg.contains("checksum"),
                "cut at {n}: {msg}"
            );
        }
    }

    #[test]
    fn every_single_bit_flip_is_detected() {
        // CRC-32 detects all single-bit errors; header fields may fail earlier checks instead.
        let bytes = sample().encode().unwrap();
        for i in 0..bytes.len() * 8 {
            let mut b = bytes.clone();
            b[i / 8] ^= 1 << (i % 8);
            assert!(Blob::decode(&b).is_err(), "flip of bit {i} went unnoticed");
        }
    }

    #[test]
    fn huge_declared_length_is_refused_without_allocating() {
        let mut bytes = sample().encode().unwrap();
        let len_at = bytes.len() - 5 - 4 - 8;
        bytes[len_at..len_at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(matches!(
            Blob::decode(&bytes),
            Err(BlobError::PayloadTooLarge(_))
        ));
        bytes[len_at..len_at + 8].copy_from_slice(&1000u64.to_le_bytes());
        assert!(matches!(
            Blob::decode(&bytes),
            Err(BlobError::PayloadBeyondFile { declared: 1000, .. })
        ));
    }
}
