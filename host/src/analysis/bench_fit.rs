//! The arithmetic of `spectrace bench speed`: the error-against-time fit, the image regions the
//! errors are split into, the reference's own noise, and the CPU the figures belong to.
//!
//! **Fit.** An unbiased renderer's expected mean squared error against the true image falls as
//! `a/t` with its sampling time `t`; a renderer that converges to something else keeps a floor
//! `b`. Against a reference that has noise of its own (variance `v_ref` per value) every
//! renderer's measured MSE gains `v_ref` as well, so the measured points follow
//! `MSE(t) = a/t + b` with `b = v_ref + bias²`. [`fit_inverse_time`] fits `a` and `b` by least
//! squares weighted by 1/MSE² (each point's MSE is known to a roughly constant *relative*
//! error), with standard errors from the residuals. Every term of `b` is non-negative, so
//! `b ≥ v_ref`: where the free fit puts `b` below the reference's noise (error falling faster
//! than 1/t over the budgets, as with quasi-Monte Carlo samplers, which the free fit books as a
//! larger `a`), the fit is the constrained least-squares one, `b` held at `v_ref` and only `a`
//! fitted ([`Fit::floor_held`]). `a` (MSE·seconds) is the renderer's
//! inverse efficiency; a floor is *significant* when `b − v_ref` exceeds both Student's t
//! (0.975, the fit's degrees of freedom) times its standard error and a tenth of the noise
//! term at the longest budget ([`Fit::biased`]): such a renderer converges to a different image and is listed as biased instead of being ranked.
//!
//! **Regions.** [`Regions::new`] splits the pixels of the scene's default camera, from the
//! scene's geometry and the reference alone (never from a render being judged), and from one
//! half of the reference's independent parts, while each region is compared with the other
//! half ([`ReferenceHalves`]): a pixel whose reference happens to come out high is more likely
//! to count as bright, so regions drawn from the very image they are compared with make every
//! render look low in the bright regions and high beside them:
//!
//! | region       | pixels                                                                     |
//! |--------------|----------------------------------------------------------------------------|
//! | (left out)   | the camera sees an emitter directly anywhere in the pixel's footprint      |
//! | lamp images  | the camera sees a specular or glossy surface, and the reference there is brighter than [`BRIGHT_FACTOR`] × the median counted luminance |
//! | caustic core | the camera sees a diffuse surface that bright                              |
//! | rest         | everything else                                                            |
//!
//! A non-finite value in a render is an error ([`Regions::split`]): dropping such pixels would
//! reward a renderer for its failures.
//!
//! **Means.** The fit's floor sees a bias only once it rises above the noise; [`mean_check`]
//! tests the mean of each region directly: the renders' mean difference from the reference,
//! pooled with inverse-variance weights, over its standard error (each render's per-pixel
//! variance bounded by its MSE, the reference's own variance added once). |z| ≤
//! [`MEAN_Z_LIMIT`] is "within 4 standard errors" (the target); pixels count as
//! independent (each pixel's channels once, not three times, since they are correlated).
//!
//! **Verdict.** A configuration is biased when its floor is significant ([`Fit::biased`]) or
//! its mean is off ([`MeanCheck::within`]): with one seed and three budgets the floor's
//! standard error has one degree of freedom and misses offsets the means show at once, such as
//! an RGB renderer's projection of a spectral scene.

use crate::analysis::RgbImage;
use crate::camera::CameraSample;
use crate::material::MaterialFlags;
use crate::scene::Scene;
use glam::Vec2;

/// A region is "bright" above this multiple of the median luminance of the counted pixels.
pub const BRIGHT_FACTOR: f64 = 4.0;

/// Names of the regions, in the order of [`RegionSplit::sse`].
pub const REGION_NAMES: [&str; 3] = ["lamp images", "caustic core", "rest"];

/// Result of [`fit_inverse_time`]: `MSE(t) = a/t + b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// Noise term, MSE·seconds (smaller is more efficient).
    pub a: f64,
    /// Standard error of `a`.
    pub se_a: f64,
    /// Floor, MSE.
    pub b: f64,
    /// Standard error of `b`.
    pub se_b: f64,
    /// Points fitted.
    pub n: usize,
    /// Longest time among the points, seconds.
    pub t_max: f64,
    /// True when the free fit's floor fell below the lowest possible one (the reference's own
    /// variance) and `b` is held there, only `a` fitted.
    pub floor_held: bool,
}

impl Fit {
    /// Efficiency 1/a (1/(MSE·s)).
    pub fn efficiency(&self) -> f64 {
        1.0 / self.a
    }
    /// True when the floor left after the reference's own noise `ref_var` is significant: more
    /// than [`student_t_975`] of the fit's degrees of freedom times its standard error (the
    /// standard error comes from the residuals, so with few points it is itself uncertain: one
    /// degree of freedom needs 12.7 of them, many about 2) and more than a tenth of the noise
    /// term at the longest budget (a floor too small to matter over the measured times is not
    /// called a bias).
    pub fn biased(&self, ref_var: f64) -> bool {
        let excess = self.b - ref_var;
        self.n > 2
            && excess > student_t_975(self.n - 2) * self.se_b
            && excess > 0.1 * self.a / self.t_max
    }
}

