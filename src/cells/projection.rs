//! How the points of a grey cell map onto its domain faces (Apaza and Andujar, section 3.2 and Figure 5).
//!
//! Everything here is in cell-local coordinates: the cell is the unit cube `[0, 1]^3`. A point `p` is projected
//! along the projection's direction at `p` until it leaves the cell; the face it leaves through, the point there and
//! the distance travelled are what a distance map stores (the map of a face holds, per texel, the distance along the
//! projection line from the face back to the surface). Each case's projection is chosen so that every point of the
//! cell leaves through one of its domain faces:
//!
//! | case | projection | parameter (the paper's choice) |
//! |---|---|---|
//! | 0, 6 | perspective | the cell's centre |
//! | 1 | perspective | the midpoint of the internal face |
//! | 2a | perspective | the midpoint of the internal edge |
//! | 2b | axial | the line through the midpoints of the two internal faces |
//! | 3a | axial | the line through the midpoints of the two internal edges |
//! | 3b | perspective | the vertex where the internal faces meet |
//! | 4a | planar | the plane through the centre, parallel to the external faces |
//! | 4b | axial | the edge opposite the external edge |
//! | 5 | parallel | the external face's normal |
//!
//! A direction is zero only on the projection's own centre, axis or (never, for planar) plane; such points have no
//! image ([`Projection::project`] returns `None`). They are a set of measure zero, but a renderer must still step off
//! them.

use super::case::{Axis, Case, Face, FaceSet};

/// One of the paper's four projection types (Figure 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Away from the centre of projection.
    Perspective {
        /// The centre of projection, in cell-local coordinates (the unit cell `[0, 1]^3`).
        centre: [f64; 3],
    },
    /// Away from the line through `point` along `axis`, perpendicular to it.
    Axial {
        /// The direction of the line (0 = x, 1 = y, 2 = z).
        axis: Axis,
        /// A point of the line, in cell-local coordinates.
        point: [f64; 3],
    },
    /// Along `axis`, away from the plane where that coordinate is `offset`.
    Planar {
        /// The axis the plane is perpendicular to and the projection runs along.
        axis: Axis,
        /// The plane's coordinate along `axis`, in cell-local coordinates.
        offset: f64,
    },
    /// Along `axis`, toward `face` (whose axis it is).
    Parallel {
        /// The domain face the lines run toward; its axis is the direction.
        face: Face,
    },
}

/// Where a point of the cell lands: the domain face, the face coordinates (its [`Face::span`] axes) and the
/// distance along the projection line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Image {
    /// The domain face the point projects onto.
    pub face: Face,
    /// Face coordinates in [0, 1] along the face's [`Face::span`] axes.
    pub uv: [f64; 2],
    /// Distance from the face point to the point along the projection line, in cell sides.
    pub distance: f64,
}

/// The domain faces of a grey cell with internal faces `internal`: its external faces, or, for a cell with none
/// (an interior grey cell, case 6), its internal faces, i.e. all six.
pub fn domain_faces(internal: FaceSet) -> FaceSet {
    let external = internal.complement();
    if external.is_empty() {
        FaceSet::ALL
    } else {
        external
    }
}

/// The cell-local point at coordinates `uv` (along its [`Face::span`] axes) of `face`.
pub fn face_point(face: Face, uv: [f64; 2]) -> [f64; 3] {
    let mut q = [0.0; 3];
    let [u, v] = face.span();
    q[face.axis] = face.offset();
    q[u] = uv[0];
    q[v] = uv[1];
    q
}

/// The midpoint of the edge where faces `a` and `b` (on different axes) meet.
fn edge_midpoint(a: Face, b: Face) -> [f64; 3] {
    let mut p = [0.5; 3];
    p[a.axis] = a.offset();
    p[b.axis] = b.offset();
    p
}

