//! `cie_sky`: the CIE standard general sky (ISO 15469:2004 / CIE S 011/E:2003), one of its 15
//! relative luminance distributions, as the scene's environment light (a scene has at most
//! one). Luminance above the horizon only; below it the sky is black (model the ground). The
//! spectrum is CIE daylight (D-series) of a CCT, or any SPD. See `docs/daylight.md`.
//!
//! | parameter                  | unit  | default         | meaning                                                  |
//! |----------------------------|-------|-----------------|----------------------------------------------------------|
//! | `sky_type`                 | —     | —               | 1–15 (1: CIE overcast, 12: CIE clear, 5: uniform)        |
//! | `sun_altitude`, `sun_azimuth` | °  | —               | the sun's position (azimuth from north through east) …   |
//! | `latitude`, `longitude`, `date`, `time`, `timezone` | °, °, —, —, h | — | … or the place and local standard time |
//! | `zenith_luminance`         | cd/m² | —               | exactly one of these two sets the brightness             |
//! | `horizontal_illuminance_lx`| lx    | —               | illuminance of the unobstructed sky on the horizontal    |
//! | `cct`                      | K     | by sky type     | D-series CCT, 4000–25000 (6500 / 8000 / 10000 K for types 1–5 / 6–10 / 11–15) |
//! | `spd`                      | —     | —               | or: any normalised spectrum instead of the D-series      |
//! | `up`                       | —     | (0, 1, 0)       | the zenith direction in the scene                        |
//! | `north`                    | —     | (0, 0, −1)      | north in the scene (east = north × up)                   |

use super::sun_place::{frame, Placement};
use crate::builtin::spectral::Spectrum;
use crate::builtin::{from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::daylight::cie_sky::SkyBrightness;
use crate::light::daylight::{cie_sky_model, daylight_spd, default_sky_cct, CieSky};
use crate::light::{EnvironmentLight, Light};
use crate::scene_file::type_doc::Param;
use crate::scene_file::{FactoryContext, FactoryError};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "cie_sky",
    aliases: &[],
    version: 1,
    description: "CIE standard general sky (ISO 15469 / CIE S 011), types 1–15, as the environment",
    params: &[
        Param::required(
            "sky_type",
            "",
            "1–15 (1: CIE standard overcast, 12: CIE standard clear, 5: uniform)",
        ),
        Param::optional(
            "sun_altitude",
            "°",
            "—",
            "sun altitude; with `sun_azimuth`, instead of place and time",
        ),
        Param::optional(
            "sun_azimuth",
            "°",
            "—",
            "sun azimuth from north through east",
        ),
        Param::optional("latitude", "°", "—", "or: latitude, −90…90, north positive"),
        Param::optional("longitude", "°", "—", "longitude, −180…180, east positive"),
        Param::optional("date", "", "—", "\"YYYY-MM-DD\""),
        Param::optional(
            "time",
            "",
            "—",
            "\"HH:MM[:SS]\", standard time of `timezone`",
        ),
        Param::optional("timezone", "h", "—", "hours east of UTC"),
        Param::optional(
            "zenith_luminance",
            "cd/m²",
            "—",
            "zenith luminance; exactly one of this and `horizontal_illuminance_lx`",
        ),
        Param::optional(
            "horizontal_illuminance_lx",
            "lx",
            "—",
            "or: illuminance of the unobstructed sky on a horizontal plane",
        ),
        Param::optional(
            "cct",
            "K",
            "by type",
            "CIE daylight CCT 4000–25000; 6500 / 8000 / 10000 K for types 1–5 / 6–10 / 11–15",
        ),
        Param::optional("spd", "", "—", "or: any spectrum instead of the D-series"),
        Param::optional("up", "", "(0, 1, 0)", "zenith direction in the scene"),
        Param::optional(
            "north",
            "",
            "(0, 0, -1)",
            "north in the scene; east = north × up",
        ),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<CieSkyParams>()),
};

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CieSkyParams {
    /// 1–15.
    pub sky_type: i64,
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
    /// cd/m².
    #[serde(default)]
    pub zenith_luminance: Option<f64>,
    /// lx.
    #[serde(default)]
    pub horizontal_illuminance_lx: Option<f64>,
    /// K.
    #[serde(default)]
    pub cct: Option<f64>,
    /// Spectrum.
    #[serde(default)]
    pub spd: Option<Spectrum>,
    /// Zenith direction.
    #[serde(default)]
    pub up: Option<[f64; 3]>,
    /// North direction.
    #[serde(default)]
    pub north: Option<[f64; 3]>,
}

impl Embed for CieSkyParams {
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.spd.embed(ctx)
    }
}

/// Build the light.
pub fn build(p: &CieSkyParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    Ok(Arc::new(EnvironmentLight::new(Arc::new(source(p, ctx)?))))
}

/// The sky's radiance source.
pub fn source(p: &CieSkyParams, ctx: &FactoryContext) -> Result<CieSky, FactoryError> {
    let ty = cie_sky_model::sky_type(p.sky_type).map_err(|e| param_err("sky_type", e))?;
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
    let spd = match (&p.spd, p.cct) {
        (Some(_), Some(_)) => return Err(param_err("cct", "give `cct` or `spd`, not both")),
        (Some(_), None) => super::light_spd(&p.spd, ctx)?,
        (None, cct) => daylight_spd(cct.unwrap_or(default_sky_cct(ty.number)))
            .map_err(|e| param_err("cct", e))?,
    };
    let brightness = match super::exactly_one(&[
        ("zenith_luminance", p.zenith_luminance),
        ("horizontal_illuminance_lx", p.horizontal_illuminance_lx),
    ])? {
        (0, l) => SkyBrightness::ZenithLuminance(non_negative("zenith_luminance", l)?),
        (_, e) => {
            SkyBrightness::HorizontalIlluminance(non_negative("horizontal_illuminance_lx", e)?)
        }
    };
    let k = crate::light::luminous::luminous_efficacy_lm_per_w(spd.as_ref());
    if !(k > 0.0) {
        return Err(param_err(
            "spd",
            "the spectrum has no visible part (0 lm/W)",
        ));
    }
    // The standard's sky models the sun at or above the horizon; below it the formula still
    // gives a distribution, which is kept (twilight skies are not in the standard).
    let zs = (90.0 - pos.altitude_deg).to_radians();
    CieSky::new(ty, zs, pos.azimuth_deg.to_radians(), fr, brightness, spd, k)
        .map_err(|e| param_err("sky_type", e))
}

fn non_negative(name: &str, v: f64) -> Result<f64, FactoryError> {
    if (0.0..1e12).contains(&v) {
        Ok(v)
    } else {
        Err(param_err(
            name,
            format!("{v} must be finite, ≥ 0 and < 1e12"),
        ))
    }
}