/// Student's t quantile at 0.975 (two-sided 95%) for `dof` degrees of freedom, from the
/// standard table (e.g. NIST/SEMATECH e-Handbook of Statistical Methods, table 1.3.6.7.2);
/// between listed values the next smaller degrees of freedom's (larger, conservative) value.
pub fn student_t_975(dof: usize) -> f64 {
    const TABLE: [(usize, f64); 16] = [
        (1, 12.706),
        (2, 4.303),
        (3, 3.182),
        (4, 2.776),
        (5, 2.571),
        (6, 2.447),
        (7, 2.365),
        (8, 2.306),
        (9, 2.262),
        (10, 2.228),
        (12, 2.179),
        (15, 2.131),
        (20, 2.086),
        (30, 2.042),
        (60, 2.000),
        (120, 1.980),
    ];
    if dof == 0 {
        return f64::INFINITY;
    }
    TABLE
        .iter()
        .rev()
        .find(|&&(d, _)| d <= dof)
        .map_or(f64::INFINITY, |&(_, t)| t)
}

/// Weighted least-squares fit of `MSE = a/t + b` to `(t, mse)` points (weights 1/mse²) with
/// `b ≥ floor_min` (the reference's own variance per value; 0 against an exact reference).
/// `None` with fewer than two distinct times or a non-positive or non-finite point.
pub fn fit_inverse_time(points: &[(f64, f64)], floor_min: f64) -> Option<Fit> {
    if points
        .iter()
        .any(|&(t, m)| !(t.is_finite() && t > 0.0 && m.is_finite() && m > 0.0))
    {
        return None;
    }
    let fit_with = |w: &dyn Fn(usize) -> f64| -> Option<(f64, f64, [f64; 3])> {
        // Normal equations of y = a·x + b, x = 1/t.
        let (mut sw, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (i, &(t, y)) in points.iter().enumerate() {
            let (x, wi) = (1.0 / t, w(i));
            sw += wi;
            sx += wi * x;
            sy += wi * y;
            sxx += wi * x * x;
            sxy += wi * x * y;
        }
        let det = sw * sxx - sx * sx;
        if det.abs() <= 1e-12 * sw * sxx {
            return None;
        }
        let a = (sw * sxy - sx * sy) / det;
        let b = (sxx * sy - sx * sxy) / det;
        Some((a, b, [sw / det, sxx / det, det]))
    };
    // First pass weighted by the measured values, second by the fitted ones (less biased
    // towards points that came out low by chance).
    let (a0, b0, _) = fit_with(&|i| 1.0 / (points[i].1 * points[i].1))?;
    let pred = |i: usize| (a0 / points[i].0 + b0).max(0.1 * points[i].1);
    let (a, b, [inv_a, inv_b, _]) = fit_with(&|i| 1.0 / (pred(i) * pred(i)))?;
    let t_max = points.iter().map(|p| p.0).fold(0.0, f64::max);
    if b < floor_min {
        return Some(fit_with_floor(points, floor_min, t_max));
    }
    let n = points.len();
    let s2 = residual_variance(points, (a, b), &pred, n.saturating_sub(2));
    Some(Fit {
        a,
        se_a: (s2 * inv_a).sqrt(),
        b,
        se_b: (s2 * inv_b).sqrt(),
        n,
        t_max,
        floor_held: false,
    })
}

/// The constrained fit of [`fit_inverse_time`]: `b` held at `floor`, `a` by weighted least
/// squares on `y − b = a·(1/t)` (the quadratic objective's minimum under `b ≥ floor` lies on
/// the bound when the free minimum is below it), weighted as the free fit (measured values,
/// then fitted ones), standard error from the residuals with n − 1 degrees of freedom.
fn fit_with_floor(points: &[(f64, f64)], floor: f64, t_max: f64) -> Fit {
    let fit_a = |w: &dyn Fn(usize) -> f64| -> (f64, f64) {
        let (mut sxx, mut sxy) = (0.0, 0.0);
        for (i, &(t, y)) in points.iter().enumerate() {
            let x = 1.0 / t;
            sxx += w(i) * x * x;
            sxy += w(i) * x * (y - floor);
        }
        (sxy / sxx, 1.0 / sxx)
    };
    let (a0, _) = fit_a(&|i| 1.0 / (points[i].1 * points[i].1));
    let pred = |i: usize| (a0 / points[i].0 + floor).max(0.1 * points[i].1);
    let (a, inv_a) = fit_a(&|i| 1.0 / (pred(i) * pred(i)));
    let n = points.len();
    let s2 = residual_variance(points, (a, floor), &pred, n.saturating_sub(1));
    Fit {
        a,
        se_a: (s2 * inv_a).sqrt(),
        b: floor,
        se_b: f64::NAN,
        n,
        t_max,
        floor_held: true,
    }
}

/// Residual variance of a weighted fit `a/t + b` (unit weight variance: squared residuals over
/// `pred(i)²`, summed over `dof` degrees of freedom); NaN without degrees of freedom, where the
/// standard errors are unknown.
fn residual_variance(
    points: &[(f64, f64)],
    (a, b): (f64, f64),
    pred: &dyn Fn(usize) -> f64,
    dof: usize,
) -> f64 {
    if dof == 0 {
        return f64::NAN;
    }
    points
        .iter()
        .enumerate()
        .map(|(i, &(t, y))| {
            let r = y - (a / t + b);
            r * r / (pred(i) * pred(i))
        })
        .sum::<f64>()
        / dof as f64
}

/// The reference's own noise per value (variance of the full reference, the mean of its `K`
/// independent parts of equal spp): per value `Σₖ (partₖ − mean)² / (K (K − 1))`, averaged over
/// the counted pixels (`counted` true) and channels. For two halves that is the MSE between
/// them over 4. `K` ≥ 2; fewer parts give 0.
pub fn reference_variance(parts: &[RgbImage], counted: &[bool]) -> f64 {
    let k = parts.len();
    if k < 2 {
        return 0.0;
    }
    let (mut s, mut n) = (0.0, 0usize);
    for (i, &c) in counted.iter().enumerate() {
        if !c {
            continue;
        }
        for ch in 0..3 {
            let mean = parts.iter().map(|p| p.rgb[i][ch]).sum::<f64>() / k as f64;
            s += parts
                .iter()
                .map(|p| (p.rgb[i][ch] - mean).powi(2))
                .sum::<f64>();
            n += 1;
        }
    }
    s / (k * (k - 1)) as f64 / n.max(1) as f64
}

/// Squared error of one render summed per region, with the number of values (pixels × 3).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RegionSplit {
    /// Σ (a − b)² over the region's counted pixels and channels.
    pub sse: [f64; 3],
    /// Number of values in each region.
    pub values: [usize; 3],
    /// Σ (a − b) over the region's values: the render's mean offset, for [`mean_check`].
    pub sum_diff: [f64; 3],
    /// Σ b over the region's values (the reference), to state the offset relative to it.
    pub sum_ref: [f64; 3],
    /// Σ (a − b)², Σ (a − b) and Σ b over every counted value, against the whole reference
    /// (the regions' sums are against the half the regions were not drawn from).
    pub total_sse: f64,
    pub total_sum_diff: f64,
    pub total_sum_ref: f64,
}

