//! IES TM-25 ray files (ANSI/IES TM-25-13, `.TM25RAY`): a light source as the rays a near-field
//! goniophotometer measured or an optical simulation traced, each with a start point (mm), a
//! direction, a flux and optionally a wavelength or an index into spectral tables.
//!
//! - [`reader`]: the header (sections 4.7.1 to 4.7.6), its consistency rules, and the rays read
//!   straight from the file's bytes (memory-mapped: a 20 M-ray file is 560 MB and is never
//!   copied; [`RayFile::open`]), one record at a time.
//! - [`writer`]: writes a ray set as TM-25-13 (radiant flux, per-ray wavelength or one spectral
//!   table), read back by [`reader`].
//!
//! # Layout (little-endian)
//!
//! The layout follows the section numbers of the standard as the public-domain reference
//! implementation by J. Muschaweck (github.com/JuliusMuschaweck/TM25RaySetTools, Unlicense)
//! names its fields, and was checked here against files written by LightTools 8.7 and by that
//! implementation, and an ams OSRAM vendor file (see `scenes/rays/README.md`).
//!
//! | offset | size | field (section) |
//! |---|---|---|
//! | 0 | 4 | `TM25` (4.7.1.1) |
//! | 4 | i32 | version, 2013 (4.7.1.2) |
//! | 8 | i32 | creation method, 0 simulation, 1 measurement (4.7.1.3) |
//! | 12 | f32 | total luminous flux, lm, NaN if unknown (4.7.1.4) |
//! | 16 | f32 | total radiant flux, W, NaN if unknown (4.7.1.5) |
//! | 20 | u64 | number of rays (4.7.1.6) |
//! | 28 | 28 B | creation date and time, ASCII (4.7.1.7) |
//! | 56 | i32 | ray start position (4.7.1.8) |
//! | 60 | i32 | spectral data identifier 0..4 (4.7.1.9) |
//! | 64, 68, 72 | f32 | single wavelength, minimum, maximum wavelength, nm (4.7.1.10–12) |
//! | 76 | i32 | number of spectral tables (4.7.1.13) |
//! | 80 | i32 | number of additional ray data items (4.7.1.14) |
//! | 84 | i32 | size of the additional text block, bytes, a multiple of 32 (4.7.1.15) |
//! | 88 | 168 B | reserved |
//! | 256 | 8 × i32 | known-data flags: position, direction (both 1), radiant flux, wavelength, luminous flux, Stokes, tristimulus, spectrum index (4.7.2) |
//! | 288 | 9 × 4000 B | nine UTF-32LE text fields of 1000 code points (4.7.3.1–9) |
//! | 36288 | | spectral tables: each an i32 count then (λ nm, weight) f32 pairs, the block padded with zeros to a multiple of 32 bytes (4.7.4) |
//! | | 512 B each | names of the additional columns, UTF-32LE (4.7.5) |
//! | | | additional text, UTF-32LE (4.7.6) |
//! | | | rays: f32 records (4.7.7) |
//!
//! A ray record is `x y z kx ky kz`, then the columns the flags switch on, in this order:
//! radiant flux (W), wavelength (nm), luminous flux (lm, "tristimulus Y"), Stokes S1 S2 S3 and
//! the polarisation ellipse axis x y z (six columns), tristimulus X and Z, the spectrum index
//! (1-based, as a float), then the additional columns. The record size is counted from the
//! flags, never assumed.
//!
//! Spectral data identifier: 0 none, 1 one wavelength for every ray (4.7.1.10), 2 a wavelength
//! per ray, 3 one spectral table for every ray, 4 a table per ray chosen by its index.
//! Rules enforced (the standard's, as the reference implementation checks them): the position
//! and direction flags are 1, every flag is 0 or 1, at least one of radiant and luminous flux,
//! identifier 2 needs the wavelength flag, identifiers 2 and 4 need radiant flux without
//! luminous flux, Stokes needs radiant flux, tristimulus needs luminous flux and identifier 0,
//! the spectrum-index flag is set exactly for identifier 4, identifiers 3 and 4 need tables.

pub mod reader;
pub mod writer;

pub use reader::{
    KnownData, RawRay, RayFile, RayLayout, SpectralId, Tm25Header, FIXED_HEADER_BYTES, TEXT_FIELDS,
};
pub use writer::{write_tm25, Tm25Spectrum, WriteHeader, WriteRay};