impl Projection {
    /// The paper's projection for a grey cell with internal faces `internal` (see the module docs).
    pub fn for_cell(internal: FaceSet) -> Projection {
        let external = internal.complement();
        let first = |set: FaceSet| set.faces().next().expect("the case has such a face");
        match Case::of_internal(internal) {
            Case::C0 | Case::C6 => Projection::Perspective { centre: [0.5; 3] },
            Case::C1 => {
                let f = first(internal);
                let mut centre = [0.5; 3];
                centre[f.axis] = f.offset();
                Projection::Perspective { centre }
            }
            Case::C2a => {
                let mut faces = internal.faces();
                let (a, b) = (faces.next().unwrap(), faces.next().unwrap());
                Projection::Perspective {
                    centre: edge_midpoint(a, b),
                }
            }
            Case::C2b => Projection::Axial {
                axis: first(internal).axis,
                point: [0.5; 3],
            },
            Case::C3a => {
                // The internal face that is not one of the opposite pair lies between them; both internal edges
                // run along the third axis, at that face's offset.
                let between = internal
                    .faces()
                    .find(|f| !internal.contains(f.opposite()))
                    .expect("case 3a has a face between its opposite pair");
                let pair = internal.faces().find(|f| f.axis != between.axis).unwrap();
                let mut point = [0.5; 3];
                point[between.axis] = between.offset();
                Projection::Axial {
                    axis: pair.axis,
                    point,
                }
            }
            Case::C3b => {
                let mut centre = [0.0; 3];
                for f in internal.faces() {
                    centre[f.axis] = f.offset();
                }
                Projection::Perspective { centre }
            }
            Case::C4a => Projection::Planar {
                axis: first(external).axis,
                offset: 0.5,
            },
            Case::C4b => {
                // The edge opposite the external one: on each external face's axis, the other side.
                let mut faces = external.faces();
                let (a, b) = (faces.next().unwrap(), faces.next().unwrap());
                let axis = 3 - a.axis - b.axis;
                Projection::Axial {
                    axis,
                    point: edge_midpoint(a.opposite(), b.opposite()),
                }
            }
            Case::C5 => Projection::Parallel {
                face: first(external),
            },
        }
    }

    /// The length of the projection line through point `uv` of `face`: from the face back to the projection's
    /// centre, axis or plane, or across the cell for a parallel projection.
    pub fn line_length(&self, face: Face, uv: [f64; 2]) -> f64 {
        let start = face_point(face, uv);
        match *self {
            Projection::Perspective { .. } | Projection::Axial { .. } => self
                .direction(start)
                .iter()
                .map(|c| c * c)
                .sum::<f64>()
                .sqrt(),
            Projection::Planar { axis, offset } => (start[axis] - offset).abs(),
            Projection::Parallel { .. } => 1.0,
        }
    }

    /// The projection's direction at `p` (not normalized), or zero where it has none.
    pub fn direction(&self, p: [f64; 3]) -> [f64; 3] {
        match *self {
            Projection::Perspective { centre } => [0, 1, 2].map(|k| p[k] - centre[k]),
            Projection::Axial { axis, point } => {
                [0, 1, 2].map(|k| if k == axis { 0.0 } else { p[k] - point[k] })
            }
            Projection::Planar { axis, offset } => {
                let side = if p[axis] >= offset { 1.0 } else { -1.0 };
                [0, 1, 2].map(|k| if k == axis { side } else { 0.0 })
            }
            Projection::Parallel { face } => {
                let side = if face.positive { 1.0 } else { -1.0 };
                [0, 1, 2].map(|k| if k == face.axis { side } else { 0.0 })
            }
        }
    }

    /// Where `p` (inside the cell or on its boundary) leaves the cell along the projection, or `None` on the
    /// projection's centre or axis. On an edge or corner the face of the lowest axis is taken.
    pub fn project(&self, p: [f64; 3]) -> Option<Image> {
        let d = self.direction(p);
        let length = d.iter().map(|c| c * c).sum::<f64>().sqrt();
        if length == 0.0 || length.is_nan() {
            return None;
        }
        let d = d.map(|c| c / length);
        let mut best: Option<(f64, Face)> = None;
        for (axis, &dk) in d.iter().enumerate() {
            if dk == 0.0 {
                continue;
            }
            let face = Face::new(axis, dk > 0.0);
            let t = ((face.offset() - p[axis]) / dk).max(0.0);
            if best.is_none_or(|(tb, _)| t < tb) {
                best = Some((t, face));
            }
        }
        let (t, face) = best?;
        let [u, v] = face.span();
        Some(Image {
            face,
            uv: [p[u] + t * d[u], p[v] + t * d[v]],
            distance: t,
        })
    }

