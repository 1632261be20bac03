//! Specular chains: the path through smooth specular surfaces (dielectric refraction or
//! reflection, smooth mirrors) that joins a fixed point `x0` to a fixed point `y`, found by
//! Newton's method on the half-vector constraints (Hanika, Droske & Fascione 2015, "Manifold
//! Next Event Estimation"; the constraint and the generalised geometry term after Jakob &
//! Marschner 2012, "Manifold Exploration").
//!
//! A chain `x0, x1 … xk, y` (1 ≤ k ≤ [`MAX_CHAIN_VERTICES`]) is admissible when at every `xi`
//! the generalised half vector `h = wa + η wb` is parallel to the shading normal, with `wa`,
//! `wb` the unit directions towards the previous and the next vertex and `η = n_b / n_a` the
//! ratio of the refractive indices on the two sides (1 for a reflection): Snell's law and the
//! law of reflection. The constraint `ci = (h·s, h·t)/|h|`, `(s, t)` the tangent frame of the
//! shading normal, vanishes there.
//!
//! - Seed ([`seed_chain`]): the straight segment `x0 → y` and the specular surfaces it
//!   crosses, in order, each crossed by refraction. Their number and order fix the chain. A
//!   chain with a reflection (the lamp seen *reflected* on a glass ball, any mirror) is never
//!   seeded: the straight segment to a reflected image does not meet the reflector, and a
//!   mirror it does cross has the two ends on its two sides. Seeds for those come from the
//!   shapes themselves (`integrator::connect::specular_seeds`, [`Chain::template`]). The solve itself
//!   handles reflections (tested below with a hand-made seed).
//! - Solve ([`solve`]): each step solves the block-tridiagonal linear system of the
//!   constraints' derivatives for the vertex offsets (2k unknowns, dense elimination), moves
//!   `x1` by the step, and re-traces the chain from `x0` through the new `x1`, refracting or
//!   reflecting by the material at each surface with the lobe of the seed (Hanika et al. §4.3);
//!   the step is halved while the constraint at the last vertex does not decrease. Converged
//!   when the re-traced last direction meets `y` to [`DIRECTION_TOLERANCE`].
//! - Generalised geometry term ([`Solved::dir_per_area`]): `|dω0/dA_y|`, the solid angle at
//!   `x0` per unit area at `y` of the solved chain, from `dx1/dy = −(A⁻¹B)₁` where `A` is the
//!   derivative of the constraints with respect to the chain vertices and `B` with respect to
//!   `y` (both in orthonormal tangent charts, area measure).
//!
//! Wavelengths: the chain is solved for the hero wavelength (the materials' `sample` with the
//! wavelengths given); a dispersive surface on the chain marks it [`Solved::dispersive`] and
//! the caller keeps only the hero lane, as a sampled path does after a dispersive event.
//!
//! | constant                | value  | meaning                                              |
//! |-------------------------|--------|------------------------------------------------------|
//! | `MAX_CHAIN_VERTICES`    | 4      | longest chain (specular vertices) that is solved     |
//! | `MAX_ITERATIONS`        | 24     | Newton steps (halvings included) before giving up    |
//! | `DIRECTION_TOLERANCE`   | 2e-5   | `|ω_traced − ω_to_y|` at convergence (radians)       |

use crate::geometry::{spawn_ray, spawn_ray_to, Hit};
use crate::material::{BsdfSample, Frame, MaterialFlags, ShadingContext, TransportMode};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{DVec3, Vec2, Vec3A};

/// Longest chain solved (specular vertices between `x0` and `y`).
pub const MAX_CHAIN_VERTICES: usize = 4;
/// Newton steps, halvings included, before a solve gives up.
pub const MAX_ITERATIONS: usize = 24;
/// Angle (radians) between the re-traced last direction and the direction to `y` below which
/// the chain counts as solved: 2e-5 rad is 0.03 mm at 1.5 m, far below any light's size here.
pub const DIRECTION_TOLERANCE: f64 = 2e-5;

/// How a chain vertex scatters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    /// Mirror reflection.
    Reflect,
    /// Refraction through the surface.
    Transmit,
}

/// A fixed end of a chain: a surface point (with its geometric normal and error bound, for
/// ray offsets) or a point in space (zero normal: a pinhole).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Endpoint {
    /// Position (scene units).
    pub p: Vec3A,
    /// Per-axis error bound of `p`.
    pub p_error: Vec3A,
    /// Unit geometric normal, or zero.
    pub n: Vec3A,
}

