//! How a triangle's surface stretches against its texture coordinates: the world vectors of one uv
//! unit, the map between two uv sets, and the world length of one unit of relief depth.

use glam::{DMat2, DVec3, Vec2};

/// World vectors per unit of `uv` along u and v over the triangle with edges `e1 = p1 - p0` and
/// `e2 = p2 - p0`, or `None` if the uvs are degenerate.
pub fn world_per_uv(e1: DVec3, e2: DVec3, uv: [Vec2; 3]) -> Option<[DVec3; 2]> {
    let (d1, d2) = ((uv[1] - uv[0]).as_dvec2(), (uv[2] - uv[0]).as_dvec2());
    let det = d1.x * d2.y - d2.x * d1.y;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some([(e1 * d2.y - e2 * d1.y) / det, (e2 * d1.x - e1 * d2.x) / det])
}

/// The linear map from `from` uvs to `to` uvs over the triangle.
pub fn uv_per_uv(to: [Vec2; 3], from: [Vec2; 3]) -> Option<DMat2> {
    let t = DMat2::from_cols((to[1] - to[0]).as_dvec2(), (to[2] - to[0]).as_dvec2());
    let f = DMat2::from_cols(
        (from[1] - from[0]).as_dvec2(),
        (from[2] - from[0]).as_dvec2(),
    );
    let m = t * f.inverse();
    m.is_finite().then_some(m)
}

/// World length of one unit of relief depth (in height-uv units) over a triangle: the geometric
/// mean of the world lengths of one uv0 unit along u and v, over the area factor of the map from
/// uv0 to height uv. The surface pass derives the same from screen derivatives, so a depth scale
/// means one thing on a stretched quad, a curved mesh and every CPU reference. `None` when a uv
/// map is degenerate.
pub fn depth_length(e1: DVec3, e2: DVec3, height_uv: [Vec2; 3], uv0: [Vec2; 3]) -> Option<f64> {
    let per_uv0 = world_per_uv(e1, e2, uv0)?;
    let area = uv_per_uv(height_uv, uv0)?.determinant().abs();
    let len = (per_uv0[0].length() * per_uv0[1].length() / area).sqrt();
    len.is_finite().then_some(len)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stretched_quad_takes_the_geometric_mean_of_its_axes() {
        // 4 world units per u, 1 per v; height uv repeats the map twice along u.
        let (e1, e2) = (DVec3::new(4.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0));
        let uv0 = [Vec2::ZERO, Vec2::X, Vec2::Y];
        let height = [Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::Y];
        let len = depth_length(e1, e2, height, uv0).expect("a frame");
        assert!((len - (4.0f64 / 2.0).sqrt()).abs() < 1e-12, "{len}");
        assert_eq!(depth_length(e1, e2, [Vec2::ZERO; 3], uv0), None);
    }
}
