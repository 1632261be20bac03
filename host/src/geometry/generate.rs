//! Procedural meshes for tests, benchmarks and scenes: an icosphere (closed, shared vertices)
//! and a flat grid.

use std::collections::HashMap;

use glam::{Vec2, Vec3A};

use super::TriangleMesh;

/// Unit-radius icosphere centred at the origin: an icosahedron whose faces are split into 4
/// `subdivisions` times (`20·4ⁿ` triangles), vertices pushed onto the sphere. Closed and
/// watertight by construction (every edge shared by exactly two triangles through shared vertex
/// indices); counter-clockwise seen from outside. Normals are the unit positions.
/// `subdivisions` is clamped to 10 (21 M triangles).
pub fn icosphere(subdivisions: u32) -> TriangleMesh {
    let t = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3A> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3A::new(x, y, z).normalize())
    .collect();
    let mut indices: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions.min(10) {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::with_capacity(indices.len() * 3 / 2);
        let mut next = Vec::with_capacity(indices.len() * 4);
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3A>| -> u32 {
            let key = (a.min(b), a.max(b));
            *mid.entry(key).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(p);
                (positions.len() - 1) as u32
            })
        };
        for &[a, b, c] in &indices {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        indices = next;
    }
    TriangleMesh {
        normals: Some(positions.clone()),
        positions,
        uvs: None,
        indices,
    }
}

/// A flat `nx × nz` grid of quads (2 triangles each) covering `[0,1]²` in the xz-plane at
/// `y = 0`, facing +y, with uvs `(x, z)`.
pub fn grid(nx: u32, nz: u32) -> TriangleMesh {
    let (nx, nz) = (nx.max(1), nz.max(1));
    let mut positions = Vec::with_capacity(((nx + 1) * (nz + 1)) as usize);
    let mut uvs = Vec::with_capacity(positions.capacity());
    for j in 0..=nz {
        for i in 0..=nx {
            let (u, v) = (i as f32 / nx as f32, j as f32 / nz as f32);
            positions.push(Vec3A::new(u, 0.0, v));
            uvs.push(Vec2::new(u, v));
        }
    }
    let mut indices = Vec::with_capacity((2 * nx * nz) as usize);
    let row = nx + 1;
    for j in 0..nz {
        for i in 0..nx {
            let a = j * row + i;
            let (b, c, d) = (a + 1, a + row + 1, a + row);
            // Counter-clockwise seen from +y: a → d → c and a → c → b.
            indices.push([a, d, c]);
            indices.push([a, c, b]);
        }
    }
    TriangleMesh {
        positions,
        normals: None,
        uvs: Some(uvs),
        indices,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::triangle::geometric_normal;

    // 20·4ⁿ triangles, every edge used exactly twice (closed), and every face normal points
    // outward (dot with the centroid > 0) — exact counts, no tolerance.
    #[test]
    fn icosphere_is_closed_and_outward() {
        let m = icosphere(2);
        assert_eq!(m.indices.len(), 320);
        let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
        for t in &m.indices {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
            let [p0, p1, p2] = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
            assert!(geometric_normal(p0, p1, p2).dot(p0 + p1 + p2) > 0.0);
        }
        assert!(edges.values().all(|&c| c == 2));
    }

    // The grid faces +y (its normal is exactly +y for axis-aligned f32 vertices).
    #[test]
    fn grid_faces_up() {
        let m = grid(3, 2);
        assert_eq!(m.indices.len(), 12);
        for i in 0..m.indices.len() {
            let [a, b, c] = m.triangle(i);
            assert_eq!(geometric_normal(a, b, c), Vec3A::Y);
        }
    }
}
