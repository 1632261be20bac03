//! A precomputed RGB → sigmoid-coefficient table for linear sRGB reflectances, so that image
//! textures are uplifted per texel by a table lookup instead of a Gauss–Newton solve per colour
//! (the scheme of Jakob & Hanika 2019, as pbrt-v4 and Mitsuba 3 tabulate it).
//!
//! # Layout
//! For a colour `c` in [0, 1]³ let `l` be the index of its largest component, `z = c[l]`,
//! `x = c[(l+1) % 3] / z` and `y = c[(l+2) % 3] / z` (both in [0, 1]). The table holds the
//! fitted coefficients ([`crate::color::SigmoidPolynomial`], in the uplifter's normalised `t`)
//! at `3 × R × R × R` nodes `(l, z_k, y_j, x_i)` with `x_i = i/(R−1)`, `y_j = j/(R−1)` and
//! `z_k = s(s(k/(R−1)))`, `s(t) = 3t² − 2t³` (nodes crowd near 0 and 1, where the coefficients
//! change fastest); a lookup interpolates the coefficients trilinearly. [`RESOLUTION`] R = 64.
//!
//! # Building and caching
//! Built from the same solver the scene's `(rgb: …)` colours use ([`RgbUplifter`] for sRGB
//! under D65, CIE 1931 2°, its weights gathered onto 5 nm nodes for speed, see
//! [`RgbUplifter::coarsened`]): each `(l, x_i, y_j)` column is a chain along z, started with the
//! full continuation fit at `z = z_{R/5}` and walked up and down with each node's fit starting
//! from its neighbour's (a few Levenberg–Marquardt steps), the chains in parallel. Node targets
//! are clamped into [10⁻⁶, 1 − 10⁻⁶] so every coefficient is finite.
//!
//! The first process that needs the table builds it (seconds) and saves it to
//! `$SPECTRACE_CACHE_DIR`, else `$XDG_CACHE_HOME/spectrace`, else `~/.cache/spectrace`
//! (`SPECTRACE_CACHE_DIR=` empty: no cache), as `rgb_to_spectrum_srgb_64_<key>.bin` (9.4 MB);
//! later processes load it (milliseconds). The key is a CRC-32 of the solver's weights, the
//! resolution and the format version, so a table made by a different solver is never read;
//! the file carries a CRC-32 of its contents and a damaged file is rebuilt. Writing goes to a
//! temporary file renamed into place, so concurrent processes never see half a table.
//!
//! # Out of gamut
//! Lookups clamp each component into [0, 1] first: a reflectance cannot exceed 1 or be
//! negative. (An RGB colour whose components are all in [0, 1] is always reachable by a
//! reflectance in [0, 1], up to the boundary colours with a component at exactly 0 or 1 and
//! others not, which the sigmoid approaches as closely as finite coefficients allow.)

use super::uplift::{RgbUplifter, SigmoidPolynomial};
use rayon::prelude::*;
use std::sync::OnceLock;

/// Nodes per axis.
pub const RESOLUTION: usize = 64;

/// Node targets stay this far inside [0, 1] (finite coefficients).
const MARGIN: f64 = 1e-6;

/// The table (see the module docs).
pub struct RgbToSpectrumTable {
    res: usize,
    z_nodes: Vec<f32>,
    /// `[l][z][y][x]` coefficients.
    coeffs: Vec<[f32; 3]>,
}

impl std::fmt::Debug for RgbToSpectrumTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "RgbToSpectrumTable({}³ × 3)", self.res)
    }
}

fn smoothstep(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
}

