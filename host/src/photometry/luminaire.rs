//! A measured luminaire: a candela table in photometric angles, its symmetry and the header
//! facts (lamps, multipliers, rated lumens) of the file it came from, independent of the file
//! format. A light type wraps it (with an SPD for the spectral side) to emit with this
//! distribution; [`super::DirectionSampler`] importance-samples it.
//!
//! ## Angles and the luminaire frame
//! The table is kept in the file's own angles, in degrees: `h` the "horizontal" angle and `v`
//! the "vertical" angle of LM-63 (C and γ for EULUMDAT). Directions use the scene's right-handed,
//! y-up frame with the luminaire unrotated (a light type rotates directions into this frame):
//! - **Type C** (polar axis vertical; architectural and road lighting, all EULUMDAT):
//!   γ = `v` from the nadir (−y, γ = 0) to the zenith (+y, γ = 180); C = `h` counter-clockwise
//!   seen from above, C0 along +x, C90 along −z:
//!   `d = (sin γ cos C, −cos γ, −sin γ sin C)`.
//! - **Type B** (polar axis horizontal, the luminaire's width, along x; floodlights): the
//!   photometric axis (`h` = `v` = 0) points down (−y); `v` tilts the measuring plane about the
//!   x axis, `h` is the angle in that plane, `h` = ±90 at ±x:
//!   `d = (sin h, −cos h cos v, −cos h sin v)`.
//! - **Type A** (polar axis along z; automotive): photometric axis −y; `h` turns about the z axis,
//!   `v` is the elevation towards −z, `v` = ±90 at ∓z:
//!   `d = (cos v sin h, −cos v cos h, −sin v)`.
//!
//! ## Values
//! `candela` holds the file's values with every multiplier that applies already applied, so
//! [`Luminaire::intensity_cd`] is in candela for the lamps as rated (relative photometry) or as
//! measured (absolute photometry). [`Luminaire::flux_lm`] integrates the table over the sphere.

use std::f64::consts::PI;

/// The format and version a luminaire was read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SourceFormat {
    /// IES LM-63 with the version its first line states (1986 when it states none).
    Ies(IesVersion),
    /// EULUMDAT (`.ldt`).
    Eulumdat,
    /// A table written out in a scene or blob ([`super::CandelaTable`]), or measured from a
    /// light ([`crate::light::measure::goniometer`]).
    Table,
}

/// LM-63 header versions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IesVersion {
    /// LM-63-1986: no version line.
    Lm63_1986,
    /// LM-63-1991: `IESNA91`.
    Lm63_1991,
    /// LM-63-1995: `IESNA:LM-63-1995` (also the non-standard `IESNA95`).
    Lm63_1995,
    /// LM-63-2002: `IESNA:LM-63-2002`.
    Lm63_2002,
    /// LM-63-2019: `IES:LM-63-2019`.
    Lm63_2019,
}

impl SourceFormat {
    /// A short name: `IES LM-63-1995`, `EULUMDAT`.
    pub fn name(self) -> &'static str {
        match self {
            SourceFormat::Ies(IesVersion::Lm63_1986) => "IES LM-63-1986",
            SourceFormat::Ies(IesVersion::Lm63_1991) => "IES LM-63-1991",
            SourceFormat::Ies(IesVersion::Lm63_1995) => "IES LM-63-1995",
            SourceFormat::Ies(IesVersion::Lm63_2002) => "IES LM-63-2002",
            SourceFormat::Ies(IesVersion::Lm63_2019) => "IES LM-63-2019",
            SourceFormat::Eulumdat => "EULUMDAT",
            SourceFormat::Table => "candela table",
        }
    }
}

/// Photometric type: where the polar axis of the angle grid lies (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhotometricType {
    /// Polar axis along z (automotive).
    A,
    /// Polar axis horizontal along x (floodlights).
    B,
    /// Polar axis vertical (y).
    C,
}

