//! Beam-representation adapters (the seed's design): a plugin light whose beams are written in
//! another representation (declared by its type, see `spectrace_plugin_api::representation`;
//! native beams pass through the same converter unchanged) is wrapped once, and each beam is converted once, in `next_beam`, by a spatial adapter
//! (units, handedness, angles → unit vector) and a colour adapter (RGB → wavelength and power,
//! flux preserved). The integrators only ever see native beams.

pub mod colour;
pub mod spatial;

use colour::ColourCache;
use spatial::SpatialAdapter;
use spectrace_plugin_api::RandomSample;
use spectrace_plugin_api::{Beam, BeamRepresentation, ColourEncoding, RepresentedBeam};

/// Which of the host's random numbers picks an RGB beam's wavelength: plugins read `u[0..5]`
/// at most (see `LightSource::next_beam`), the rest are the host's.
pub const WAVELENGTH_U: usize = 5;

/// Converts beams of one declared representation into native [`Beam`]s.
#[derive(Debug)]
pub struct BeamConverter {
    representation: BeamRepresentation,
    spatial: SpatialAdapter,
    colours: Option<ColourCache>,
}

impl BeamConverter {
    /// The converter for `representation`; an error says what in the declaration is unusable.
    pub fn new(representation: BeamRepresentation) -> Result<Self, String> {
        Ok(Self {
            representation,
            spatial: SpatialAdapter::new(&representation)?,
            colours: (representation.colour == ColourEncoding::LinearSrgb)
                .then(ColourCache::default),
        })
    }

    /// The declared representation.
    pub fn representation(&self) -> &BeamRepresentation {
        &self.representation
    }

    /// `beam` as a native beam, drawing an RGB beam's wavelength with `sample.u[WAVELENGTH_U]`.
    /// An error names what made the beam unusable (it is then dropped and counted).
    pub fn convert(
        &self,
        beam: &RepresentedBeam,
        sample: &RandomSample,
    ) -> Result<Beam, &'static str> {
        let origin = self.spatial.origin(beam.origin);
        let direction = self.spatial.direction(beam.direction);
        let (wavelength_nm, power_w) = match &self.colours {
            None => (beam.colour[0], beam.power_w),
            Some(cache) => {
                let spectrum = cache
                    .get(beam.colour)
                    .ok_or("RGB colour not finite, negative or black")?;
                let (nm, weight) = spectrum.sample(sample.u[WAVELENGTH_U]);
                (nm, beam.power_w * weight)
            }
        };
        Ok(Beam {
            origin,
            direction,
            wavelength_nm,
            power_w,
            source_id: 0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spectrace_plugin_api::{DirectionEncoding, Handedness, Vec3};

    // The whole chain on one beam of the third-party example's kind: 2500 mm up and 1000 mm
    // "into" a left-handed screen is (0, 2.5, -1) m; θ = π (straight down) is -y; a grey colour
    // keeps its power exactly (weight 1, flat spectrum: 1e-9) and lands inside 360–830 nm.
    #[test]
    fn a_millimetre_left_handed_rgb_beam_converts() {
        let c = BeamConverter::new(BeamRepresentation {
            metres_per_unit: 0.001,
            handedness: Handedness::Left,
            direction: DirectionEncoding::Angles,
            colour: ColourEncoding::LinearSrgb,
        })
        .unwrap();
        let mut sample = RandomSample::default();
        sample.u[WAVELENGTH_U] = 0.37;
        let b = c
            .convert(
                &RepresentedBeam {
                    origin: Vec3::new(0.0, 2500.0, 1000.0),
                    direction: [std::f64::consts::PI, 0.0, 0.0],
                    colour: [0.5, 0.5, 0.5],
                    power_w: 7.0,
                },
                &sample,
            )
            .unwrap();
        assert!((b.origin - Vec3::new(0.0, 2.5, -1.0)).length() < 1e-12);
        assert!((b.direction - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-12);
        assert!((b.power_w - 7.0).abs() < 1e-9 * 7.0, "{}", b.power_w);
        assert!((360.0..830.0).contains(&b.wavelength_nm));
        let black = RepresentedBeam {
            colour: [0.0; 3],
            ..RepresentedBeam::default()
        };
        assert!(c.convert(&black, &sample).is_err());
    }
}
