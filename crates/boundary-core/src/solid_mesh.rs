//! Solid regions given as the inside of a closed triangle mesh (3D).
//!
//! A [`SolidMesh`] is built from vertices and triangles and validated once: at least one
//! triangle, finite coordinates, indices in range, no triangle of zero area, and a closed,
//! consistently oriented surface (every edge shared by exactly two triangles that run along
//! it in opposite directions). The solid is the bounded region the surface encloses, closed:
//! points on the surface are solid, as for a [`crate::HalfSpace`]. A mesh whose triangles
//! face inward (negative signed volume) is **flipped**, not refused: a closed surface encloses
//! the same region whichever way its triangles turn; [`SolidMesh::was_flipped`] says whether
//! that happened.
//!
//! Queries go through parry's `TriMesh` with oriented pseudo-normals: [`SolidMesh::contains`]
//! and [`SolidMesh::distance`] to the surface, both computed in `f64` by projection onto the
//! nearest triangle. They are accurate to [`SolidMesh::rounding`], a bound a few orders of
//! magnitude above the rounding of the projection: a point within it of the surface counts as
//! on the surface (solid).
//!
//! ```
//! use boundary_core::{Point, SolidMesh};
//! // The unit cube [0, 1]^3: 8 corners, 12 triangles facing outward.
//! let v: Vec<[f64; 3]> = (0..8)
//!     .map(|k| [(k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64])
//!     .collect();
//! let t = vec![
//!     [0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
//!     [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5],
//! ];
//! let cube = SolidMesh::new(v, t).unwrap();
//! assert!(cube.contains(&Point::<3>::new(0.5, 0.5, 0.5)));
//! assert!(cube.contains(&Point::<3>::new(1.0, 0.5, 0.5))); // closed: the surface is solid
//! assert!(!cube.contains(&Point::<3>::new(1.5, 0.5, 0.5)));
//! assert!((cube.distance(&Point::<3>::new(1.5, 0.5, 0.5)) - 0.5).abs() < 1e-15);
//! ```

use crate::Point;
use parry3d_f64::math::Vector;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};
use rustc_hash::FxHashMap;
use std::fmt;

/// The relative size of [`SolidMesh::rounding`]: `ROUNDING · (extent + |x|∞)`.
const ROUNDING: f64 = 1e-12;

/// A closed, consistently oriented triangle mesh whose inside is solid (module docs).
#[derive(Clone)]
pub struct SolidMesh {
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    flipped: bool,
    /// The largest absolute vertex coordinate: the scale of the projection's rounding.
    extent: f64,
    mesh: TriMesh,
}

/// Why a mesh is not a usable solid: the message names the vertex, triangle or edge.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("solid mesh: {message}")]
pub struct MeshError {
    message: String,
}

impl MeshError {
    fn new(message: String) -> Self {
        MeshError { message }
    }
}

