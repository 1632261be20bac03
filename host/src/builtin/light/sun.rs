//! `sun`: the sun as a distant disc of 0.533° angular diameter, placed by altitude and
//! azimuth or by place, date and time (NOAA / Meeus solar position, about 0.01°), with a CIE
//! daylight spectrum. A sun below the horizon gives no direct light (a warning says so). See
//! `docs/daylight.md`.
//!
//! | parameter                    | unit  | default      | meaning                                               |
//! |------------------------------|-------|--------------|-------------------------------------------------------|
//! | `sun_altitude`, `sun_azimuth`| °     | —            | position (azimuth from north through east) …          |
//! | `latitude`, `longitude`, `date`, `time`, `timezone` | °, °, —, —, h | — | … or place and local standard time |
//! | `normal_illuminance_lx`      | lx    | —            | exactly one of: illuminance on a plane facing the sun |
//! | `horizontal_illuminance_lx`  | lx    | —            | illuminance on the horizontal (E⊥ = E_h / sin altitude)|
//! | `luminance`                  | cd/m² | —            | the disc's luminance (E⊥ = L·Ω, Ω = 6.797e-5 sr)       |
//! | `irradiance`                 | W/m²  | —            | irradiance on a plane facing the sun                  |
//! | `cct`                        | K     | by altitude  | D-series CCT 4000–25000; 5500 K above 30°, down to 4000 K at the horizon |
//! | `spd`                        | —     | —            | or: any spectrum                                      |
//! | `angular_diameter`           | °     | 0.533        | disc diameter                                         |
//! | `up`, `north`                | —     | (0,1,0), (0,0,−1) | orientation of the sky in the scene              |

use super::sun_place::{frame, Placement};
use crate::builtin::spectral::Spectrum;
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::daylight::sun::{disc_solid_angle, SUN_DIAMETER_DEG};
use crate::light::daylight::{daylight_spd, default_sun_cct, direction, SunLight};
use crate::light::Light;
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use glam::Vec3A;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "sun",
    aliases: &[],
    version: 1,
    description: "the sun: a 0.533° disc placed by angles or by place, date and time",
    params: &[
        Param::optional("sun_altitude", "°", "—", "sun altitude; with `sun_azimuth`, instead of place and time"),
        Param::optional("sun_azimuth", "°", "—", "sun azimuth from north through east"),
        Param::optional("latitude", "°", "—", "or: latitude, −90…90, north positive"),
        Param::optional("longitude", "°", "—", "longitude, −180…180, east positive"),
        Param::optional("date", "", "—", "\"YYYY-MM-DD\""),
        Param::optional("time", "", "—", "\"HH:MM[:SS]\", standard time of `timezone`"),
        Param::optional("timezone", "h", "—", "hours east of UTC"),
        Param::optional("normal_illuminance_lx", "lx", "—", "exactly one of the four: illuminance on a plane facing the sun"),
        Param::optional("horizontal_illuminance_lx", "lx", "—", "or: direct illuminance on the horizontal"),
        Param::optional("luminance", "cd/m²", "—", "or: luminance of the disc"),
        Param::optional("irradiance", "W/m²", "—", "or: irradiance on a plane facing the sun"),
        Param::optional("cct", "K", "by altitude", "CIE daylight CCT 4000–25000; default 5500 K above 30° altitude, down to 4000 K at the horizon"),
        Param::optional("spd", "", "—", "or: any spectrum"),
        Param::optional("angular_diameter", "°", "0.533", "disc diameter"),
        Param::optional("up", "", "(0, 1, 0)", "zenith direction in the scene"),
        Param::optional("north", "", "(0, 0, -1)", "north in the scene; east = north × up"),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<SunParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SunParams {
    /// Degrees.
    #[serde(default)]
    pub sun_altitude: Option<f64>,
    /// Degrees.
    #[serde(default)]
    pub sun_azimuth: Option<f64>,
    /// Degrees.
    #[serde(default)]
    pub latitude: Option<f64>,
    /// Degrees.
    #[serde(default)]
    pub longitude: Option<f64>,
    /// YYYY-MM-DD.
    #[serde(default)]
    pub date: Option<String>,
    /// HH:MM[:SS].
    #[serde(default)]
    pub time: Option<String>,
    /// Hours east of UTC.
    #[serde(default)]
    pub timezone: Option<f64>,
    /// lx.
    #[serde(default)]
    pub normal_illuminance_lx: Option<f64>,
    /// lx.
    #[serde(default)]
    pub horizontal_illuminance_lx: Option<f64>,
    /// cd/m².
    #[serde(default)]
    pub luminance: Option<f64>,
    /// W/m².
    #[serde(default)]
    pub irradiance: Option<f64>,
    /// K.
    #[serde(default)]
    pub cct: Option<f64>,
    /// Spectrum.
    #[serde(default)]
    pub spd: Option<Spectrum>,
    /// Degrees.
    #[serde(default)]
    pub angular_diameter: Option<f64>,
    /// Zenith direction.
    #[serde(default)]
    pub up: Option<[f64; 3]>,
    /// North direction.
    #[serde(default)]
    pub north: Option<[f64; 3]>,
}

impl Embed for SunParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.spd.embed(ctx)
    }
}