impl RgbToSpectrumTable {
    /// The table for linear sRGB reflectances under D65 (loaded from the cache or built at
    /// first use, then shared).
    pub fn srgb() -> &'static Self {
        &srgb_entry().0
    }

    /// How [`srgb`](Self::srgb) got its table: `"cache"` or `"built"`, and the seconds it took.
    pub fn srgb_origin() -> (&'static str, f64) {
        let e = srgb_entry();
        (e.1, e.2)
    }

    /// Build a table of `res` nodes per axis (≥ 2) for `uplifter`.
    pub fn build(uplifter: &RgbUplifter, res: usize) -> Self {
        let res = res.max(2);
        let z_nodes: Vec<f64> = (0..res)
            .map(|k| smoothstep(smoothstep(k as f64 / (res - 1) as f64)))
            .collect();
        let chains: Vec<(usize, usize, usize)> = (0..3)
            .flat_map(|l| (0..res).flat_map(move |j| (0..res).map(move |i| (l, j, i))))
            .collect();
        let columns: Vec<Vec<[f32; 3]>> = chains
            .par_iter()
            .map(|&(l, j, i)| {
                let target = |k: usize| {
                    let z = z_nodes[k];
                    let mut c = [0.0; 3];
                    c[l] = z;
                    c[(l + 1) % 3] = i as f64 / (res - 1) as f64 * z;
                    c[(l + 2) % 3] = j as f64 / (res - 1) as f64 * z;
                    c.map(|v| v.clamp(MARGIN, 1.0 - MARGIN))
                };
                let fit_from = |k: usize, start: [f64; 3]| {
                    let t = target(k);
                    let (c, res) = uplifter.refine(t, start, 30);
                    if res < 1e-6 {
                        return c;
                    }
                    let full = uplifter.fit(t).coeffs;
                    if uplifter.residual(t, full) < res {
                        full
                    } else {
                        c
                    }
                };
                let mut out = vec![[0.0f32; 3]; res];
                let k0 = res / 5;
                let c0 = uplifter.fit(target(k0)).coeffs;
                out[k0] = c0.map(|v| v as f32);
                let mut c = c0;
                for (k, o) in out.iter_mut().enumerate().skip(k0 + 1) {
                    c = fit_from(k, c);
                    *o = c.map(|v| v as f32);
                }
                c = c0;
                for k in (0..k0).rev() {
                    c = fit_from(k, c);
                    out[k] = c.map(|v| v as f32);
                }
                out
            })
            .collect();
        // Reorder from [l][y][x][z] chains into [l][z][y][x].
        let mut coeffs = vec![[0.0f32; 3]; 3 * res * res * res];
        for (n, &(l, j, i)) in chains.iter().enumerate() {
            for k in 0..res {
                coeffs[((l * res + k) * res + j) * res + i] = columns[n][k];
            }
        }
        Self {
            res,
            z_nodes: z_nodes.iter().map(|&z| z as f32).collect(),
            coeffs,
        }
    }

    /// The table as bytes: magic, resolution, z nodes, coefficients (f32 little-endian), then
    /// a CRC-32 of all that.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(16 + self.coeffs.len() * 12 + self.res * 4 + 4);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&(self.res as u32).to_le_bytes());
        for z in &self.z_nodes {
            out.extend_from_slice(&z.to_le_bytes());
        }
        for c in self.coeffs.iter().flatten() {
            out.extend_from_slice(&c.to_le_bytes());
        }
        let crc = crc32fast::hash(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        out
    }

    /// Read [`to_bytes`](Self::to_bytes)' format; `None` unless it is exactly a table of
    /// resolution `res` with a matching checksum and finite values.
    pub fn from_bytes(bytes: &[u8], res: usize) -> Option<Self> {
        let n = 3 * res * res * res;
        let want = MAGIC.len() + 4 + res * 4 + n * 12 + 4;
        if bytes.len() != want || !bytes.starts_with(MAGIC) {
            return None;
        }
        let (body, crc) = bytes.split_at(want - 4);
        if crc32fast::hash(body).to_le_bytes() != crc {
            return None;
        }
        let mut floats = body[MAGIC.len() + 4..]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        if u32::from_le_bytes(body[MAGIC.len()..MAGIC.len() + 4].try_into().ok()?) as usize != res {
            return None;
        }
        let z_nodes: Vec<f32> = floats.by_ref().take(res).collect();
        let flat: Vec<f32> = floats.collect();
        if flat.len() != n * 3 || flat.iter().chain(&z_nodes).any(|v| !v.is_finite()) {
            return None;
        }
        Some(Self {
            res,
            z_nodes,
            coeffs: flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        })
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.coeffs.len() * std::mem::size_of::<[f32; 3]>() + self.z_nodes.len() * 4
    }

    /// The coefficients for linear RGB `rgb` (each component clamped into [0, 1]).
    pub fn lookup(&self, rgb: [f32; 3]) -> [f32; 3] {
        let c = rgb.map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) });
        let l = if c[0] >= c[1] && c[0] >= c[2] {
            0
        } else if c[1] >= c[2] {
            1
        } else {
            2
        };
        let z = c[l];
        let r1 = (self.res - 1) as f32;
        let (x, y) = if z > 0.0 {
            (c[(l + 1) % 3] / z * r1, c[(l + 2) % 3] / z * r1)
        } else {
            (0.0, 0.0)
        };
        let xi = (x as usize).min(self.res - 2);
        let yi = (y as usize).min(self.res - 2);
        let zi = (self.z_nodes.partition_point(|&n| n <= z).max(1) - 1).min(self.res - 2);
        let (dx, dy) = (x - xi as f32, y - yi as f32);
        let dz = (z - self.z_nodes[zi]) / (self.z_nodes[zi + 1] - self.z_nodes[zi]);
        let idx = |k: usize, j: usize, i: usize| ((l * self.res + k) * self.res + j) * self.res + i;
        let mut out = [0.0f32; 3];
        for (corner, w) in [
            ((0, 0, 0), (1.0 - dz) * (1.0 - dy) * (1.0 - dx)),
            ((0, 0, 1), (1.0 - dz) * (1.0 - dy) * dx),
            ((0, 1, 0), (1.0 - dz) * dy * (1.0 - dx)),
            ((0, 1, 1), (1.0 - dz) * dy * dx),
            ((1, 0, 0), dz * (1.0 - dy) * (1.0 - dx)),
            ((1, 0, 1), dz * (1.0 - dy) * dx),
            ((1, 1, 0), dz * dy * (1.0 - dx)),
            ((1, 1, 1), dz * dy * dx),
        ] {
            if w == 0.0 {
                continue;
            }
            let v = self.coeffs[idx(zi + corner.0, yi + corner.1, xi + corner.2)];
            for k in 0..3 {
                out[k] += w * v[k];
            }
        }
        out
    }

    /// The smooth reflectance of `rgb` (see [`lookup`](Self::lookup)).
    pub fn polynomial(&self, rgb: [f32; 3]) -> SigmoidPolynomial {
        SigmoidPolynomial {
            coeffs: self.lookup(rgb).map(|v| v as f64),
        }
    }
}

