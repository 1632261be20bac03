//! `glare_observer`: discomfort glare as the Unified Glare Rating (UGR, CIE 117-1995) seen
//! from an eye position in a view direction, computed from a rendered fisheye luminance image.
//!
//! ```ron
//! sensors: [(name: "desk", type: "glare_observer",
//!            params: (position: (1.5, 1.2, 2), direction: (0, 0, -1), resolution: 256))]
//! ```
//!
//! | parameter          | unit        | default          | meaning                                        |
//! |--------------------|-------------|------------------|------------------------------------------------|
//! | `position`         | scene units | —                | the eye, (x, y, z)                             |
//! | `direction`        | —           | —                | line of sight, non-zero                        |
//! | `up`               | —           | (0, 1, 0)        | the vertical (for the position index); not parallel to `direction` |
//! | `resolution`       | pixels      | 256              | side of the square fisheye image, 16–4096      |
//! | `samples`          | per pixel   | the render's spp | path-traced samples per pixel                  |
//! | `source_threshold` | cd/m²       | 5 × mean         | pixels brighter than this are glare sources    |
//!
//! # Method
//! The hemisphere in front of the eye is rendered as an equidistant (angular) fisheye
//! (radius ∝ angle from the line of sight, 180°): each pixel's luminance is the path tracer's
//! radiance along jittered rays through it, converted with 683 lm/W · V(λ). Pixel solid angle
//! `ω = (π/2)² · sin θ / θ · Δx Δy` (Δ in units of the image radius). Pixels above
//! `source_threshold` (default: 5 × the image's mean luminance, evalglare's default rule) are
//! the glare sources. Then, per CIE 117,
//!
//! ```text
//! UGR = 8 log10( 0.25 / L_b · Σ L² ω / p² )
//! ```
//!
//! with the sum over source pixels, `L_b = E_ind / π` the background luminance from the
//! vertical illuminance at the eye of all non-source pixels (`Σ L cos θ ω`), and `p` Guth's
//! position index in the closed form fitted to the Luckiesh–Guth table,
//! `p = exp[(35.2 − 0.31889 τ − 1.22 e^(−2τ/9))·10⁻³ σ + (21 + 0.26667 τ − 0.002963 τ²)·10⁻⁵ σ²]`
//! (τ: angle from the vertical of the plane through the line of sight and the source, σ: angle
//! between the line of sight and the source, degrees), evaluated per pixel.
//!
//! # Limits
//! UGR is defined for luminaires of 0.0003–0.1 sr above the line of sight against a uniform
//! background; the sum here also takes sources below the line of sight with the same index,
//! and windows or the sun in view (for which daylight glare probability is the measure) are
//! reported like any other source. Values are Monte Carlo estimates: the standard error is
//! propagated from the pixels' sample variance (see [`GlareReading`]).

use glam::DVec3;
use serde::Deserialize;
use std::f64::consts::FRAC_PI_2;

/// The scene item type name.
pub const TYPE_NAME: &str = "glare_observer";

/// Parameters as written.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlareParams {
    /// Eye position.
    pub position: [f64; 3],
    /// Line of sight.
    pub direction: [f64; 3],
    /// Vertical.
    #[serde(default)]
    pub up: Option<[f64; 3]>,
    /// Image side, pixels.
    #[serde(default)]
    pub resolution: Option<u32>,
    /// Samples per pixel.
    #[serde(default)]
    pub samples: Option<u32>,
    /// Source threshold, cd/m².
    #[serde(default)]
    pub source_threshold: Option<f64>,
}

/// A built glare observer (position in metres).
#[derive(Clone, Debug, PartialEq)]
pub struct GlareObserver {
    /// Unique name (output file stem).
    pub name: String,
    /// Eye position, m.
    pub position: DVec3,
    /// Unit line of sight.
    pub view: DVec3,
    /// Unit vertical, perpendicular to `view`.
    pub up: DVec3,
    /// Image side.
    pub resolution: u32,
    /// Samples per pixel when fixed.
    pub samples: Option<u32>,
    /// Source threshold, cd/m² (None: 5 × mean).
    pub source_threshold: Option<f64>,
}

