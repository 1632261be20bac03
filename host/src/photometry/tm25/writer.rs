//! Writing TM-25-13 ray files (layout in [`super`]): radiant flux per ray, and the spectrum as
//! one wavelength, a wavelength per ray or one spectral table. Rays are streamed to the file,
//! so a ray set of any size is written in constant memory.

use std::io::Write;

/// How the spectrum of the written rays is given.
#[derive(Clone, Debug, PartialEq)]
pub enum Tm25Spectrum {
    /// Identifier 0: no spectral data.
    None,
    /// Identifier 1: every ray at this wavelength, nm.
    Single(f32),
    /// Identifier 2: each ray's own wavelength (the wavelength column).
    PerRay,
    /// Identifier 3: one table `(nm, weight)` for every ray.
    Table(Vec<(f32, f32)>),
}

/// One ray to write.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WriteRay {
    /// Start point, mm.
    pub position_mm: [f32; 3],
    /// Unit direction.
    pub direction: [f32; 3],
    /// Radiant flux, W.
    pub flux_w: f32,
    /// Wavelength, nm (written with [`Tm25Spectrum::PerRay`], ignored otherwise).
    pub wavelength_nm: f32,
}

/// What goes in the header besides the rays.
#[derive(Clone, Debug, PartialEq)]
pub struct WriteHeader {
    /// Total luminous flux, lm (NaN: unknown).
    pub luminous_flux_lm: f32,
    /// Total radiant flux, W.
    pub radiant_flux_w: f32,
    /// Creation date and time (ISO 8601), at most 28 bytes kept.
    pub date: String,
    /// The nine text fields ([`super::TEXT_FIELDS`]).
    pub texts: [String; 9],
    /// The spectrum.
    pub spectrum: Tm25Spectrum,
}

fn utf32_block(out: &mut impl Write, s: &str, bytes: usize) -> std::io::Result<()> {
    let mut buf = Vec::with_capacity(bytes);
    for ch in s.chars().take(bytes / 4 - 1) {
        buf.extend_from_slice(&(ch as u32).to_le_bytes());
    }
    buf.resize(bytes, 0);
    out.write_all(&buf)
}

