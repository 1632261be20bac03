//! The sun's position in the sky from a place, a date and a clock time.
//!
//! Algorithm: the NOAA solar calculator's equations (NOAA Global Monitoring Laboratory, "Solar
//! Calculation Details"), which are the lower-accuracy solar coordinates of J. Meeus,
//! *Astronomical Algorithms*, 2nd ed. (1998), chapters 25 (the sun's apparent longitude and
//! declination, the obliquity of the ecliptic with the nutation term in Ω) and 28 (the equation of
//! time), and the hour angle at the place. Meeus states 0.01° for the sun's coordinates with these
//! series; NOAA quotes its calculator as accurate to about a minute of time (≈ 0.25°… of
//! azimuth near sunrise) between ±72° latitude for the years 1800–2100, the range we accept
//! without warning. Universal time is used as dynamical time (ΔT ≈ 70 s moves the sun by
//! 0.0008°, far below the stated accuracy). Atmospheric refraction (optional) is NOAA's
//! piecewise fit for a standard atmosphere.
//!
//! Angles in degrees. Latitude north positive, longitude east positive, the time zone in hours
//! east of Greenwich (UTC+1 → `1.0`); the clock time is that zone's standard time (add no
//! daylight saving hour). Azimuth is measured from north through east (clockwise seen from
//! above), altitude above the horizon.

/// A civil date and clock time in a time zone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalTime {
    /// Year (Gregorian calendar).
    pub year: i32,
    /// Month, 1–12.
    pub month: u32,
    /// Day of the month, 1–28/29/30/31.
    pub day: u32,
    /// Hours since local midnight, 0 ≤ h ≤ 24 (fractional: minutes and seconds included).
    pub hours: f64,
    /// Time zone, hours east of UTC (−12 … +14).
    pub timezone_h: f64,
}

/// Where the sun is: angles in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunPosition {
    /// Altitude above the horizon (90° − zenith angle), degrees.
    pub altitude_deg: f64,
    /// Azimuth from north through east, [0, 360) degrees.
    pub azimuth_deg: f64,
}

impl SunPosition {
    /// Zenith angle, degrees.
    pub fn zenith_deg(&self) -> f64 {
        90.0 - self.altitude_deg
    }
}

fn is_leap(y: i32) -> bool {
    (y % 4 == 0 && y % 100 != 0) || y % 400 == 0
}

/// Days in `month` of `year`.
pub fn days_in_month(year: i32, month: u32) -> u32 {
    match month {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 if is_leap(year) => 29,
        2 => 28,
        _ => 0,
    }
}

impl LocalTime {
    /// Parse `date` (`YYYY-MM-DD`) and `time` (`HH:MM` or `HH:MM:SS`, 24 h clock, `24:00` allowed)
    /// in time zone `timezone_h` (hours east of UTC). Errors say what is impossible.
    pub fn parse(date: &str, time: &str, timezone_h: f64) -> Result<Self, String> {
        let d: Vec<&str> = date.trim().split('-').collect();
        let bad_date = || format!("date {date:?} is not YYYY-MM-DD");
        if d.len() != 3 {
            return Err(bad_date());
        }
        let year: i32 = d[0].parse().map_err(|_| bad_date())?;
        let month: u32 = d[1].parse().map_err(|_| bad_date())?;
        let day: u32 = d[2].parse().map_err(|_| bad_date())?;
        let t: Vec<&str> = time.trim().split(':').collect();
        let bad_time = || format!("time {time:?} is not HH:MM or HH:MM:SS");
        if !(2..=3).contains(&t.len()) {
            return Err(bad_time());
        }
        let h: u32 = t[0].parse().map_err(|_| bad_time())?;
        let m: u32 = t[1].parse().map_err(|_| bad_time())?;
        let s: f64 = match t.get(2) {
            Some(x) => x.parse().map_err(|_| bad_time())?,
            None => 0.0,
        };
        let lt = Self {
            year,
            month,
            day,
            hours: 0.0,
            timezone_h,
        };
        if !(m < 60 && s.is_finite() && (0.0..60.0).contains(&s)) || h > 24 {
            return Err(format!(
                "time {time:?} is impossible: hours 0–24, minutes 0–59, seconds 0–59.999"
            ));
        }
        if h == 24 && (m > 0 || s > 0.0) {
            return Err(format!("time {time:?} is after 24:00"));
        }
        let lt = Self {
            hours: h as f64 + m as f64 / 60.0 + s / 3600.0,
            ..lt
        };
        lt.check()?;
        Ok(lt)
    }

