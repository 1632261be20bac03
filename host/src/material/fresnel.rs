//! Fresnel reflectance for dielectric interfaces and for conductors with complex IOR.
//! Unpolarised light: the average of the s and p reflectances.

/// Reflectance of a dielectric interface for incident cosine `cos_i` (measured on the side the
/// light arrives from: negative means "from inside") and relative IOR `eta = n_inside / n_outside`.
pub fn dielectric(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta)
    } else {
        (cos_i, eta)
    };
    let cos_i = cos_i.min(1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0; // total internal reflection
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

/// A complex number, just enough for conductor Fresnel.
#[derive(Clone, Copy, Debug)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    fn new(re: f32, im: f32) -> Self {
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
    fn norm2(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    /// Principal square root (non-negative real part).
    fn sqrt(self) -> Self {
        let r = self.norm2().sqrt();
        if r == 0.0 {
            return Self::new(0.0, 0.0);
        }
        let re = (0.5 * (r + self.re)).max(0.0).sqrt();
        let im = (0.5 * (r - self.re)).max(0.0).sqrt();
        Self::new(re, if self.im < 0.0 { -im } else { im })
    }
}

/// Reflectance of a conductor with complex IOR `n + i·k` (relative to the outside medium) for
/// incident cosine `cos_i ∈ [0, 1]`.
pub fn conductor(cos_i: f32, n: f32, k: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let eta = Complex::new(n, k);
    let ci = Complex::new(cos_i, 0.0);
    let sin2_i = Complex::new(1.0 - cos_i * cos_i, 0.0);
    let sin2_t = sin2_i.div(eta.mul(eta));
    let cos_t = Complex::new(1.0, 0.0).sub(sin2_t).sqrt();
    let r_parl = eta.mul(ci).sub(cos_t).div(eta.mul(ci).add(cos_t));
    let r_perp = ci.sub(eta.mul(cos_t)).div(ci.add(eta.mul(cos_t)));
    (0.5 * (r_parl.norm2() + r_perp.norm2())).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Normal incidence has the closed form ((n-1)/(n+1))² for dielectrics and
    /// ((n-1)²+k²)/((n+1)²+k²) for conductors; both within 1e-6 (f32 rounding of a few ops).
    #[test]
    fn normal_incidence_matches_closed_form() {
        let n = 1.5f32;
        assert!((dielectric(1.0, n) - ((n - 1.0) / (n + 1.0)).powi(2)).abs() < 1e-6);
        let (n, k) = (0.2f32, 3.5f32);
        let want = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        assert!((conductor(1.0, n, k) - want).abs() < 1e-6);
    }

    /// Beyond the critical angle (from glass at cos 0.5, sin 0.866 > 1/1.5) the interface reflects
    /// everything; at grazing incidence both kinds go to 1 (checked to 1e-3 at cos = 1e-4).
    #[test]
    fn total_internal_reflection_and_grazing() {
        assert_eq!(dielectric(-0.5, 1.5), 1.0);
        assert!(dielectric(1e-4, 1.5) > 0.999);
        assert!(conductor(1e-4, 0.2, 3.5) > 0.999);
    }

    /// A conductor with k = 0 is a dielectric: the two formulas must agree (1e-5, f32 rounding).
    #[test]
    fn conductor_with_zero_k_is_dielectric() {
        for i in 1..=10 {
            let c = i as f32 / 10.0;
            assert!((conductor(c, 1.7, 0.0) - dielectric(c, 1.7)).abs() < 1e-5);
        }
    }
}
