//! Deterministic seed chains for specular-chain solves whose straight segment gives no seed
//! (`integrator::connect::specular_chain::seed_chain` covers only refractions the segment `x0 → y`
//! crosses): a reflection off a glass ball or a mirror, and the lamp seen *through* a ball
//! from a point beside it. Each smooth specular object gets a few seeds from its shape alone:
//!
//! - **Round shapes** (spheres exactly; meshes through their bounding sphere): the
//!   *reflection* seed at the point whose normal bisects the directions to `x0` and `y` (the
//!   specular point of a convex mirror, found by a few fixed-point steps); for transmitting
//!   materials also seeds of the chains *through* it, `T T`, `T R T` and `T R R T` (in, zero to
//!   two internal reflections, out): a ray refracted or reflected by a sphere stays in the plane
//!   of `x0`, the centre `o` and `y`, so every such solution is aimed at a point `o + b·r·u`,
//!   `u` across the view towards `y`'s side, `b` in (−1, 1). A scan traces [`SCAN_POINTS`] rays
//!   per lobe sequence across `b` and seeds where the signed angle between the leaving direction
//!   and the direction to `y` changes sign (measured on the caustic scene's ball: the lamp's
//!   images are the reflection and `T R R T`, both at b ≈ 0.75; `T T` cannot turn a ray from
//!   the camera up to the lamp, its deviation stays under 97°).
//! - **Closed-form `T T` seeds** ([`SpecularShapes::for_each_through_seed`], for the
//!   connection from a diffuse vertex, run at every sample): the same in-plane idea without
//!   tracing rays: the two refractions of a circle are followed in closed form at
//!   [`THROUGH_POINTS`] impact parameters, each sign change narrowed by bisection, and a fold
//!   of the map (two solutions within one step, where the caustic is brightest) found by a
//!   golden-section search for the smallest angle between two neighbours of one sign.
//! - **Quads** (mirrors and glass panes): the reflection seed aimed at `y` mirrored in the
//!   quad's plane (exact for a flat mirror).
//!
//! Not seeded: chains through two or more objects, more than one internal reflection, rough
//! surfaces. Different seeds may converge to the same solution; the caller keeps each
//! solution once ([`SolutionSet`]), so a path is counted once whichever seed found it. The set
//! is a deterministic function of `(x0, y)` and the wavelengths, which is what lets the MIS
//! weight of another strategy ask "would the solve from this path's `(x0, y)` find this path".
//!
//! | constant                | value                     | meaning                                  |
//! |-------------------------|---------------------------|------------------------------------------|
//! | `SCAN_POINTS`           | 32                        | scan rays per lobe sequence and shape    |
//! | `MAX_SHAPES`            | 8                         | smooth specular objects seeded at most   |
//! | `BISECTOR_STEPS`        | 12                        | fixed-point steps of the reflection seed |
//! | `THROUGH_POINTS`        | 32                        | closed-form `T T` impact parameters      |
//! | `THROUGH_BISECTIONS`    | 10                        | bisection steps per sign change          |
//! | `FOLD_STEPS`            | 12                        | golden-section steps at a fold           |

use crate::geometry::WorldShape;
use crate::integrator::connect::specular_chain::{
    same_chain, solve, trace_chain, Chain, Endpoint, Lobe, Solved, MAX_CHAIN_VERTICES,
};
use crate::material::{MaterialFlags, ShadingContext, TransportMode};
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use glam::{Vec2, Vec3A};

/// Smooth specular objects seeded at most (a scene with more seeds only the first ones).
pub const MAX_SHAPES: usize = 8;
/// Rays per lobe sequence of the scan across a transmitting round shape.
pub const SCAN_POINTS: usize = 32;
/// Impact parameters of the closed-form `T T` scan through a round shape (no rays traced).
pub const THROUGH_POINTS: usize = 32;
/// Bisection steps narrowing each sign change of that scan before the solve.
pub const THROUGH_BISECTIONS: usize = 10;
/// Golden-section steps searching a fold of that scan (two roots within one step).
pub const FOLD_STEPS: usize = 12;
/// Fixed-point steps of the reflection seed on a round shape.
pub const BISECTOR_STEPS: usize = 12;

