//! A monochromatic line: all power at one wavelength (a laser). It has no density; it is drawn
//! with probability 1 and estimators must treat the draw as discrete.

use super::spd::{DeltaLine, Spd, SpdSample};

/// A delta SPD at `lambda` nm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSpd {
    /// Wavelength of the line in nm.
    pub lambda: f64,
}

impl Spd for LineSpd {
    fn value(&self, _lambda_nm: f64) -> f64 {
        0.0
    }

    fn sample(&self, _u: f64) -> SpdSample {
        SpdSample {
            lambda: self.lambda,
            pdf: 1.0,
            is_delta: true,
        }
    }

    fn pdf(&self, _lambda_nm: f64) -> f64 {
        0.0
    }

    fn range(&self) -> (f64, f64) {
        (self.lambda, self.lambda)
    }

    fn delta_lines(&self) -> Vec<DeltaLine> {
        vec![DeltaLine {
            lambda: self.lambda,
            weight: 1.0,
        }]
    }
}