/// File format tag (and version).
const MAGIC: &[u8; 8] = b"SPTRGB01";

/// The shared sRGB table, how it was obtained and the seconds that took.
fn srgb_entry() -> &'static (RgbToSpectrumTable, &'static str, f64) {
    static CELL: OnceLock<(RgbToSpectrumTable, &'static str, f64)> = OnceLock::new();
    CELL.get_or_init(|| {
        let t0 = std::time::Instant::now();
        let uplifter = RgbUplifter::srgb().coarsened(5.0);
        let path = cache_file(&uplifter);
        if let Some(p) = &path {
            if let Some(t) = std::fs::read(p)
                .ok()
                .and_then(|b| RgbToSpectrumTable::from_bytes(&b, RESOLUTION))
            {
                return (t, "cache", t0.elapsed().as_secs_f64());
            }
        }
        let table = RgbToSpectrumTable::build(&uplifter, RESOLUTION);
        if let Some(p) = &path {
            // Best effort: a read-only home only costs the next process the build again.
            let _ = save_atomically(p, &table.to_bytes());
        }
        (table, "built", t0.elapsed().as_secs_f64())
    })
}

/// Where the cached table lives (see the module docs), or `None` when caching is off.
fn cache_file(uplifter: &RgbUplifter) -> Option<std::path::PathBuf> {
    use std::path::PathBuf;
    let dir = match std::env::var_os("SPECTRACE_CACHE_DIR") {
        Some(d) if d.is_empty() => return None,
        Some(d) => PathBuf::from(d),
        None => match std::env::var_os("XDG_CACHE_HOME") {
            Some(d) if !d.is_empty() => PathBuf::from(d).join("spectrace"),
            _ => PathBuf::from(std::env::var_os("HOME")?).join(".cache/spectrace"),
        },
    };
    let mut h = crc32fast::Hasher::new();
    h.update(MAGIC);
    h.update(&(RESOLUTION as u32).to_le_bytes());
    h.update(&MARGIN.to_le_bytes());
    for (t, w) in uplifter.weights() {
        h.update(&t.to_le_bytes());
        for v in w {
            h.update(&v.to_le_bytes());
        }
    }
    Some(dir.join(format!(
        "rgb_to_spectrum_srgb_{RESOLUTION}_{:08x}.bin",
        h.finalize()
    )))
}

fn save_atomically(path: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().unwrap_or(std::path::Path::new("."));
    std::fs::create_dir_all(dir)?;
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        path.file_name().and_then(|n| n.to_str()).unwrap_or("table"),
        std::process::id()
    ));
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path)
}