/// One specular vertex of a chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainVertex {
    /// Scene object it lies on.
    pub object: u32,
    /// Primitive of the object (triangle index for meshes).
    pub primitive: u32,
    /// Reflection or refraction.
    pub lobe: Lobe,
    /// Position (scene units) and its error bound.
    pub p: Vec3A,
    /// Per-axis error bound of `p`.
    pub p_error: Vec3A,
    /// Unit geometric normal.
    pub ng: Vec3A,
    /// Unit shading normal.
    pub ns: Vec3A,
    /// Texture coordinates.
    pub uv: Vec2,
    /// `n_b / n_a` across the vertex (1 for a reflection), from the material at the solve's
    /// wavelengths.
    pub eta: f32,
    /// `f·|cos θ|` of the specular lobe in radiance transport (Fresnel R, or T/η²): the
    /// throughput factor of this vertex for light going from `y` towards `x0`.
    pub weight: SampledSpectrum,
    /// Probability with which the material's sampling picks this lobe here (R or T): the
    /// discrete density of a sampled path through this vertex.
    pub lobe_pdf: f32,
    /// The lobe's direction depends on the wavelength.
    pub dispersive: bool,
}

/// Up to [`MAX_CHAIN_VERTICES`] specular vertices, `x1` first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chain {
    vertices: [Option<ChainVertex>; MAX_CHAIN_VERTICES],
    len: usize,
}

impl Chain {
    /// The empty chain.
    pub fn new() -> Self {
        Self {
            vertices: [None; MAX_CHAIN_VERTICES],
            len: 0,
        }
    }

    /// Number of specular vertices.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True without vertices.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Vertex `i` (0 = `x1`).
    pub fn get(&self, i: usize) -> &ChainVertex {
        self.vertices[i].as_ref().expect("index below len")
    }

    /// Appends a vertex; `false` when the chain is full.
    fn push(&mut self, v: ChainVertex) -> bool {
        if self.len == MAX_CHAIN_VERTICES {
            return false;
        }
        self.vertices[self.len] = Some(v);
        self.len += 1;
        true
    }

    /// A seed for [`solve`]: the surfaces and lobes `(object, lobe)` in order, the first
    /// direction aimed from `x0` at `first` (only that direction and the surfaces matter: the
    /// solve re-traces the chain from `x0`). At most [`MAX_CHAIN_VERTICES`] are kept.
    pub fn template(first: Vec3A, surfaces: &[(u32, Lobe)]) -> Self {
        let mut c = Self::new();
        for &(object, lobe) in surfaces {
            c.push(ChainVertex {
                object,
                primitive: 0,
                lobe,
                p: first,
                p_error: Vec3A::ZERO,
                ng: Vec3A::Z,
                ns: Vec3A::Z,
                uv: Vec2::ZERO,
                eta: 1.0,
                weight: SampledSpectrum::splat(1.0),
                lobe_pdf: 1.0,
                dispersive: false,
            });
        }
        c
    }

    /// The vertices, `x1` first.
    pub fn iter(&self) -> impl Iterator<Item = &ChainVertex> {
        self.vertices[..self.len].iter().flatten()
    }
}

impl Default for Chain {
    fn default() -> Self {
        Self::new()
    }
}

/// True when `object`'s material scatters only by delta lobes (smooth glass, mirrors).
fn smooth_specular(scene: &Scene, object: u32) -> Option<MaterialFlags> {
    let flags = scene.objects.material(object).flags();
    (flags.is_specular() && !flags.has_non_specular() && !flags.contains(MaterialFlags::EMISSIVE))
        .then_some(flags)
}

/// The seed chain of `x0 → y`: the smooth specular surfaces the straight segment crosses, in
/// order, refracting where the material transmits and reflecting otherwise (see the module
/// documentation). `None` when the segment meets a surface that is not smooth specular, crosses
/// more than [`MAX_CHAIN_VERTICES`], or none at all (then it is an ordinary connection).
pub fn seed_chain(scene: &Scene, x0: &Endpoint, y: &Endpoint) -> Option<Chain> {
    let mut chain = Chain::new();
    let (mut p, mut p_error, mut n) = (x0.p, x0.p_error, x0.n);
    loop {
        let (ray, t_max) = spawn_ray_to(p, p_error, n, y.p, y.p_error, y.n);
        let Some(hit) = scene.geometry.intersect(&ray, t_max) else {
            break;
        };
        let flags = smooth_specular(scene, hit.object)?;
        if !flags.contains(MaterialFlags::TRANSMISSION) {
            // A mirror crossed by the segment cannot reflect towards `y` (both ends lie on
            // its two sides): no chain.
            return None;
        }
        let v = vertex_at(&hit, Lobe::Transmit);
        if !chain.push(v) {
            return None;
        }
        (p, p_error, n) = (hit.point, hit.point_error, hit.geometric_normal);
    }
    (!chain.is_empty()).then_some(chain)
}