/// The geometry a seed is made from.
#[derive(Clone, Copy, Debug)]
enum SeedShape {
    /// A sphere, or a mesh's bounding sphere: centre and radius (scene units).
    Round { center: Vec3A, radius: f32 },
    /// A planar quad: a point of it and its unit normal.
    Plane { point: Vec3A, normal: Vec3A },
}

/// One smooth specular object and its seed geometry.
#[derive(Clone, Copy, Debug)]
struct Seeded {
    object: u32,
    transmits: bool,
    shape: SeedShape,
}

/// The smooth specular objects of a scene with their seed geometry, found once per render.
#[derive(Clone, Debug, Default)]
pub struct SpecularShapes {
    shapes: Vec<Seeded>,
}

impl SpecularShapes {
    /// The scene's objects whose material scatters only by delta lobes (not emissive), at most
    /// [`MAX_SHAPES`] of them.
    pub fn new(scene: &Scene) -> Self {
        let mut shapes = Vec::new();
        for object in 0..scene.geometry.object_count() as u32 {
            if shapes.len() == MAX_SHAPES {
                break;
            }
            let flags = scene.objects.material(object).flags();
            if !flags.is_specular()
                || flags.has_non_specular()
                || flags.contains(MaterialFlags::EMISSIVE)
            {
                continue;
            }
            let shape = match scene.geometry.shape(object) {
                Some(WorldShape::Sphere(s)) => SeedShape::Round {
                    center: s.center,
                    radius: s.radius,
                },
                Some(WorldShape::Quad(q)) => SeedShape::Plane {
                    point: q.vertices[0],
                    normal: q.normal,
                },
                Some(WorldShape::Mesh(m)) if !m.positions.is_empty() => {
                    let (lo, hi) = m.positions.iter().fold(
                        (Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY)),
                        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
                    );
                    let center = 0.5 * (lo + hi);
                    let radius = m
                        .positions
                        .iter()
                        .fold(0.0f32, |r, p| r.max((*p - center).length()));
                    SeedShape::Round { center, radius }
                }
                _ => continue,
            };
            shapes.push(Seeded {
                object,
                transmits: flags.contains(MaterialFlags::TRANSMISSION),
                shape,
            });
        }
        Self { shapes }
    }

    /// The first transmitting round shape: object, centre, radius (for tests).
    #[cfg(test)]
    pub fn first_round(&self) -> Option<(u32, Vec3A, f32)> {
        self.shapes.iter().find_map(|s| match s.shape {
            SeedShape::Round { center, radius } if s.transmits => Some((s.object, center, radius)),
            _ => None,
        })
    }

    /// True when the scene has no smooth specular object.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// Calls `f` with every seed chain from `x0` to `y` of at most `max_len` vertices (see
    /// the module documentation); `lambda` for the scan's traced refractions.
    ///
    /// With `table` (made by [`SpecularShapes::scan_table`] for this `x0`), the chains through
    /// round shapes are seeded at the table's impact parameters instead of by a scan of their
    /// own: a few Newton solves instead of the scan's rays.
    #[allow(clippy::too_many_arguments)]
    pub fn for_each_seed(
        &self,
        scene: &Scene,
        x0: &Endpoint,
        y: Vec3A,
        lambda: &SampledWavelengths,
        max_len: usize,
        table: Option<&ScanTable>,
        mut f: impl FnMut(&Chain),
    ) {
        for (index, s) in self.shapes.iter().enumerate() {
            match s.shape {
                SeedShape::Round { center, radius } => {
                    if let Some(p) = bisector_point(center, radius, x0.p, y) {
                        f(&Chain::template(p, &[(s.object, Lobe::Reflect)]));
                    }
                    if !s.transmits {
                        continue;
                    }
                    let Some(table) = table else {
                        let shape = (s.object, center, radius);
                        scan_round(scene, shape, x0, y, lambda, max_len, &mut |p, b| {
                            f(&round_seed(shape, x0.p, y, p, b))
                        });
                        continue;
                    };
                    for e in table.entries.iter().filter(|e| e.shape == index) {
                        if ROUND_PATTERNS[e.pattern].len() <= max_len {
                            f(&round_seed(
                                (s.object, center, radius),
                                x0.p,
                                y,
                                e.pattern,
                                e.b,
                            ));
                        }
                    }
                }
                SeedShape::Plane { point, normal } => {
                    // Both ends on the mirror's front side: aim at y's mirror image.
                    let (hx, hy) = ((x0.p - point).dot(normal), (y - point).dot(normal));
                    if hx * hy > 0.0 {
                        let image = y - normal * (2.0 * hy);
                        let t = hx / (hx + hy);
                        f(&Chain::template(
                            x0.p + (image - x0.p) * t,
                            &[(s.object, Lobe::Reflect)],
                        ));
                    }
                }
            }
        }
    }

    /// Calls `f` with the reflection seeds alone from `x0` to `y` (one vertex each: the
    /// bisector point of every round shape, the mirror image through every quad): the cheap
    /// part of [`for_each_seed`](Self::for_each_seed), for connections run at every sample.
    pub fn for_each_reflection_seed(&self, x0: Vec3A, y: Vec3A, mut f: impl FnMut(&Chain)) {
        for s in &self.shapes {
            let p = match s.shape {
                SeedShape::Round { center, radius } => bisector_point(center, radius, x0, y),
                SeedShape::Plane { point, normal } => {
                    let (hx, hy) = ((x0 - point).dot(normal), (y - point).dot(normal));
                    (hx * hy > 0.0).then(|| {
                        let image = y - normal * (2.0 * hy);
                        x0 + (image - x0) * (hx / (hx + hy))
                    })
                }
            };
            if let Some(p) = p {
                f(&Chain::template(p, &[(s.object, Lobe::Reflect)]));
            }
        }
    }

    /// Calls `f` with the seeds of the chains *in, out* (`T T`) through every transmitting
    /// round shape from `x0` to `y`, found in the plane of `x0`, the centre and `y` without
    /// tracing a ray: [`ThroughPlane::angle`] follows the two refractions of a circle in closed form
    /// at [`THROUGH_POINTS`] impact parameters, and every sign change of the signed angle
    /// between the leaving direction and the direction to `y` is narrowed by
    /// [`THROUGH_BISECTIONS`] bisection steps to a seed aimed at its entry point (folds: see
    /// [`ThroughPlane::roots`]). This finds the several solutions a ball lens has between a
    /// point near its focus and a light (the floor caustic seen in the ball), for about 7 k
    /// instructions per `(x0, y)`. A deterministic function of `(x0, y)` and the hero
    /// wavelength's index of refraction.
    pub fn for_each_through_seed(
        &self,
        scene: &Scene,
        x0: Vec3A,
        y: Vec3A,
        lambda: &SampledWavelengths,
        mut f: impl FnMut(&Chain),
    ) {
        for s in &self.shapes {
            let SeedShape::Round { center, radius } = s.shape else {
                continue;
            };
            if !s.transmits || (x0 - center).length() <= radius || (y - center).length() <= radius {
                continue;
            }
            let Some(eta) = entering_eta(scene, s.object, lambda) else {
                continue;
            };
            let (u, _) = scan_axes(center, x0, y);
            let axis = (center - x0).normalize();
            let plane = ThroughPlane {
                d: (center - x0).length(),
                radius,
                eta,
                y: [(y - center).dot(axis), (y - center).dot(u)],
            };
            plane.roots(&mut |entry| {
                let p = center + axis * entry[0] + u * entry[1];
                f(&Chain::template(
                    p,
                    &[(s.object, Lobe::Transmit), (s.object, Lobe::Transmit)],
                ));
            });
        }
    }

    /// The impact parameters at which the scan from `x0` finds sign changes towards any of
    /// `ys` (e.g. a few points of each light), per round transmitting shape and lobe sequence,
    /// merged where closer than 0.02: a per-render seed table for a fixed `x0` (the pinhole).
    /// Built once; a function of the scene, `x0` and `ys` only, so the seed set stays a
    /// deterministic function of `(x0, y)`.
    pub fn scan_table(
        &self,
        scene: &Scene,
        x0: &Endpoint,
        ys: &[Vec3A],
        lambda: &SampledWavelengths,
        max_len: usize,
    ) -> ScanTable {
        let mut entries: Vec<ScanEntry> = Vec::new();
        for (index, s) in self.shapes.iter().enumerate() {
            let SeedShape::Round { center, radius } = s.shape else {
                continue;
            };
            if !s.transmits {
                continue;
            }
            for &y in ys {
                scan_round(
                    scene,
                    (s.object, center, radius),
                    x0,
                    y,
                    lambda,
                    max_len,
                    &mut |pattern, b| {
                        let near = entries.iter().any(|e| {
                            e.shape == index && e.pattern == pattern && (e.b - b).abs() < 0.02
                        });
                        if !near {
                            entries.push(ScanEntry {
                                shape: index,
                                pattern,
                                b,
                            });
                        }
                    },
                );
            }
        }
        ScanTable { entries }
    }
}

