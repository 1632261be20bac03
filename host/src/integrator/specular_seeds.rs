//! Deterministic seed chains for specular-chain solves whose straight segment gives no seed
//! (`integrator::specular_chain::seed_chain` covers only refractions the segment `x0 → y`
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

use super::specular_chain::{
    same_chain, solve, trace_chain, Chain, Endpoint, Lobe, Solved, MAX_CHAIN_VERTICES,
};
use crate::geometry::WorldShape;
use crate::material::MaterialFlags;
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use glam::Vec3A;

/// Smooth specular objects seeded at most (a scene with more seeds only the first ones).
pub const MAX_SHAPES: usize = 8;
/// Rays per lobe sequence of the scan across a transmitting round shape.
pub const SCAN_POINTS: usize = 32;
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
            let phi = -1.0 + (i as f32 + 0.5) * 2.0 / SCAN_POINTS as f32;
            let b = b_max * (std::f32::consts::FRAC_PI_2 * phi).sin();
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
