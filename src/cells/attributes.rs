//! The surface's shading attributes as the cells pass reads them. Paper 002 keeps a colour and a normal map beside
//! each distance map, sampled where each texel's line meets the surface, and blends them at a hit. Blending texels
//! smears whatever changes faster than a texel: a crease where the mesh's normals turn sharply (a sphere's pole),
//! or two sheets of surface that one texel quad straddles, which shade the hit with a normal from a part of the
//! mesh it is not on. Here a texel keeps only which triangle of the mesh its line meets
//! ([`super::surface_triangles`]), and the pass interpolates that triangle's own corners at the hit itself: the
//! normal, tangent, vertex colour and both uv sets are then those the rasterised mesh would have there, at any map
//! resolution, and a texel costs 4 bytes instead of 32.

/// One corner of one of the mesh's triangles, in world space, as the shader reads it (`CellCorner` in
/// `cells.frag`, 48 bytes, three per triangle in the mesh's triangle order).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CornerAttributes {
    /// World-space position.
    pub position: [f32; 3],
    /// Octahedral unit normal, two snorm16 (x in the low half).
    pub normal: u32,
    /// The first texture coordinate set (glTF `TEXCOORD_0`).
    pub uv0: [f32; 2],
    /// The second texture coordinate set (glTF `TEXCOORD_1`); zeros when the mesh has none.
    pub uv1: [f32; 2],
    /// The tangent's direction, octahedral like `normal`.
    pub tangent: u32,
    /// RGBA8 unorm, red in the low byte.
    pub colour: u32,
    /// The bitangent's sign.
    pub tangent_sign: f32,
    /// The triangle across the edge opposite this corner (in the same order), or
    /// [`super::NO_TRIANGLE`]: the pass walks from a texel's triangle to the one a hit lies on.
    pub opposite: u32,
}

impl CornerAttributes {
    /// Packs a corner with no triangle across from it yet: `tangent`'s w is the bitangent's sign, `colour`
    /// linear RGBA.
    pub fn pack(
        position: [f32; 3],
        normal: [f32; 3],
        tangent: [f32; 4],
        uv0: [f32; 2],
        uv1: [f32; 2],
        colour: [f32; 4],
    ) -> CornerAttributes {
        let [tx, ty, tz, sign] = tangent;
        CornerAttributes {
            position,
            normal: encode_octahedral(normal),
            uv0,
            uv1,
            tangent: encode_octahedral([tx, ty, tz]),
            colour: u32::from_le_bytes(colour.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)),
            tangent_sign: if sign < 0.0 { -1.0 } else { 1.0 },
            opposite: super::NO_TRIANGLE,
        }
    }

    /// The normal as the shader decodes it.
    pub fn decoded_normal(&self) -> [f32; 3] {
        decode_octahedral(self.normal)
    }
}

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
    fn a_corner_packs_as_the_shader_reads_it() {
        assert_eq!(std::mem::size_of::<CornerAttributes>(), 48);
        let c = CornerAttributes::pack(
            [1.0, 2.0, 3.0],
            [0.0, 0.0, -1.0],
            [0.0, 1.0, 0.0, -0.5],
            [0.25, 0.5],
            [0.0; 2],
            [1.0, 0.0, 0.5, 2.0],
        );
        assert_eq!(c.decoded_normal(), [0.0, 0.0, -1.0]);
        assert_eq!(decode_octahedral(c.tangent), [0.0, 1.0, 0.0]);
        assert_eq!(c.tangent_sign, -1.0);
        // Red in the low byte, out-of-range channels clamped.
        assert_eq!(c.colour.to_le_bytes(), [255, 0, 128, 255]);
    }
}
