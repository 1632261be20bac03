//! The sidecar state of a resumable reference render (`REF.exr.state`): the per-pixel XYZ sums in
//! f64 and how many passes made them, so a stopped render resumes without losing a sample.
//!
//! # Format (version 1, all integers little-endian)
//! | bytes | field |
//! |---|---|
//! | 8 | magic `SPTREF01` |
//! | 4 | version `u32` = 1 |
//! | 4, 4 | width, height `u32` (pixels) |
//! | 8 | base seed `u64` |
//! | 4 | samples per pixel per pass `u32` |
//! | 8 | passes done `u64` |
//! | 4 + n | key: length `u32`, then UTF-8 (scene, integrator, depth: what must not change on resume) |
//! | 24·w·h | per-pixel XYZ sums, 3 × `f64` each, row-major from the top-left pixel |
//! | 4 | CRC-32 (IEEE) of every byte before it |
//!
//! The file is written to `NAME.tmp` and renamed over `NAME`, so a crash mid-write leaves the
//! previous state intact.
//!
//! A reference keeps f64 sums (a progressive reference only ever grows on one machine); renders
//! that are split or resumed use the exact film in the render state file
//! ([`crate::film::state_file`]), whose framing (magic, version, CRC-32, atomic write) is the same.

use super::AnalysisError;
use std::path::Path;

const MAGIC: &[u8; 8] = b"SPTREF01";
const VERSION: u32 = 1;

/// Accumulated sums of a progressive reference render.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceState {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Seed from which every pass's seed is derived.
    pub base_seed: u64,
    /// Samples per pixel of one pass.
    pub pass_spp: u32,
    /// Passes accumulated so far.
    pub passes: u64,
    /// What the sums were rendered from; resuming with a different key is refused.
    pub key: String,
    /// Per-pixel Σ XYZ over all samples (film convention, see [`crate::film`]).
    pub sums: Vec<[f64; 3]>,
}

impl ReferenceState {
    /// An empty state.
    pub fn new(width: u32, height: u32, base_seed: u64, pass_spp: u32, key: String) -> Self {
        Self {
            width,
            height,
            base_seed,
            pass_spp,
            passes: 0,
            key,
            sums: vec![[0.0; 3]; width as usize * height as usize],
        }
    }

    /// Samples per pixel accumulated.
    pub fn spp(&self) -> u64 {
        self.passes * self.pass_spp as u64
    }

    /// Mean XYZ per pixel.
    pub fn image(&self) -> crate::film::XyzImage {
        let n = self.spp().max(1) as f64;
        crate::film::XyzImage {
            width: self.width,
            height: self.height,
            xyz: self.sums.iter().map(|s| s.map(|v| v / n)).collect(),
        }
    }