    /// Check the fields: a real calendar date, 0 ≤ hours ≤ 24, a time zone in −12…+14 h.
    pub fn check(&self) -> Result<(), String> {
        if !(1..=12).contains(&self.month) {
            return Err(format!("month {} is impossible (1–12)", self.month));
        }
        let dim = days_in_month(self.year, self.month);
        if !(1..=dim).contains(&self.day) {
            return Err(format!(
                "{:04}-{:02}-{:02} is impossible: month {} of {} has {dim} days",
                self.year, self.month, self.day, self.month, self.year
            ));
        }
        if !(self.year >= -4712 && self.year <= 9999) {
            return Err(format!("year {} is outside −4712…9999", self.year));
        }
        if !(self.hours.is_finite() && (0.0..=24.0).contains(&self.hours)) {
            return Err(format!("time {} h is outside 0–24 h", self.hours));
        }
        if !(self.timezone_h.is_finite() && (-12.0..=14.0).contains(&self.timezone_h)) {
            return Err(format!(
                "time zone {} h is outside UTC−12…UTC+14",
                self.timezone_h
            ));
        }
        Ok(())
    }

    /// Julian day (UT) of this instant (Meeus ch. 7, Gregorian calendar).
    pub fn julian_day(&self) -> f64 {
        let (mut y, mut m) = (self.year as f64, self.month as f64);
        if m <= 2.0 {
            y -= 1.0;
            m += 12.0;
        }
        let a = (y / 100.0).floor();
        let b = 2.0 - a + (a / 4.0).floor();
        let jd0 =
            (365.25 * (y + 4716.0)).floor() + (30.6001 * (m + 1.0)).floor() + self.day as f64 + b
                - 1524.5;
        jd0 + (self.hours - self.timezone_h) / 24.0
    }
}

/// The sun's apparent declination (degrees) and the equation of time (minutes: apparent minus
/// mean solar time) at Julian day `jd` (Meeus ch. 25 and 28, lower accuracy, as NOAA).
pub fn declination_and_equation_of_time(jd: f64) -> (f64, f64) {
    let t = (jd - 2_451_545.0) / 36_525.0;
    let l0 = (280.46646 + t * (36_000.769_83 + t * 0.0003032)).rem_euclid(360.0);
    let m = 357.52911 + t * (35_999.050_29 - 0.0001537 * t);
    let e = 0.016708634 - t * (0.000042037 + 0.0000001267 * t);
    let mr = m.to_radians();
    let c = mr.sin() * (1.914602 - t * (0.004817 + 0.000014 * t))
        + (2.0 * mr).sin() * (0.019993 - 0.000101 * t)
        + (3.0 * mr).sin() * 0.000289;
    let true_long = l0 + c;
    let omega = (125.04 - 1934.136 * t).to_radians();
    let lambda = (true_long - 0.00569 - 0.00478 * omega.sin()).to_radians();
    let eps0 = 23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60.0) / 60.0;
    let eps = (eps0 + 0.00256 * omega.cos()).to_radians();
    let decl = (eps.sin() * lambda.sin()).asin().to_degrees();
    let y = (eps / 2.0).tan().powi(2);
    let l0r = l0.to_radians();
    let eot = y * (2.0 * l0r).sin() - 2.0 * e * mr.sin()
        + 4.0 * e * y * mr.sin() * (2.0 * l0r).cos()
        - 0.5 * y * y * (4.0 * l0r).sin()
        - 1.25 * e * e * (2.0 * mr).sin();
    (decl, 4.0 * eot.to_degrees())
}

/// NOAA's atmospheric refraction (degrees) at true altitude `alt` (degrees), standard atmosphere.
pub fn refraction_deg(alt: f64) -> f64 {
    let tan = alt.to_radians().tan();
    let arcsec = if alt > 85.0 {
        0.0
    } else if alt > 5.0 {
        58.1 / tan - 0.07 / tan.powi(3) + 0.000086 / tan.powi(5)
    } else if alt > -0.575 {
        1735.0 + alt * (-518.2 + alt * (103.4 + alt * (-12.79 + alt * 0.711)))
    } else {
        -20.774 / tan
    };
    arcsec / 3600.0
}

