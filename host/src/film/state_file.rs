//! The render state file: one format for a slice of a distributed render
//! (`render --slice K/M`) and for the checkpoint of an interrupted one (`render --resume`).
//! It holds the exact film ([`FilmState`]) and what is needed to check that parts belong
//! together and to continue: the scene's and settings' fingerprint, the seed, the total samples
//! per pixel, the slice and the sample indices done.
//!
//! # Format (version 2)
//! | bytes | field |
//! |---|---|
//! | 8 | magic `SPTSTATE` |
//! | 4 | version `u32` little-endian = 2 |
//! | n | [`RenderState`] encoded with bincode 2 (standard configuration: little-endian, varint lengths) |
//! | 4 | CRC-32 (IEEE) of every byte before it, little-endian |
//!
//! Version 2 added the spectral sums (`FilmState::spectral`, the last field of the last field,
//! an `Option`). A version 1 file is therefore a version 2 body without the `None` tag (one 0
//! byte) at its end: it still loads, as a state without spectral sums.
//!
//! Written to `NAME.tmp`, flushed and renamed over `NAME`, so a crash mid-write leaves the
//! previous file intact and a slice that is rerun simply replaces its file.

use super::FilmState;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"SPTSTATE";
const VERSION: u32 = 2;
/// The previous version, still read (see the module docs).
const VERSION_1: u32 = 1;

/// A problem reading, writing or combining state files; names the file.
#[derive(Debug, thiserror::Error)]
pub enum StateError {
    /// The file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Cause.
        message: String,
    },
    /// The file is not a valid state file.
    #[error("{path}: {message}")]
    Content {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Slice `index` of `count` (1-based): its share of every pixel's sample indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SliceSpec {
    /// Which slice, 1 ≤ index ≤ count.
    pub index: u32,
    /// How many slices the render is cut into.
    pub count: u32,
}

impl SliceSpec {
    /// The whole render as its only slice.
    pub const WHOLE: SliceSpec = SliceSpec { index: 1, count: 1 };

    /// Parse `K/M` (1 ≤ K ≤ M).
    pub fn parse(text: &str) -> Result<Self, String> {
        let bad = || format!("--slice {text:?}: expected K/M with 1 ≤ K ≤ M, e.g. 2/8");
        let (k, m) = text.split_once('/').ok_or_else(bad)?;
        let index: u32 = k.trim().parse().map_err(|_| bad())?;
        let count: u32 = m.trim().parse().map_err(|_| bad())?;
        if index == 0 || count == 0 || index > count {
            return Err(bad());
        }
        Ok(Self { index, count })
    }

    /// The sample indices of this slice out of `spp` per pixel: the contiguous range
    /// `⌊(K−1)·N/M⌋ .. ⌊K·N/M⌋` (slices differ by at most one sample per pixel).
    pub fn range(&self, spp: u32) -> std::ops::Range<u32> {
        let at = |k: u32| (k as u64 * spp as u64 / self.count as u64) as u32;
        at(self.index - 1)..at(self.index)
    }
}

impl std::fmt::Display for SliceSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// A slice or checkpoint of a render.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RenderState {
    /// The scene file as given on the command line (made absolute), `None` for the embedded
    /// Cornell box.
    pub scene: Option<PathBuf>,
    /// FNV-1a 64 of the scene file's bytes and of [`settings`](Self::settings).
    pub fingerprint: u64,
    /// Every setting that changes the image, as `name=value` pairs (integrator, depth,
    /// wavelength options, camera, representation switches, plugins).
    pub settings: String,
    /// The render's command-line arguments after `render`, to resume with.
    pub args: Vec<String>,
    /// Seed of all random numbers.
    pub seed: u64,
    /// Samples per pixel of the whole render (all slices).
    pub spp_total: u32,
    /// Which slice this is.
    pub slice: SliceSpec,
    /// Sample indices done: `slice.range(spp_total).start .. done_until`.
    pub done_until: u32,
    /// The scene's output RGB space by name (`srgb`, …), for the merged EXR.
    pub rgb_space: String,
    /// The scene's PNG exposure, for the merged PNG.
    pub png_exposure: f64,
    /// The accumulated film of those samples.
    pub film: FilmState,
}

impl RenderState {
    /// The sample indices this slice must cover.
    pub fn range(&self) -> std::ops::Range<u32> {
        self.slice.range(self.spp_total)
    }

    /// True when every sample of the slice is in the film.
    pub fn is_complete(&self) -> bool {
        self.done_until == self.range().end
    }

    /// Serialise (see the module docs).
    pub fn to_bytes(&self) -> Result<Vec<u8>, String> {
        let mut b = MAGIC.to_vec();
        b.extend_from_slice(&VERSION.to_le_bytes());
        let body = bincode::serde::encode_to_vec(self, bincode::config::standard())
            .map_err(|e| e.to_string())?;
        b.extend_from_slice(&body);
        let crc = crc32fast::hash(&b);
        b.extend_from_slice(&crc.to_le_bytes());
        Ok(b)
    }

