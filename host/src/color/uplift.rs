//! RGB → smooth reflectance spectrum ("uplift") for RGB-specified materials.
//!
//! Model (Jakob & Hanika, "A Low-Dimensional Function Space for Efficient Spectral Upsampling",
//! Computer Graphics Forum 38(2), 2019): `R(λ) = S(c₀t² + c₁t + c₂)` with the sigmoid
//! `S(x) = ½ + x / (2√(1+x²))`, which lies in (0,1) for every finite x, so any fitted spectrum
//! is a valid, energy-conserving reflectance. Here `t = (λ − 360)/(830 − 360)` so the
//! coefficients stay well scaled. The coefficients are solved per colour at load time by
//! damped Gauss–Newton (Levenberg–Marquardt) on the three RGB residuals, walking from the
//! grey of equal mean to the target (continuation) so each solve starts close to its answer.

use super::matrix3::{inverse, mul_vec, Mat3};
use super::observer::{integration_grid, CieObserverKind, Observer};
use super::rgb_space::{RgbColorSpace, SRGB};
use crate::spectrum::{parse_spd_spec, Spd};

/// Wavelength range (nm) the polynomial's `t` is normalized to.
pub const UPLIFT_RANGE: (f64, f64) = (360.0, 830.0);

/// `S(x) = ½ + x/(2√(1+x²))`, with the limits 0 and 1 for x = ∓∞.
pub fn sigmoid(x: f64) -> f64 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// `dS/dx = 1/(2(1+x²)^{3/2})`.
fn sigmoid_derivative(x: f64) -> f64 {
    let q = 1.0 + x * x;
    0.5 / (q * q.sqrt())
}

/// Inverse of [`sigmoid`] on [0,1]: `x = y/√(1−y²)` with `y = 2s − 1` (±∞ at the ends).
fn sigmoid_inverse(s: f64) -> f64 {
    let y = 2.0 * s - 1.0;
    if y >= 1.0 {
        f64::INFINITY
    } else if y <= -1.0 {
        f64::NEG_INFINITY
    } else {
        y / (1.0 - y * y).sqrt()
    }
}

/// A smooth reflectance spectrum `S(c₀t² + c₁t + c₂)`, values in [0,1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SigmoidPolynomial {
    /// `[c₀, c₁, c₂]` in normalized `t` (see [`UPLIFT_RANGE`]).
    pub coeffs: [f64; 3],
}

impl SigmoidPolynomial {
    /// Reflectance at `lambda_nm` (the polynomial is evaluated for any λ, also outside the range).
    pub fn value(&self, lambda_nm: f64) -> f64 {
        let t = (lambda_nm - UPLIFT_RANGE.0) / (UPLIFT_RANGE.1 - UPLIFT_RANGE.0);
        let [a, b, c] = self.coeffs;
        if c.is_infinite() && a == 0.0 && b == 0.0 {
            return sigmoid(c);
        }
        sigmoid((a * t + b) * t + c)
    }

    /// Value at each lane's wavelength.
    pub fn eval(
        &self,
        lambda: &crate::spectrum::SampledWavelengths,
    ) -> crate::spectrum::SampledSpectrum {
        crate::spectrum::SampledSpectrum(std::array::from_fn(|i| {
            self.value(lambda.lambda[i] as f64) as f32
        }))
    }
}

/// Precomputed weights that turn a reflectance into RGB for one (space, illuminant, observer):
/// `rgb = Σ_λ w(λ)·R(λ)`, with `w = M·k·S(λ)·[x̄,ȳ,z̄](λ)` and `M` the space's XYZ→RGB matrix,
/// Bradford-adapted from the illuminant's white so that R ≡ 1 maps to RGB (1,1,1) exactly.
#[derive(Clone, Debug)]
pub struct RgbUplifter {
    /// `(t, rgb weight)` per grid wavelength.
    weights: Vec<(f64, [f64; 3])>,
}

impl RgbUplifter {
    /// Build for `space` under `illuminant` and `observer`.
    pub fn new(space: &RgbColorSpace, illuminant: &dyn Spd, observer: &dyn Observer) -> Self {
        let grid: Vec<f64> = integration_grid(observer).collect();
        let mut white = [0.0; 3];
        for &l in &grid {
            let c = observer.xyz_bar(l);
            let s = illuminant.value(l);
            for k in 0..3 {
                white[k] += s * c[k];
            }
        }
        let k = 1.0 / white[1];
        let m: Mat3 = space.xyz_to_rgb_matrix_from(white);
        let weights = grid
            .iter()
            .map(|&l| {
                let s = illuminant.value(l) * k;
                let c = observer.xyz_bar(l).map(|v| v * s);
                let t = (l - UPLIFT_RANGE.0) / (UPLIFT_RANGE.1 - UPLIFT_RANGE.0);
                (t, mul_vec(&m, c))
            })
            .filter(|(_, w)| w.iter().any(|&v| v != 0.0))
            .collect();
        Self { weights }
    }

