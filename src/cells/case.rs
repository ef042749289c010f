//! The faces of a cubic cell, which of them are external, and the base case (Apaza and Andujar, Figure 4) that decides how
//! the cell is parameterized.
//!
//! A grey cell's face is *external* when the 6-connected neighbour across it is white (outside the mesh), else
//! *internal*. The 2^6 configurations fall, under the 24 rotations of the cube, into ten base cases, named by the
//! number of internal faces and, where that does not settle it, by how they meet:
//!
//! | case | internal faces | configurations |
//! |---|---|---|
//! | 0 | none | 1 |
//! | 1 | one | 6 |
//! | 2a | two sharing an edge | 12 |
//! | 2b | two opposite | 3 |
//! | 3a | three: an opposite pair and one between them (two internal edges) | 12 |
//! | 3b | three meeting at a vertex | 8 |
//! | 4a | four, the two external faces opposite | 3 |
//! | 4b | four, the two external faces sharing an edge | 12 |
//! | 5 | five | 6 |
//! | 6 | six | 1 |

use std::fmt;

/// Coordinate axes of the cell, as indices into a point: 0 = x, 1 = y, 2 = z.
pub type Axis = usize;

/// One of the six faces of the unit cell `[0, 1]^3`: the face where coordinate `axis` is `1` if `positive`, else `0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Face {
    /// The axis the face is perpendicular to (0 = x, 1 = y, 2 = z).
    pub axis: Axis,
    /// `true` for the face at coordinate 1 along `axis`, `false` for the one at 0.
    pub positive: bool,
}

impl Face {
    /// All six faces in index order: -x, +x, -y, +y, -z, +z.
    pub const ALL: [Face; 6] = [
        Face::new(0, false),
        Face::new(0, true),
        Face::new(1, false),
        Face::new(1, true),
        Face::new(2, false),
        Face::new(2, true),
    ];

    /// The face perpendicular to `axis` (0, 1 or 2) at coordinate 1 if `positive`, else 0.
    pub const fn new(axis: Axis, positive: bool) -> Face {
        Face { axis, positive }
    }

    /// The face's index in [`Face::ALL`] (its bit in a [`FaceSet`]).
    pub const fn index(self) -> usize {
        2 * self.axis + self.positive as usize
    }

    /// The face across the cell.
    pub const fn opposite(self) -> Face {
        Face::new(self.axis, !self.positive)
    }

    /// The face's plane coordinate along its axis: 0 or 1.
    pub fn offset(self) -> f64 {
        if self.positive {
            1.0
        } else {
            0.0
        }
    }

    /// The two axes that span the face, in increasing order: its (u, v).
    pub const fn span(self) -> [Axis; 2] {
        match self.axis {
            0 => [1, 2],
            1 => [0, 2],
            _ => [0, 1],
        }
    }
}

impl fmt::Display for Face {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sign = if self.positive { '+' } else { '-' };
        write!(f, "{sign}{}", ['x', 'y', 'z'][self.axis])
    }
}

/// A set of faces of one cell, one bit per face in [`Face::ALL`] order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct FaceSet(u8);

impl FaceSet {
    /// No face.
    pub const EMPTY: FaceSet = FaceSet(0);
    /// All six faces.
    pub const ALL: FaceSet = FaceSet(0b11_1111);

    /// The set with bits `bits` (the low six are used).
    pub const fn from_bits(bits: u8) -> FaceSet {
        FaceSet(bits & 0b11_1111)
    }

    /// The set as bits, bit `f.index()` for face `f` (only the low six can be set).
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// The set of the given faces (duplicates are harmless).
    pub fn of(faces: &[Face]) -> FaceSet {
        faces.iter().fold(FaceSet::EMPTY, |set, &f| set.with(f))
    }

    /// This set with `face` added.
    pub const fn with(self, face: Face) -> FaceSet {
        FaceSet(self.0 | 1 << face.index())
    }

    /// Whether `face` is in the set.
    pub const fn contains(self, face: Face) -> bool {
        self.0 & (1 << face.index()) != 0
    }

    /// Number of faces in the set, 0 to 6.
    pub const fn len(self) -> u32 {
        self.0.count_ones()
    }

    /// Whether the set holds no face.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The faces not in the set.
    pub const fn complement(self) -> FaceSet {
        FaceSet(!self.0 & 0b11_1111)
    }

    /// The faces of the set, in [`Face::ALL`] order.
    pub fn faces(self) -> impl Iterator<Item = Face> {
        Face::ALL.into_iter().filter(move |&f| self.contains(f))
    }

    /// Whether the set holds both faces of some axis.
    pub fn has_opposite_pair(self) -> bool {
        (0..3).any(|axis| {
            self.contains(Face::new(axis, false)) && self.contains(Face::new(axis, true))
        })
    }
}

/// The ten base cases of Apaza and Andujar (Figure 4); see the module docs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Case {
    /// No internal face: an isolated grey cell.
    C0,
    /// One internal face.
    C1,
    /// Two internal faces sharing an edge.
    C2a,
    /// Two opposite internal faces.
    C2b,
    /// Three internal faces: an opposite pair and one between them.
    C3a,
    /// Three internal faces meeting at a vertex.
    C3b,
    /// Four internal faces, the two external ones opposite.
    C4a,
    /// Four internal faces, the two external ones sharing an edge.
    C4b,
    /// Five internal faces: one external face.
    C5,
    /// Six internal faces: an interior grey cell, every neighbour grey or black.
    C6,
}

