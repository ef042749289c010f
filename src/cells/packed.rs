//! A cell complex in the layout the GPU march reads (`shaders/passes/cells_trace.comp`): plain arrays, no Vulkan.
//!
//! - `cells`: one word per grid cell in [`CellGrid`]'s order (x fastest): the colour in the low two bits (0 white,
//!   1 grey, 2 black) and, for grey cells, the cell's slot in `grey` above them;
//! - `grey`: per grey cell its projection and the map layer of each face (-1 for faces that are not domain faces);
//! - `maps`: every domain face's map, a layer of `resolution`^2 16-bit texels, two to a word (the even texel in
//!   the low half): the distance over a cell's diagonal (sqrt 3 sides) in the top 15 bits, whether the texel's
//!   face point lies inside the mesh in the lowest, rounded up (see [`PackedComplex::new`]). The paper stores
//!   16-bit distances; the flag costs one bit of them (5e-5 cell sides) and only interior cells ever set it.

use super::distance_map::CellMaps;
use super::grid::{CellGrid, Colour};
use super::projection::Projection;

/// Distances are stored over this length (a cell's diagonal, the longest projection line).
pub const DISTANCE_RANGE: f64 = 1.732_050_807_568_877_2;

/// Steps of a stored distance over [`DISTANCE_RANGE`].
const DISTANCE_STEPS: f64 = 32767.0;

/// One grey cell as the shader reads it (`GreyCell` in cells_trace.comp, 64 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GreyRecord {
    /// Perspective: the centre; axial: a point of the axis; planar: the plane's offset in `w`.
    pub param: [f32; 4],
    /// 0 perspective, 1 axial, 2 planar, 3 parallel.
    pub kind: u32,
    /// The axis of an axial, planar or parallel projection.
    pub axis: u32,
    /// Parallel: 1 when the projection runs toward the positive face.
    pub positive: u32,
    /// Padding to the shader's 16-byte alignment; always 0.
    pub pad: u32,
    /// Map layer per face in [`super::Face::ALL`] order, -1 for a face that carries none.
    pub layers: [i32; 6],
    /// Padding to the record's 64 bytes; always 0.
    pub pad2: [i32; 2],
}

/// The complex's arrays and the numbers the shader needs with them.
#[derive(Debug, Clone)]
pub struct PackedComplex {
    /// One word per grid cell, x fastest: colour in the low two bits (0 white, 1 grey, 2 black), a grey cell's
    /// index into `grey` above them (see the module docs).
    pub cells: Vec<u32>,
    /// One record per grey cell, in the order the maps first name it.
    pub grey: Vec<GreyRecord>,
    /// All map layers, `resolution`^2 16-bit texels each, two to a word: distance over [`DISTANCE_RANGE`] in the
    /// top 15 bits (decode with [`PackedComplex::decode`]), the inside flag in the lowest.
    pub maps: Vec<u32>,
    /// The grid cube's least corner, in mesh space ([`CellGrid::origin`]).
    pub origin: [f32; 3],
    /// The side of one cell, in mesh units ([`CellGrid::cell_size`]).
    pub cell_size: f32,
    /// Cells per axis of the grid.
    pub n: u32,
    /// Texels along each side of a map layer.
    pub resolution: u32,
}