/// Which part of the distribution the table stores; the rest follows by symmetry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Symmetry {
    /// Every `h` stored (type C: 0..360; types A and B: −90..90).
    None,
    /// Type C, one plane: the same in every C-plane.
    Axial,
    /// Type C, C0..C90: mirror symmetric about the C0–C180 and the C90–C270 planes.
    Quadrant,
    /// Type C, C0..C180: mirror symmetric about the C0–C180 plane.
    BilateralC0C180,
    /// Type C, C90..C270: mirror symmetric about the C90–C270 plane.
    BilateralC90C270,
    /// Types A and B, `h` 0..90: mirror symmetric about `h` = 0.
    LateralH,
}

impl Symmetry {
    /// A short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Symmetry::None => "none",
            Symmetry::Axial => "axial",
            Symmetry::Quadrant => "quadrant",
            Symmetry::BilateralC0C180 => "bilateral (C0-C180 plane)",
            Symmetry::BilateralC90C270 => "bilateral (C90-C270 plane)",
            Symmetry::LateralH => "lateral (h = 0 plane)",
        }
    }
}

/// One set of lamps as the file states it.
#[derive(Clone, Debug, PartialEq)]
pub struct LampSet {
    /// Number of lamps (EULUMDAT absolute photometry stores it negative; kept as read).
    pub count: i64,
    /// Lumens per lamp (IES) or total lamp lumens of the set (EULUMDAT), `None` for absolute
    /// photometry in IES (lumens −1).
    pub lumens: Option<f64>,
    /// Lamp description (IES `[LAMP]` keyword or EULUMDAT lamp type), may be empty.
    pub description: String,
    /// Input power in W (IES input watts or EULUMDAT wattage including ballast), if stated.
    pub watts: Option<f64>,
}

/// A factor from the file and whether it scales the candela values.
#[derive(Clone, Debug, PartialEq)]
pub struct Multiplier {
    /// What the file calls it.
    pub name: &'static str,
    /// The value read.
    pub value: f64,
    /// Whether the stored candela values include it.
    pub applied: bool,
}

/// A lamp tilt table (LM-63 `TILT=INCLUDE` or `TILT=<file>`): factors that scale the
/// candela values when the lamp is tilted by an angle from its measured orientation.
#[derive(Clone, Debug, PartialEq)]
pub struct TiltTable {
    /// Lamp-to-luminaire geometry: 1 vertical base-up/down, 2 horizontal lamp along 0°, 3 along 90°.
    pub geometry: i64,
    /// Tilt angles in degrees.
    pub angles_deg: Vec<f64>,
    /// Multiplying factors at those angles.
    pub factors: Vec<f64>,
    /// Where the table came from: `INCLUDE` or the tilt file's path.
    pub source: String,
}

impl TiltTable {
    /// The multiplying factor for a lamp tilted by `angle_deg` from its measured orientation:
    /// linear between the table's angles (sorted first: files list them ascending, but nothing
    /// checks it), the end value beyond either end (the table says nothing there; the nearest
    /// measured factor is the best guess). 1 for an empty table.
    pub fn factor_at(&self, angle_deg: f64) -> f64 {
        let mut pairs: Vec<(f64, f64)> = self
            .angles_deg
            .iter()
            .copied()
            .zip(self.factors.iter().copied())
            .collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (Some(first), Some(last)) = (pairs.first(), pairs.last()) else {
            return 1.0;
        };
        if angle_deg <= first.0 {
            return first.1;
        }
        if angle_deg >= last.0 {
            return last.1;
        }
        let i = pairs
            .partition_point(|p| p.0 <= angle_deg)
            .clamp(1, pairs.len() - 1);
        let ((a0, f0), (a1, f1)) = (pairs[i - 1], pairs[i]);
        if a1 > a0 {
            f0 + (f1 - f0) * (angle_deg - a0) / (a1 - a0)
        } else {
            f1
        }
    }
}