/// One seed of a [`ScanTable`]: shape index, lobe sequence (index into the sequences),
/// impact parameter.
#[derive(Clone, Copy, Debug)]
struct ScanEntry {
    shape: usize,
    pattern: usize,
    b: f32,
}

/// Impact parameters of chains through round shapes, scanned once for a fixed `x0`.
#[derive(Clone, Debug, Default)]
pub struct ScanTable {
    entries: Vec<ScanEntry>,
}

impl ScanTable {
    /// Number of seeds in the table.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True without seeds.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// The in-plane axis `u` (across the view from `x0` to the centre, towards `y`'s side) and
/// the plane's normal.
fn scan_axes(center: Vec3A, x0: Vec3A, y: Vec3A) -> (Vec3A, Vec3A) {
    let axis = (center - x0).normalize_or_zero();
    let side = y - center;
    let mut u = (side - axis * side.dot(axis)).normalize_or_zero();
    if u == Vec3A::ZERO {
        u = axis.any_orthonormal_vector();
    }
    (u, axis.cross(u))
}

/// The seed of lobe sequence `pattern` through round shape `(object, center, radius)` aimed
/// from `x0` at impact parameter `b` in the plane of `x0`, the centre and `y`.
fn round_seed(
    (object, center, radius): (u32, Vec3A, f32),
    x0: Vec3A,
    y: Vec3A,
    pattern: usize,
    b: f32,
) -> Chain {
    let (u, _) = scan_axes(center, x0, y);
    let lobes = ROUND_PATTERNS[pattern];
    let mut surfaces = [(object, Lobe::Transmit); MAX_CHAIN_VERTICES];
    for (s, &l) in surfaces.iter_mut().zip(lobes.iter()) {
        s.1 = l;
    }
    Chain::template(center + u * (b * radius), &surfaces[..lobes.len()])
}

/// The lobe sequences seeded through a transmitting round shape: in, out; in, one internal
/// reflection, out; in, two internal reflections, out.
const ROUND_PATTERNS: [&[Lobe]; 3] = [
    &[Lobe::Transmit, Lobe::Transmit],
    &[Lobe::Transmit, Lobe::Reflect, Lobe::Transmit],
    &[Lobe::Transmit, Lobe::Reflect, Lobe::Reflect, Lobe::Transmit],
];

/// Seeds of the refraction chains through round shape `object` (`center`, `radius`) from
/// `x0` to `y`: for each lobe sequence, rays from `x0` aimed at [`SCAN_POINTS`] points across
/// the shape in the plane of `x0`, the centre and `y` are traced through the sequence, and
/// where the signed angle between the leaving direction and the direction to `y` changes sign
/// between neighbours (both under 90°), a seed is aimed at the interpolated point.
fn scan_round(
    scene: &Scene,
    (object, center, radius): (u32, Vec3A, f32),
    x0: &Endpoint,
    y: Vec3A,
    lambda: &SampledWavelengths,
    max_len: usize,
    f: &mut dyn FnMut(usize, f32),
) {
    let (u, normal) = scan_axes(center, x0.p, y);
    // Aims beyond `b_max` (the tangent from `x0`) miss the shape; the sine spacing puts more
    // rays near the rim, where grazing chains turn fastest.
    let d = (center - x0.p).length();
    if d <= radius {
        return;
    }
    let b_max = d / (d * d - radius * radius).sqrt();
    for (pi, pattern) in ROUND_PATTERNS.iter().enumerate() {
        if pattern.len() > max_len {
            continue;
        }
        let template = round_seed((object, center, radius), x0.p, y, pi, 0.0);
        let mut prev: Option<(f32, f32)> = None;
        for i in 0..SCAN_POINTS {
            let b = rim_spaced(i, SCAN_POINTS, b_max);
            let target = center + u * (b * radius);
            let dir = (target - x0.p).normalize();
            let angle = trace_chain(scene, x0, dir, &template, lambda).and_then(|(c, out)| {
                let last = c.get(c.len() - 1).p;
                let to_y = (y - last).normalize_or_zero();
                // Signed angle (sine) in the plane, only while the two point the same way.
                (out.dot(to_y) > 0.0).then(|| out.cross(to_y).dot(normal))
            });
            match (prev, angle) {
                (Some((pb, pa)), Some(a)) if (pa <= 0.0) != (a <= 0.0) => {
                    f(pi, pb + (b - pb) * pa / (pa - a));
                }
                _ => {}
            }
            prev = angle.map(|a| (b, a));
        }
    }
}

/// Impact parameter `i` of `n` across `[-extent, extent]`, sine-spaced so the points crowd
/// towards the rim, where a chain's leaving direction turns fastest.
fn rim_spaced(i: usize, n: usize, extent: f32) -> f32 {
    extent * rim_sine(i, n)
}

/// The sine of [`rim_spaced`] (its value for `extent` 1).
fn rim_sine(i: usize, n: usize) -> f32 {
    let phi = -1.0 + (i as f32 + 0.5) * 2.0 / n as f32;
    (std::f32::consts::FRAC_PI_2 * phi).sin()
}

/// [`rim_sine`] of the [`THROUGH_POINTS`] impact parameters, computed once: the closed-form
/// scan runs at every specular-chain connection, and its 32 sines were an eighth of the
/// scan's instructions (`extent * sine` is the same product, so the same parameters).
static THROUGH_SINES: std::sync::LazyLock<[f32; THROUGH_POINTS]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|i| rim_sine(i, THROUGH_POINTS)));