    /// Parse the bytes of `path` (named in errors).
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, StateError> {
        let bad = |message: String| StateError::Content {
            path: path.to_path_buf(),
            message,
        };
        if bytes.len() < 8 || &bytes[..8] != MAGIC {
            return Err(bad(
                "not a spectrace render state (slice or checkpoint): magic SPTSTATE missing".into(),
            ));
        }
        if bytes.len() < 16 {
            return Err(bad(format!("truncated: only {} bytes", bytes.len())));
        }
        let (body, crc) = bytes.split_at(bytes.len() - 4);
        let stored = u32::from_le_bytes(crc.try_into().unwrap_or([0; 4]));
        let computed = crc32fast::hash(body);
        if stored != computed {
            return Err(bad(format!(
                "checksum mismatch (stored {stored:08x}, computed {computed:08x}): the file is \
                 damaged or cut short; render this slice again"
            )));
        }
        let version = u32::from_le_bytes(body[8..12].try_into().unwrap_or([0; 4]));
        let mut payload = std::borrow::Cow::Borrowed(&body[12..]);
        match version {
            VERSION => {}
            // No spectral sums yet: append the `None` the encoding of version 2 ends with.
            VERSION_1 => payload.to_mut().push(0),
            _ => {
                return Err(bad(format!(
                    "state format version {version}, this spectrace reads versions \
                     {VERSION_1} and {VERSION}"
                )))
            }
        }
        let (state, used): (RenderState, usize) =
            bincode::serde::decode_from_slice(&payload, bincode::config::standard())
                .map_err(|e| bad(format!("cannot decode: {e}")))?;
        if used != payload.len() {
            return Err(bad(format!(
                "{} unexpected bytes after the state",
                payload.len() - used
            )));
        }
        state.validate().map_err(bad)?;
        Ok(state)
    }

    /// Internal consistency: film sizes and the sample range.
    fn validate(&self) -> Result<(), String> {
        let (w, h) = self.film.resolution();
        let n = w as usize * h as usize;
        if self.film.camera.pixels().len() != n
            || !(self.film.splats.is_empty() || self.film.splats.len() == n)
        {
            return Err(format!("film arrays do not match its {w}×{h} pixels"));
        }
        if let Some(sp) = &self.film.spectral {
            sp.validate()?;
            if (sp.width, sp.height) != (w, h) {
                return Err(format!(
                    "spectral sums of {}×{} pixels in a {w}×{h} film",
                    sp.width, sp.height
                ));
            }
        }
        let s = self.slice;
        if s.index == 0 || s.index > s.count || s.count > self.spp_total.max(1) {
            return Err(format!(
                "slice {s} of a {} spp render is not valid",
                self.spp_total
            ));
        }
        let r = self.range();
        if !(r.start <= self.done_until && self.done_until <= r.end) {
            return Err(format!(
                "samples done up to {} lie outside the slice's range {}..{}",
                self.done_until, r.start, r.end
            ));
        }
        Ok(())
    }

    /// Read a state file.
    pub fn load(path: &Path) -> Result<Self, StateError> {
        let bytes = std::fs::read(path).map_err(|e| StateError::Io {
            path: path.to_path_buf(),
            message: format!("cannot read: {e}"),
        })?;
        Self::from_bytes(&bytes, path)
    }

    /// Write atomically (temporary file, flushed, renamed).
    pub fn save(&self, path: &Path) -> Result<(), StateError> {
        let bytes = self.to_bytes().map_err(|message| StateError::Content {
            path: path.to_path_buf(),
            message,
        })?;
        write_atomically(path, &bytes).map_err(|e| StateError::Io {
            path: path.to_path_buf(),
            message: format!("cannot write: {e}"),
        })
    }