/// A measured luminaire: see the module docs for angles and frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Luminaire {
    /// Format and version read.
    pub format: SourceFormat,
    /// Photometric type.
    pub photometric_type: PhotometricType,
    /// Symmetry of the stored table.
    pub symmetry: Symmetry,
    /// Stored `h` angles in degrees, ascending.
    pub h_deg: Vec<f64>,
    /// Stored `v` angles in degrees, ascending.
    pub v_deg: Vec<f64>,
    /// Candela, `candela[ih * v_deg.len() + iv]`, every applied multiplier included.
    pub candela: Vec<f64>,
    /// Lamp sets as stated.
    pub lamps: Vec<LampSet>,
    /// Multipliers read, with whether each scales the table.
    pub multipliers: Vec<Multiplier>,
    /// Absolute photometry: the table is the luminaire as measured, not per rated lamp lumens.
    pub absolute: bool,
    /// Rated lamp lumens (all lamps) the relative table refers to; `None` for absolute photometry.
    pub rated_lamp_lumens: Option<f64>,
    /// Luminaire (luminous opening) size in m: width, length, height as the file gives them.
    pub size_m: [f64; 3],
    /// Lamp tilt table, if the file has one.
    pub tilt: Option<TiltTable>,
    /// Descriptive header lines (`KEY value` or free text), in file order.
    pub header: Vec<String>,
    /// Things that are legal but probably not what the file's author meant.
    pub warnings: Vec<String>,
}

/// Tolerance (degrees) for matching angles: files print angles with 2 to 4 decimals.
const ANGLE_EPS: f64 = 1e-6;

impl Luminaire {
    /// Candela at index (`ih`, `iv`) of the stored table.
    pub fn stored_cd(&self, ih: usize, iv: usize) -> f64 {
        self.candela[ih * self.v_deg.len() + iv]
    }

    /// Candela at file angles `h`, `v` (degrees): folded into the stored range by the
    /// symmetry, then bilinear in the stored angles. Zero outside the measured `v` range (and
    /// outside the `h` range for types A and B): the file says nothing is emitted there.
    pub fn candela_at(&self, h: f64, v: f64) -> f64 {
        let Some(h) = self.fold_h(h) else {
            return 0.0;
        };
        let Some((iv, tv)) = segment(&self.v_deg, v) else {
            return 0.0;
        };
        let row = |ih: usize| {
            let a = self.stored_cd(ih, iv);
            if tv == 0.0 {
                a
            } else {
                a + (self.stored_cd(ih, iv + 1) - a) * tv
            }
        };
        if self.h_deg.len() == 1 {
            return row(0);
        }
        if self.symmetry == Symmetry::None && self.photometric_type == PhotometricType::C {
            // Periodic in C: between the last stored plane and the first + 360.
            let last = self.h_deg.len() - 1;
            if h > self.h_deg[last] + ANGLE_EPS {
                let span = self.h_deg[0] + 360.0 - self.h_deg[last];
                let t = (h - self.h_deg[last]) / span;
                return row(last) + (row(0) - row(last)) * t;
            }
        }
        match segment(&self.h_deg, h) {
            Some((ih, 0.0)) => row(ih),
            Some((ih, th)) => row(ih) + (row(ih + 1) - row(ih)) * th,
            None => 0.0,
        }
    }

    /// Candela towards `direction` (unit vector, luminaire frame of the module docs).
    pub fn intensity_cd(&self, direction: [f64; 3]) -> f64 {
        let (h, v) = self.angles_of(direction);
        self.candela_at(h, v)
    }

    /// File angles (`h`, `v`) in degrees of a unit direction in the luminaire frame.
    pub fn angles_of(&self, d: [f64; 3]) -> (f64, f64) {
        let [x, y, z] = d;
        match self.photometric_type {
            PhotometricType::C => {
                let gamma = (-y).clamp(-1.0, 1.0).acos().to_degrees();
                let c = atan2_deg(-z, x).rem_euclid(360.0);
                (c, gamma)
            }
            PhotometricType::B => {
                let h = x.clamp(-1.0, 1.0).asin().to_degrees();
                let v = atan2_deg(-z, -y);
                (h, v)
            }
            PhotometricType::A => {
                let v = (-z).clamp(-1.0, 1.0).asin().to_degrees();
                let h = atan2_deg(x, -y);
                (h, v)
            }
        }
    }