/// Write `n_rays` rays from `rays` as a TM-25-13 file to `out` (creation method 0, simulation).
/// An error if `rays` yields another number of rays than `n_rays`.
pub fn write_tm25(
    out: &mut impl Write,
    header: &WriteHeader,
    n_rays: u64,
    rays: impl Iterator<Item = WriteRay>,
) -> std::io::Result<()> {
    type Table<'a> = Vec<&'a Vec<(f32, f32)>>;
    let (id, lambda, lmin, lmax, tables): (i32, f32, f32, f32, Table) = match &header.spectrum {
        Tm25Spectrum::None => (0, f32::NAN, f32::NAN, f32::NAN, vec![]),
        Tm25Spectrum::Single(l) => (1, *l, *l, *l, vec![]),
        Tm25Spectrum::PerRay => (2, f32::NAN, f32::NAN, f32::NAN, vec![]),
        Tm25Spectrum::Table(t) => (
            3,
            f32::NAN,
            t.first().map_or(f32::NAN, |p| p.0),
            t.last().map_or(f32::NAN, |p| p.0),
            vec![t],
        ),
    };
    let per_ray = id == 2;
    let mut h = Vec::with_capacity(super::FIXED_HEADER_BYTES);
    h.extend_from_slice(b"TM25");
    h.extend_from_slice(&2013i32.to_le_bytes());
    h.extend_from_slice(&0i32.to_le_bytes());
    h.extend_from_slice(&header.luminous_flux_lm.to_le_bytes());
    h.extend_from_slice(&header.radiant_flux_w.to_le_bytes());
    h.extend_from_slice(&n_rays.to_le_bytes());
    let mut date = header.date.as_bytes().to_vec();
    date.truncate(28);
    date.resize(28, 0);
    h.extend_from_slice(&date);
    h.extend_from_slice(&0i32.to_le_bytes()); // start position unknown
    h.extend_from_slice(&id.to_le_bytes());
    for v in [lambda, lmin, lmax] {
        h.extend_from_slice(&v.to_le_bytes());
    }
    h.extend_from_slice(&(tables.len() as i32).to_le_bytes());
    h.extend_from_slice(&0i32.to_le_bytes()); // no additional items
    h.extend_from_slice(&0i32.to_le_bytes()); // no additional text
    h.resize(256, 0);
    for f in [1, 1, 1, per_ray as i32, 0, 0, 0, 0] {
        h.extend_from_slice(&f.to_le_bytes());
    }
    for t in &header.texts {
        utf32_block(&mut h, t, 4000)?;
    }
    let start = h.len();
    for t in &tables {
        h.extend_from_slice(&(t.len() as i32).to_le_bytes());
        for &(l, w) in t.iter() {
            h.extend_from_slice(&l.to_le_bytes());
            h.extend_from_slice(&w.to_le_bytes());
        }
    }
    let pad = (h.len() - start) % 32;
    if pad != 0 {
        h.resize(h.len() + 32 - pad, 0);
    }
    out.write_all(&h)?;
    let mut written = 0u64;
    let mut rec = Vec::with_capacity(32);
    for r in rays {
        rec.clear();
        for v in r.position_mm.iter().chain(r.direction.iter()) {
            rec.extend_from_slice(&v.to_le_bytes());
        }
        rec.extend_from_slice(&r.flux_w.to_le_bytes());
        if per_ray {
            rec.extend_from_slice(&r.wavelength_nm.to_le_bytes());
        }
        out.write_all(&rec)?;
        written += 1;
    }
    if written != n_rays {
        return Err(std::io::Error::other(format!(
            "{written} rays written, the header says {n_rays}"
        )));
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::super::reader::{parse_header, SpectralId};
    use super::*;
    use std::path::Path;

    fn header(spectrum: Tm25Spectrum) -> WriteHeader {
        WriteHeader {
            luminous_flux_lm: 10.0,
            radiant_flux_w: 0.5,
            date: "2026-12-06T21:00:00Z".into(),
            texts: std::array::from_fn(|i| format!("text {i}")),
            spectrum,
        }
    }

    fn rays(n: usize) -> Vec<WriteRay> {
        (0..n)
            .map(|i| WriteRay {
                position_mm: [i as f32, 1.0, -2.0],
                direction: [0.0, 0.6, 0.8],
                flux_w: 0.5 / n as f32,
                wavelength_nm: 400.0 + i as f32,
            })
            .collect()
    }

    /// What is written reads back field for field, for each spectrum kind, and the record
    /// size follows the flags (28 bytes, 32 with the wavelength column).
    #[test]
    fn written_files_read_back() {
        for (spectrum, id, cols) in [
            (Tm25Spectrum::None, SpectralId::None, 7),
            (Tm25Spectrum::Single(555.0), SpectralId::Single, 7),
            (Tm25Spectrum::PerRay, SpectralId::PerRay, 8),
            (
                Tm25Spectrum::Table(vec![(400.0, 1.0), (500.0, 2.0), (700.0, 0.5)]),
                SpectralId::Table,
                7,
            ),
        ] {
            let mut out = Vec::new();
            let h = header(spectrum.clone());
            write_tm25(&mut out, &h, 5, rays(5).into_iter()).unwrap();
            let (r, layout) = parse_header(&out, Path::new("t.TM25RAY")).unwrap();
            assert_eq!(r.spectral_id, id);
            assert_eq!(layout.columns, cols);
            assert_eq!(r.n_rays, 5);
            assert_eq!(r.texts[3], "text 3");
            assert_eq!(r.date, "2026-12-06T21:00:00Z");
            assert_eq!(r.radiant_flux_w, 0.5);
            if let Tm25Spectrum::Table(t) = &spectrum {
                assert_eq!(&r.spectra[0], t);
                // 36288 + 4 + 24 = 36316, padded to 36320.
                assert_eq!(layout.offset, 36320);
            }
            let ray = layout.ray(&out, 2);
            assert_eq!(ray.position_mm, [2.0, 1.0, -2.0]);
            assert_eq!(ray.radiant_w, Some(0.1));
            assert_eq!(ray.wavelength_nm, (cols == 8).then_some(402.0));
        }
        let mut out = Vec::new();
        let e = write_tm25(
            &mut out,
            &header(Tm25Spectrum::None),
            6,
            rays(5).into_iter(),
        );
        assert!(e.is_err());
    }
}