impl SolidMesh {
    /// Validates and builds the solid (module docs). Triangles facing inward are flipped.
    /// Errors name the first non-finite vertex, the first triangle with an index out of range
    /// or of zero area, or the first edge (by its two vertex indices) that is not shared by
    /// exactly two triangles in opposite directions.
    pub fn new(vertices: Vec<[f64; 3]>, mut triangles: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::new("no triangle".to_owned()));
        }
        if let Some(k) = vertices
            .iter()
            .position(|v| !v.iter().all(|c| c.is_finite()))
        {
            return Err(MeshError::new(format!(
                "vertex {k} has a non-finite coordinate {:?}",
                vertices[k]
            )));
        }
        let n = vertices.len();
        for (k, t) in triangles.iter().enumerate() {
            if let Some(&bad) = t.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::new(format!(
                    "triangle {k} {t:?}: vertex index {bad} out of range ({n} vertices)"
                )));
            }
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let cross = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            if cross.iter().all(|&c| c == 0.0) {
                return Err(MeshError::new(format!(
                    "triangle {k} {t:?} has zero area (repeated or collinear vertices)"
                )));
            }
        }
        check_closed(&triangles)?;
        // Signed volume: the sum of the tetrahedra from the origin, taken about the first
        // vertex so that a mesh far from the origin loses nothing to cancellation.
        let o = vertices[triangles[0][0] as usize];
        let rel = |i: u32| {
            let v = vertices[i as usize];
            [v[0] - o[0], v[1] - o[1], v[2] - o[2]]
        };
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(rel);
                a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0])
            })
            .sum::<f64>()
            / 6.0;
        if volume == 0.0 || !volume.is_finite() {
            return Err(MeshError::new(format!(
                "the surface encloses no volume (signed volume {volume})"
            )));
        }
        let flipped = volume < 0.0;
        if flipped {
            for t in &mut triangles {
                t.swap(1, 2);
            }
        }
        let extent = vertices
            .iter()
            .flat_map(|v| v.iter())
            .fold(0.0f64, |m, c| m.max(c.abs()));
        let points: Vec<Vector> = vertices
            .iter()
            .map(|v| Vector::new(v[0], v[1], v[2]))
            .collect();
        let mesh = TriMesh::with_flags(points, triangles.clone(), TriMeshFlags::ORIENTED)
            .map_err(|e| MeshError::new(format!("not a usable triangle mesh: {e}")))?;
        Ok(SolidMesh {
            vertices,
            triangles,
            flipped,
            extent,
            mesh,
        })
    }

    /// The vertices.
    pub fn vertices(&self) -> &[[f64; 3]] {
        &self.vertices
    }

    /// The triangles, facing outward (flipped if they were given facing inward).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Whether the triangles were given facing inward and have been flipped.
    pub fn was_flipped(&self) -> bool {
        self.flipped
    }

    /// The bounding box `(min, max)` of the vertices.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in &self.vertices {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        (lo, hi)
    }

    /// A bound on the error of [`SolidMesh::distance`] at `x` (and the width of the surface
    /// band that [`SolidMesh::contains`] counts as solid): `1e-12·(extent + |x|∞)`, with
    /// `extent` the largest absolute vertex coordinate.
    pub fn rounding(&self, x: &Point<3>) -> f64 {
        ROUNDING * (self.extent + x.amax())
    }

    /// Whether the closed solid holds `x`: inside, or on the surface (within
    /// [`SolidMesh::rounding`] of it).
    pub fn contains(&self, x: &Point<3>) -> bool {
        let (inside, distance) = self.locate(x);
        inside || distance <= self.rounding(x)
    }

    /// The distance from `x` to the surface (whether `x` is inside or outside).
    pub fn distance(&self, x: &Point<3>) -> f64 {
        self.locate(x).1
    }

    /// `(inside, distance to the surface)` from one projection: `inside` is parry's answer
    /// for the open inside (a point on the surface may be either; [`SolidMesh::contains`]
    /// settles that with the rounding band).
    pub fn locate(&self, x: &Point<3>) -> (bool, f64) {
        let q = Vector::new(x[0], x[1], x[2]);
        let projection = self.mesh.project_local_point(q, false);
        let d = projection.point - q;
        (projection.is_inside, d.length())
    }
}

/// Every edge must be used once in each direction: a directed edge seen twice, or one whose
/// reverse is missing, is reported by its vertex indices.
fn check_closed(triangles: &[[u32; 3]]) -> Result<(), MeshError> {
    let mut directed: FxHashMap<(u32, u32), usize> = FxHashMap::default();
    for (k, t) in triangles.iter().enumerate() {
        for e in 0..3 {
            let edge = (t[e], t[(e + 1) % 3]);
            if let Some(first) = directed.insert(edge, k) {
                return Err(MeshError::new(format!(
                    "edge {}-{} is used in the same direction by triangles {first} and {k}: \
                     the surface is not consistently oriented, or more than two triangles \
                     share the edge",
                    edge.0, edge.1
                )));
            }
        }
    }
    for (k, t) in triangles.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            if !directed.contains_key(&(b, a)) {
                return Err(MeshError::new(format!(
                    "edge {a}-{b} of triangle {k} has no triangle on its other side running \
                     {b}-{a}: the surface is not closed"
                )));
            }
        }
    }
    Ok(())
}

impl PartialEq for SolidMesh {
    /// Same vertices and (oriented) triangles.
    fn eq(&self, other: &Self) -> bool {
        self.vertices == other.vertices && self.triangles == other.triangles
    }
}