    /// Unit direction in the luminaire frame of file angles `h`, `v` in degrees.
    pub fn direction_of(&self, h: f64, v: f64) -> [f64; 3] {
        let (h, v) = (h.to_radians(), v.to_radians());
        match self.photometric_type {
            PhotometricType::C => [v.sin() * h.cos(), -v.cos(), -v.sin() * h.sin()],
            PhotometricType::B => [h.sin(), -h.cos() * v.cos(), -h.cos() * v.sin()],
            PhotometricType::A => [v.cos() * h.sin(), -v.cos() * h.cos(), -v.sin()],
        }
    }

    /// Fold `h` (degrees) into the stored range by the symmetry; `None` where nothing is stored.
    fn fold_h(&self, h: f64) -> Option<f64> {
        match self.photometric_type {
            PhotometricType::C => {
                let mut c = h.rem_euclid(360.0);
                if c > 360.0 - ANGLE_EPS {
                    c = 0.0;
                }
                Some(match self.symmetry {
                    Symmetry::Axial => self.h_deg[0],
                    Symmetry::Quadrant => {
                        let c = if c > 180.0 { 360.0 - c } else { c };
                        if c > 90.0 {
                            180.0 - c
                        } else {
                            c
                        }
                    }
                    Symmetry::BilateralC0C180 => {
                        if c > 180.0 {
                            360.0 - c
                        } else {
                            c
                        }
                    }
                    Symmetry::BilateralC90C270 => {
                        if c < 90.0 {
                            180.0 - c
                        } else if c > 270.0 {
                            540.0 - c
                        } else {
                            c
                        }
                    }
                    Symmetry::None | Symmetry::LateralH => {
                        // Stored planes may start above 0 (rare): shift into [first, first+360).
                        let first = self.h_deg[0];
                        if c < first - ANGLE_EPS {
                            c + 360.0
                        } else {
                            c
                        }
                    }
                })
            }
            PhotometricType::A | PhotometricType::B => match self.symmetry {
                Symmetry::LateralH => Some(h.abs()),
                _ => Some(h),
            },
        }
    }

    /// The `h` angles of the whole distribution (the stored ones and their mirror images),
    /// ascending. Type C: in [0, 360), periodic; types A and B: the full measured range.
    pub fn expanded_h_deg(&self) -> Vec<f64> {
        let s = &self.h_deg;
        let mut all: Vec<f64> = match (self.photometric_type, self.symmetry) {
            (PhotometricType::C, Symmetry::Axial) => vec![0.0],
            (PhotometricType::C, Symmetry::Quadrant) => s
                .iter()
                .flat_map(|&a| [a, 180.0 - a, 180.0 + a, 360.0 - a])
                .collect(),
            (PhotometricType::C, Symmetry::BilateralC0C180) => {
                s.iter().flat_map(|&a| [a, 360.0 - a]).collect()
            }
            (PhotometricType::C, Symmetry::BilateralC90C270) => {
                s.iter().flat_map(|&a| [a, 180.0 - a]).collect()
            }
            (PhotometricType::C, _) => s.clone(),
            (_, Symmetry::LateralH) => s.iter().flat_map(|&a| [a, -a]).collect(),
            (_, _) => s.clone(),
        };
        if self.photometric_type == PhotometricType::C {
            for a in &mut all {
                *a = a.rem_euclid(360.0);
                if *a > 360.0 - ANGLE_EPS {
                    *a = 0.0;
                }
            }
        }
        all.sort_by(f64::total_cmp);
        all.dedup_by(|a, b| (*a - *b).abs() < ANGLE_EPS);
        all
    }