/// `S(c₀t² + c₁t + c₂)` at normalised wavelength `t` (see [`crate::color::uplift`]), in f32 for
/// per-texel evaluation.
#[inline]
pub fn eval_coeffs(c: [f32; 3], t: f32) -> f32 {
    let x = (c[0] * t + c[1]) * t + c[2];
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// The normalised wavelength `t` of `lambda_nm` (see [`super::uplift::UPLIFT_RANGE`]).
#[inline]
pub fn t_of(lambda_nm: f32) -> f32 {
    let (lo, hi) = super::uplift::UPLIFT_RANGE;
    (lambda_nm - lo as f32) / (hi - lo) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shared table's origin and cost (printed, `--nocapture`), and its accuracy against
    /// the direct solve with the full 1 nm weights: over 2000 pseudo-random colours in [0, 1]³
    /// (fixed seed) the table's spectrum reproduces the colour's RGB within 3e-3 per channel
    /// (below an 8-bit step of a linear value near 1, 1/255 ≈ 3.9e-3; the largest errors are
    /// at the gamut boundary, where a component is near 0 or 1), and within 1.5e-3 inside
    /// [0.02, 0.98]³ (the trilinear interpolation of coefficients and the 5 nm weights the table
    /// is built with). The spectra themselves may differ from the direct fit's (the boundary
    /// fits are not unique): the largest difference and its 99th percentile are printed.
    #[test]
    fn table_matches_the_direct_solve() {
        let table = RgbToSpectrumTable::srgb();
        let (origin, secs) = RgbToSpectrumTable::srgb_origin();
        eprintln!(
            "rgb table: {} nodes, {:.1} MB, {origin} in {secs:.2} s",
            table.coeffs.len(),
            table.memory_bytes() as f64 / 1e6,
        );
        let up = RgbUplifter::srgb();
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut worst_rgb, mut worst_inner) = (0.0f64, 0.0f64);
        let mut refl = Vec::new();
        let t1 = std::time::Instant::now();
        let n = 2000;
        for _ in 0..n {
            let c = [rnd(), rnd(), rnd()];
            let p = table.polynomial(c.map(|v| v as f32));
            let back = up.rgb_of(|l| p.value(l));
            let err = (0..3).map(|k| (back[k] - c[k]).abs()).fold(0.0, f64::max);
            worst_rgb = worst_rgb.max(err);
            if c.iter().all(|v| (0.02..=0.98).contains(v)) {
                worst_inner = worst_inner.max(err);
            }
            let direct = up.fit(c);
            let d = (360..=830)
                .step_by(5)
                .map(|l| (p.value(l as f64) - direct.value(l as f64)).abs())
                .fold(0.0, f64::max);
            refl.push(d);
        }
        refl.sort_by(f64::total_cmp);
        eprintln!(
            "rgb table vs direct fit over {n} colours: RGB error max {worst_rgb:.2e} \
             (inside [0.02, 0.98]³: {worst_inner:.2e}); reflectance difference max {:.3}, 99th \
             percentile {:.3}, median {:.4} ({:.2} ms per direct fit)",
            refl[n - 1],
            refl[n * 99 / 100],
            refl[n / 2],
            t1.elapsed().as_secs_f64() * 1e3 / n as f64
        );
        assert!(worst_rgb < 3e-3, "{worst_rgb}");
        assert!(worst_inner < 1.5e-3, "{worst_inner}");
    }

    /// Greys come back flat: within 1e-3 of the grey at 400, 550 and 700 nm (z between nodes:
    /// the interpolated coefficient's sigmoid is not exactly the interpolated grey).
    #[test]
    fn greys_are_flat() {
        let table = RgbToSpectrumTable::srgb();
        for g in [0.0f32, 0.01, 0.25, 0.5, 0.9, 1.0] {
            let p = table.polynomial([g; 3]);
            for l in [400.0, 550.0, 700.0] {
                assert!(
                    (p.value(l) - g as f64).abs() < 1e-3,
                    "{g} at {l}: {}",
                    p.value(l)
                );
            }
        }
    }

    /// The cache format round-trips exactly, and a flipped byte, a wrong resolution or a cut
    /// file is refused (then the table is rebuilt). A small table (8³ × 3) keeps this fast.
    #[test]
    fn cache_format_round_trips_and_refuses_damage() {
        let t = RgbToSpectrumTable::build(&RgbUplifter::srgb().coarsened(5.0), 8);
        let bytes = t.to_bytes();
        let back = RgbToSpectrumTable::from_bytes(&bytes, 8).unwrap();
        assert_eq!(back.coeffs, t.coeffs);
        assert_eq!(back.z_nodes, t.z_nodes);
        let mut bad = bytes.clone();
        bad[100] ^= 1;
        assert!(RgbToSpectrumTable::from_bytes(&bad, 8).is_none());
        assert!(RgbToSpectrumTable::from_bytes(&bytes, 9).is_none());
        assert!(RgbToSpectrumTable::from_bytes(&bytes[..bytes.len() - 1], 8).is_none());
    }
}
