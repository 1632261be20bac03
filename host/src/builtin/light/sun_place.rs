//! Where the sun is, for the `cie_sky` and `sun` lights: either given as angles
//! (`sun_altitude`, `sun_azimuth`) or computed from `latitude`, `longitude`, `date`, `time` and
//! `timezone` ([`crate::light::daylight::solar_position`], the NOAA / Meeus algorithm, about
//! 0.01°); and the sky's orientation in the scene (`up`, `north`; east = north × up).

use crate::builtin::param_err;
use crate::light::daylight::solar_position::{sun_position, LocalTime, SunPosition};
use crate::scene_file::FactoryError;

/// The placement parameters as written (shared by both lights' parameter structs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Placement<'a> {
    /// Sun altitude, degrees.
    pub sun_altitude: Option<f64>,
    /// Sun azimuth from north through east, degrees.
    pub sun_azimuth: Option<f64>,
    /// Latitude, degrees north.
    pub latitude: Option<f64>,
    /// Longitude, degrees east.
    pub longitude: Option<f64>,
    /// `YYYY-MM-DD`.
    pub date: Option<&'a str>,
    /// `HH:MM[:SS]`, standard time of the zone.
    pub time: Option<&'a str>,
    /// Hours east of UTC.
    pub timezone: Option<f64>,
}

impl Placement<'_> {
    /// The sun's true (unrefracted) position. Errors name the parameter: missing or extra
    /// parameters, a latitude outside ±90°, an impossible date or time.
    pub fn resolve(&self) -> Result<SunPosition, FactoryError> {
        let by_angle = self.sun_altitude.is_some() || self.sun_azimuth.is_some();
        let by_place = self.latitude.is_some()
            || self.longitude.is_some()
            || self.date.is_some()
            || self.time.is_some()
            || self.timezone.is_some();
        match (by_angle, by_place) {
            (true, true) => Err(param_err(
                "sun_altitude",
                "give the sun either by `sun_altitude`/`sun_azimuth` or by `latitude`, \
                 `longitude`, `date`, `time`, `timezone`, not both",
            )),
            (false, false) => Err(param_err(
                "sun_altitude",
                "missing: give `sun_altitude` and `sun_azimuth` (degrees), or `latitude`, \
                 `longitude`, `date`, `time` and `timezone`",
            )),
            (true, false) => {
                let alt = self
                    .sun_altitude
                    .ok_or_else(|| param_err("sun_altitude", "missing (with `sun_azimuth`)"))?;
                let az = self
                    .sun_azimuth
                    .ok_or_else(|| param_err("sun_azimuth", "missing (with `sun_altitude`)"))?;
                if !(alt.is_finite() && (-90.0..=90.0).contains(&alt)) {
                    return Err(param_err(
                        "sun_altitude",
                        format!("{alt}° is outside −90°…90°"),
                    ));
                }
                if !az.is_finite() {
                    return Err(param_err("sun_azimuth", format!("{az}° is not finite")));
                }
                Ok(SunPosition {
                    altitude_deg: alt,
                    azimuth_deg: az.rem_euclid(360.0),
                })
            }
            (false, true) => {
                let need = |v: Option<f64>, n: &str| {
                    v.ok_or_else(|| param_err(n, "missing: the sun's position needs `latitude`, `longitude`, `date`, `time` and `timezone`"))
                };
                let lat = need(self.latitude, "latitude")?;
                let lon = need(self.longitude, "longitude")?;
                let tz = need(self.timezone, "timezone")?;
                let date = self.date.ok_or_else(|| param_err("date", "missing"))?;
                let time = self.time.ok_or_else(|| param_err("time", "missing"))?;
                if !(lat.is_finite() && (-90.0..=90.0).contains(&lat)) {
                    return Err(param_err("latitude", format!("{lat}° is outside −90°…90°")));
                }
                if !(lon.is_finite() && (-180.0..=180.0).contains(&lon)) {
                    return Err(param_err(
                        "longitude",
                        format!("{lon}° is outside −180°…180°"),
                    ));
                }
                let t = LocalTime::parse(date, time, tz).map_err(|e| param_err("date", e))?;
                sun_position(lat, lon, &t, false).map_err(|e| param_err("date", e))
            }
        }
    }
}

/// The sky frame from the `up` and `north` parameters (defaults +y and −z).
pub fn frame(
    up: Option<[f64; 3]>,
    north: Option<[f64; 3]>,
) -> Result<[glam::DVec3; 3], FactoryError> {
    crate::light::daylight::sky_frame(
        up.unwrap_or([0.0, 1.0, 0.0]),
        north.unwrap_or([0.0, 0.0, -1.0]),
    )
    .map_err(|e| param_err("north", e))
}