    /// Total luminous flux in lm: the table expanded by its symmetry and integrated over the
    /// sphere with the trapezoid rule in both angles (type C: ∫∫ I sin γ dγ dC, periodic in C;
    /// type A: ∫∫ I cos v dv dh; type B: ∫∫ I cos h dh dv). Zero outside the measured range.
    pub fn flux_lm(&self) -> f64 {
        let hs = self.expanded_h_deg();
        let vs = &self.v_deg;
        // Weight of each v sample (trapezoid) times the Jacobian of v where v is the latitude-like angle.
        let trapezoid_weights = |xs: &[f64]| -> Vec<f64> {
            let mut w = vec![0.0; xs.len()];
            for i in 1..xs.len() {
                let d = (xs[i] - xs[i - 1]).to_radians() * 0.5;
                w[i - 1] += d;
                w[i] += d;
            }
            w
        };
        match self.photometric_type {
            PhotometricType::C => {
                let wv = trapezoid_weights(vs);
                // Periodic trapezoid weights in C (radians); one plane means axial: 2π.
                let n = hs.len();
                let mut wh = vec![0.0; n];
                if n == 1 {
                    wh[0] = 2.0 * PI;
                } else {
                    for i in 0..n {
                        let next = if i + 1 < n { hs[i + 1] } else { hs[0] + 360.0 };
                        let d = (next - hs[i]).to_radians() * 0.5;
                        wh[i] += d;
                        wh[(i + 1) % n] += d;
                    }
                }
                let mut sum = 0.0;
                for (i, &h) in hs.iter().enumerate() {
                    for (j, &v) in vs.iter().enumerate() {
                        sum += wh[i] * wv[j] * v.to_radians().sin() * self.candela_at(h, v);
                    }
                }
                sum
            }
            PhotometricType::A => {
                let wh = trapezoid_weights(&hs);
                let wv = trapezoid_weights(vs);
                let mut sum = 0.0;
                for (i, &h) in hs.iter().enumerate() {
                    for (j, &v) in vs.iter().enumerate() {
                        sum += wh[i] * wv[j] * v.to_radians().cos() * self.candela_at(h, v);
                    }
                }
                sum
            }
            PhotometricType::B => {
                let wh = trapezoid_weights(&hs);
                let wv = trapezoid_weights(vs);
                let mut sum = 0.0;
                for (i, &h) in hs.iter().enumerate() {
                    for (j, &v) in vs.iter().enumerate() {
                        sum += wh[i] * wv[j] * h.to_radians().cos() * self.candela_at(h, v);
                    }
                }
                sum
            }
        }
    }

    /// The same luminaire with every candela value multiplied by `factor` (a lamp tilt factor,
    /// a user multiplier or a flux override).
    pub fn scaled(&self, factor: f64) -> Luminaire {
        let mut out = self.clone();
        for c in &mut out.candela {
            *c *= factor;
        }
        out
    }

    /// Largest candela value of the table.
    pub fn max_cd(&self) -> f64 {
        self.candela.iter().copied().fold(0.0, f64::max)
    }
}

/// atan2 in degrees with −0 read as +0, so that a pole (both arguments zero) gives 0, not ±180.
fn atan2_deg(y: f64, x: f64) -> f64 {
    (y + 0.0).atan2(x + 0.0).to_degrees()
}

/// The segment of ascending `xs` holding `x`: index `i` and fraction `t` in [0, 1) of the way
/// to `xs[i + 1]` (`t` = 0 at an exact sample, including the last). `None` outside.
pub(crate) fn segment(xs: &[f64], x: f64) -> Option<(usize, f64)> {
    let n = xs.len();
    if n == 0 || x < xs[0] - ANGLE_EPS || x > xs[n - 1] + ANGLE_EPS {
        return None;
    }
    if n == 1 {
        return Some((0, 0.0));
    }
    // First index with xs[i] > x, minus one.
    let i = xs.partition_point(|&a| a <= x).clamp(1, n) - 1;
    if i == n - 1 || (x - xs[i]).abs() < ANGLE_EPS {
        return Some((i, 0.0));
    }
    if (xs[i + 1] - x).abs() < ANGLE_EPS {
        return Some((i + 1, 0.0));
    }
    Some((i, (x - xs[i]) / (xs[i + 1] - xs[i])))
}