/// A mean further than this many standard errors from the reference's is reported as off.
pub const MEAN_Z_LIMIT: f64 = 4.0;

/// Result of [`mean_check`]: how far the renders' mean is from the reference's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanCheck {
    /// (render − reference) / reference, pooled over the renders (0.01 = 1%).
    pub relative: f64,
    /// The pooled difference over its standard error.
    pub z: f64,
}

impl MeanCheck {
    /// True when the mean is within [`MEAN_Z_LIMIT`] standard errors of the reference's.
    pub fn within(&self) -> bool {
        self.z.abs() <= MEAN_Z_LIMIT
    }
}

/// Pooled mean of a set of renders against the reference in `region` (`None`: every counted
/// pixel), with `ref_var` the reference's own variance per value (see the module docs).
/// `None` when the region is empty or no render has a usable variance.
pub fn mean_check(
    splits: &[&RegionSplit],
    region: Option<usize>,
    ref_var: f64,
) -> Option<MeanCheck> {
    let (mut wsum, mut wd, mut reference, mut pixels) = (0.0, 0.0, 0.0, 0.0);
    for s in splits {
        let (sse, sum_diff, sum_ref, n) = match region {
            Some(r) => (s.sse[r], s.sum_diff[r], s.sum_ref[r], s.values[r]),
            None => (
                s.total_sse,
                s.total_sum_diff,
                s.total_sum_ref,
                s.values.iter().sum(),
            ),
        };
        let n = n as f64;
        if n == 0.0 {
            continue;
        }
        let mse = sse / n;
        // Variance of the region's mean: the per-value variance (≤ MSE) over the pixel count.
        let var = mse / (n / 3.0);
        if !(var > 0.0) {
            continue;
        }
        wsum += 1.0 / var;
        wd += sum_diff / n / var;
        reference = sum_ref / n;
        pixels = n / 3.0;
    }
    if wsum == 0.0 {
        return None;
    }
    let d = wd / wsum;
    let se = (1.0 / wsum + ref_var / pixels).sqrt();
    Some(MeanCheck {
        relative: if reference != 0.0 {
            d / reference
        } else {
            f64::NAN
        },
        z: d / se,
    })
}