/// A chain vertex at `hit` with `lobe`, its material data not yet filled in.
fn vertex_at(hit: &Hit, lobe: Lobe) -> ChainVertex {
    ChainVertex {
        object: hit.object,
        primitive: hit.primitive,
        lobe,
        p: hit.point,
        p_error: hit.point_error,
        ng: hit.geometric_normal,
        ns: hit.shading_normal,
        uv: hit.uv,
        eta: 1.0,
        weight: SampledSpectrum::splat(1.0),
        lobe_pdf: 1.0,
        dispersive: false,
    }
}

/// Traces from `x0` along `dir` through the surfaces of `template` (same objects, same lobes),
/// scattering by each material's specular lobe at `lambda`. Returns the traced chain and the
/// direction leaving its last vertex, or `None` when a ray misses the expected surface or the
/// lobe does not exist there (e.g. total internal reflection for a refraction).
pub fn trace_chain(
    scene: &Scene,
    x0: &Endpoint,
    dir: Vec3A,
    template: &Chain,
    lambda: &SampledWavelengths,
) -> Option<(Chain, Vec3A)> {
    let mut chain = Chain::new();
    let mut ray = spawn_ray(x0.p, x0.p_error, x0.n, dir);
    let mut dir = dir;
    for want in template.iter() {
        let hit = scene.geometry.intersect(&ray, f32::INFINITY)?;
        if hit.object != want.object {
            return None;
        }
        let mut v = vertex_at(&hit, want.lobe);
        let material = scene.objects.material(hit.object);
        let frame = Frame::from_normal(hit.shading_normal);
        let wo = frame.to_local(-dir.normalize());
        let ctx = ShadingContext::at(hit.point, hit.geometric_normal, hit.shading_normal, hit.uv);
        // u_lobe 0 picks reflection whenever it has weight, just below 1 refraction.
        let u_lobe = match want.lobe {
            Lobe::Reflect => 0.0,
            Lobe::Transmit => 1.0 - f32::EPSILON / 2.0,
        };
        let mut record = BsdfSample::ZERO;
        let bs = material.sample_into(
            wo,
            &ctx,
            lambda,
            u_lobe,
            Vec2::splat(0.5),
            TransportMode::Radiance,
            &mut record,
        )?;
        let got = if bs.flags.contains(MaterialFlags::TRANSMISSION) {
            Lobe::Transmit
        } else {
            Lobe::Reflect
        };
        if got != want.lobe || !bs.flags.is_specular() || !(bs.pdf > 0.0) {
            return None;
        }
        v.eta = bs.eta;
        v.weight = bs.f * bs.wi.z.abs();
        v.lobe_pdf = bs.pdf;
        v.dispersive = bs.flags.contains(MaterialFlags::DISPERSIVE);
        dir = frame.to_world(bs.wi);
        chain.push(v);
        ray = spawn_ray(hit.point, hit.point_error, hit.geometric_normal, dir);
    }
    Some((chain, dir.normalize()))
}

/// A solved chain from `x0` to `y`.
#[derive(Clone, Copy, Debug)]
pub struct Solved {
    /// The specular vertices, `x1` first.
    pub chain: Chain,
    /// `|dω0/dA_y|` (sr per scene unit²): solid angle of directions leaving `x0` per unit area
    /// of `y`'s surface (its geometric normal), through the chain. For an empty chain this
    /// would be `|cos θ_y|/d²`.
    pub dir_per_area: f32,
    /// Unit direction from `x0` to `x1`.
    pub w0: Vec3A,
    /// Product of the vertices' `weight` (radiance transport from `y` to `x0`).
    pub weight: SampledSpectrum,
    /// Product of the vertices' `lobe_pdf`.
    pub lobe_pdf: f32,
    /// A vertex's direction depends on the wavelength: only the hero lane is valid.
    pub dispersive: bool,
}

/// An orthonormal tangent chart at a chain vertex: positions move in the geometric tangent
/// plane along `s`, `t`; the constraint is measured in the frame `(fs, ft)` of the shading
/// normal `n`, which turns by `dn_ds`, `dn_dt` per unit of `s`, `t`.
#[derive(Clone, Copy, Debug)]
struct Chart {
    s: DVec3,
    t: DVec3,
    n: DVec3,
    fs: DVec3,
    ft: DVec3,
    dn_ds: DVec3,
    dn_dt: DVec3,
}