    /// The point at `image.distance` back along the projection line from `image`'s face point: the inverse of
    /// [`Projection::project`].
    pub fn unproject(&self, image: &Image) -> [f64; 3] {
        let q = face_point(image.face, image.uv);
        // Every projection line through q points the same way along its whole length: away from the centre, the
        // axis or the plane, or along the parallel direction.
        let d = self.direction(q);
        let length = d.iter().map(|c| c * c).sum::<f64>().sqrt();
        [0, 1, 2].map(|k| q[k] - image.distance * d[k] / length)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::rng::SplitMix64;

    fn configurations() -> impl Iterator<Item = FaceSet> {
        (0..64u8).map(FaceSet::from_bits)
    }

    fn random_point(rng: &mut SplitMix64) -> [f64; 3] {
        [(); 3].map(|_| f64::from(rng.next_f32()))
    }

    #[test]
    fn every_point_projects_onto_a_domain_face_of_its_cell() {
        let mut rng = SplitMix64::new(2010);
        for internal in configurations() {
            let projection = Projection::for_cell(internal);
            let domain = domain_faces(internal);
            let case = Case::of_internal(internal);
            let mut hit = FaceSet::EMPTY;
            for _ in 0..2000 {
                let p = random_point(&mut rng);
                let image = projection
                    .project(p)
                    .unwrap_or_else(|| panic!("{case} {internal:?}: {p:?} has no image"));
                assert!(
                    domain.contains(image.face),
                    "{case}, internal {:?}: {p:?} lands on {} ({projection:?})",
                    internal.faces().collect::<Vec<_>>(),
                    image.face
                );
                assert!(image.uv.iter().all(|c| (-1e-12..=1.0 + 1e-12).contains(c)));
                assert!(image.distance >= 0.0 && image.distance <= 3f64.sqrt() + 1e-12);
                hit = hit.with(image.face);
            }
            // Every domain face receives points, so none of its map is wasted.
            assert_eq!(hit, domain, "{case} {internal:?}");
        }
    }

    #[test]
    fn projection_round_trips() {
        let mut rng = SplitMix64::new(7);
        for internal in configurations() {
            let projection = Projection::for_cell(internal);
            for _ in 0..500 {
                let p = random_point(&mut rng);
                let image = projection.project(p).expect("random points have images");
                let back = projection.unproject(&image);
                let error = (0..3).map(|k| (back[k] - p[k]).abs()).fold(0.0, f64::max);
                assert!(
                    error < 1e-12,
                    "{internal:?}: {p:?} -> {image:?} -> {back:?}"
                );
            }
        }
    }

    #[test]
    fn projections_are_the_papers() {
        let (mx, my, pz) = (Face::new(0, false), Face::new(1, false), Face::new(2, true));
        assert_eq!(
            Projection::for_cell(FaceSet::of(&[mx, my, pz])),
            Projection::Perspective {
                centre: [0.0, 0.0, 1.0]
            }
        );
        assert_eq!(
            Projection::for_cell(FaceSet::of(&[mx, my])),
            Projection::Perspective {
                centre: [0.0, 0.0, 0.5]
            }
        );
        // 3a with the opposite pair on x and -y between: the internal edges' midpoints (0, 0, 0.5), (1, 0, 0.5).
        assert_eq!(
            Projection::for_cell(FaceSet::of(&[mx, mx.opposite(), my])),
            Projection::Axial {
                axis: 0,
                point: [0.5, 0.0, 0.5]
            }
        );
        assert_eq!(
            Projection::for_cell(FaceSet::of(&[pz]).complement()),
            Projection::Parallel { face: pz }
        );
        // Points on the centre or axis have no image.
        assert!(Projection::for_cell(FaceSet::EMPTY)
            .project([0.5; 3])
            .is_none());
    }
}
