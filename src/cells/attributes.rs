//! The surface's attributes on the distance maps' texels. Paper 002 keeps a colour and a normal map beside each
//! distance map, sampled where each texel's line meets the surface; here a texel keeps what the mesh's material
//! is shaded from at that point: the interpolated normal, tangent, vertex colour and both texture coordinate
//! sets. The material's textures are then read at the hit at their own resolution, as the rasterised mesh reads
//! them, instead of through a second copy at the maps' resolution.
//!
//! Texels whose line crosses nothing take the attributes of the nearest texel that does (the hit of a ray near a
//! silhouette interpolates between them), so that no texel holds a zero normal. Layers are in the maps' order,
//! which is [`super::PackedComplex`]'s.

use super::distance_map::{CellMaps, FaceMap, SurfacePoint};
use super::parallel::map_in_parallel;

/// A surface point's attributes, as the caller interpolates them from its mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceAttributes {
    /// The first texture coordinate set (glTF `TEXCOORD_0`).
    pub uv0: [f32; 2],
    /// The second texture coordinate set (glTF `TEXCOORD_1`); zeros when the mesh has none.
    pub uv1: [f32; 2],
    /// Unit length.
    pub normal: [f32; 3],
    /// xyz: unit tangent; w: the bitangent's sign.
    pub tangent: [f32; 4],
    /// Linear RGBA.
    pub colour: [f32; 4],
}

/// One texel of the attribute maps as the shader reads it (`CellAttributes` in `cells_march.glsl`, 32 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct AttributeTexel {
    /// [`SurfaceAttributes::uv0`], unchanged.
    pub uv0: [f32; 2],
    /// [`SurfaceAttributes::uv1`], unchanged.
    pub uv1: [f32; 2],
    /// Octahedral, two snorm16 (x in the low half).
    pub normal: u32,
    /// The tangent's direction, octahedral like `normal`.
    pub tangent: u32,
    /// RGBA8 unorm, red in the low byte.
    pub colour: u32,
    /// The bitangent's sign.
    pub tangent_sign: f32,
}

impl AttributeTexel {
    fn pack(a: &SurfaceAttributes) -> AttributeTexel {
        let [tx, ty, tz, sign] = a.tangent;
        AttributeTexel {
            uv0: a.uv0,
            uv1: a.uv1,
            normal: encode_octahedral(a.normal),
            tangent: encode_octahedral([tx, ty, tz]),
            colour: u32::from_le_bytes(a.colour.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)),
            tangent_sign: if sign < 0.0 { -1.0 } else { 1.0 },
        }
    }

    /// The normal as the shader decodes it.
    pub fn decoded_normal(&self) -> [f32; 3] {
        decode_octahedral(self.normal)
    }
}

/// Every domain face's attribute map, `resolution`^2 texels a layer.
pub fn attribute_maps(
    maps: &CellMaps,
    attributes: impl Fn(SurfacePoint) -> SurfaceAttributes + Sync,
) -> Vec<AttributeTexel> {
    let layers = map_in_parallel(&maps.faces, |map| layer(map, maps.resolution, &attributes));
    layers.into_iter().flatten().collect()
}

fn layer(
    map: &FaceMap,
    resolution: u32,
    attributes: &impl Fn(SurfacePoint) -> SurfaceAttributes,
) -> Vec<AttributeTexel> {
    let r = resolution as usize;
    let mut texels: Vec<Option<AttributeTexel>> = map
        .surface
        .iter()
        .map(|&point| {
            point
                .is_hit()
                .then(|| AttributeTexel::pack(&attributes(point)))
        })
        .collect();
    if texels.iter().all(Option::is_none) {
        // No line of this face meets the surface; a ray that stops in its cell reads one of its neighbours'.
        return vec![AttributeTexel::pack(&UNLIT); r * r];
    }
    // Grown one ring of texels at a time from the ones that have a surface point.
    while texels.iter().any(Option::is_none) {
        let previous = texels.clone();
        for (i, texel) in texels.iter_mut().enumerate().filter(|(_, t)| t.is_none()) {
            let (a, b) = (i % r, i / r);
            let neighbours = [
                (a > 0).then(|| i - 1),
                (a + 1 < r).then(|| i + 1),
                (b > 0).then(|| i - r),
                (b + 1 < r).then(|| i + r),
            ];
            *texel = neighbours.into_iter().flatten().find_map(|k| previous[k]);
        }
    }
    texels.into_iter().flatten().collect()
}

/// What a face with no surface point anywhere holds.
const UNLIT: SurfaceAttributes = SurfaceAttributes {
    uv0: [0.0; 2],
    uv1: [0.0; 2],
    normal: [0.0, 0.0, 1.0],
    tangent: [1.0, 0.0, 0.0, 1.0],
    colour: [1.0; 4],
};

/// A unit vector folded onto the octahedron and stored as two snorm16 values (x in the low half), as GLSL's
/// `unpackSnorm2x16` reads them.
pub fn encode_octahedral(v: [f32; 3]) -> u32 {
    let l1 = v[0].abs() + v[1].abs() + v[2].abs();
    if l1.is_nan() || l1 <= 0.0 {
        return encode_octahedral([0.0, 0.0, 1.0]);
    }
    let [x, y, z] = v.map(|c| c / l1);
    let (x, y) = if z < 0.0 {
        ((1.0 - y.abs()) * x.signum(), (1.0 - x.abs()) * y.signum())
    } else {
        (x, y)
    };
    let snorm = |c: f32| (c.clamp(-1.0, 1.0) * 32767.0).round() as i16 as u16;
    u32::from(snorm(x)) | u32::from(snorm(y)) << 16
}