/// Two unit vectors completing `w` (unit) to an orthonormal basis (Duff et al. 2017).
fn basis(w: DVec3) -> (DVec3, DVec3) {
    let sign = 1.0f64.copysign(w.z);
    let a = -1.0 / (sign + w.z);
    let b = w.x * w.y * a;
    (
        DVec3::new(1.0 + sign * w.x * w.x * a, sign * b, -sign * w.x),
        DVec3::new(b, sign + w.y * w.y * a, -w.y),
    )
}

impl Chart {
    /// The chart of a flat point with normal `n` (a light's surface).
    fn flat(n: Vec3A) -> Self {
        let n = n.as_dvec3().normalize();
        let (s, t) = basis(n);
        Self {
            s,
            t,
            n,
            fs: s,
            ft: t,
            dn_ds: DVec3::ZERO,
            dn_dt: DVec3::ZERO,
        }
    }

    /// The chart of chain vertex `v`, from its shape's derivatives; `None` where the shape's
    /// parameterisation is singular.
    fn at(scene: &Scene, v: &ChainVertex) -> Option<Self> {
        let d = scene.geometry.derivatives(v.object, v.primitive, v.p)?;
        let ng = v.ng.as_dvec3().normalize();
        let n = v.ns.as_dvec3().normalize();
        let (s, t) = basis(ng);
        let (fs, ft) = basis(n);
        let (pu, pv) = (d.dpdu.as_dvec3(), d.dpdv.as_dvec3());
        // (a, b) = M (du, dv) with a = s·dp, b = t·dp; dn = dndu du + dndv dv.
        let (m00, m01, m10, m11) = (s.dot(pu), s.dot(pv), t.dot(pu), t.dot(pv));
        let det = m00 * m11 - m01 * m10;
        if !(det.abs() > 1e-12 * pu.length_squared().max(pv.length_squared())) {
            return None;
        }
        let (i00, i01, i10, i11) = (m11 / det, -m01 / det, -m10 / det, m00 / det);
        let (nu, nv) = (d.dndu.as_dvec3(), d.dndv.as_dvec3());
        Some(Self {
            s,
            t,
            n,
            fs,
            ft,
            dn_ds: nu * i00 + nv * i10,
            dn_dt: nu * i01 + nv * i11,
        })
    }
}

/// `(I − w wᵀ) v`.
fn perp(w: DVec3, v: DVec3) -> DVec3 {
    v - w * w.dot(v)
}

/// Row-major `2k × 2k` matrix and `2k × 2` right-hand side, `k ≤ MAX_CHAIN_VERTICES`.
const N: usize = 2 * MAX_CHAIN_VERTICES;

/// The constraints of the chain `x0, xs…, y` and their derivatives: `c` (2k), `A = ∂c/∂x`
/// (2k × 2k, block tridiagonal) and `B = ∂c/∂y` (2k × 2, only the last block row non-zero).
struct Linearised {
    c: [f64; N],
    a: [[f64; N]; N],
    b: [[f64; 2]; N],
}

fn linearise(
    x0: DVec3,
    xs: &[(DVec3, f64, Chart)],
    y: DVec3,
    y_chart: &Chart,
) -> Option<Linearised> {
    let k = xs.len();
    let mut out = Linearised {
        c: [0.0; N],
        a: [[0.0; N]; N],
        b: [[0.0; 2]; N],
    };
    for i in 0..k {
        let (xi, eta, ch) = &xs[i];
        let prev = if i == 0 { x0 } else { xs[i - 1].0 };
        let next = if i + 1 == k { y } else { xs[i + 1].0 };
        let (va, vb) = (prev - *xi, next - *xi);
        let (da, db) = (va.length(), vb.length());
        if !(da > 0.0 && db > 0.0) {
            return None;
        }
        let (wa, wb) = (va / da, vb / db);
        let h = wa + wb * *eta;
        let hl = h.length();
        if !(hl > 1e-9) {
            return None;
        }
        let hh = h / hl;
        let r = 2 * i;
        out.c[r] = ch.fs.dot(hh);
        out.c[r + 1] = ch.ft.dot(hh);
        // dc = [fs ft]ᵀ (dĥ − (ĥ·n) dn): the frame turns with the normal by the smallest
        // rotation, so d(fs·ĥ) = fs·dĥ − (fs·dn)(ĥ·n); dĥ = (I − ĥĥᵀ) dh / |h|.
        let g = |dh: DVec3| {
            let d = perp(hh, dh) / hl;
            (ch.fs.dot(d), ch.ft.dot(d))
        };
        let hn = hh.dot(ch.n);
        // d wa = (I − wa waᵀ)(dprev − dxi)/da, d wb = (I − wb wbᵀ)(dnext − dxi)/db.
        for (col, (dx, dn)) in [(ch.s, ch.dn_ds), (ch.t, ch.dn_dt)].into_iter().enumerate() {
            let dh = -perp(wa, dx) / da - perp(wb, dx) * (*eta / db);
            let (c0, c1) = g(dh);
            out.a[r][r + col] = c0 - hn * ch.fs.dot(dn);
            out.a[r + 1][r + col] = c1 - hn * ch.ft.dot(dn);
        }
        if i > 0 {
            let pc = &xs[i - 1].2;
            for (col, dx) in [pc.s, pc.t].into_iter().enumerate() {
                let (c0, c1) = g(perp(wa, dx) / da);
                out.a[r][r - 2 + col] = c0;
                out.a[r + 1][r - 2 + col] = c1;
            }
        }
        let next_dirs = if i + 1 == k {
            [y_chart.s, y_chart.t]
        } else {
            [xs[i + 1].2.s, xs[i + 1].2.t]
        };
        for (col, dx) in next_dirs.into_iter().enumerate() {
            let (c0, c1) = g(perp(wb, dx) * (*eta / db));
            if i + 1 == k {
                out.b[r][col] = c0;
                out.b[r + 1][col] = c1;
            } else {
                out.a[r][r + 2 + col] = c0;
                out.a[r + 1][r + 2 + col] = c1;
            }
        }
    }
    Some(out)
}