    /// Merge the complete slices `parts` (with their file names for errors) into the state of
    /// the whole render, after checking they belong together: same scene and settings
    /// (fingerprint), seed, samples per pixel, slice count and resolution; every slice present
    /// exactly once and finished.
    pub fn merge_parts(parts: &[(PathBuf, RenderState)]) -> Result<RenderState, String> {
        let Some((first_path, first)) = parts.first() else {
            return Err("no parts to merge".into());
        };
        let mut seen: Vec<Option<&Path>> = vec![None; first.slice.count as usize];
        for (path, s) in parts {
            s.belongs_with(path, first, first_path)?;
            s.check_complete(path)?;
            let slot = &mut seen[s.slice.index as usize - 1];
            if let Some(other) = slot {
                return Err(format!(
                    "slice {} is given twice: {} and {}",
                    s.slice,
                    other.display(),
                    path.display()
                ));
            }
            *slot = Some(path);
        }
        let missing: Vec<String> = seen
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_none())
            .map(|(i, _)| format!("{}/{}", i + 1, first.slice.count))
            .collect();
        if !missing.is_empty() {
            return Err(format!(
                "missing slice(s) {} of the {} spp render (seed {}): render them with \
                 `--slice K/{}` and merge again",
                missing.join(", "),
                first.spp_total,
                first.seed,
                first.slice.count
            ));
        }
        Ok(first.merged(parts))
    }

    /// An error unless this slice (read from `path`) belongs to the same render as `first`
    /// (read from `first_path`): scene and settings, seed, spp, slice count, resolution and
    /// spectral sums.
    fn belongs_with(
        &self,
        path: &Path,
        first: &RenderState,
        first_path: &Path,
    ) -> Result<(), String> {
        let s = self;
        let differs = |what: &str, a: String, b: String| {
            Err(format!(
                "{} does not belong with {}: {what} {b} there, {a} here",
                path.display(),
                first_path.display()
            ))
        };
        if s.fingerprint != first.fingerprint || s.settings != first.settings {
            return differs(
                "scene/settings",
                format!("{:016x} [{}]", s.fingerprint, s.settings),
                format!("{:016x} [{}]", first.fingerprint, first.settings),
            );
        }
        if s.seed != first.seed {
            return differs("seed", s.seed.to_string(), first.seed.to_string());
        }
        if s.spp_total != first.spp_total {
            return differs("spp", s.spp_total.to_string(), first.spp_total.to_string());
        }
        if s.slice.count != first.slice.count {
            return differs(
                "slice count",
                s.slice.count.to_string(),
                first.slice.count.to_string(),
            );
        }
        if s.film.resolution() != first.film.resolution() {
            return differs(
                "resolution",
                format!("{:?}", s.film.resolution()),
                format!("{:?}", first.film.resolution()),
            );
        }
        match (&s.film.spectral, &first.film.spectral) {
            (Some(a), Some(b)) => b.compatible(a).map_err(|e| {
                format!(
                    "{} does not belong with {}: {e}",
                    path.display(),
                    first_path.display()
                )
            }),
            (None, None) => Ok(()),
            (a, _) => {
                let has = |x: bool| if x { "carries" } else { "does not carry" };
                Err(format!(
                    "{} {} spectral sums and {} {}: render every slice with the same \
                     --spectral-exr and --bins, or none",
                    path.display(),
                    has(a.is_some()),
                    first_path.display(),
                    has(a.is_none())
                ))
            }
        }
    }

    /// An error unless this slice (read from `path`) holds all its samples.
    fn check_complete(&self, path: &Path) -> Result<(), String> {
        if self.is_complete() {
            return Ok(());
        }
        let r = self.range();
        Err(format!(
            "{} is slice {} but holds only samples {}..{} of {}..{}: finish it with \
             `spectrace render --resume {}` (or render the slice again)",
            path.display(),
            self.slice,
            r.start,
            self.done_until,
            r.start,
            r.end,
            path.display()
        ))
    }

    /// The whole render from `parts`, checked to belong with this one (the first): their films
    /// summed in slice order (exact sums: the order does not change the bits, but the
    /// refused-sample lists read better this way).
    fn merged(&self, parts: &[(PathBuf, RenderState)]) -> RenderState {
        let first = self;
        let mut ordered: Vec<&RenderState> = parts.iter().map(|(_, s)| s).collect();
        ordered.sort_by_key(|s| s.slice.index);
        let (w, h) = first.film.resolution();
        let mut film = FilmState::new(w, h, false);
        film.spectral = first
            .film
            .spectral
            .as_ref()
            .map(|sp| super::spectral_film::SpectralSums::new(sp.bins, w, h));
        for s in &ordered {
            film.merge(&s.film);
        }
        RenderState {
            scene: first.scene.clone(),
            fingerprint: first.fingerprint,
            settings: first.settings.clone(),
            args: first.args.clone(),
            seed: first.seed,
            spp_total: first.spp_total,
            slice: SliceSpec::WHOLE,
            done_until: first.spp_total,
            rgb_space: first.rgb_space.clone(),
            png_exposure: first.png_exposure,
            film,
        }
    }
}

/// Write `bytes` to `path.tmp`, flush to disk, rename over `path`.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
    }
    std::fs::rename(&tmp, path)
}