impl fmt::Debug for SolidMesh {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SolidMesh")
            .field("vertices", &self.vertices.len())
            .field("triangles", &self.triangles.len())
            .field("flipped", &self.flipped)
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let v: Vec<[f64; 3]> = (0..8)
            .map(|k| [(k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64])
            .collect();
        let t = vec![
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        (v, t)
    }

    #[test]
    fn a_cube_contains_its_inside_and_surface_and_measures_distances() {
        let (v, t) = cube();
        let m = SolidMesh::new(v, t).unwrap();
        assert!(!m.was_flipped());
        let p = |x: f64, y: f64, z: f64| Point::<3>::new(x, y, z);
        for (x, inside, d) in [
            (p(0.5, 0.5, 0.5), true, 0.5),
            (p(0.1, 0.5, 0.5), true, 0.1),
            (p(0.0, 0.3, 0.7), true, 0.0),
            (p(1.0, 1.0, 1.0), true, 0.0),
            (p(2.0, 0.5, 0.5), false, 1.0),
            (p(2.0, 2.0, 0.5), false, 2f64.sqrt()),
            (p(-1.0, -1.0, -1.0), false, 3f64.sqrt()),
        ] {
            assert_eq!(m.contains(&x), inside, "{x:?}");
            assert!(
                (m.distance(&x) - d).abs() < 1e-14,
                "{x:?}: {}",
                m.distance(&x)
            );
        }
        assert_eq!(m.bounds(), ([0.0; 3], [1.0; 3]));
    }

    #[test]
    fn an_inward_mesh_is_flipped_to_the_same_solid() {
        let (v, mut t) = cube();
        for tri in &mut t {
            tri.swap(1, 2);
        }
        let m = SolidMesh::new(v.clone(), t).unwrap();
        assert!(m.was_flipped());
        assert_eq!(m, SolidMesh::new(v, cube().1).unwrap());
        assert!(m.contains(&Point::<3>::new(0.5, 0.5, 0.5)));
        assert!(!m.contains(&Point::<3>::new(1.5, 0.5, 0.5)));
    }

    #[test]
    fn bad_meshes_are_named() {
        let (v, t) = cube();
        let err =
            |v: Vec<[f64; 3]>, t: Vec<[u32; 3]>| SolidMesh::new(v, t).unwrap_err().to_string();
        assert!(err(v.clone(), vec![]).contains("no triangle"));
        let mut nan = v.clone();
        nan[3][1] = f64::NAN;
        assert!(err(nan, t.clone()).contains("vertex 3"));
        let mut out = t.clone();
        out[5] = [1, 5, 8];
        assert!(err(v.clone(), out).contains("triangle 5 [1, 5, 8]: vertex index 8"));
        // An open box: the top's two triangles removed.
        let open: Vec<[u32; 3]> = t[..2].iter().chain(&t[4..]).copied().collect();
        let e = err(v.clone(), open);
        assert!(e.contains("edge 5-4") && e.contains("not closed"), "{e}");
        // One triangle turned the wrong way.
        let mut turned = t.clone();
        turned[7].swap(0, 1);
        let e = err(v.clone(), turned);
        assert!(e.contains("same direction"), "{e}");
        assert!(
            e.contains("edge 6-3") || e.contains("edge 7-3") || e.contains("edge 6-7"),
            "{e}"
        );
        // A degenerate triangle.
        let mut flat = v.clone();
        flat.push([0.5, 0.0, 0.0]);
        let mut t2 = t.clone();
        t2.push([0, 1, 8]);
        assert!(err(flat, t2).contains("triangle 12 [0, 1, 8] has zero area"));
    }

    #[test]
    fn far_from_the_origin_the_volume_and_queries_hold() {
        let (v, t) = cube();
        let shifted: Vec<[f64; 3]> = v.iter().map(|p| p.map(|c| c + 1e6)).collect();
        let m = SolidMesh::new(shifted, t).unwrap();
        assert!(!m.was_flipped());
        assert!(m.contains(&Point::<3>::new(1e6 + 0.5, 1e6 + 0.5, 1e6 + 0.25)));
        assert!(
            (m.distance(&Point::<3>::new(1e6 + 0.5, 1e6 + 0.5, 1e6 + 0.25)) - 0.25).abs() < 1e-9
        );
    }
}