/// The in-plane direction `v` (unit) refracted at a surface with unit normal `m` facing it
/// (`m · v < 0`), `e` = incident over transmitted index; `None` at total internal reflection.
fn refract_2d(v: [f32; 2], m: [f32; 2], e: f32) -> Option<[f32; 2]> {
    let cos_i = -(m[0] * v[0] + m[1] * v[1]);
    let k = 1.0 - e * e * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        return None;
    }
    let c = e * cos_i - k.sqrt();
    Some([e * v[0] + c * m[0], e * v[1] + c * m[1]])
}

/// The relative index of refraction (inside over outside) of `object`'s material entering at
/// normal incidence for the hero wavelength of `lambda`; `None` without a refraction there.
fn entering_eta(scene: &Scene, object: u32, lambda: &SampledWavelengths) -> Option<f32> {
    let ctx = ShadingContext::at(Vec3A::ZERO, Vec3A::Z, Vec3A::Z, Vec2::ZERO);
    let bs = scene.objects.material(object).sample(
        Vec3A::Z,
        &ctx,
        lambda,
        1.0 - f32::EPSILON / 2.0,
        Vec2::splat(0.5),
        TransportMode::Radiance,
    )?;
    (bs.flags.contains(MaterialFlags::TRANSMISSION) && bs.eta > 0.0).then_some(bs.eta)
}