/// [`encode_octahedral`]'s inverse (unit length).
pub fn decode_octahedral(word: u32) -> [f32; 3] {
    let unsnorm = |h: u32| (f32::from(h as u16 as i16) / 32767.0).max(-1.0);
    let (x, y) = (unsnorm(word & 0xffff), unsnorm(word >> 16));
    let z = 1.0 - x.abs() - y.abs();
    let (x, y) = if z < 0.0 {
        ((1.0 - y.abs()) * x.signum(), (1.0 - x.abs()) * y.signum())
    } else {
        (x, y)
    };
    let len = (x * x + y * y + z * z).sqrt();
    [x / len, y / len, z / len]
}

#[cfg(test)]
mod tests {
    use super::super::distance_map::choose_grid;
    use super::super::mesh::shapes::icosphere;
    use super::super::mesh::ClosedMesh;
    use super::*;

    #[test]
    fn octahedral_normals_round_trip_in_every_octant() {
        for x in [-0.9f32, -0.3, 0.0, 0.4, 1.0] {
            for y in [-1.0f32, -0.2, 0.0, 0.7] {
                for z in [-1.0f32, -0.5, 0.0, 0.1, 1.0] {
                    let len = (x * x + y * y + z * z).sqrt();
                    if len == 0.0 {
                        continue;
                    }
                    let v = [x / len, y / len, z / len];
                    let back = decode_octahedral(encode_octahedral(v));
                    let err = (0..3).map(|k| (back[k] - v[k]).abs()).fold(0.0, f32::max);
                    assert!(err < 1e-4, "{v:?} came back as {back:?}");
                }
            }
        }
    }

    #[test]
    fn sphere_texels_carry_the_normal_where_their_line_meets_the_sphere() {
        let (positions, triangles) = icosphere([0.0; 3], 1.0, 3);
        let mesh = ClosedMesh::new("sphere", &positions, &triangles).expect("closed");
        let (_, maps) = choose_grid(&mesh, 16, 0.05, 8);
        // The point itself as its normal: on a sphere about the origin that is the surface normal.
        let point = |p: SurfacePoint| {
            let [a, b, c] = mesh.triangle(p.triangle as usize);
            let [u, v] = p.barycentric.map(f64::from);
            let q: [f64; 3] = std::array::from_fn(|k| a[k] * (1.0 - u - v) + b[k] * u + c[k] * v);
            q.map(|c| c as f32)
        };
        let texels = attribute_maps(&maps, |p| {
            let q = point(p);
            let len = q.iter().map(|c| c * c).sum::<f32>().sqrt();
            SurfaceAttributes {
                uv0: [q[0], q[1]],
                uv1: p.barycentric,
                normal: q.map(|c| c / len),
                tangent: [1.0, 0.0, 0.0, -1.0],
                colour: [0.5; 4],
            }
        });
        let per_layer = (maps.resolution as usize).pow(2);
        assert_eq!(texels.len(), maps.faces.len() * per_layer);
        let mut checked = 0;
        for (map, layer) in maps.faces.iter().zip(texels.chunks(per_layer)) {
            for (point_at, texel) in map.surface.iter().zip(layer) {
                let n = texel.decoded_normal();
                assert!(n.iter().all(|c| c.is_finite()), "{n:?}");
                if !point_at.is_hit() {
                    continue;
                }
                let q = point(*point_at);
                let len = q.iter().map(|c| c * c).sum::<f32>().sqrt();
                // The icosphere's flat faces keep points within 1.5% of the radius.
                assert!((len - 1.0).abs() < 0.015, "{q:?} is off the sphere");
                let err = (0..3)
                    .map(|k| (n[k] - q[k] / len).abs())
                    .fold(0.0, f32::max);
                assert!(err < 1e-3, "normal {n:?} at {q:?}");
                assert_eq!(texel.uv0, [q[0], q[1]]);
                assert_eq!(texel.uv1, point_at.barycentric);
                assert_eq!(texel.tangent_sign, -1.0);
                assert_eq!(texel.colour, 0x8080_8080);
                checked += 1;
            }
        }
        assert!(checked > 1000, "only {checked} texels met the sphere");
    }

    #[test]
    fn texels_without_a_surface_point_take_their_nearest_neighbours() {
        let none = SurfacePoint {
            triangle: SurfacePoint::NONE,
            barycentric: [0.0; 2],
        };
        let hit = |t: u32| SurfacePoint {
            triangle: t,
            barycentric: [0.25, 0.5],
        };
        // 3x3: only the middle-left and the top-right texels meet the surface.
        let mut surface = vec![none; 9];
        surface[3] = hit(7);
        surface[2] = hit(9);
        let map = FaceMap {
            cell: [0, 0, 0],
            face: super::super::Face::ALL[0],
            distances: vec![0.5; 9],
            inside_at_face: Vec::new(),
            surface,
        };
        let texels = layer(&map, 3, &|p: SurfacePoint| SurfaceAttributes {
            uv0: [p.triangle as f32, 0.0],
            ..UNLIT
        });
        let from: Vec<f32> = texels.iter().map(|t| t.uv0[0]).collect();
        // Row by row: each texel's nearest texel with a point (the first found in -x, +x, -y, +y order on a tie).
        assert_eq!(from, vec![7.0, 9.0, 9.0, 7.0, 7.0, 9.0, 7.0, 7.0, 9.0]);
    }
}