    /// Serialise (see the module docs for the layout).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut b = Vec::with_capacity(48 + self.key.len() + 24 * self.sums.len());
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&VERSION.to_le_bytes());
        b.extend_from_slice(&self.width.to_le_bytes());
        b.extend_from_slice(&self.height.to_le_bytes());
        b.extend_from_slice(&self.base_seed.to_le_bytes());
        b.extend_from_slice(&self.pass_spp.to_le_bytes());
        b.extend_from_slice(&self.passes.to_le_bytes());
        b.extend_from_slice(&(self.key.len() as u32).to_le_bytes());
        b.extend_from_slice(self.key.as_bytes());
        for s in &self.sums {
            for v in s {
                b.extend_from_slice(&v.to_le_bytes());
            }
        }
        let crc = crc32fast::hash(&b);
        b.extend_from_slice(&crc.to_le_bytes());
        b
    }

    /// Parse bytes read from `path` (named in errors).
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, AnalysisError> {
        let bad = |message: String| AnalysisError::Content {
            path: path.to_path_buf(),
            message,
        };
        if bytes.len() < 8 || &bytes[..8] != MAGIC {
            return Err(bad(
                "not a spectrace reference state file (magic SPTREF01 missing)".into(),
            ));
        }
        if bytes.len() < 44 {
            return Err(bad(format!("truncated: only {} bytes", bytes.len())));
        }
        let (body, crc) = bytes.split_at(bytes.len() - 4);
        let stored = u32::from_le_bytes(crc.try_into().unwrap_or([0; 4]));
        let computed = crc32fast::hash(body);
        if stored != computed {
            return Err(bad(format!(
                "checksum mismatch (stored {stored:08x}, computed {computed:08x}): the file is \
                 damaged; delete it to start the reference again"
            )));
        }
        let mut r = Reader { b: body, at: 8 };
        let version = r.u32().ok_or_else(|| bad("truncated header".into()))?;
        if version != VERSION {
            return Err(bad(format!(
                "state format version {version}, this spectrace reads version {VERSION}"
            )));
        }
        let truncated = || bad("truncated header".into());
        let width = r.u32().ok_or_else(truncated)?;
        let height = r.u32().ok_or_else(truncated)?;
        let base_seed = r.u64().ok_or_else(truncated)?;
        let pass_spp = r.u32().ok_or_else(truncated)?;
        let passes = r.u64().ok_or_else(truncated)?;
        let key_len = r.u32().ok_or_else(truncated)? as usize;
        let key = r.take(key_len).ok_or_else(truncated).and_then(|k| {
            String::from_utf8(k.to_vec()).map_err(|_| bad("key is not UTF-8".into()))
        })?;
        // u64 products: 24·width·height overflows a 64-bit count for damaged sizes (found by
        // fuzzing; wrapped, it could match the file's length and ask for an absurd allocation).
        let n = width as u64 * height as u64;
        let rest = (body.len() - r.at) as u64;
        match n.checked_mul(24) {
            Some(need) if need == rest => {}
            need => {
                return Err(bad(format!(
                    "{width}×{height} pixels need {} bytes of sums, found {rest}",
                    need.map_or("more than 2^64".to_string(), |b| b.to_string())
                )));
            }
        }
        let n = n as usize;
        let sums = (0..n)
            .map(|_| {
                let mut p = [0.0; 3];
                for v in &mut p {
                    *v = f64::from_le_bytes(
                        r.take(8).unwrap_or(&[0; 8]).try_into().unwrap_or([0; 8]),
                    );
                }
                p
            })
            .collect();
        Ok(Self {
            width,
            height,
            base_seed,
            pass_spp,
            passes,
            key,
            sums,
        })
    }

    /// Read a state file.
    pub fn load(path: &Path) -> Result<Self, AnalysisError> {
        // Sums of a render that fits in memory: half the available memory at most.
        let limit = crate::limits::available_memory_bytes() / 2;
        let bytes = crate::limits::read_limited(path, limit, "reference state").map_err(|e| {
            AnalysisError::Read {
                path: path.to_path_buf(),
                message: e.to_string(),
            }
        })?;
        Self::from_bytes(&bytes, path)
    }

    /// Write atomically: to `path.tmp`, flushed to disk, then renamed over `path` (the same
    /// writer as the render state files of slices and checkpoints).
    pub fn save(&self, path: &Path) -> Result<(), AnalysisError> {
        crate::film::state_file::write_atomically(path, &self.to_bytes()).map_err(|e| {
            AnalysisError::Write {
                path: path.to_path_buf(),
                message: e.to_string(),
            }
        })
    }
}

/// A cursor over little-endian fields.
struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let s = self.b.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(s)
    }
    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }
    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bytes round-trip exactly (f64 bit patterns included); one flipped byte anywhere is caught
    /// by the CRC and the error names the file; a truncated file is refused, never a panic.
    #[test]
    fn round_trip_and_damage() {
        let mut s = ReferenceState::new(3, 2, 42, 8, "scene=x".into());
        s.passes = 5;
        s.sums[4] = [1.0 / 3.0, -0.0, 1e300];
        let p = Path::new("ref.exr.state");
        let bytes = s.to_bytes();
        assert_eq!(ReferenceState::from_bytes(&bytes, p).unwrap(), s);
        for i in [0, 9, 20, 60, bytes.len() - 1] {
            let mut b = bytes.clone();
            b[i] ^= 0x10;
            let e = ReferenceState::from_bytes(&b, p).unwrap_err().to_string();
            assert!(e.contains("ref.exr.state"), "{e}");
        }
        for n in [0, 7, 30, bytes.len() - 5] {
            assert!(ReferenceState::from_bytes(&bytes[..n], p).is_err());
        }
    }

    /// A damaged size whose byte count overflows 64 bits is refused: 2^31 × 2^30 pixels need
    /// 24 · 2^61 = 3 · 2^64 bytes, which wrapped to 0 and matched an empty sum block, so the
    /// reader went on to allocate 2^61 pixels (found by fuzzing the reader).
    #[test]
    fn overflowing_size_is_refused() {
        let s = ReferenceState::new(1, 1, 42, 8, "scene=x".into());
        let bytes = s.to_bytes();
        let mut b = bytes[..bytes.len() - 4 - 24].to_vec();
        b[12..16].copy_from_slice(&(1u32 << 31).to_le_bytes());
        b[16..20].copy_from_slice(&(1u32 << 30).to_le_bytes());
        let crc = crc32fast::hash(&b);
        b.extend_from_slice(&crc.to_le_bytes());
        let e = ReferenceState::from_bytes(&b, Path::new("ref.exr.state"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("2147483648×1073741824") && e.contains("2^64"),
            "{e}"
        );
    }
}