/// Solves `A X = R` for the first `n` unknowns by Gaussian elimination with partial pivoting
/// (`R` with `m` columns); `None` when `A` is singular to working precision. Written out: a
/// system of at most 8 unknowns, which no linear-algebra crate in use here provides.
fn solve_linear<const M: usize>(
    mut a: [[f64; N]; N],
    mut r: [[f64; M]; N],
    n: usize,
) -> Option<[[f64; M]; N]> {
    let scale = a[..n]
        .iter()
        .flat_map(|row| row[..n].iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    if !(scale > 0.0) {
        return None;
    }
    for col in 0..n {
        let piv = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if !(a[piv][col].abs() > 1e-12 * scale) {
            return None;
        }
        a.swap(col, piv);
        r.swap(col, piv);
        let (pivot_a, pivot_r) = (a[col], r[col]);
        for row in col + 1..n {
            let f = a[row][col] / pivot_a[col];
            if f != 0.0 {
                for (x, p) in a[row][col..n].iter_mut().zip(&pivot_a[col..n]) {
                    *x -= f * p;
                }
                for (x, p) in r[row].iter_mut().zip(&pivot_r) {
                    *x -= f * p;
                }
            }
        }
    }
    for col in (0..n).rev() {
        let mut v = r[col];
        for k in col + 1..n {
            for (x, rk) in v.iter_mut().zip(&r[k]) {
                *x -= a[col][k] * rk;
            }
        }
        r[col] = v.map(|x| x / a[col][col]);
    }
    Some(r)
}

/// Chain positions with their `η` and charts, for [`linearise`].
fn charted(scene: &Scene, chain: &Chain) -> Option<[(DVec3, f64, Chart); MAX_CHAIN_VERTICES]> {
    let mut out = [(DVec3::ZERO, 1.0, Chart::flat(Vec3A::Z)); MAX_CHAIN_VERTICES];
    for (i, v) in chain.iter().enumerate() {
        out[i] = (v.p.as_dvec3(), v.eta as f64, Chart::at(scene, v)?);
    }
    Some(out)
}

/// The angle-like mismatch `|ω_traced − ω_to_y|` of a traced chain at its last vertex.
fn mismatch(chain: &Chain, out_dir: Vec3A, y: &Endpoint) -> f64 {
    let last = chain.get(chain.len() - 1).p.as_dvec3();
    let to_y = (y.p.as_dvec3() - last).normalize_or_zero();
    (out_dir.as_dvec3() - to_y).length()
}

/// Solves the chain of `seed`'s surfaces and lobes from `x0` to `y` (`y.n` must be the light
/// surface's geometric normal, which defines the area measure at `y`). `None` when Newton's
/// method does not converge within [`MAX_ITERATIONS`], the traced chain leaves the seed's
/// surfaces, or the last segment's direction is not the specular one (e.g. a refraction
/// solved on the wrong side). Visibility of the last segment `xk → y` is not checked here.
pub fn solve(
    scene: &Scene,
    x0: &Endpoint,
    y: &Endpoint,
    seed: &Chain,
    lambda: &SampledWavelengths,
) -> Option<Solved> {
    let k = seed.len();
    if k == 0 {
        return None;
    }
    let y_chart = Chart::flat(y.n);
    let yd = y.p.as_dvec3();
    let x0d = x0.p.as_dvec3();
    let dir = (seed.get(0).p - x0.p).normalize();
    let (mut chain, out_dir) = trace_chain(scene, x0, dir, seed, lambda)?;
    let mut err = mismatch(&chain, out_dir, y);
    let mut step = 1.0f64;
    let mut iterations = 0;
    while err > DIRECTION_TOLERANCE {
        iterations += 1;
        if iterations > MAX_ITERATIONS {
            return None;
        }
        let xs = charted(scene, &chain)?;
        let lin = linearise(x0d, &xs[..k], yd, &y_chart)?;
        let mut rhs = [[0.0f64; 1]; N];
        for (r, c) in rhs.iter_mut().zip(lin.c.iter()) {
            r[0] = -c;
        }
        let dx = solve_linear(lin.a, rhs, 2 * k)?;
        let ch = &xs[0].2;
        // Try the step, halving it until the mismatch at the last vertex decreases.
        loop {
            let x1 = xs[0].0 + (ch.s * dx[0][0] + ch.t * dx[1][0]) * step;
            let trial = Vec3A::from((x1 - x0d).normalize().as_vec3());
            if let Some((c, o)) = trace_chain(scene, x0, trial, seed, lambda) {
                let e = mismatch(&c, o, y);
                if e < err {
                    (chain, err) = (c, e);
                    step = (step * 2.0).min(1.0);
                    break;
                }
            }
            step *= 0.5;
            iterations += 1;
            if iterations > MAX_ITERATIONS {
                return None;
            }
        }
    }
    finish(scene, x0, y, chain)
}

/// The [`Solved`] of a chain that satisfies its constraints: the generalised geometry term
/// and the products of the vertices' weights.
fn finish(scene: &Scene, x0: &Endpoint, y: &Endpoint, chain: Chain) -> Option<Solved> {
    let k = chain.len();
    let xs = charted(scene, &chain)?;
    let x0d = x0.p.as_dvec3();
    let lin = linearise(x0d, &xs[..k], y.p.as_dvec3(), &Chart::flat(y.n))?;
    // dx/dy = −A⁻¹B; only x1's rows are needed.
    let m = solve_linear(lin.a, lin.b, 2 * k)?;
    let (x1, ch) = (xs[0].0, &xs[0].2);
    let v = x1 - x0d;
    let d = v.length();
    let w0 = v / d;
    let col = |j: usize| perp(w0, ch.s * -m[0][j] + ch.t * -m[1][j]) / d;
    let dir_per_area = col(0).cross(col(1)).length();
    if !(dir_per_area.is_finite() && dir_per_area > 0.0) {
        return None;
    }
    let mut weight = SampledSpectrum::splat(1.0);
    let mut lobe_pdf = 1.0f32;
    let mut dispersive = false;
    for v in chain.iter() {
        weight *= v.weight;
        lobe_pdf *= v.lobe_pdf;
        dispersive |= v.dispersive;
    }
    Some(Solved {
        chain,
        dir_per_area: dir_per_area as f32,
        w0: Vec3A::from(w0.as_vec3()),
        weight,
        lobe_pdf,
        dispersive,
    })
}

/// The solved chain of a path that was *sampled* through the specular vertices `path_chain`
/// (e.g. by a camera subpath from `x0` that ended on a light at `y`): the same data as
/// [`solve`] gives, for the path as it is (no Newton steps), so a strategy's density can be
/// evaluated for it. `None` when the chain is not admissible at the solve's tolerance.
pub fn evaluate(
    scene: &Scene,
    x0: &Endpoint,
    y: &Endpoint,
    path_chain: &Chain,
    lambda: &SampledWavelengths,
) -> Option<Solved> {
    let dir = (path_chain.get(0).p - x0.p).normalize();
    let (chain, out_dir) = trace_chain(scene, x0, dir, path_chain, lambda)?;
    if mismatch(&chain, out_dir, y) > 10.0 * DIRECTION_TOLERANCE {
        return None;
    }
    finish(scene, x0, y, chain)
}

/// True when two chains run through the same surfaces with the same lobes and their vertices
/// lie within `tolerance` (scene units) of each other: the test that a solve found *this*
/// path and not another solution.
pub fn same_chain(a: &Chain, b: &Chain, tolerance: f32) -> bool {
    a.len() == b.len()
        && a.iter().zip(b.iter()).all(|(u, v)| {
            u.object == v.object && u.lobe == v.lobe && (u.p - v.p).length() <= tolerance
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{build_scene, parse_scene_str, BuiltinFactory};
    use crate::spectrum::SampledWavelengths;
    use std::path::Path;

    /// A glass ball (IOR 1.5, radius 0.5 at height 1) over a floor, a 10 cm lamp at 2.5 m.
    const SCENE: &str = r#"(
        observer: "cie1931-2",
        output: (spp: 1, max_depth: 8, rgb_space: "srgb"),
        materials: [
            (name: "floor", type: "lambertian", params: (reflectance: 0.5)),
            (name: "glass", type: "dielectric", params: (ior: 1.5)),
            (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 1000.0)),
        ],
        objects: [
            (name: "floor", type: "quad", material: "floor",
             params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
            (name: "ball", type: "sphere", material: "glass",
             params: (center: (0, 1, 0), radius: 0.5)),
            (name: "lamp", type: "quad", material: "lamp",
             params: (corner: (-0.05, 2.5, -0.05), edge0: (0.1, 0, 0), edge1: (0, 0, 0.1))),
        ],
        lights: [],
        cameras: [(name: "c", type: "perspective",
                   params: (position: (0, 1.6, 4.5), look_at: (0, 0.8, 0), fov: 45,
                            resolution: (32, 24)))],
    )"#;

    fn scene() -> Scene {
        let file = Path::new("chain.ron");
        let desc = parse_scene_str(SCENE, file).unwrap();
        build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
    }

    fn lambda() -> SampledWavelengths {
        SampledWavelengths::sample_uniform(0.37, 380.0, 780.0)
    }

    fn floor_point(x: f32, z: f32) -> Endpoint {
        Endpoint {
            p: Vec3A::new(x, 0.0, z),
            p_error: Vec3A::splat(1e-6),
            n: Vec3A::Y,
        }
    }

    fn lamp_point(x: f32, z: f32) -> Endpoint {
        Endpoint {
            p: Vec3A::new(x, 2.5, z),
            p_error: Vec3A::splat(1e-6),
            n: -Vec3A::Y,
        }
    }

    /// A reflection seed on the ball's top, as seen from `x0`.
    fn reflection_seed(scene: &Scene, x0: &Endpoint, towards: Vec3A) -> Chain {
        let ray = spawn_ray(x0.p, x0.p_error, x0.n, (towards - x0.p).normalize());
        let hit = scene.geometry.intersect(&ray, f32::INFINITY).unwrap();
        let mut c = Chain::new();
        c.push(vertex_at(&hit, Lobe::Reflect));
        c
    }

    /// `ω0` leaving `x0` after solving towards `y`.
    fn w0(scene: &Scene, x0: &Endpoint, y: &Endpoint, seed: &Chain) -> DVec3 {
        solve(scene, x0, y, seed, &lambda())
            .expect("solve must converge")
            .w0
            .as_dvec3()
    }

    /// `|dω0/dA_y|` by central differences of the solved `ω0` over `y`'s surface (the lamp's
    /// x and z axes, step `h`): the area of the image of the unit square on the unit sphere.
    fn dir_per_area_fd(scene: &Scene, x0: &Endpoint, y: &Endpoint, seed: &Chain, h: f32) -> f64 {
        let at = |dx: f32, dz: f32| lamp_point(y.p.x + dx, y.p.z + dz);
        let dx = (w0(scene, x0, &at(h, 0.0), seed) - w0(scene, x0, &at(-h, 0.0), seed))
            / (2.0 * h as f64);
        let dz = (w0(scene, x0, &at(0.0, h), seed) - w0(scene, x0, &at(0.0, -h), seed))
            / (2.0 * h as f64);
        dx.cross(dz).length()
    }

    // The straight segment from the floor under the ball to the lamp crosses the glass twice:
    // the seed is two refractions, and the solve must converge to a chain whose last
    // direction meets the lamp point to the tolerance; the chain's weight is T₁T₂ (radiance
    // transport: T/η² entering and T·η² leaving cancel in the η²), in (0.5, 1) (T ≥ 0.7 below
    // 70° incidence); lobe_pdf the same T₁T₂ (Fresnel-weighted lobe choice).
    #[test]
    fn solves_a_refraction_through_the_ball() {
        let scene = scene();
        let (x0, y) = (floor_point(0.2, 0.06), lamp_point(0.02, -0.01));
        let seed = seed_chain(&scene, &x0, &y).expect("two crossings");
        assert_eq!(seed.len(), 2);
        assert!(seed.iter().all(|v| v.lobe == Lobe::Transmit));
        let s = solve(&scene, &x0, &y, &seed, &lambda()).expect("converges");
        let last = s.chain.get(1);
        let (_, out) = trace_chain(&scene, &x0, s.w0, &s.chain, &lambda()).unwrap();
        let to_y = (y.p - last.p).normalize();
        assert!((out - to_y).length() < 5e-5, "{out:?} vs {to_y:?}");
        let w = s.weight[0];
        assert!(w > 0.5 && w < 1.0, "weight {w}");
        assert!((s.lobe_pdf - w).abs() < 1e-5, "{} vs {w}", s.lobe_pdf);
        // The floor far from the ball: the segment to the lamp meets no glass.
        assert!(seed_chain(&scene, &floor_point(1.5, 1.5), &y).is_none());
    }

    // Generalised geometry term of a two-refraction chain (floor → glass → glass → lamp)
    // against central differences of the solved first direction over the lamp's area, step
    // 5 mm: the truncation error is O(h²) relative to the scale of the ball's focusing
    // (≈ 0.5 m), about 1e-4, and the solved directions are exact to f32 precision (≈ 1e-7 in
    // a difference over 1e-2): tolerance 1%.
    #[test]
    fn generalised_geometry_matches_finite_differences_refraction() {
        let scene = scene();
        for &(fx, fz, lx, lz) in &[
            (0.02f32, 0.006f32, 0.02f32, -0.01f32),
            (0.0, 0.0, 0.03, 0.02),
        ] {
            let (x0, y) = (floor_point(fx, fz), lamp_point(lx, lz));
            let seed = seed_chain(&scene, &x0, &y).unwrap();
            let s = solve(&scene, &x0, &y, &seed, &lambda()).unwrap();
            let fd = dir_per_area_fd(&scene, &x0, &y, &seed, 5e-3);
            let rel = (s.dir_per_area as f64 - fd).abs() / fd;
            assert!(rel < 0.01, "analytic {} fd {fd} ({rel})", s.dir_per_area);
        }
    }

    // The same for a reflection on the ball's top seen from the camera position (a point
    // without normal): here the normal's turning (∂n = ∂p / r) makes the whole term, which a
    // flat mirror would get wrong by a factor ≈ (1 + 2d/(r cos θ))². Same tolerance and why.
    // Also checks the reflection's weight: Fresnel R of glass at these angles, 0.04–0.2.
    #[test]
    fn generalised_geometry_matches_finite_differences_reflection() {
        let scene = scene();
        let x0 = Endpoint {
            p: Vec3A::new(0.0, 1.6, 4.5),
            p_error: Vec3A::ZERO,
            n: Vec3A::ZERO,
        };
        let y = lamp_point(0.01, 0.02);
        let seed = reflection_seed(&scene, &x0, Vec3A::new(0.0, 1.45, 0.3));
        let s = solve(&scene, &x0, &y, &seed, &lambda()).unwrap();
        let r = s.weight[0];
        assert!(r > 0.04 && r < 0.2, "R {r}");
        let fd = dir_per_area_fd(&scene, &x0, &y, &seed, 5e-3);
        let rel = (s.dir_per_area as f64 - fd).abs() / fd;
        assert!(rel < 0.01, "analytic {} fd {fd} ({rel})", s.dir_per_area);
        // The flat-mirror value, for contrast: cos θ_y / (d₁ + d₂)².
        let v = s.chain.get(0).p;
        let flat = ((y.p - v).normalize().y.abs()) as f64
            / ((v - x0.p).length() + (y.p - v).length()).powi(2) as f64;
        assert!(
            fd < 0.5 * flat,
            "curvature must matter: fd {fd}, flat {flat}"
        );
    }

    // `evaluate` of a chain that was traced (not solved) through the ball gives the same
    // generalised geometry term and weights as the solve that ends at the traced path's light
    // point, and `same_chain` recognises the two (0.1 mm tolerance, f32 positions ≈ 1e-7 m).
    #[test]
    fn evaluate_agrees_with_solve() {
        let scene = scene();
        let (x0, y) = (floor_point(0.2, 0.06), lamp_point(0.02, -0.01));
        let seed = seed_chain(&scene, &x0, &y).unwrap();
        let s = solve(&scene, &x0, &y, &seed, &lambda()).unwrap();
        let e = evaluate(&scene, &x0, &y, &s.chain, &lambda()).unwrap();
        assert!(same_chain(&s.chain, &e.chain, 1e-4));
        assert!((e.dir_per_area / s.dir_per_area - 1.0).abs() < 1e-3);
        assert!((e.weight[0] - s.weight[0]).abs() < 1e-5);
    }
}