/// One `T T` problem through a circle in its plane: the centre at the origin, `x0` at
/// `(−d, 0)`, `y` at `y` (second coordinate ≥ 0), relative index `eta` inside.
struct ThroughPlane {
    d: f32,
    radius: f32,
    eta: f32,
    y: [f32; 2],
}

impl ThroughPlane {
    /// The ray from `x0` passing the centre at signed distance `p` (|p| < radius), refracted
    /// in and out of the circle: the sine of the signed angle from its leaving direction to
    /// the direction to `y`, and its entry point; `None` when it leaves away from `y`.
    fn angle(&self, p: f32) -> Option<(f32, [f32; 2])> {
        let (d, r) = (self.d, self.radius);
        let sin_a = p / d;
        let cos_a = (1.0 - sin_a * sin_a).max(0.0).sqrt();
        let v = [cos_a, sin_a];
        let t1 = d * cos_a - (r * r - p * p).max(0.0).sqrt();
        let p1 = [-d + t1 * v[0], t1 * v[1]];
        let n1 = [p1[0] / r, p1[1] / r];
        // In: relative index 1/eta, the normal facing the incoming ray.
        let w = refract_2d(v, n1, 1.0 / self.eta)?;
        // The chord to the exit point.
        let t2 = -2.0 * (p1[0] * w[0] + p1[1] * w[1]);
        let p2 = [p1[0] + t2 * w[0], p1[1] + t2 * w[1]];
        let n2 = [p2[0] / r, p2[1] / r];
        // Out: relative index eta, the inward normal facing the ray inside.
        let out = refract_2d(w, [-n2[0], -n2[1]], self.eta)?;
        let to_y = [self.y[0] - p2[0], self.y[1] - p2[1]];
        let len = (to_y[0] * to_y[0] + to_y[1] * to_y[1]).sqrt();
        if !(out[0] * to_y[0] + out[1] * to_y[1] > 0.0) || !(len > 0.0) {
            return None;
        }
        Some(((out[0] * to_y[1] - out[1] * to_y[0]) / len, p1))
    }

