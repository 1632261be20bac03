//! Measured luminaires: IES LM-63 and EULUMDAT readers, the format-independent [`Luminaire`]
//! model (candela table, symmetry, lamps, multipliers, flux) and a [`DirectionSampler`] that
//! importance-samples its emission directions; writers for IES LM-63-2019 and EULUMDAT.

pub mod candela_table;
pub mod direction_sampler;
pub mod efficacy;
pub mod error;
pub mod eulumdat;
pub mod eulumdat_writer;
pub mod gldf;
pub mod ies;
pub mod ies_writer;
pub mod luminaire;
mod number_stream;
pub mod tm25;

pub use candela_table::CandelaTable;
pub use direction_sampler::DirectionSampler;
pub use error::PhotometryError;
pub use luminaire::{
    IesVersion, LampSet, Luminaire, Multiplier, PhotometricType, SourceFormat, Symmetry, TiltTable,
};

use std::path::Path;

/// Read an IES LM-63 (`.ies`) or EULUMDAT (`.ldt`) file, chosen by extension; a file with
/// another extension is read as IES when it has a `TILT=` line and as EULUMDAT otherwise.
pub fn load_luminaire(path: &Path) -> Result<Luminaire, PhotometryError> {
    let bytes = crate::limits::read_limited(
        path,
        crate::limits::LUMINAIRE_FILE_MAX_BYTES,
        "luminaire file",
    )
    .map_err(|e| PhotometryError::file(path, "file", format!("cannot read: {e}")))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("ies") => ies::parse_ies(&bytes, path),
        Some("ldt") | Some("eul") => eulumdat::parse_eulumdat(&bytes, path),
        _ => {
            let has_tilt = bytes.windows(5).any(|w| w.eq_ignore_ascii_case(b"TILT="));
            if has_tilt {
                ies::parse_ies(&bytes, path)
            } else {
                eulumdat::parse_eulumdat(&bytes, path)
            }
        }
    }
}