impl RegionSplit {
    /// MSE of region `i` (0 for an empty region).
    pub fn mse(&self, i: usize) -> f64 {
        self.sse[i] / self.values[i].max(1) as f64
    }
    /// MSE over all counted pixels, against the whole reference.
    pub fn total_mse(&self) -> f64 {
        self.total_sse / self.values.iter().sum::<usize>().max(1) as f64
    }
}

/// The region of every pixel (`None`: left out), see the module docs.
#[derive(Clone, Debug)]
pub struct Regions {
    /// Per pixel, row-major.
    pub region: Vec<Option<usize>>,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
}

fn luminance(p: &[f64; 3]) -> f64 {
    0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
}

/// What the default camera sees first in each pixel's footprint (a 3×3 grid over the pixel and
/// half of each neighbour, lens centre): (emitter anywhere, specular/glossy anywhere).
pub fn view_masks(scene: &Scene) -> Result<(Vec<bool>, Vec<bool>, u32, u32), String> {
    let cam = scene.cameras.get(None)?;
    let (w, h) = cam.camera.resolution();
    let mut emitter = vec![false; (w * h) as usize];
    let mut shiny = vec![false; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let k = (y * w + x) as usize;
            for j in 0..3 {
                for i in 0..3 {
                    let sample = CameraSample {
                        p_film: Vec2::new(x as f32 - 0.5 + i as f32, y as f32 - 0.5 + j as f32),
                        p_lens: Vec2::splat(0.5),
                    };
                    let Some(r) = cam.camera.generate_ray(&sample) else {
                        continue;
                    };
                    if let Some(hit) = scene.geometry.intersect(&r.ray, f32::INFINITY) {
                        let f = scene.objects.material(hit.object).flags();
                        emitter[k] |= f.contains(MaterialFlags::EMISSIVE);
                        shiny[k] |= f.intersects(MaterialFlags::SPECULAR)
                            || f.intersects(MaterialFlags::GLOSSY);
                    }
                }
            }
        }
    }
    Ok((emitter, shiny, w, h))
}

/// A reference's independent parts arranged for [`Regions`]: the mean of the odd-numbered
/// parts (1, 3, …) draws the regions, the mean of the even-numbered ones is what each region
/// is compared with, and the mean of all parts is the whole image's reference.
///
/// Why: the bright regions are found by a threshold on the reference, and its noise decides
/// pixels near the threshold. Compared with the image that chose them, bright regions get the
/// pixels whose reference came out high. On the bench's glass sphere (path-traced reference,
/// heavy-tailed in the caustic seen through the ball) every renderer, Mitsuba 3's own short
/// renders included, sat 0.4–3% below the reference in the lamp images that way.
#[derive(Clone, Debug)]
pub struct ReferenceHalves {
    /// Mean of the odd-numbered parts: what [`Regions::from_masks`] thresholds.
    pub regions_from: RgbImage,
    /// Mean of the even-numbered parts: what [`Regions::split`] compares each region with.
    pub compared: RgbImage,
    /// The compared half's variance per value over the whole mean's (K parts, ⌊K/2⌋ of them
    /// even-numbered: K / ⌊K/2⌋, 2 for an even K).
    pub compared_variance_factor: f64,
}

impl ReferenceHalves {
    /// From `parts` (at least two, of equal sample counts and the same size).
    pub fn new(parts: &[RgbImage]) -> Result<Self, String> {
        if parts.len() < 2 {
            return Err(format!(
                "{} reference part(s): two or more are needed to draw the regions from one \
                 and compare with another",
                parts.len()
            ));
        }
        let first = &parts[0];
        if let Some((k, p)) = parts
            .iter()
            .enumerate()
            .find(|(_, p)| (p.width, p.height) != (first.width, first.height))
        {
            return Err(format!(
                "reference part {} is {}×{} but part 1 is {}×{}",
                k + 1,
                p.width,
                p.height,
                first.width,
                first.height
            ));
        }
        let half =
            |pick: usize| mean_image(&parts.iter().skip(pick).step_by(2).collect::<Vec<_>>());
        Ok(Self {
            regions_from: half(0),
            compared: half(1),
            compared_variance_factor: parts.len() as f64 / (parts.len() / 2) as f64,
        })
    }
}

/// The per-value mean of `images` (at least one, all of the first one's size).
fn mean_image(images: &[&RgbImage]) -> RgbImage {
    let first = images[0];
    let k = images.len() as f64;
    let rgb = (0..first.rgb.len())
        .map(|i| {
            let mut v = [0.0; 3];
            for p in images {
                for (c, x) in v.iter_mut().enumerate() {
                    *x += p.rgb[i][c] / k;
                }
            }
            v
        })
        .collect();
    RgbImage {
        width: first.width,
        height: first.height,
        rgb,
    }
}