    /// Calls `f` with the entry point of every root found by the scan (see
    /// [`SpecularShapes::for_each_through_seed`]): a sign change between neighbours is one
    /// root; a local minimum of `|angle|` between two neighbours of the same sign (a fold of
    /// the map, where two roots may lie within one step) is searched by golden-section steps
    /// and, where the angle changes sign there, gives the two roots on either side.
    fn roots(&self, f: &mut dyn FnMut([f32; 2])) {
        let r = self.radius;
        // (impact parameter, angle) of the last two points; `None` where the ray missed.
        let mut prev2: Option<(f32, f32)> = None;
        let mut prev: Option<(f32, f32)> = None;
        let sines = &*THROUGH_SINES;
        for &sine in sines {
            // `rim_spaced(i, THROUGH_POINTS, r)`, bit for bit.
            let p = r * sine;
            let cur = self.angle(p).map(|(a, _)| (p, a));
            match (prev2, prev, cur) {
                (_, Some(a), Some(b)) if (a.1 <= 0.0) != (b.1 <= 0.0) => self.narrow(a, b.0, f),
                (Some(a), Some(m), Some(b))
                    if (a.1 <= 0.0) == (m.1 <= 0.0)
                        && (m.1 <= 0.0) == (b.1 <= 0.0)
                        && m.1.abs() < a.1.abs()
                        && m.1.abs() <= b.1.abs() =>
                {
                    if let Some(low) = self.fold_minimum(a, b) {
                        if (low.1 <= 0.0) != (m.1 <= 0.0) {
                            self.narrow(a, low.0, f);
                            self.narrow(low, b.0, f);
                        }
                    }
                }
                _ => {}
            }
            (prev2, prev) = (prev, cur);
        }
    }

    /// The root between `lo = (p, angle)` and `hi` (the angle changes sign between them),
    /// narrowed by [`THROUGH_BISECTIONS`] bisection steps: its entry point to `f`.
    fn narrow(&self, lo: (f32, f32), hi: f32, f: &mut dyn FnMut([f32; 2])) {
        let ((mut lo, mut a_lo), mut hi) = (lo, hi);
        for _ in 0..THROUGH_BISECTIONS {
            let mid = 0.5 * (lo + hi);
            match self.angle(mid) {
                Some((am, _)) if (am <= 0.0) == (a_lo <= 0.0) => (lo, a_lo) = (mid, am),
                Some(_) => hi = mid,
                None => return,
            }
        }
        if let Some((_, entry)) = self.angle(0.5 * (lo + hi)) {
            f(entry);
        }
    }

    /// The point `(p, angle)` between `a` and `b` where the angle comes closest to the other
    /// sign ([`FOLD_STEPS`] golden-section steps on `angle · sign`); `None` if a ray misses.
    fn fold_minimum(&self, a: (f32, f32), b: (f32, f32)) -> Option<(f32, f32)> {
        let sign = if a.1 <= 0.0 { -1.0 } else { 1.0 };
        let g = 0.5 * (5.0f32.sqrt() - 1.0);
        let (mut lo, mut hi) = (a.0, b.0);
        let mut c = hi - g * (hi - lo);
        let mut d = lo + g * (hi - lo);
        let mut fc = self.angle(c)?.0;
        let mut fd = self.angle(d)?.0;
        for _ in 0..FOLD_STEPS {
            if (fc * sign <= 0.0) || (fd * sign <= 0.0) {
                break;
            }
            if fc * sign < fd * sign {
                (hi, d, fd) = (d, c, fc);
                c = hi - g * (hi - lo);
                fc = self.angle(c)?.0;
            } else {
                (lo, c, fc) = (c, d, fd);
                d = lo + g * (hi - lo);
                fd = self.angle(d)?.0;
            }
        }
        Some(if fc * sign < fd * sign {
            (c, fc)
        } else {
            (d, fd)
        })
    }
}