    /// The uplifter for linear sRGB under CIE D65 with the CIE 1931 2° observer (shared).
    pub fn srgb() -> &'static Self {
        static CELL: std::sync::OnceLock<RgbUplifter> = std::sync::OnceLock::new();
        CELL.get_or_init(|| {
            let d65 = parse_spd_spec("d65").expect("bundled D65");
            Self::new(&SRGB, &d65, CieObserverKind::Cie1931_2.get())
        })
    }

    /// The same weights gathered onto nodes every `step_nm` nm (each 1 nm weight split between
    /// its two neighbouring nodes linearly): `rgb_of` then integrates the piecewise-linear
    /// interpolant of the reflectance between nodes, which for the smooth sigmoid spectra
    /// differs from the full sum by a few 1e-4 at 5 nm. Fewer terms per evaluation: what the
    /// precomputed table ([`super::rgb_table`]) is built with.
    pub fn coarsened(&self, step_nm: f64) -> Self {
        let span = UPLIFT_RANGE.1 - UPLIFT_RANGE.0;
        let dt = step_nm / span;
        let n = (1.0 / dt).ceil() as usize;
        let mut nodes = vec![[0.0f64; 3]; n + 1];
        for &(t, w) in &self.weights {
            let x = (t / dt).clamp(0.0, n as f64);
            let k = (x as usize).min(n - 1);
            let f = x - k as f64;
            for c in 0..3 {
                nodes[k][c] += w[c] * (1.0 - f);
                nodes[k + 1][c] += w[c] * f;
            }
        }
        Self {
            weights: nodes
                .into_iter()
                .enumerate()
                .map(|(k, w)| ((k as f64 * dt).min(1.0), w))
                .filter(|(_, w)| w.iter().any(|&v| v != 0.0))
                .collect(),
        }
    }

    /// The weights as `(t, [r, g, b])` (for cache keys and checks).
    pub fn weights(&self) -> &[(f64, [f64; 3])] {
        &self.weights
    }

    /// RGB of a reflectance under this uplifter's illuminant and observer.
    pub fn rgb_of(&self, reflectance: impl Fn(f64) -> f64) -> [f64; 3] {
        let mut acc = [0.0; 3];
        for &(t, w) in &self.weights {
            let r = reflectance(UPLIFT_RANGE.0 + t * (UPLIFT_RANGE.1 - UPLIFT_RANGE.0));
            for k in 0..3 {
                acc[k] += w[k] * r;
            }
        }
        acc
    }

    /// RGB of the sigmoid polynomial `c` and its 3×3 Jacobian `∂rgb/∂c`.
    fn rgb_and_jacobian(&self, c: [f64; 3]) -> ([f64; 3], Mat3) {
        let mut rgb = [0.0; 3];
        let mut jac = [[0.0; 3]; 3];
        for &(t, w) in &self.weights {
            let x = (c[0] * t + c[1]) * t + c[2];
            let s = sigmoid(x);
            let ds = sigmoid_derivative(x);
            let basis = [t * t, t, 1.0];
            for r in 0..3 {
                rgb[r] += w[r] * s;
                for (k, b) in basis.iter().enumerate() {
                    jac[r][k] += w[r] * ds * b;
                }
            }
        }
        (rgb, jac)
    }

    /// Levenberg–Marquardt iterations from `c` towards `target`; returns the best coefficients
    /// found and their residual norm.
    fn solve(&self, target: [f64; 3], mut c: [f64; 3], iterations: usize) -> ([f64; 3], f64) {
        let norm = |r: [f64; 3]| (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let (mut rgb, mut jac) = self.rgb_and_jacobian(c);
        let mut res = norm(std::array::from_fn(|k| rgb[k] - target[k]));
        let mut mu = 1e-6;
        for _ in 0..iterations {
            if res < 1e-10 {
                break;
            }
            let r: [f64; 3] = std::array::from_fn(|k| rgb[k] - target[k]);
            // Normal equations (JᵀJ + μ·diag(JᵀJ)) δ = −Jᵀr.
            let jtj: Mat3 = std::array::from_fn(|a| {
                std::array::from_fn(|b| (0..3).map(|k| jac[k][a] * jac[k][b]).sum())
            });
            let jtr: [f64; 3] = std::array::from_fn(|a| (0..3).map(|k| jac[k][a] * r[k]).sum());
            let mut improved = false;
            for _ in 0..12 {
                let mut a = jtj;
                for d in 0..3 {
                    a[d][d] += mu * jtj[d][d].max(1e-12);
                }
                let Some(inv) = inverse(&a) else {
                    mu *= 10.0;
                    continue;
                };
                let delta = mul_vec(&inv, jtr);
                let trial: [f64; 3] = std::array::from_fn(|k| c[k] - delta[k]);
                if trial.iter().any(|v| !v.is_finite()) {
                    mu *= 10.0;
                    continue;
                }
                let (trgb, tjac) = self.rgb_and_jacobian(trial);
                let tres = norm(std::array::from_fn(|k| trgb[k] - target[k]));
                if tres < res {
                    c = trial;
                    rgb = trgb;
                    jac = tjac;
                    res = tres;
                    mu = (mu * 0.1).max(1e-12);
                    improved = true;
                    break;
                }
                mu *= 10.0;
            }
            if !improved {
                break;
            }
        }
        (c, res)
    }

    /// Levenberg–Marquardt from the coefficients `start` (a nearby colour's fit) towards
    /// `rgb` (not clamped), at most `iterations` steps: the coefficients and the RGB residual
    /// norm. What a table of fits uses to walk from one entry to the next.
    pub fn refine(&self, rgb: [f64; 3], start: [f64; 3], iterations: usize) -> ([f64; 3], f64) {
        self.solve(rgb, start, iterations)
    }

    /// RGB residual norm of the coefficients `c` against `rgb`.
    pub fn residual(&self, rgb: [f64; 3], c: [f64; 3]) -> f64 {
        let (got, _) = self.rgb_and_jacobian(c);
        (0..3)
            .map(|k| (got[k] - rgb[k]).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// Fit a smooth reflectance whose RGB (under this uplifter) is `rgb`, clamped to [0,1].
    /// Greys are exact; other colours inside the reflectance gamut come back within ~1e-6;
    /// colours at the gamut boundary (a channel at 0 or 1 with others not) are approached as
    /// closely as finite coefficients allow.
    pub fn fit(&self, rgb: [f64; 3]) -> SigmoidPolynomial {
        let target = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) });
        let mean = (target[0] + target[1] + target[2]) / 3.0;
        if target.iter().all(|&v| (v - mean).abs() < 1e-12) {
            return SigmoidPolynomial {
                coeffs: [0.0, 0.0, sigmoid_inverse(mean)],
            };
        }
        // Continuation: from a grey of the same mean (kept off 0 and 1 so the start is finite).
        let g = mean.clamp(0.02, 0.98);
        let mut c = [0.0, 0.0, sigmoid_inverse(g)];
        const STEPS: usize = 8;
        for step in 1..=STEPS {
            let tau = step as f64 / STEPS as f64;
            let goal: [f64; 3] = std::array::from_fn(|k| g + tau * (target[k] - g));
            let iterations = if step == STEPS { 100 } else { 15 };
            c = self.solve(goal, c, iterations).0;
        }
        SigmoidPolynomial { coeffs: c }
    }
}