impl Regions {
    /// Regions from the two view masks and the reference (the odd-numbered parts' mean,
    /// [`ReferenceHalves::regions_from`]).
    pub fn from_masks(
        emitter: &[bool],
        shiny: &[bool],
        reference: &RgbImage,
    ) -> Result<Self, String> {
        let n = reference.rgb.len();
        if emitter.len() != n || shiny.len() != n {
            return Err(format!(
                "the reference is {}×{} but the scene's camera has {} pixels",
                reference.width,
                reference.height,
                emitter.len()
            ));
        }
        let mut lum: Vec<f64> = (0..n)
            .filter(|&i| !emitter[i])
            .map(|i| luminance(&reference.rgb[i]))
            .collect();
        lum.sort_by(f64::total_cmp);
        let median = lum.get(lum.len() / 2).copied().unwrap_or(0.0);
        let bright = BRIGHT_FACTOR * median;
        let region = (0..n)
            .map(|i| {
                if emitter[i] {
                    None
                } else if luminance(&reference.rgb[i]) > bright {
                    Some(if shiny[i] { 0 } else { 1 })
                } else {
                    Some(2)
                }
            })
            .collect();
        Ok(Self {
            region,
            width: reference.width,
            height: reference.height,
        })
    }

    /// Pixels counted in each region.
    pub fn pixels(&self) -> [usize; 3] {
        let mut n = [0; 3];
        for r in self.region.iter().flatten() {
            n[*r] += 1;
        }
        n
    }

    /// Counted pixels (not left out).
    pub fn counted(&self) -> Vec<bool> {
        self.region.iter().map(Option::is_some).collect()
    }

    /// Squared error of `test` per region against `region_reference`, an estimate of the image
    /// independent of the one the regions were drawn from, and over every counted pixel
    /// against `reference`, the best estimate. A non-finite value anywhere in `test`
    /// (left-out pixels included) is an error naming the first such pixel.
    pub fn split(
        &self,
        test: &RgbImage,
        region_reference: &RgbImage,
        reference: &RgbImage,
    ) -> Result<RegionSplit, String> {
        if (test.width, test.height) != (self.width, self.height) {
            return Err(format!(
                "the render is {}×{} but the reference is {}×{}",
                test.width, test.height, self.width, self.height
            ));
        }
        let bad = test
            .rgb
            .iter()
            .filter(|p| p.iter().any(|v| !v.is_finite()))
            .count();
        if let Some(i) = test
            .rgb
            .iter()
            .position(|p| p.iter().any(|v| !v.is_finite()))
        {
            let w = self.width as usize;
            return Err(format!(
                "{bad} pixel(s) with a non-finite value, the first at ({}, {}): {:?}",
                i % w,
                i / w,
                test.rgb[i]
            ));
        }
        let mut out = RegionSplit::default();
        for (((r, t), f), g) in self
            .region
            .iter()
            .zip(&test.rgb)
            .zip(&region_reference.rgb)
            .zip(&reference.rgb)
        {
            let Some(r) = *r else { continue };
            out.sse[r] += (0..3).map(|c| (t[c] - f[c]) * (t[c] - f[c])).sum::<f64>();
            out.sum_diff[r] += (0..3).map(|c| t[c] - f[c]).sum::<f64>();
            out.sum_ref[r] += f.iter().sum::<f64>();
            out.values[r] += 3;
            out.total_sse += (0..3).map(|c| (t[c] - g[c]) * (t[c] - g[c])).sum::<f64>();
            out.total_sum_diff += (0..3).map(|c| t[c] - g[c]).sum::<f64>();
            out.total_sum_ref += g.iter().sum::<f64>();
        }
        Ok(out)
    }
}

/// The CPU the figures belong to: model name and the vector extensions the Linux kernel
/// reports (`/proc/cpuinfo`), and the logical CPU count; "unknown" elsewhere.
pub fn cpu_description() -> String {
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    cpu_description_from(&info)
}