/// The point of the sphere (`center`, `radius`) whose outward normal bisects the directions
/// to `a` and `b` (the specular reflection point of a convex mirror), by fixed-point steps
/// from the bisector of the directions seen from the centre; `None` when an end lies inside.
fn bisector_point(center: Vec3A, radius: f32, a: Vec3A, b: Vec3A) -> Option<Vec3A> {
    if (a - center).length() <= radius || (b - center).length() <= radius {
        return None;
    }
    let mut n = ((a - center).normalize() + (b - center).normalize()).normalize_or_zero();
    if n == Vec3A::ZERO {
        return None;
    }
    for _ in 0..BISECTOR_STEPS {
        let p = center + n * radius;
        let m = ((a - p).normalize() + (b - p).normalize()).normalize_or_zero();
        if m == Vec3A::ZERO {
            return None;
        }
        n = m;
    }
    Some(center + n * radius)
}

/// The distinct solved chains of one `(x0, y)`: every seed solved, each solution kept once
/// (the same surfaces and lobes, vertices within `1e-3 · |y − x0|`: distinct solutions lie
/// centimetres apart, one solution reached from two seeds agrees to the solve's tolerance).
#[derive(Clone, Debug, Default)]
pub struct SolutionSet {
    /// The solutions, in the order their seeds were tried.
    pub solved: Vec<Solved>,
    tolerance: f32,
}

impl SolutionSet {
    /// Solves every seed of `shapes` from `x0` to `y` at `lambda` (`y.n` the light surface's
    /// geometric normal) and keeps the distinct solutions of at most `max_len` vertices.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_all(
        &mut self,
        scene: &Scene,
        shapes: &SpecularShapes,
        x0: &Endpoint,
        y: &Endpoint,
        lambda: &SampledWavelengths,
        max_len: usize,
        table: Option<&ScanTable>,
    ) {
        self.begin(x0.p, y.p);
        shapes.for_each_seed(scene, x0, y.p, lambda, max_len, table, |seed| {
            if let Some(s) = solve(scene, x0, y, seed, lambda) {
                self.add(s);
            }
        });
    }

    /// Empties the set for the solutions from `x0` to `y`.
    pub fn begin(&mut self, x0: Vec3A, y: Vec3A) {
        self.solved.clear();
        self.tolerance = 1e-3 * (y - x0).length();
    }

    /// Keeps `s` unless the set has it already.
    pub fn add(&mut self, s: Solved) {
        if !self.contains(&s.chain) {
            self.solved.push(s);
        }
    }

    /// The solution that is `chain`, if the set has it.
    pub fn find(&self, chain: &Chain) -> Option<&Solved> {
        self.solved
            .iter()
            .find(|s| same_chain(&s.chain, chain, self.tolerance))
    }

    fn contains(&self, chain: &Chain) -> bool {
        self.find(chain).is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form scan's impact parameters from the table equal `rim_spaced`'s, bit for
    /// bit (the seeds, hence the images, must not move): every index at radii over ten
    /// decades, including 0, subnormal and huge ones.
    #[test]
    fn through_sines_give_the_rim_spaced_parameters() {
        let mut radii = vec![0.0f32, f32::MIN_POSITIVE / 4.0, 1.0, 0.1, 0.5, 3.0e30];
        let mut r = 1.0e-5f32;
        while r < 1.0e5 {
            radii.push(r);
            r *= 1.37;
        }
        for &r in &radii {
            for (i, &sine) in THROUGH_SINES.iter().enumerate() {
                assert_eq!(
                    (r * sine).to_bits(),
                    rim_spaced(i, THROUGH_POINTS, r).to_bits(),
                    "radius {r}, point {i}"
                );
            }
        }
    }
}