/// The sun seen from latitude `lat` and longitude `lon` (degrees; north and east positive) at
/// `time`; `refraction` adds the standard atmosphere's refraction to the altitude (what an
/// observer sees; the sky models of CIE S 011 use the true position, so the lights do not).
/// An error for a latitude outside ±90°, a longitude outside ±180° or an impossible time.
pub fn sun_position(
    lat: f64,
    lon: f64,
    time: &LocalTime,
    refraction: bool,
) -> Result<SunPosition, String> {
    if !(lat.is_finite() && (-90.0..=90.0).contains(&lat)) {
        return Err(format!("latitude {lat}° is outside −90°…90°"));
    }
    if !(lon.is_finite() && (-180.0..=180.0).contains(&lon)) {
        return Err(format!("longitude {lon}° is outside −180°…180°"));
    }
    time.check()?;
    let jd = time.julian_day();
    let (decl, eot) = declination_and_equation_of_time(jd);
    // True solar time, minutes, from the local clock time.
    let tst = (time.hours * 60.0 + eot + 4.0 * lon - 60.0 * time.timezone_h).rem_euclid(1440.0);
    let h = (tst / 4.0 - 180.0).to_radians();
    let (phi, d) = (lat.to_radians(), decl.to_radians());
    let cos_z = (phi.sin() * d.sin() + phi.cos() * d.cos() * h.cos()).clamp(-1.0, 1.0);
    let alt = 90.0 - cos_z.acos().to_degrees();
    // Azimuth from south towards west (Meeus 13.5), turned to from north through east.
    let az_south = h.sin().atan2(h.cos() * phi.sin() - d.tan() * phi.cos());
    let azimuth_deg = (az_south.to_degrees() + 180.0).rem_euclid(360.0);
    let altitude_deg = if refraction {
        alt + refraction_deg(alt)
    } else {
        alt
    };
    Ok(SunPosition {
        altitude_deg,
        azimuth_deg,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Meeus, Astronomical Algorithms, example 25.a (1992 October 13.0 TD, JD 2448908.5): the
    /// lower-accuracy method gives the apparent declination −7.78507°; example 28.b's equation
    /// of time by the same series (Smart's formula) is 13.71 min (13 m 42.7 s). Tolerances: the
    /// example's printed digits (1e-4°) and 0.02 min (the rounding of the example's value).
    #[test]
    fn meeus_examples() {
        let (decl, eot) = declination_and_equation_of_time(2_448_908.5);
        println!("declination {decl:.5}°, equation of time {eot:.4} min");
        assert!((decl - (-7.78507)).abs() < 2e-4, "{decl}");
        assert!((eot - 13.711).abs() < 0.02, "{eot}");
    }

    /// Julian days of Meeus example 7.a (1957 October 4.81 → 2436116.31) and of J2000.0.
    #[test]
    fn julian_days() {
        let t = LocalTime {
            year: 1957,
            month: 10,
            day: 4,
            hours: 0.81 * 24.0,
            timezone_h: 0.0,
        };
        assert!((t.julian_day() - 2_436_116.31).abs() < 1e-6);
        let t = LocalTime {
            year: 2000,
            month: 1,
            day: 1,
            hours: 12.0,
            timezone_h: 0.0,
        };
        assert_eq!(t.julian_day(), 2_451_545.0);
    }

    /// Impossible dates, times and latitudes are refused with what is wrong.
    #[test]
    fn impossible_inputs() {
        let e = LocalTime::parse("2023-02-29", "12:00", 0.0).unwrap_err();
        assert!(e.contains("28 days"), "{e}");
        assert!(LocalTime::parse("2024-02-29", "12:00", 0.0).is_ok());
        assert!(LocalTime::parse("2024-13-01", "12:00", 0.0)
            .unwrap_err()
            .contains("month"));
        assert!(LocalTime::parse("2024-04-31", "12:00", 0.0)
            .unwrap_err()
            .contains("30 days"));
        assert!(LocalTime::parse("2024-04-30", "25:00", 0.0)
            .unwrap_err()
            .contains("impossible"));
        assert!(LocalTime::parse("2024-04-30", "12:60", 0.0)
            .unwrap_err()
            .contains("minutes"));
        assert!(LocalTime::parse("2024-04-30", "24:01", 0.0).is_err());
        assert!(LocalTime::parse("2024-04-30", "12:00", 15.0)
            .unwrap_err()
            .contains("zone"));
        assert!(LocalTime::parse("30/04/2024", "12:00", 0.0)
            .unwrap_err()
            .contains("YYYY"));
        let t = LocalTime::parse("2024-04-30", "12:00", 0.0).unwrap();
        assert!(sun_position(91.0, 0.0, &t, false)
            .unwrap_err()
            .contains("latitude"));
        assert!(sun_position(45.0, 181.0, &t, false)
            .unwrap_err()
            .contains("longitude"));
    }
}
