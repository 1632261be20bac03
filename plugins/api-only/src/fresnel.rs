//! Fresnel reflectance of a conductor with complex index `η = n + i·k` relative to the outside
//! medium, unpolarised (the mean of the s and p reflectances), in single precision.
//!
//! With cos θi = c and the complex cos θt = √(1 − (1 − c²)/η²):
//! r∥ = (η c − cos θt)/(η c + cos θt), r⊥ = (c − η cos θt)/(c + η cos θt), R = (|r∥|² + |r⊥|²)/2.
//! At normal incidence R = ((n − 1)² + k²)/((n + 1)² + k²).

/// A complex number: only what the Fresnel equations use.
#[derive(Clone, Copy, Debug)]
struct C {
    re: f32,
    im: f32,
}

impl C {
    const fn new(re: f32, im: f32) -> Self {
        Self { re, im }
    }
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Self) -> Self {
        Self::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    fn div(self, o: Self) -> Self {
        let d = o.re * o.re + o.im * o.im;
        Self::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    fn abs2(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    /// The principal square root (real part ≥ 0).
    fn sqrt(self) -> Self {
        let m = self.abs2().sqrt();
        if m == 0.0 {
            return Self::new(0.0, 0.0);
        }
        let re = (0.5 * (m + self.re)).max(0.0).sqrt();
        let im = (0.5 * (m - self.re)).max(0.0).sqrt();
        Self::new(re, if self.im < 0.0 { -im } else { im })
    }
}

/// Reflectance for incident cosine `cos_i` (clamped to [0, 1]) and index `n + i·k`, in [0, 1].
pub fn conductor(cos_i: f32, n: f32, k: f32) -> f32 {
    let c = cos_i.clamp(0.0, 1.0);
    let eta = C::new(n, k);
    let ci = C::new(c, 0.0);
    let sin2_t = C::new(1.0 - c * c, 0.0).div(eta.mul(eta));
    let cos_t = C::new(1.0, 0.0).sub(sin2_t).sqrt();
    let eta_ci = eta.mul(ci);
    let eta_ct = eta.mul(cos_t);
    let r_p = eta_ci.sub(cos_t).div(eta_ci.add(cos_t));
    let r_s = ci.sub(eta_ct).div(ci.add(eta_ct));
    (0.5 * (r_p.abs2() + r_s.abs2())).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    /// Normal incidence against the closed form ((n−1)² + k²)/((n+1)² + k²), and k = 0 against
    /// the dielectric closed form at 45°; 1e-6 absolute (a few f32 operations).
    #[test]
    fn closed_forms() {
        let (n, k) = (0.2f32, 3.5f32);
        let want = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        assert!((super::conductor(1.0, n, k) - want).abs() < 1e-6);
        let (c, n) = (std::f32::consts::FRAC_1_SQRT_2, 1.5f32);
        let ct = (1.0 - (1.0 - c * c) / (n * n)).sqrt();
        let rs = ((c - n * ct) / (c + n * ct)).powi(2);
        let rp = ((n * c - ct) / (n * c + ct)).powi(2);
        assert!((super::conductor(c, n, 0.0) - 0.5 * (rs + rp)).abs() < 1e-6);
    }
}
