//! Complex numbers in f64, just the operations thin-film optics needs (Fresnel amplitudes,
//! phase factors). Written here because these few lines are all that is needed and no
//! complex-number crate is among the project's chosen dependencies.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// `re + i·im`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Complex {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

impl Complex {
    /// `re + i·im`.
    pub const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }

    /// A real number.
    pub const fn real(re: f64) -> Self {
        Self { re, im: 0.0 }
    }

    /// `|z|²`.
    pub fn norm_sqr(self) -> f64 {
        self.re * self.re + self.im * self.im
    }

    /// Complex conjugate.
    pub fn conj(self) -> Self {
        Self::new(self.re, -self.im)
    }

    /// `e^{iφ}` for real φ (radians).
    pub fn cis(phi: f64) -> Self {
        Self::new(phi.cos(), phi.sin())
    }

    /// `e^z`.
    pub fn exp(self) -> Self {
        Self::cis(self.im) * self.re.exp()
    }

    /// Principal square root (non-negative real part; on the negative real axis `+i·√|z|`).
    pub fn sqrt(self) -> Self {
        let r = self.norm_sqr().sqrt();
        let re = (0.5 * (r + self.re)).max(0.0).sqrt();
        let im = (0.5 * (r - self.re)).max(0.0).sqrt();
        Self::new(re, if self.im < 0.0 { -im } else { im })
    }
}

impl Add for Complex {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
}

impl Sub for Complex {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
}

impl Neg for Complex {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.re, -self.im)
    }
}

impl Mul for Complex {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Self::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}

impl Mul<f64> for Complex {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.re * s, self.im * s)
    }
}

impl Div for Complex {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let d = o.norm_sqr();
        Self::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Arithmetic identities to 1e-12 (f64 rounding on numbers of order 1).
    #[test]
    fn identities() {
        let a = Complex::new(1.5, -0.25);
        let b = Complex::new(-0.3, 2.0);
        let q = (a / b) * b;
        assert!((q - a).norm_sqr() < 1e-24);
        let s = b.sqrt();
        assert!((s * s - b).norm_sqr() < 1e-24 && s.re >= 0.0);
        assert!((Complex::real(-4.0).sqrt() - Complex::new(0.0, 2.0)).norm_sqr() < 1e-24);
        let e = Complex::new(0.0, std::f64::consts::PI).exp();
        assert!((e - Complex::real(-1.0)).norm_sqr() < 1e-24);
    }
}
