//! Illuminance sensors: grids of points where a render measures the illuminance in lux, with
//! its standard error, as a lighting designer's calculation grid (the scene's `sensors` list).
//!
//! - [`grid`]: the `illuminance_grid` scene item and its parameter table.
//! - [`estimate`]: the estimators (sensor path tracing, light tracing) and the photometric
//!   conversion (683 lm/W × ȳ).
//! - [`output`]: the CSV and the false-colour map with isolux contours (`--sensors-out`).
//! - [`luminance`]: luminance in cd/m² per pixel of a rendered image (`--luminance-out`).
//!
//! See `docs/sensors.md` for the analytic cases they are checked against.

pub mod daylight_factor;
pub mod estimate;
pub mod glare;
pub mod glare_observer;
pub mod grid;
pub mod limits;
pub mod luminance;
pub mod output;
pub mod report;
pub mod statistics;

pub use estimate::{measure, Estimator, MeasureSettings, SensorReading, KM_LM_PER_W};
pub use grid::{build_sensors, IlluminanceGrid};
pub use limits::MAX_SAMPLES;