/// FNV-1a, 64 bit: a stable fingerprint (std's hashers may change between Rust releases; a
/// cryptographic hash is not needed to tell scenes apart). Hand-written: eight lines.
pub fn fnv1a64(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in parts {
        for &b in *p {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        // Separate the parts so ("ab", "c") and ("a", "bc") differ.
        h ^= 0xff;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Slice ranges tile 0..N without gaps or overlaps for every M ≤ N tried; parsing refuses
    /// 0/M, K > M and junk.
    #[test]
    fn slices_tile_the_samples() {
        for n in [1u32, 2, 7, 16, 1000] {
            for m in 1..=n.min(9) {
                let mut next = 0;
                for k in 1..=m {
                    let r = SliceSpec { index: k, count: m }.range(n);
                    assert_eq!(r.start, next);
                    next = r.end;
                }
                assert_eq!(next, n);
            }
        }
        assert_eq!(
            SliceSpec::parse("2/8").unwrap(),
            SliceSpec { index: 2, count: 8 }
        );
        for bad in ["0/3", "4/3", "x", "1/0", "1-3"] {
            assert!(SliceSpec::parse(bad).is_err(), "{bad}");
        }
    }

    /// A state round-trips exactly; a flipped or cut byte is refused with the file named.
    #[test]
    fn round_trip_and_damage() {
        let mut film = FilmState::new(2, 1, true);
        film.splats[1][0].add(0.25);
        film.spp = 3;
        let s = RenderState {
            scene: None,
            fingerprint: 7,
            settings: "integrator=lt".into(),
            args: vec!["--spp".into(), "3".into()],
            seed: 1,
            spp_total: 3,
            slice: SliceSpec::WHOLE,
            done_until: 3,
            rgb_space: "srgb".into(),
            png_exposure: 1.0,
            film,
        };
        let p = Path::new("part.state");
        let bytes = s.to_bytes().unwrap();
        assert_eq!(RenderState::from_bytes(&bytes, p).unwrap(), s);
        for i in [0, 9, 20, bytes.len() - 1] {
            let mut b = bytes.clone();
            b[i] ^= 0x10;
            let e = RenderState::from_bytes(&b, p).unwrap_err().to_string();
            assert!(e.contains("part.state"), "{e}");
        }
        for n in [0, 7, 15, bytes.len() - 5] {
            assert!(RenderState::from_bytes(&bytes[..n], p).is_err());
        }
        // A version 1 file (no spectral sums: the body without its final `None` byte) loads
        // as the same state; an unknown version is refused naming the versions read.
        let mut v1 = bytes[..bytes.len() - 5].to_vec();
        v1[8..12].copy_from_slice(&1u32.to_le_bytes());
        let crc = crc32fast::hash(&v1);
        v1.extend_from_slice(&crc.to_le_bytes());
        assert_eq!(RenderState::from_bytes(&v1, p).unwrap(), s);
        let mut v9 = bytes[..bytes.len() - 4].to_vec();
        v9[8..12].copy_from_slice(&9u32.to_le_bytes());
        let crc = crc32fast::hash(&v9);
        v9.extend_from_slice(&crc.to_le_bytes());
        let e = RenderState::from_bytes(&v9, p).unwrap_err().to_string();
        assert!(e.contains("version 9") && e.contains("1 and 2"), "{e}");
    }

    /// A state with spectral sums round-trips exactly, and `merge_parts` refuses to mix a part
    /// with spectral sums and one without, or parts with different nodes.
    #[test]
    fn spectral_sums_round_trip_and_must_match() {
        use crate::film::spectral::SpectralBins;
        use crate::film::spectral_film::SpectralSums;
        let part = |k: u32, bins: Option<&str>| {
            let mut film = FilmState::new(2, 1, false);
            film.spp = 1;
            film.spectral = bins.map(|b| {
                let mut sp = SpectralSums::new(SpectralBins::parse(b).unwrap(), 2, 1);
                sp.sums[3].add(0.5 * k as f64);
                sp
            });
            RenderState {
                scene: None,
                fingerprint: 7,
                settings: "integrator=pt".into(),
                args: Vec::new(),
                seed: 1,
                spp_total: 2,
                slice: SliceSpec { index: k, count: 2 },
                done_until: k,
                rgb_space: "srgb".into(),
                png_exposure: 1.0,
                film,
            }
        };
        let a = part(1, Some("400:700:100"));
        let back = RenderState::from_bytes(&a.to_bytes().unwrap(), Path::new("a")).unwrap();
        assert_eq!(back, a);
        let merged = RenderState::merge_parts(&[
            ("a".into(), a.clone()),
            ("b".into(), part(2, Some("400:700:100"))),
        ])
        .unwrap();
        assert_eq!(merged.film.spectral.as_ref().unwrap().sums[3].value(), 1.5);
        let e = RenderState::merge_parts(&[("a".into(), a.clone()), ("b".into(), part(2, None))])
            .unwrap_err();
        assert!(e.contains("spectral") && e.contains('b'), "{e}");
        let e =
            RenderState::merge_parts(&[("a".into(), a), ("b".into(), part(2, Some("400:700:50")))])
                .unwrap_err();
        assert!(e.contains("400:700:50"), "{e}");
    }
}