/// Uplift a linear-sRGB reflectance colour (components in [0,1]) to a smooth spectrum.
pub fn uplift_srgb(rgb: [f64; 3]) -> SigmoidPolynomial {
    RgbUplifter::srgb().fit(rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Greys are constant spectra and the perfect white maps to RGB (1,1,1): 1e-12 because the
    // Bradford-adapted matrix is built to make it exact up to rounding.
    #[test]
    fn greys_are_flat_and_white_is_one() {
        let up = RgbUplifter::srgb();
        let w = up.rgb_of(|_| 1.0);
        assert!(w.iter().all(|v| (v - 1.0).abs() < 1e-12), "{w:?}");
        let g = up.fit([0.3, 0.3, 0.3]);
        assert!((g.value(400.0) - 0.3).abs() < 1e-12 && (g.value(700.0) - 0.3).abs() < 1e-12);
        assert_eq!(up.fit([0.0; 3]).value(500.0), 0.0);
        assert_eq!(up.fit([1.0; 3]).value(500.0), 1.0);
    }

    // Round trip RGB → spectrum → RGB on a grid of colours inside [0.05, 0.95]³ (all inside the
    // reflectance gamut of sRGB/D65): max channel error 1e-5, far below 8-bit resolution
    // (1/255 ≈ 4e-3) and loose enough for the solver's stopping rule. Spectra stay in [0,1].
    #[test]
    fn round_trip_grid() {
        let up = RgbUplifter::srgb();
        let levels = [0.05, 0.35, 0.65, 0.95];
        let mut worst: f64 = 0.0;
        for &r in &levels {
            for &g in &levels {
                for &b in &levels {
                    let s = up.fit([r, g, b]);
                    let back = up.rgb_of(|l| s.value(l));
                    for (k, v) in [r, g, b].iter().enumerate() {
                        worst = worst.max((back[k] - v).abs());
                    }
                    for l in (360..=830).step_by(10) {
                        let v = s.value(l as f64);
                        assert!((0.0..=1.0).contains(&v));
                    }
                }
            }
        }
        assert!(worst < 1e-5, "worst channel error {worst}");
    }
}