/// Build the light.
pub fn build(p: &SunParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    Ok(Arc::new(build_concrete(p, ctx)?))
}

/// [`build`] as the concrete type.
pub fn build_concrete(p: &SunParams, ctx: &FactoryContext) -> Result<SunLight, FactoryError> {
    let pos = Placement {
        sun_altitude: p.sun_altitude,
        sun_azimuth: p.sun_azimuth,
        latitude: p.latitude,
        longitude: p.longitude,
        date: p.date.as_deref(),
        time: p.time.as_deref(),
        timezone: p.timezone,
    }
    .resolve()?;
    let fr = frame(p.up, p.north)?;
    let diameter = p.angular_diameter.unwrap_or(SUN_DIAMETER_DEG);
    if !(diameter.is_finite() && diameter > 0.0 && diameter < 90.0) {
        return Err(param_err(
            "angular_diameter",
            format!("{diameter}° must be in (0°, 90°)"),
        ));
    }
    let spd = match (&p.spd, p.cct) {
        (Some(_), Some(_)) => return Err(param_err("cct", "give `cct` or `spd`, not both")),
        (Some(_), None) => super::light_spd(&p.spd, ctx)?,
        (None, cct) => daylight_spd(cct.unwrap_or(default_sun_cct(pos.altitude_deg)))
            .map_err(|e| param_err("cct", e))?,
    };
    let sin_alt = pos.altitude_deg.to_radians().sin();
    let (which, value) = super::exactly_one(&[
        ("normal_illuminance_lx", p.normal_illuminance_lx),
        ("horizontal_illuminance_lx", p.horizontal_illuminance_lx),
        ("luminance", p.luminance),
        ("irradiance", p.irradiance),
    ])?;
    let below = pos.altitude_deg <= 0.0;
    let irradiance = match which {
        0 => super::from_photometric("normal_illuminance_lx", value, spd.as_ref())?,
        1 => {
            if below {
                0.0
            } else {
                // Finite for any altitude > 0; a very low sun needs a huge normal value.
                super::from_photometric("horizontal_illuminance_lx", value, spd.as_ref())? / sin_alt
            }
        }
        2 => {
            super::from_photometric("luminance", value, spd.as_ref())? * disc_solid_angle(diameter)
        }
        _ => value,
    };
    let name = [
        "normal_illuminance_lx",
        "horizontal_illuminance_lx",
        "luminance",
        "irradiance",
    ][which];
    let irradiance = super::non_negative(name, irradiance, "W/m²")?;
    let note = below.then(|| {
        format!(
            "the sun is {:.2}° below the horizon (azimuth {:.1}°): no direct sunlight",
            -pos.altitude_deg, pos.azimuth_deg
        )
    });
    let irradiance = if below { 0.0 } else { irradiance };
    let d = direction(
        &fr,
        (90.0 - pos.altitude_deg).to_radians(),
        pos.azimuth_deg.to_radians(),
    );
    SunLight::new(
        Vec3A::new(d.x as f32, d.y as f32, d.z as f32),
        diameter,
        spd,
        irradiance,
        note,
    )
    .map_err(|e| param_err("sun_altitude", e))
}