impl GlareObserver {
    /// Check and build from parameters; errors name the parameter.
    pub fn from_params(name: &str, params: &ron::Value) -> Result<Self, String> {
        let p: GlareParams =
            crate::builtin::from_value(params).map_err(|e| format!("parameters: {e}"))?;
        let fin = |k: &str, v: [f64; 3]| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(DVec3::from_array(v))
            } else {
                Err(format!("parameter `{k}` must be finite, got {v:?}"))
            }
        };
        let position = fin("position", p.position)?;
        let view = fin("direction", p.direction)?;
        if view.length() == 0.0 {
            return Err("parameter `direction` must be non-zero".into());
        }
        let view = view.normalize();
        let up = fin("up", p.up.unwrap_or([0.0, 1.0, 0.0]))?;
        let up = up - view * up.dot(view);
        if !(up.length() > 1e-6) {
            return Err(
                "parameter `up` must not be parallel to `direction` (the position index needs the vertical)"
                    .into(),
            );
        }
        let resolution = p.resolution.unwrap_or(256);
        if !(16..=4096).contains(&resolution) {
            return Err(format!(
                "parameter `resolution` {resolution}: must be 16–4096 pixels"
            ));
        }
        if let Some(s) = p.samples {
            if s == 0 || s > super::limits::MAX_SAMPLES {
                return Err(format!(
                    "parameter `samples` {s}: must be 1–{}",
                    super::limits::MAX_SAMPLES
                ));
            }
        }
        if let Some(t) = p.source_threshold {
            if !(t.is_finite() && t > 0.0) {
                return Err(format!(
                    "parameter `source_threshold` {t}: must be > 0 cd/m²"
                ));
            }
        }
        Ok(Self {
            name: name.to_string(),
            position,
            view,
            up: up.normalize(),
            resolution,
            samples: p.samples,
            source_threshold: p.source_threshold,
        })
    }

    /// The unit direction of image point (x, y) ∈ [−1, 1]² (x right, y up) and its angle θ
    /// from the line of sight; `None` outside the image circle.
    pub fn direction(&self, x: f64, y: f64) -> Option<(DVec3, f64)> {
        let r = (x * x + y * y).sqrt();
        if r > 1.0 {
            return None;
        }
        let theta = r * FRAC_PI_2;
        let right = self.view.cross(self.up);
        let (c, s) = if r > 0.0 { (x / r, y / r) } else { (0.0, 0.0) };
        let d = self.view * theta.cos() + (right * c + self.up * s) * theta.sin();
        Some((d.normalize(), theta))
    }

    /// Solid angle (sr) of the pixel centred at (x, y) of side `dx` (image-radius units).
    pub fn pixel_solid_angle(theta: f64, dx: f64) -> f64 {
        let sinc = if theta > 1e-9 {
            theta.sin() / theta
        } else {
            1.0
        };
        FRAC_PI_2 * FRAC_PI_2 * sinc * dx * dx
    }

    /// Guth's position index of unit direction `d` (see the module docs).
    pub fn position_index(&self, d: DVec3) -> f64 {
        let right = self.view.cross(self.up);
        let sigma = d.dot(self.view).clamp(-1.0, 1.0).acos().to_degrees();
        let (v, h) = (d.dot(self.up), d.dot(right));
        let tau = if v == 0.0 && h == 0.0 {
            0.0
        } else {
            h.abs().atan2(v.abs()).to_degrees()
        };
        guth_position_index(tau, sigma)
    }
}

/// Guth's position index from τ and σ in degrees (the closed form of the module docs).
pub fn guth_position_index(tau: f64, sigma: f64) -> f64 {
    ((35.2 - 0.31889 * tau - 1.22 * (-2.0 * tau / 9.0).exp()) * 1e-3 * sigma
        + (21.0 + 0.26667 * tau - 0.002963 * tau * tau) * 1e-5 * sigma * sigma)
        .exp()
}

/// Build the scene's `glare_observer` sensor items (other types are left to
/// [`super::grid::build_sensors`]), positions converted to metres; names must be unique among all
/// sensors. An error names the item.
pub fn build_glare_observers(
    items: &[crate::scene_file::description::ItemDescription],
    metres: f64,
) -> Result<Vec<GlareObserver>, (String, String)> {
    let mut out: Vec<GlareObserver> = Vec::new();
    for it in items.iter().filter(|it| it.type_name == TYPE_NAME) {
        let item = format!("sensor {:?}", it.name);
        if it.name.is_empty()
            || it
                .name
                .chars()
                .any(|c| !(c.is_alphanumeric() || c == '_' || c == '-' || c == '.'))
        {
            return Err((
                item,
                "a sensor name is also its output file name: use letters, digits, `_`, `-` and `.` only".into(),
            ));
        }
        if items.iter().filter(|o| o.name == it.name).count() > 1 {
            return Err((item, "duplicate sensor name".into()));
        }
        let mut g = GlareObserver::from_params(&it.name, &it.params).map_err(|e| (item, e))?;
        g.position *= metres;
        out.push(g);
    }
    Ok(out)
}
