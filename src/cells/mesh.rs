//! A closed, consistently oriented triangle mesh: what a cell complex is built from (Apaza and Andujar needs a closed
//! boundary so that every cell is inside, outside or on it).
//!
//! Vertices with equal positions are welded before the checks, since meshes from glTF split vertices along
//! normal and texture seams. A mesh is accepted when every edge of the welded mesh belongs to exactly two
//! triangles that run along it in opposite directions. Degenerate triangles (two equal corners) are dropped.

use std::collections::HashMap;

/// Why a mesh cannot carry a cell complex. Every message names the mesh (`origin`: a file and mesh name, or a
/// description of a procedural mesh) and is one line.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// No triangles were given, or none is left once degenerate ones are dropped.
    #[error("mesh \"{origin}\": has no triangles")]
    Empty {
        /// The mesh's name: a file and mesh name, or a description of a procedural mesh.
        origin: String,
    },
    #[error("mesh \"{origin}\": triangle {triangle} refers to vertex {vertex}, but there are {count} vertices")]
    /// A triangle refers to a vertex past the end of the positions.
    BadIndex {
        /// The mesh's name.
        origin: String,
        /// Index of the offending triangle, as given.
        triangle: usize,
        /// The vertex index it refers to.
        vertex: u32,
        /// Number of vertices given.
        count: usize,
    },
    #[error("mesh \"{origin}\": vertex {vertex} is not finite ({position:?})")]
    /// A vertex position holds a NaN or infinity.
    NotFinite {
        /// The mesh's name.
        origin: String,
        /// Index of the vertex, as given.
        vertex: usize,
        /// Its position.
        position: [f64; 3],
    },
    #[error("mesh \"{origin}\": is open: the edge from {a:?} to {b:?} borders one triangle only; a cell complex needs a closed mesh")]
    /// An edge borders only one triangle: the mesh has a hole.
    Open {
        /// The mesh's name.
        origin: String,
        /// The edge's start, in mesh space.
        a: [f64; 3],
        /// The edge's end, in mesh space.
        b: [f64; 3],
    },
    #[error("mesh \"{origin}\": is not manifold: the edge from {a:?} to {b:?} borders {count} triangles")]
    /// An edge borders more than two triangles.
    NonManifold {
        /// The mesh's name.
        origin: String,
        /// The edge's start, in mesh space.
        a: [f64; 3],
        /// The edge's end, in mesh space.
        b: [f64; 3],
        /// Number of triangles along it.
        count: usize,
    },
    #[error("mesh \"{origin}\": is not consistently oriented: two triangles run the same way along the edge from {a:?} to {b:?}")]
    /// Two triangles run the same way along an edge: their windings disagree.
    Inconsistent {
        /// The mesh's name.
        origin: String,
        /// The edge's start, in mesh space.
        a: [f64; 3],
        /// The edge's end, in mesh space.
        b: [f64; 3],
    },
}

/// A checked closed mesh (see the module docs); positions welded, triangles as index triples.
#[derive(Debug, Clone)]
pub struct ClosedMesh {
    positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    /// Each kept triangle's index in the triangles it was made from (degenerate ones are dropped).
    sources: Vec<u32>,
}

impl ClosedMesh {
    /// Welds, checks and keeps the mesh; `origin` names it in errors.
    pub fn new(
        origin: &str,
        positions: &[[f64; 3]],
        triangles: &[[u32; 3]],
    ) -> Result<ClosedMesh, MeshError> {
        let origin = origin.to_string();
        if let Some((vertex, &position)) = positions
            .iter()
            .enumerate()
            .find(|(_, p)| !p.iter().all(|c| c.is_finite()))
        {
            return Err(MeshError::NotFinite {
                origin,
                vertex,
                position,
            });
        }
        // Welding: the first vertex at each position stands for all of them (-0.0 and 0.0 are one position).
        let key = |p: [f64; 3]| p.map(|c| (c + 0.0).to_bits());
        let mut welded_index = HashMap::new();
        let mut welded = Vec::new();
        let remap: Vec<u32> = positions
            .iter()
            .map(|&p| {
                *welded_index.entry(key(p)).or_insert_with(|| {
                    welded.push(p);
                    (welded.len() - 1) as u32
                })
            })
            .collect();
        let mut kept = Vec::with_capacity(triangles.len());
        let mut sources = Vec::with_capacity(triangles.len());
        for (triangle, corners) in triangles.iter().enumerate() {
            if let Some(&vertex) = corners.iter().find(|&&v| v as usize >= positions.len()) {
                return Err(MeshError::BadIndex {
                    origin,
                    triangle,
                    vertex,
                    count: positions.len(),
                });
            }
            let [a, b, c] = corners.map(|v| remap[v as usize]);
            if a != b && b != c && c != a {
                kept.push([a, b, c]);
                sources.push(triangle as u32);
            }
        }
        if kept.is_empty() {
            return Err(MeshError::Empty { origin });
        }
        check_closed(&origin, &welded, &kept)?;
        Ok(ClosedMesh {
            positions: welded,
            triangles: kept,
            sources,
        })
    }

