//! Which dimensions of the pixel's sampler ([`PixelSampler`](crate::sampler::PixelSampler))
//! each request of a BDPT camera sample reads. Every walk and connection starts its own block
//! ([`PixelSampler::set_block`](crate::sampler::PixelSampler::set_block)), so a request keeps
//! its dimension in every sample of a pixel however long the other subpaths were, and a
//! pixel's samples are stratified in it. The numbers that matter most (the first bounces of
//! both subpaths, next-event estimation at the first camera vertices, the light's start) get
//! Owen-scrambled Sobol' points; the rest of each block continues on a PCG stream of its own.
//!
//! | dimensions | requests |
//! |---|---|
//! | 0–2 | wavelengths (1D × 3) |
//! | 3, 4 | film position, lens (2D) |
//! | 5–7 | first light subpath's start: light (1D), `sample_le` (2D × 2) |
//! | 8–23 | camera subpath: 3 per bounce (lobe 1D, direction 2D, roulette 1D), 4 with fluorescence |
//! | 24–31 | s = 1 at camera vertex t = 2…5: light (1D), point (2D) |
//! | 32–47 | first light subpath's walk (after its fluorescence mode, 2 × 1D, if any) |
//! | 48–51 | t = 1 lens point of light vertex s = 1…4 (2D; not drawn for a pinhole camera) |
//! | 52, 53 | specular-chain connection (1D, 2D) |
//! | 54–56 | camera-side chain connection (1D, 1D, 2D) |
//! | 57 + 13 (j − 1) … | light subpath j ≥ 1 (scenes with delta surfaces): start (3), walk (8), t = 1 at s = 1, 2 |
//! | 96 | whether the camera sample traces light subpaths (1D; only drawn when q < 1, `light_fraction`) |
//!
//! Beyond these (deeper vertices, beams of beams-only lights), each block's requests are
//! independent PCG numbers. With `--sampler independent` every block is PCG from its start.
//!
//! The cost: a Sobol' request is about 80 instructions against 10 for PCG; the commit that
//! introduced this layout gives the instruction counts and the variance gained.

/// A block: its first dimension and how many requests from there are Sobol' points.
pub type Block = (u32, u32);

/// First light subpath's start (light choice, `sample_le`), drawn right after the camera's.
pub const LIGHT_START_0: u32 = 5;
/// The camera subpath's walk.
pub const CAMERA_WALK: Block = (8, 16);
const S1: u32 = 24;
const S1_LD_VERTICES: usize = 4;
const LIGHT_WALK_0: Block = (32, 16);
const T1_0: u32 = 48;
const T1_0_LD_VERTICES: usize = 4;
/// The specular-chain connection.
pub const MANIFOLD: Block = (52, 2);
/// The camera-side chain connection.
pub const CAMERA_CHAIN: Block = (54, 3);
const EXTRA: u32 = 57;
const EXTRA_STRIDE: u32 = 13;
/// Further light subpaths with Sobol' points; later ones are PCG throughout.
const EXTRA_LD_PATHS: u32 = 3;
const EXTRA_T1_LD_VERTICES: usize = 2;

/// Whether a camera sample traces its light subpaths (drawn only when the fraction q < 1).
pub const LIGHT_FRACTION: Block = (EXTRA + EXTRA_STRIDE * EXTRA_LD_PATHS, 1);

/// Blocks that are PCG from their start live apart from every Sobol' block, one 2²⁴ range per
/// kind, so no two blocks share a start (hence a stream).
const FAR: u32 = 1 << 24;

/// The start (light choice, `sample_le`) of light subpath `j` (3 requests from there).
pub fn light_start(j: u32) -> Block {
    match j {
        0 => (LIGHT_START_0, 3),
        1..=EXTRA_LD_PATHS => (EXTRA + EXTRA_STRIDE * (j - 1), 3),
        _ => (FAR + (j & 0xFFF), 0),
    }
}

/// The walk of light subpath `j`.
pub fn light_walk(j: u32) -> Block {
    match j {
        0 => LIGHT_WALK_0,
        1..=EXTRA_LD_PATHS => (EXTRA + EXTRA_STRIDE * (j - 1) + 3, 8),
        _ => (FAR + 0x1000 + (j & 0xFFF), 0),
    }
}

/// s = 1 (a fresh light point) at camera vertex `t ≥ 2`.
pub fn s1(t: usize) -> Block {
    if t >= 2 && t - 2 < S1_LD_VERTICES {
        (S1 + 2 * (t as u32 - 2), 2)
    } else {
        (2 * FAR + (t as u32 & (FAR - 1)), 0)
    }
}

/// t = 1 (a fresh lens point) for vertex `s ≥ 1` of light subpath `j`.
pub fn t1(j: u32, s: usize) -> Block {
    if j == 0 && s >= 1 && s - 1 < T1_0_LD_VERTICES {
        (T1_0 + s as u32 - 1, 1)
    } else if (1..=EXTRA_LD_PATHS).contains(&j) && s >= 1 && s - 1 < EXTRA_T1_LD_VERTICES {
        (EXTRA + EXTRA_STRIDE * (j - 1) + 11 + s as u32 - 1, 1)
    } else {
        // 256 light subpaths × 2¹⁶ vertices per range; beyond, blocks may repeat (harmless
        // for a mean, and no scene comes near).
        let k = ((j & 0xFF) << 16) | (s as u32 & 0xFFFF);
        (3 * FAR + k, 0)
    }
}

/// The beam of a beams-only light chosen for light subpath `j` (PCG only: rare lights).
pub fn beams(j: u32) -> Block {
    (FAR + 0x2000 + (j & 0xFFF), 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quantity: the Sobol' dimensions of all blocks (up to 64 light subpaths, 256 vertices)
    /// and the starts of all blocks. Tolerance: none may overlap (two overlapping blocks would
    /// read the same point set and correlate, biasing nothing but wasting stratification) and
    /// no two blocks may share a start (they would share a PCG stream).
    #[test]
    fn blocks_do_not_overlap() {
        let mut blocks = vec![
            (0, LIGHT_START_0),
            CAMERA_WALK,
            MANIFOLD,
            CAMERA_CHAIN,
            LIGHT_FRACTION,
        ];
        for j in 0..64 {
            blocks.push(light_start(j));
            blocks.push(light_walk(j));
            blocks.push(beams(j));
            for s in 1..256 {
                blocks.push(t1(j, s));
            }
        }
        for t in 2..256 {
            blocks.push(s1(t));
        }
        let mut starts: Vec<u32> = blocks.iter().map(|b| b.0).collect();
        starts.sort_unstable();
        let n = starts.len();
        starts.dedup();
        assert_eq!(starts.len(), n, "two blocks share a start");
        let mut dims: Vec<u32> = blocks.iter().flat_map(|&(a, l)| a..a + l).collect();
        dims.sort_unstable();
        let n = dims.len();
        dims.dedup();
        assert_eq!(dims.len(), n, "two blocks share a Sobol' dimension");
        assert!(dims.iter().all(|&d| d < FAR));
    }
}
