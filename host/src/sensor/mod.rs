//! Sensor measurements: after the image, a render measures the illuminance in lux at the
//! scene's sensor grids, with its standard error, as a lighting designer's calculation grid,
//! and the glare and daylight factor seen by its observers. The sensor items themselves
//! (`illuminance_grid`, `glare_observer` and their parameter tables) are built-in types, a floor
//! below the scene ([`crate::builtin::sensor`]); this floor renders, so it sits above the
//! integrator.
//!
//! - [`estimate`]: the estimators (sensor path tracing, light tracing) and the photometric
//!   conversion (683 lm/W × ȳ).
//! - [`output`]: the CSV and the false-colour map with isolux contours (`--sensors-out`).
//! - [`luminance`]: luminance in cd/m² per pixel of a rendered image (`--luminance-out`).
//!
//! See `docs/sensors.md` for the analytic cases they are checked against.

pub mod daylight_factor;
pub mod estimate;
pub mod glare;
pub mod luminance;
pub mod output;
pub mod report;
pub mod statistics;

pub use estimate::{measure, Estimator, MeasureSettings, SensorReading, KM_LM_PER_W};