impl PackedComplex {
    /// Packs `maps` (sampled on `grid`).
    pub fn new(grid: &CellGrid, maps: &CellMaps) -> PackedComplex {
        let mut grey_slot = std::collections::HashMap::new();
        let mut grey: Vec<GreyRecord> = Vec::new();
        let texels = (maps.resolution as usize).pow(2);
        let mut halves: Vec<u16> = Vec::with_capacity(maps.faces.len() * texels);
        let r = maps.resolution;
        for (layer, map) in maps.faces.iter().enumerate() {
            let projection = Projection::for_cell(grid.internal_faces(map.cell));
            let slot = *grey_slot.entry(map.cell).or_insert_with(|| {
                grey.push(record(projection));
                grey.len() - 1
            });
            grey[slot].layers[map.face.index()] = layer as i32;
            for (t, &d) in map.distances.iter().enumerate() {
                let uv = [t as u32 % r, t as u32 / r].map(|x| (f64::from(x) + 0.5) / f64::from(r));
                let full = projection.line_length(map.face, uv);
                // Rounded up, so that no stored surface comes nearer than the sampled one; a line that crosses
                // nothing gets a step past its end, so that no point of it (in f32) ever lies past its surface.
                let steps = if f64::from(d) >= full * (1.0 - 1e-6) {
                    (full / DISTANCE_RANGE * DISTANCE_STEPS).ceil() + 1.0
                } else {
                    (f64::from(d) / DISTANCE_RANGE * DISTANCE_STEPS).ceil()
                };
                let steps = steps.clamp(0.0, DISTANCE_STEPS) as u16;
                let inside = map.inside_at_face.get(t).copied().unwrap_or(false);
                halves.push(steps << 1 | u16::from(inside));
            }
        }
        let maps_words = halves
            .chunks(2)
            .map(|pair| u32::from(pair[0]) | u32::from(*pair.get(1).unwrap_or(&0)) << 16)
            .collect();
        let cells = grid
            .cells()
            .map(|cell| match grid.colour(cell) {
                Colour::White => 0,
                Colour::Grey => 1 | (*grey_slot.get(&cell).unwrap_or(&0) as u32) << 2,
                Colour::Black => 2,
            })
            .collect();
        PackedComplex {
            cells,
            grey,
            maps: maps_words,
            origin: grid.origin().map(|c| c as f32),
            cell_size: grid.cell_size() as f32,
            n: grid.n(),
            resolution: maps.resolution,
        }
    }

    /// A stored distance (cell sides) as the shader decodes it.
    pub fn decode(half: u16) -> f64 {
        f64::from(half >> 1) / DISTANCE_STEPS * DISTANCE_RANGE
    }
}

fn record(projection: Projection) -> GreyRecord {
    let mut r = GreyRecord {
        param: [0.0; 4],
        kind: 0,
        axis: 0,
        positive: 0,
        pad: 0,
        layers: [-1; 6],
        pad2: [0; 2],
    };
    match projection {
        Projection::Perspective { centre } => {
            r.param = [centre[0] as f32, centre[1] as f32, centre[2] as f32, 0.0];
        }
        Projection::Axial { axis, point } => {
            r.kind = 1;
            r.axis = axis as u32;
            r.param = [point[0] as f32, point[1] as f32, point[2] as f32, 0.0];
        }
        Projection::Planar { axis, offset } => {
            r.kind = 2;
            r.axis = axis as u32;
            r.param[3] = offset as f32;
        }
        Projection::Parallel { face } => {
            r.kind = 3;
            r.axis = face.axis as u32;
            r.positive = u32::from(face.positive);
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::super::mesh::shapes::torus;
    use super::super::mesh::ClosedMesh;
    use super::*;

    #[test]
    fn cells_point_at_their_grey_records_and_maps_round_trip() {
        let (p, t) = torus([0.0; 3], 1.0, 0.4, 24, 12);
        let ring = ClosedMesh::new("torus", &p, &t).expect("closed");
        let grid = CellGrid::classify(&ring, 4);
        let maps = CellMaps::sample(&ring, &grid, 8);
        let packed = PackedComplex::new(&grid, &maps);
        assert_eq!(packed.cells.len(), 64);
        assert_eq!(packed.maps.len(), (maps.faces.len() * 64).div_ceil(2));
        for (i, cell) in grid.cells().enumerate() {
            let word = packed.cells[i];
            match grid.colour(cell) {
                Colour::White => assert_eq!(word, 0),
                Colour::Black => assert_eq!(word, 2),
                Colour::Grey => {
                    assert_eq!(word & 3, 1);
                    let record = packed.grey[(word >> 2) as usize];
                    for (layer, map) in maps
                        .faces
                        .iter()
                        .enumerate()
                        .filter(|(_, m)| m.cell == cell)
                    {
                        assert_eq!(record.layers[map.face.index()], layer as i32);
                        for (t, &d) in map.distances.iter().enumerate() {
                            let index = layer * 64 + t;
                            let half = (packed.maps[index / 2] >> (16 * (index % 2))) as u16;
                            // Rounded up by at most two steps (a line that crosses nothing gets one more).
                            let stored = PackedComplex::decode(half);
                            assert!(
                                stored >= f64::from(d) - 1e-6 && stored - f64::from(d) < 1.1e-4,
                                "{stored} for {d}"
                            );
                        }
                    }
                }
            }
        }
    }
}