    /// The welded vertex positions, in the units of the positions given.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    /// The kept triangles as indices into [`ClosedMesh::positions`], consistently wound; see
    /// [`ClosedMesh::source_triangle`] for which input triangle each is.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Which of the triangles given to [`ClosedMesh::new`] triangle `t` is.
    pub fn source_triangle(&self, t: usize) -> usize {
        self.sources[t] as usize
    }

    /// The corners of triangle `t`.
    pub fn triangle(&self, t: usize) -> [[f64; 3]; 3] {
        self.triangles[t].map(|v| self.positions[v as usize])
    }

    /// The axis-aligned bounds: (least corner, greatest corner).
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        self.positions.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(lo, hi), p| {
                (
                    [0, 1, 2].map(|k| lo[k].min(p[k])),
                    [0, 1, 2].map(|k| hi[k].max(p[k])),
                )
            },
        )
    }

    /// The median length of the triangles' edges: the scale of the mesh's own detail (its shading normals
    /// are known at the vertices only).
    pub fn median_edge(&self) -> f64 {
        let mut lengths: Vec<f64> = (0..self.triangles.len())
            .flat_map(|t| {
                let [a, b, c] = self.triangle(t);
                [norm(sub(b, a)), norm(sub(c, b)), norm(sub(a, c))]
            })
            .collect();
        lengths.sort_by(f64::total_cmp);
        lengths[lengths.len() / 2]
    }

    /// The generalized winding number of the mesh around `p` (the solid angle of all triangles over 4 pi): +-1
    /// inside, 0 outside, its sign the orientation's; well conditioned away from the surface.
    pub fn winding_number(&self, p: [f64; 3]) -> f64 {
        let mut total = 0.0;
        for t in 0..self.triangles.len() {
            let [a, b, c] = self.triangle(t).map(|q| sub(q, p));
            let (la, lb, lc) = (norm(a), norm(b), norm(c));
            let numerator = dot(a, cross(b, c));
            let denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
            // Van Oosterom and Strackee: the signed solid angle of the triangle seen from p.
            total += 2.0 * numerator.atan2(denominator);
        }
        total / (4.0 * std::f64::consts::PI)
    }
}

impl ClosedMesh {
    /// The distance from `p` to the nearest point of the mesh's surface.
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        (0..self.triangles.len())
            .map(|t| norm(sub(p, closest_on_triangle(p, self.triangle(t)))))
            .fold(f64::INFINITY, f64::min)
    }
}

