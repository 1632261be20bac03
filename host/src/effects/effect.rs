//! [`Effect`]: one optical effect a scene may call for, with how the renderer handles it
//! today (the text `spectrace explain` prints).

/// An optical effect found in a scene (see [`super::analyze`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Effect {
    /// Wavelength-dependent refraction (a dispersive IOR).
    Dispersion,
    /// Re-emission at other wavelengths.
    Fluorescence,
    /// Thin-film interference.
    ThinFilm,
    /// A continuous emission spectrum narrower than
    /// [`NARROWBAND_WIDTH_NM`](crate::spectrum::bandwidth::NARROWBAND_WIDTH_NM).
    NarrowbandEmission,
    /// Emission in delta spectral lines (lasers, `line:NM`).
    LineEmission,
    /// Point-like or directional lights: camera paths can never hit them.
    DeltaLights,
    /// Mirror-like or smooth glass surfaces: sampled, never evaluated.
    DeltaBsdfs,
    /// Light reflected or refracted by a delta BSDF onto a surface (caustics: only some
    /// strategies find them).
    SpecularChains,
    /// Lights that only hand out beams: light tracing alone renders them.
    BeamOnlyLights,
    /// Every light and material is spectrally flat over 380–780 nm.
    SpectrallyFlat,
    /// Some light or material varies with wavelength.
    SpectrallyVarying,
}

impl Effect {
    /// All effects, in report order.
    pub const ALL: [Self; 11] = [
        Self::Dispersion,
        Self::Fluorescence,
        Self::ThinFilm,
        Self::NarrowbandEmission,
        Self::LineEmission,
        Self::DeltaLights,
        Self::DeltaBsdfs,
        Self::SpecularChains,
        Self::BeamOnlyLights,
        Self::SpectrallyFlat,
        Self::SpectrallyVarying,
    ];

    /// Short name (command line and summaries).
    pub fn name(self) -> &'static str {
        match self {
            Self::Dispersion => "dispersion",
            Self::Fluorescence => "fluorescence",
            Self::ThinFilm => "thin-film",
            Self::NarrowbandEmission => "narrowband-emission",
            Self::LineEmission => "line-emission",
            Self::DeltaLights => "delta-lights",
            Self::DeltaBsdfs => "delta-bsdfs",
            Self::SpecularChains => "specular-chains",
            Self::BeamOnlyLights => "beam-only-lights",
            Self::SpectrallyFlat => "spectrally-flat",
            Self::SpectrallyVarying => "spectrally-varying",
        }
    }

    /// What the renderer does for this effect.
    pub fn handling(self) -> &'static str {
        match self {
            Self::Dispersion => {
                "a dispersive event keeps only the hero wavelength (the other lanes are \
                 terminated), in pt, bdpt and lt"
            }
            Self::Fluorescence => {
                "the wavelength shifts at fluorescent surfaces, per lane (pt, lt, and both bdpt \
                 subpaths: shifted paths by s = 0, s = 1 and t = 1); --effect fluorescence=off \
                 renders the reflectance only"
            }
            Self::ThinFilm => {
                "every wavelength lane is weighted by its own Airy reflectance/transmittance \
                 (no lane is dropped: the direction does not depend on wavelength)"
            }
            Self::NarrowbandEmission => {
                "bdpt and lt draw wavelengths half from the lights' spectra, half from the \
                 observer's sensitivity; pt does the same when a light is narrowband"
            }
            Self::LineEmission => {
                "a lane drawn on a line carries the line's discrete probability (pt, bdpt, lt)"
            }
            Self::DeltaLights => {
                "pt: next-event estimation; bdpt: strategies with s ≥ 1; lt: light paths"
            }
            Self::DeltaBsdfs => "sampled only (never evaluated or connected through)",
            Self::SpecularChains => {
                "bdpt and lt render them through light paths; pt only where BSDF sampling hits \
                 an area light"
            }
            Self::BeamOnlyLights => "light tracing of their beams (bdpt's t = 1, lt)",
            Self::SpectrallyFlat => {
                "bdpt and lt give every path the exact colour of its emitter (flat-path-colour); \
                 pt: the usual hero-wavelength sampling"
            }
            Self::SpectrallyVarying => {
                "hero wavelength plus rotated lanes, 4 wavelengths per path (pt: \
                 --wavelengths-per-path up to 16)"
            }
        }
    }

    /// What the renderer skips or gets wrong for this effect today; `None` when nothing.
    pub fn skipped(self) -> Option<&'static str> {
        match self {
            Self::DeltaLights => Some("camera paths never hit them (no s = 0 strategy)"),
            Self::DeltaBsdfs => Some(
                "lt cannot show them where the camera sees them directly (t = 1 needs an \
                 evaluable BSDF)",
            ),
            Self::SpecularChains => Some(
                "pt cannot render light from point-like or directional lights via delta BSDFs, \
                 and is noisy for small area lights (use bdpt or lt)",
            ),
            Self::BeamOnlyLights => Some("pt does not render them"),
            _ => None,
        }
    }

    /// True when what is skipped is probably not what the user wants (printed as a warning).
    /// (None does today: fluorescence, the last one, is rendered now.)
    pub fn is_warning(self) -> bool {
        false
    }
}