/// [`cpu_description`] from the text of /proc/cpuinfo.
pub fn cpu_description_from(info: &str) -> String {
    let field = |name: &str| {
        info.lines()
            .find(|l| l.split(':').next().is_some_and(|k| k.trim() == name))
            .and_then(|l| l.split_once(':'))
            .map(|(_, v)| v.trim().to_string())
    };
    let model = field("model name").unwrap_or_else(|| "unknown CPU".into());
    let flags = field("flags")
        .or_else(|| field("Features"))
        .unwrap_or_default();
    const VECTOR: [&str; 9] = [
        "sse4_2", "avx", "avx2", "fma", "avx512f", "avx512bw", "avx512vl", "asimd", "sve",
    ];
    let have: Vec<&str> = VECTOR
        .iter()
        .copied()
        .filter(|v| flags.split_whitespace().any(|f| f == *v))
        .collect();
    let cpus = info.lines().filter(|l| l.starts_with("processor")).count();
    format!(
        "{model}; {cpus} logical CPU(s) visible; vector extensions: {}",
        if have.is_empty() {
            "none reported".to_string()
        } else {
            have.join(" ")
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    // Exact data on MSE = a/t + b are fitted exactly (a = 2, b = 0.01 at t = 1, 2, 4, 8;
    // 1e-9 relative: rounding). The floor is not significant once it is the reference's
    // variance, nor without that allowance, because 0.01 is under a tenth of the noise term at
    // the longest budget (a/t_max = 0.25): a floor too small to matter is not called a bias.
    #[test]
    fn fit_recovers_exact_parameters() {
        let pts: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0]
            .iter()
            .map(|&t| (t, 2.0 / t + 0.01))
            .collect();
        let f = fit_inverse_time(&pts, 0.0).unwrap();
        assert!((f.a - 2.0).abs() < 1e-9 * 2.0, "{f:?}");
        assert!((f.b - 0.01).abs() < 1e-9, "{f:?}");
        assert!(!f.biased(0.01));
        assert!(!f.biased(0.0));
        assert!((f.efficiency() - 0.5).abs() < 1e-9);
    }

    // Noisy unbiased data (relative noise ±10%, alternating) with a = 1, b = 0 at budgets 1..16
    // s, two runs each: the fitted floor is not significant, a is within 10%. A renderer with a
    // floor of 0.05 (a fifth of its noise at 4 s, 80% at 16 s) on the same noise is called
    // biased. The tolerances are the noise's size.
    #[test]
    fn floor_is_detected_only_when_present() {
        let mut unbiased = Vec::new();
        let mut biased = Vec::new();
        for (k, &t) in [1.0, 2.0, 4.0, 8.0, 16.0].iter().enumerate() {
            for s in [-1.0, 1.0] {
                let noise = 1.0 + 0.1 * s * if k % 2 == 0 { 1.0 } else { -1.0 };
                unbiased.push((t, noise / t));
                biased.push((t, noise * (1.0 / t + 0.05)));
            }
        }
        let f = fit_inverse_time(&unbiased, 0.0).unwrap();
        assert!((f.a - 1.0).abs() < 0.1, "{f:?}");
        assert!(!f.biased(0.0), "{f:?}");
        let g = fit_inverse_time(&biased, 0.0).unwrap();
        assert!(g.biased(0.0), "{g:?}");
        assert!((g.b - 0.05).abs() < 0.02, "{g:?}");
    }

    // Error falling faster than 1/t (MSE = 1/t^1.5 at 1..16 s, as a quasi-Monte Carlo sampler
    // can over a few budgets): the free fit's floor is negative, below the reference's noise
    // 1e-3, which no renderer can reach; the fit holds b there and fits a alone. Quantities:
    // the held b exactly, and a between the smallest and largest (MSE − b)·t of the points
    // (a weighted mean of them, so it must lie in their range), below the free fit's a (the
    // free fit books the fast fall as a larger a).
    #[test]
    fn floor_below_the_reference_noise_is_held_there() {
        let pts: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0, 16.0]
            .iter()
            .map(|&t: &f64| (t, 1e-3 + t.powf(-1.5)))
            .collect();
        let free = fit_inverse_time(&pts, f64::NEG_INFINITY).unwrap();
        assert!(free.b < 1e-3 && !free.floor_held, "{free:?}");
        let f = fit_inverse_time(&pts, 1e-3).unwrap();
        assert!(f.floor_held && f.b == 1e-3, "{f:?}");
        let scaled: Vec<f64> = pts.iter().map(|&(t, y)| (y - 1e-3) * t).collect();
        let (lo, hi) = scaled
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        assert!(
            f.a >= lo && f.a <= hi && f.a < free.a,
            "{f:?} {lo} {hi} {free:?}"
        );
        assert!(!f.biased(1e-3));
        // A free floor above the bound is left free.
        let g = fit_inverse_time(&pts, -1.0).unwrap();
        assert!(!g.floor_held && g == free, "{g:?}");
    }

    // The bias test's factor is Student's t at 0.975: 12.706 for one degree of freedom (three
    // budgets, one seed), 2.365 for seven (three seeds), 1.98 for 120 and more (table values,
    // exact); between listed values the smaller degrees of freedom's. A floor of 5 standard
    // errors is significant with seven degrees of freedom, not with one.
    #[test]
    fn floor_significance_follows_the_degrees_of_freedom() {
        assert_eq!(student_t_975(1), 12.706);
        assert_eq!(student_t_975(7), 2.365);
        assert_eq!(student_t_975(11), 2.228);
        assert_eq!(student_t_975(1000), 1.980);
        assert!(student_t_975(0).is_infinite());
        let fit = |n: usize| Fit {
            a: 1.0,
            se_a: 0.1,
            b: 0.5,
            se_b: 0.1,
            n,
            t_max: 1.0,
            floor_held: false,
        };
        assert!(!fit(3).biased(0.0));
        assert!(fit(9).biased(0.0));
    }

    // Degenerate input is refused: one distinct time, a zero or non-finite MSE.
    #[test]
    fn fit_refuses_degenerate_points() {
        assert!(fit_inverse_time(&[(1.0, 1.0), (1.0, 2.0)], 0.0).is_none());
        assert!(fit_inverse_time(&[(1.0, 0.0), (2.0, 1.0)], 0.0).is_none());
        assert!(fit_inverse_time(&[(1.0, f64::NAN), (2.0, 1.0)], 0.0).is_none());
    }

    // Regions on a 4×2 image: pixel 0 sees an emitter (left out), pixels 1 and 2 are bright
    // (> 4 × the median 0.1 of the counted luminances), 1 on a shiny surface (lamp image), 2 on
    // a diffuse one (caustic core); the others are the rest. A NaN in the render is an error
    // naming its pixel; the region MSEs are the sums of the squared differences per region.
    #[test]
    fn regions_and_non_finite_pixels() {
        let grey = |v: f64| [v; 3];
        let reference = RgbImage {
            width: 4,
            height: 2,
            rgb: vec![
                grey(9.0),
                grey(1.0),
                grey(2.0),
                grey(0.1),
                grey(0.1),
                grey(0.1),
                grey(0.1),
                grey(0.3),
            ],
        };
        let emitter = [true, false, false, false, false, false, false, false];
        let shiny = [false, true, false, true, false, false, false, false];
        let r = Regions::from_masks(&emitter, &shiny, &reference).unwrap();
        assert_eq!(r.pixels(), [1, 1, 5]);
        let mut test = reference.clone();
        test.rgb[1] = grey(1.5);
        test.rgb[7] = grey(0.2);
        let s = r.split(&test, &reference, &reference).unwrap();
        assert!((s.mse(0) - 0.25).abs() < 1e-12);
        assert_eq!(s.mse(1), 0.0);
        assert!((s.mse(2) - 0.01 / 5.0).abs() < 1e-12, "{s:?}");
        // The left-out pixel is still checked for finiteness.
        test.rgb[0] = [f64::NAN, 0.0, 0.0];
        let e = r.split(&test, &reference, &reference).unwrap_err();
        assert!(e.contains("(0, 0)") && e.contains("non-finite"), "{e}");
        test.rgb[0] = grey(9.0);
        test.rgb[6][2] = f64::INFINITY;
        let e = r.split(&test, &reference, &reference).unwrap_err();
        assert!(e.contains("(2, 1)"), "{e}");
    }

    // The mean check on synthetic renders of 10⁴ pixels around a reference of 1.0 with Gaussian
    // noise σ = 0.1 per value: unbiased renders give |z| ≲ 3 (z is a standard normal; a fixed
    // seed, so the test is exact), a 1% offset is 0.01/(0.1/√10⁴ /√2 renders) ≈ 14 standard errors
    // off, and the relative offset is reported as 1% within 0.2% (its standard error ~0.07%).
    #[test]
    fn mean_check_finds_an_offset_noise_hides() {
        let n = 10_000usize;
        let reference = RgbImage {
            width: n as u32,
            height: 1,
            rgb: vec![[1.0; 3]; n],
        };
        let r = Regions::from_masks(&vec![false; n], &vec![false; n], &reference).unwrap();
        let mut rng = crate::sampler::SampleRng::for_sample(5, 0, 0);
        let mut gauss = || {
            // Box–Muller.
            let (u, v) = (rng.next_1d().max(1e-7) as f64, rng.next_1d() as f64);
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        };
        let mut render = |offset: f64| {
            let mut t = reference.clone();
            for p in &mut t.rgb {
                let e = gauss();
                *p = [1.0 + offset + 0.1 * e; 3];
            }
            r.split(&t, &reference, &reference).unwrap()
        };
        let fair = [render(0.0), render(0.0)];
        let off = [render(0.01), render(0.01)];
        let m = mean_check(&[&fair[0], &fair[1]], None, 0.0).unwrap();
        assert!(m.within() && m.z.abs() < 3.0, "{m:?}");
        let m = mean_check(&[&off[0], &off[1]], Some(2), 0.0).unwrap();
        assert!(!m.within() && m.z > 10.0, "{m:?}");
        assert!((m.relative - 0.01).abs() < 0.002, "{m:?}");
        // A noisy reference widens the standard error: the same offset against a reference
        // with σ = 1 per value (its mean ±0.01) is no longer significant.
        let m = mean_check(&[&off[0], &off[1]], Some(2), 1.0).unwrap();
        assert!(m.within(), "{m:?}");
        assert_eq!(mean_check(&[&off[0]], Some(0), 0.0), None);
    }

    // Selection by the reference's own noise. Truth: 10⁴ dim pixels at 1 (the median), 4·10³
    // exactly at the bright threshold (4× the median) and 2·10³ well above it (10); eight
    // reference parts with Gaussian noise σ = 0.3 × the value per part; two unbiased renders
    // with σ = 0.1 × the value. Regions drawn from the full reference and compared with it put
    // into the caustic core the threshold pixels whose reference came out high: the renders
    // sit about 2% low there (6.6 standard errors, the reference's variance counted).
    // Drawn from the odd parts and compared with the even ones, the core's mean is within
    // 3 standard errors (a fixed seed: the test is exact).
    #[test]
    fn regions_drawn_from_the_compared_reference_bias_its_means() {
        let truth: Vec<f64> = (0..16_000)
            .map(|i| match i {
                0..10_000 => 1.0,
                10_000..14_000 => 4.0,
                _ => 10.0,
            })
            .collect();
        let n = truth.len();
        let mut rng = crate::sampler::SampleRng::for_sample(11, 0, 0);
        let mut gauss = || {
            let (u, v) = (rng.next_1d().max(1e-7) as f64, rng.next_1d() as f64);
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        };
        let mut noisy = |sigma: f64| RgbImage {
            width: n as u32,
            height: 1,
            rgb: truth
                .iter()
                .map(|&t| [t * (1.0 + sigma * gauss()); 3])
                .collect(),
        };
        let parts: Vec<RgbImage> = (0..8).map(|_| noisy(0.3)).collect();
        let renders = [noisy(0.1), noisy(0.1)];
        let halves = ReferenceHalves::new(&parts).unwrap();
        let full = mean_image(&parts.iter().collect::<Vec<_>>());
        let no = vec![false; n];
        let everything = vec![true; n];
        let core_check = |regions_from: &RgbImage, compared: &RgbImage, var_factor: f64| {
            let r = Regions::from_masks(&no, &no, regions_from).unwrap();
            let mask: Vec<bool> = r.region.iter().map(|x| *x == Some(1)).collect();
            let splits: Vec<RegionSplit> = renders
                .iter()
                .map(|t| r.split(t, compared, &full).unwrap())
                .collect();
            let ref_var = reference_variance(&parts, &mask) * var_factor;
            mean_check(&[&splits[0], &splits[1]], Some(1), ref_var).unwrap()
        };
        let same = core_check(&full, &full, 1.0);
        assert!(same.z < -5.0 && same.relative < -0.01, "{same:?}");
        let split = core_check(
            &halves.regions_from,
            &halves.compared,
            halves.compared_variance_factor,
        );
        assert!(split.z.abs() < 3.0, "{split:?}");
        assert!(reference_variance(&parts, &everything) > 0.0);
        assert_eq!(halves.compared_variance_factor, 2.0);
        assert!(ReferenceHalves::new(&parts[..1]).is_err());
        let mut odd_size = parts.clone();
        odd_size[5].width -= 1;
        let e = ReferenceHalves::new(&odd_size).unwrap_err();
        assert!(e.contains("part 6"), "{e}");
    }

    // Two halves differing by ±d per value: MSE between them 4d², so the full reference's
    // variance is d² (exact); four parts alternating between the same two values: the
    // variance of a mean of four.
    #[test]
    fn reference_variance_from_halves() {
        let a = RgbImage {
            width: 2,
            height: 1,
            rgb: vec![[1.0; 3], [2.0; 3]],
        };
        let b = RgbImage {
            width: 2,
            height: 1,
            rgb: vec![[1.2; 3], [1.8; 3]],
        };
        let v = reference_variance(&[a.clone(), b.clone()], &[true, true]);
        assert!((v - 0.01).abs() < 1e-12, "{v}");
        // Four parts 1, 1.2, 1 and 1.2 (mean 1.1): Σ (x − m)² = 4·0.01, over K(K − 1) = 12,
        // so 1/300 per value; the second pixel's 2, 1.8, 2, 1.8 the same (exact).
        let v = reference_variance(&[a.clone(), b.clone(), a, b], &[true, true]);
        assert!((v - 0.04 / 12.0).abs() < 1e-12, "{v}");
    }

    // The CPU line names the model and the vector extensions present, not those absent.
    #[test]
    fn cpu_line_from_cpuinfo() {
        let info = "processor\t: 0\nmodel name\t: Test CPU 9000\nflags\t\t: fpu sse4_2 avx avx2 fma\n\
                    processor\t: 1\nmodel name\t: Test CPU 9000\nflags\t\t: fpu sse4_2 avx avx2 fma\n";
        let s = cpu_description_from(info);
        assert!(
            s.contains("Test CPU 9000") && s.contains("avx2") && s.contains("2 logical"),
            "{s}"
        );
        assert!(!s.contains("avx512"), "{s}");
    }
}
