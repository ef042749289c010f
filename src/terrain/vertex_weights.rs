//! Layer weights from vertex colours: a mesh's colours (channel k weighs layer k) rasterised over
//! its texture coordinates into a splat map, so that painted vertices weigh layers like a painted
//! texture does. Texel centres inside a triangle take its colours interpolated; texels no
//! triangle covers take the mean of covered neighbours, a few rings out, so that bilinear reads
//! along a chart's edge do not fetch zero weights.

use super::layers::{LayerError, SplatMap};
use crate::geometry::Mesh;

/// Rings of uncovered texels filled from their covered neighbours.
const DILATION_RINGS: usize = 4;

/// The `size` x `size` splat map of `meshes`' vertex colours over their first uv set (wrapped
/// into 0..1 per triangle only as given: uvs outside 0..1 fall off the map).
pub fn splat_from_vertex_colors(meshes: &[&Mesh], size: u32) -> Result<SplatMap, LayerError> {
    let n = size as usize;
    let mut texels = vec![[0.0f32; 4]; n * n];
    let mut covered = vec![false; n * n];
    for mesh in meshes {
        for tri in mesh.indices.chunks_exact(3) {
            let v = [0, 1, 2].map(|k| &mesh.vertices[tri[k] as usize]);
            let p = v.map(|v| [v.uv[0] * size as f32, v.uv[1] * size as f32]);
            let area = edge(p[0], p[1], p[2]);
            if area.abs() < 1e-12 {
                continue;
            }
            let lo = |a: usize| p.iter().map(|q| q[a]).fold(f32::MAX, f32::min);
            let hi = |a: usize| p.iter().map(|q| q[a]).fold(f32::MIN, f32::max);
            let range = |a: usize| {
                let first = (lo(a) - 0.5).ceil().max(0.0) as usize;
                let last = (hi(a) - 0.5).floor().min(size as f32 - 1.0);
                (first, last)
            };
            let ((x0, x1), (y0, y1)) = (range(0), range(1));
            if x1 < 0.0 || y1 < 0.0 {
                continue;
            }
            for y in y0..=y1 as usize {
                for x in x0..=x1 as usize {
                    let c = [x as f32 + 0.5, y as f32 + 0.5];
                    let b = [
                        edge(p[1], p[2], c),
                        edge(p[2], p[0], c),
                        edge(p[0], p[1], c),
                    ]
                    .map(|e| e / area);
                    if b.iter().any(|&w| w < -1e-6) {
                        continue;
                    }
                    let t = y * n + x;
                    texels[t] = std::array::from_fn(|k| {
                        (b[0] * v[0].color[k] + b[1] * v[1].color[k] + b[2] * v[2].color[k])
                            .max(0.0)
                    });
                    covered[t] = true;
                }
            }
        }
    }
    dilate(&mut texels, &mut covered, n);
    SplatMap::new(size, size, texels)
}

/// Twice the signed area of triangle (a, b, c).
fn edge(a: [f32; 2], b: [f32; 2], c: [f32; 2]) -> f32 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn dilate(texels: &mut [[f32; 4]], covered: &mut [bool], n: usize) {
    for _ in 0..DILATION_RINGS {
        let before = covered.to_vec();
        let values = texels.to_vec();
        for y in 0..n {
            for x in 0..n {
                let t = y * n + x;
                if before[t] {
                    continue;
                }
                let mut sum = [0.0f32; 4];
                let mut count = 0.0;
                for (dx, dy) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if nx < 0 || ny < 0 || nx >= n as i64 || ny >= n as i64 {
                        continue;
                    }
                    let s = ny as usize * n + nx as usize;
                    if before[s] {
                        for k in 0..4 {
                            sum[k] += values[s][k];
                        }
                        count += 1.0;
                    }
                }
                if count > 0.0 {
                    texels[t] = sum.map(|v| v / count);
                    covered[t] = true;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Vertex;
    use glam::Mat4;

    fn vertex(uv: [f32; 2], color: [f32; 4]) -> Vertex {
        Vertex {
            color,
            ..Vertex::new(
                [uv[0], 0.0, uv[1]],
                [0.0, 1.0, 0.0],
                uv,
                [1.0, 0.0, 0.0, 1.0],
            )
        }
    }

    #[test]
    fn a_quad_painted_left_red_right_green_weighs_layers_across() {
        let red = [1.0, 0.0, 0.0, 0.0];
        let green = [0.0, 1.0, 0.0, 0.0];
        let mesh = Mesh {
            name: "quad".into(),
            vertices: vec![
                vertex([0.0, 0.0], red),
                vertex([1.0, 0.0], green),
                vertex([1.0, 1.0], green),
                vertex([0.0, 1.0], red),
            ],
            indices: vec![0, 2, 1, 0, 3, 2],
            material: 0,
            transform: Mat4::IDENTITY,
        };
        let splat = splat_from_vertex_colors(&[&mesh], 16).unwrap();
        for x in 0..16 {
            let w = splat.texel(x, 7);
            let u = (x as f32 + 0.5) / 16.0;
            assert!((w[0] - (1.0 - u)).abs() < 1e-4, "{x}: {w:?}");
            assert!((w[1] - u).abs() < 1e-4, "{x}: {w:?}");
        }
    }

    #[test]
    fn uncovered_texels_take_their_covered_neighbours_weights() {
        // One triangle over the lower-left half: the texels just past its diagonal are filled.
        let blue = [0.0, 0.0, 1.0, 0.0];
        let mesh = Mesh {
            name: "half".into(),
            vertices: vec![
                vertex([0.0, 0.0], blue),
                vertex([1.0, 1.0], blue),
                vertex([0.0, 1.0], blue),
            ],
            indices: vec![0, 1, 2],
            material: 0,
            transform: Mat4::IDENTITY,
        };
        let splat = splat_from_vertex_colors(&[&mesh], 16).unwrap();
        assert_eq!(splat.texel(9, 7), blue);
        assert_eq!(splat.texel(15, 0), [0.0; 4], "far from any triangle");
    }
}