/// The point of the closed triangle nearest to `p` (by the triangle's Voronoi regions: corners, edges, face).
fn closest_on_triangle(p: [f64; 3], [a, b, c]: [[f64; 3]; 3]) -> [f64; 3] {
    let along = |o: [f64; 3], d: [f64; 3], t: f64| [0, 1, 2].map(|k| o[k] + t * d[k]);
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return along(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return along(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    [0, 1, 2].map(|k| a[k] + ab[k] * v + ac[k] * w)
}

/// Every undirected edge must border exactly two triangles, once in each direction.
fn check_closed(
    origin: &str,
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
) -> Result<(), MeshError> {
    // Per undirected edge (low, high): how often it runs low -> high and high -> low.
    let mut edges: HashMap<(u32, u32), (usize, usize)> = HashMap::new();
    for &[a, b, c] in triangles {
        for (from, to) in [(a, b), (b, c), (c, a)] {
            let entry = edges.entry((from.min(to), from.max(to))).or_default();
            if from < to {
                entry.0 += 1;
            } else {
                entry.1 += 1;
            }
        }
    }
    // Sorted, so that the error names the same edge on every run.
    let mut sorted: Vec<_> = edges.into_iter().collect();
    sorted.sort_unstable_by_key(|&(edge, _)| edge);
    for ((low, high), (forward, backward)) in sorted {
        let origin = origin.to_string();
        let (a, b) = (positions[low as usize], positions[high as usize]);
        match forward + backward {
            1 => return Err(MeshError::Open { origin, a, b }),
            2 if forward == 1 => {}
            2 => return Err(MeshError::Inconsistent { origin, a, b }),
            count => {
                return Err(MeshError::NonManifold {
                    origin,
                    a,
                    b,
                    count,
                })
            }
        }
    }
    Ok(())
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

pub mod shapes {
    //! Procedural closed meshes with analytic answers: the cells module's test shapes (`relief cells --shape`).

    /// An icosahedron subdivided `levels` times, projected onto the sphere of `radius` around `centre`;
    /// triangles wound counter-clockwise seen from outside.
    pub fn icosphere(centre: [f64; 3], radius: f64, levels: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let t = (1.0 + 5f64.sqrt()) / 2.0;
        let mut unit: Vec<[f64; 3]> = vec![
            [-1.0, t, 0.0],
            [1.0, t, 0.0],
            [-1.0, -t, 0.0],
            [1.0, -t, 0.0],
            [0.0, -1.0, t],
            [0.0, 1.0, t],
            [0.0, -1.0, -t],
            [0.0, 1.0, -t],
            [t, 0.0, -1.0],
            [t, 0.0, 1.0],
            [-t, 0.0, -1.0],
            [-t, 0.0, 1.0],
        ];
        let mut triangles: Vec<[u32; 3]> = vec![
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
        let normalize = |p: [f64; 3]| {
            let l = super::norm(p);
            p.map(|c| c / l)
        };
        unit = unit.into_iter().map(normalize).collect();
        for _ in 0..levels {
            let mut midpoints = std::collections::HashMap::new();
            let mut next = Vec::with_capacity(triangles.len() * 4);
            let mut midpoint = |a: u32, b: u32, unit: &mut Vec<[f64; 3]>| -> u32 {
                *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let (p, q) = (unit[a as usize], unit[b as usize]);
                    unit.push(normalize([0, 1, 2].map(|k| 0.5 * (p[k] + q[k]))));
                    (unit.len() - 1) as u32
                })
            };
            for [a, b, c] in triangles {
                let ab = midpoint(a, b, &mut unit);
                let bc = midpoint(b, c, &mut unit);
                let ca = midpoint(c, a, &mut unit);
                next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
            }
            triangles = next;
        }
        let positions = unit
            .into_iter()
            .map(|p| [0, 1, 2].map(|k| centre[k] + radius * p[k]))
            .collect();
        (positions, triangles)
    }

    /// The radius of the largest sphere around `centre` inside the closed convex mesh: the least distance from
    /// `centre` to a triangle's plane.
    pub fn inscribed_radius(mesh: &super::ClosedMesh, centre: [f64; 3]) -> f64 {
        (0..mesh.triangles().len())
            .map(|t| {
                let [a, b, c] = mesh.triangle(t).map(|p| super::sub(p, centre));
                let normal = super::cross(super::sub(b, a), super::sub(c, a));
                super::dot(a, normal) / super::norm(normal)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// A torus around the z axis through `centre`: tube radius `minor` around the circle of radius `major`, with
    /// `segments` quads around the circle and `sides` around the tube; wound outward.
    pub fn torus(
        centre: [f64; 3],
        major: f64,
        minor: f64,
        segments: u32,
        sides: u32,
    ) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let tau = std::f64::consts::TAU;
        let mut positions = Vec::new();
        for i in 0..segments {
            let phi = tau * f64::from(i) / f64::from(segments);
            for j in 0..sides {
                let theta = tau * f64::from(j) / f64::from(sides);
                let r = major + minor * theta.cos();
                positions.push([
                    centre[0] + r * phi.cos(),
                    centre[1] + r * phi.sin(),
                    centre[2] + minor * theta.sin(),
                ]);
            }
        }
        let index = |i: u32, j: u32| (i % segments) * sides + (j % sides);
        let mut triangles = Vec::new();
        for i in 0..segments {
            for j in 0..sides {
                let (a, b, c, d) = (
                    index(i, j),
                    index(i + 1, j),
                    index(i + 1, j + 1),
                    index(i, j + 1),
                );
                triangles.extend([[a, b, c], [a, c, d]]);
            }
        }
        (positions, triangles)
    }

    /// An icosphere of `levels` subdivisions whose radius swells and sinks by up to `amplitude` (a fraction of
    /// `radius`) in `lobes` bumps around each axis: a closed star-shaped surface with concave folds, the paper's
    /// kind of detail that one cell sees overlapping.
    pub fn bumpy_sphere(
        centre: [f64; 3],
        radius: f64,
        levels: u32,
        amplitude: f64,
        lobes: f64,
    ) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let (positions, triangles) = icosphere([0.0; 3], 1.0, levels);
        let positions = positions
            .into_iter()
            .map(|p| {
                let bump = (lobes * p[0]).sin() * (lobes * p[1]).sin() * (lobes * p[2]).cos();
                let r = radius * (1.0 + amplitude * bump);
                [0, 1, 2].map(|k| centre[k] + r * p[k])
            })
            .collect();
        (positions, triangles)
    }
}

#[cfg(test)]
mod tests {
    use super::shapes::*;
    use super::*;

    #[test]
    fn distance_reaches_corners_edges_and_faces() {
        let (p, t) = icosphere([0.0; 3], 1.0, 2);
        let sphere = ClosedMesh::new("icosphere", &p, &t).expect("closed");
        let inscribed = inscribed_radius(&sphere, [0.0; 3]);
        assert!((sphere.distance([0.0; 3]) - inscribed).abs() < 1e-12);
        // Off a vertex, straight out: the vertex is nearest.
        let v = sphere.positions()[0];
        assert!((sphere.distance(v.map(|c| 3.0 * c)) - 2.0).abs() < 1e-12);
        // A point of an edge, moved out along the edge's outward bisector, is nearest to the edge.
        let [a, b, _] = sphere.triangle(0);
        let m = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
        let out = m.map(|c| c / norm(m));
        let q = [0, 1, 2].map(|k| m[k] + 0.25 * out[k]);
        assert!(
            (sphere.distance(q) - 0.25).abs() < 1e-9,
            "{}",
            sphere.distance(q)
        );
    }

    #[test]
    fn procedural_shapes_are_closed_and_wind_outward() {
        let (p, t) = icosphere([0.1, 0.2, 0.3], 1.0, 2);
        let sphere = ClosedMesh::new("icosphere", &p, &t).expect("closed");
        assert!((sphere.winding_number([0.1, 0.2, 0.3]) - 1.0).abs() < 1e-9);
        assert!(sphere.winding_number([2.0, 0.0, 0.0]).abs() < 1e-9);
        let (p, t) = torus([0.0; 3], 1.0, 0.3, 24, 12);
        let ring = ClosedMesh::new("torus", &p, &t).expect("closed");
        assert!((ring.winding_number([1.0, 0.0, 0.0]) - 1.0).abs() < 1e-9);
        assert!(
            ring.winding_number([0.0, 0.0, 0.0]).abs() < 1e-9,
            "the hole is outside"
        );
    }

    #[test]
    fn seams_are_welded() {
        // Every triangle with its own three vertices, as a glTF mesh with flat normals stores it.
        let (p, t) = icosphere([0.0; 3], 1.0, 1);
        let split: Vec<[f64; 3]> = t
            .iter()
            .flat_map(|tri| tri.map(|v| p[v as usize]))
            .collect();
        let indices: Vec<[u32; 3]> = (0..t.len() as u32)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        let mesh = ClosedMesh::new("split", &split, &indices).expect("welded into a closed mesh");
        assert_eq!(mesh.positions().len(), p.len());
    }

    #[test]
    fn bad_meshes_are_named_and_explained() {
        let (p, t) = icosphere([0.0; 3], 1.0, 1);
        let open = ClosedMesh::new("cup", &p, &t[1..]).unwrap_err();
        assert!(matches!(open, MeshError::Open { .. }), "{open}");
        assert!(
            open.to_string().starts_with("mesh \"cup\": is open"),
            "{open}"
        );
        let mut doubled = t.clone();
        doubled.push(t[0]);
        let error = ClosedMesh::new("doubled", &p, &doubled).unwrap_err();
        assert!(
            matches!(error, MeshError::NonManifold { count: 3, .. }),
            "{error}"
        );
        let mut flipped = t.clone();
        flipped[0] = [t[0][0], t[0][2], t[0][1]];
        let error = ClosedMesh::new("flipped", &p, &flipped).unwrap_err();
        assert!(matches!(error, MeshError::Inconsistent { .. }), "{error}");
        let error = ClosedMesh::new("short", &p, &[[0, 1, 999]]).unwrap_err();
        assert!(
            error.to_string().contains("refers to vertex 999"),
            "{error}"
        );
        let mut nan = p.clone();
        nan[3][1] = f64::NAN;
        let error = ClosedMesh::new("nan", &nan, &t).unwrap_err();
        assert!(
            matches!(error, MeshError::NotFinite { vertex: 3, .. }),
            "{error}"
        );
        assert!(matches!(
            ClosedMesh::new("none", &p, &[]),
            Err(MeshError::Empty { .. })
        ));
    }
}