impl Case {
    /// The ten cases in the module docs' table order.
    pub const ALL: [Case; 10] = [
        Case::C0,
        Case::C1,
        Case::C2a,
        Case::C2b,
        Case::C3a,
        Case::C3b,
        Case::C4a,
        Case::C4b,
        Case::C5,
        Case::C6,
    ];

    /// The case of a grey cell whose internal faces are `internal`. Rotations preserve the number of internal faces,
    /// whether two of them are opposite, and the same of the external ones, which is all that tells the cases apart.
    pub fn of_internal(internal: FaceSet) -> Case {
        let external = internal.complement();
        match internal.len() {
            0 => Case::C0,
            1 => Case::C1,
            2 if internal.has_opposite_pair() => Case::C2b,
            2 => Case::C2a,
            3 if internal.has_opposite_pair() => Case::C3a,
            3 => Case::C3b,
            4 if external.has_opposite_pair() => Case::C4a,
            4 => Case::C4b,
            5 => Case::C5,
            _ => Case::C6,
        }
    }

    /// The paper's name: "0", "1", "2a", ...
    pub fn name(self) -> &'static str {
        match self {
            Case::C0 => "0",
            Case::C1 => "1",
            Case::C2a => "2a",
            Case::C2b => "2b",
            Case::C3a => "3a",
            Case::C3b => "3b",
            Case::C4a => "4a",
            Case::C4b => "4b",
            Case::C5 => "5",
            Case::C6 => "6",
        }
    }
}

impl fmt::Display for Case {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "case {}", self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// The 24 rotations of the cube as face permutations, generated by quarter turns about x and y.
    fn rotations() -> Vec<[Face; 6]> {
        // A quarter turn about `axis` maps the face on axis a (the next axis cyclically) to axis b (the one after),
        // and the face on b to the opposite side of a.
        let turn = |axis: Axis, f: Face| -> Face {
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            if f.axis == a {
                Face::new(b, f.positive)
            } else if f.axis == b {
                Face::new(a, !f.positive)
            } else {
                f
            }
        };
        let identity = Face::ALL;
        let mut found: Vec<[Face; 6]> = vec![identity];
        let mut seen: HashSet<[Face; 6]> = found.iter().copied().collect();
        let mut next = 0;
        while next < found.len() {
            let current = found[next];
            next += 1;
            for axis in [0, 1] {
                let moved = current.map(|f| turn(axis, f));
                if seen.insert(moved) {
                    found.push(moved);
                }
            }
        }
        found
    }

    fn rotate(set: FaceSet, rotation: &[Face; 6]) -> FaceSet {
        FaceSet::of(&set.faces().map(|f| rotation[f.index()]).collect::<Vec<_>>())
    }

    #[test]
    fn the_cube_has_24_rotations() {
        assert_eq!(rotations().len(), 24);
    }

    #[test]
    fn the_64_configurations_fall_into_the_ten_cases_as_the_rotations_imply() {
        let rotations = rotations();
        // Per case: its configurations, and the orbit of the first under the rotations.
        let expected = [
            (Case::C0, 1),
            (Case::C1, 6),
            (Case::C2a, 12),
            (Case::C2b, 3),
            (Case::C3a, 12),
            (Case::C3b, 8),
            (Case::C4a, 3),
            (Case::C4b, 12),
            (Case::C5, 6),
            (Case::C6, 1),
        ];
        let mut total = 0;
        for (case, count) in expected {
            let members: HashSet<FaceSet> = (0..64u8)
                .map(FaceSet::from_bits)
                .filter(|&s| Case::of_internal(s) == case)
                .collect();
            assert_eq!(members.len(), count, "{case}");
            let first = *members.iter().next().expect("every case occurs");
            let orbit: HashSet<FaceSet> = rotations.iter().map(|r| rotate(first, r)).collect();
            assert_eq!(orbit, members, "{case} is one orbit of the rotations");
            total += count;
        }
        assert_eq!(total, 64);
    }

    #[test]
    fn cases_follow_the_papers_descriptions() {
        let (mx, px, my, py, pz) = (
            Face::new(0, false),
            Face::new(0, true),
            Face::new(1, false),
            Face::new(1, true),
            Face::new(2, true),
        );
        assert_eq!(Case::of_internal(FaceSet::of(&[mx, my])), Case::C2a);
        assert_eq!(Case::of_internal(FaceSet::of(&[mx, px])), Case::C2b);
        // An opposite pair and a face between them: internal edges (-x, -y) and (+x, -y).
        assert_eq!(Case::of_internal(FaceSet::of(&[mx, px, my])), Case::C3a);
        assert_eq!(Case::of_internal(FaceSet::of(&[mx, my, pz])), Case::C3b);
        // Complements: external +-y opposite (4a), external +x, +y adjacent (4b).
        assert_eq!(
            Case::of_internal(FaceSet::of(&[my, py]).complement()),
            Case::C4a
        );
        assert_eq!(
            Case::of_internal(FaceSet::of(&[px, py]).complement()),
            Case::C4b
        );
        assert_eq!(format!("{}", Case::C3b), "case 3b");
        assert_eq!(format!("{px} {my}"), "+x -y");
    }
}
