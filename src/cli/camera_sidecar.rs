//! `relief render --camera-out FILE.json`: each frame's camera as JSON beside its image, so that
//! a dataset builder or a compositor can unproject the depth without reading relief's code.

use glam::Mat4;
use relief::scene::{Camera, Projection};
use serde_json::{json, Value};

/// What the matrices mean, written into every file.
const CONVENTIONS: &str = "matrices are column-major (16 numbers, column after column) and \
multiply column vectors; world and view space are right-handed, y up, the camera looking down -z; \
clip space is Vulkan's: x right, y down, depth 0 at the near plane and 1 at the far one; pixel \
(i, j) has its centre at ndc ((i + 0.5) / width * 2 - 1, (j + 0.5) / height * 2 - 1), rows top \
to bottom; the EXR's Z is the distance along the camera's axis (-z of view space)";

/// The JSON for `camera` drawing frame `frame` (1-based, as in the file names) at `width` x
/// `height`. Keys come out sorted, so the same camera gives the same bytes.
pub fn camera_json(camera: &Camera, frame: u32, width: u32, height: u32) -> Value {
    let aspect = width as f32 / height.max(1) as f32;
    let (near, far) = camera.near_far();
    let lens = match camera.projection {
        Projection::Perspective { yfov, aspect, .. } => json!({
            "type": "perspective",
            "yfov_radians": yfov,
            "aspect": aspect.unwrap_or(width as f32 / height.max(1) as f32),
        }),
        Projection::Orthographic { xmag, ymag, .. } => json!({
            "type": "orthographic",
            "xmag": xmag,
            "ymag": ymag,
        }),
    };
    let matrix = |m: Mat4| m.to_cols_array().to_vec();
    json!({
        "frame": frame,
        "width": width,
        "height": height,
        "near": near,
        "far": far,
        "lens": lens,
        "eye": camera.eye().to_array(),
        "view": matrix(camera.view),
        "camera_to_world": matrix(camera.view.inverse()),
        "projection": matrix(camera.clip_from_view(aspect)),
        "view_projection": matrix(camera.view_projection(aspect)),
        "conventions": CONVENTIONS,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, Vec4};

    #[test]
    fn the_matrices_project_a_point_where_the_conventions_say() {
        let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 0.9, 0.5, 50.0);
        let value = camera_json(&camera, 1, 640, 480);
        let read = |key: &str| {
            let v: Vec<f32> = value[key]
                .as_array()
                .expect("an array")
                .iter()
                .map(|x| x.as_f64().expect("a number") as f32)
                .collect();
            Mat4::from_cols_slice(&v)
        };
        let (view, projection) = (read("view"), read("projection"));
        assert!(read("view_projection").abs_diff_eq(projection * view, 1e-5));
        // A point 3 units in front of the camera, above its axis: its view z is -3, and it
        // projects above the centre, that is at negative clip y.
        let p = view * Vec4::new(0.0, 1.0, 2.0, 1.0);
        assert!((p.z + 3.0).abs() < 1e-5, "{p}");
        let clip = projection * p;
        assert!(clip.y / clip.w < 0.0, "{clip}");
        // A point on the near plane has depth 0, one on the far plane depth 1.
        for (distance, depth) in [(0.5, 0.0), (50.0, 1.0)] {
            let c = projection * Vec4::new(0.0, 0.0, -distance, 1.0);
            assert!((c.z / c.w - depth).abs() < 1e-4, "{distance}: {c}");
        }
        assert_eq!(value["near"], 0.5);
        assert_eq!(value["lens"]["type"], "perspective");
        let eye = read("camera_to_world").transform_point3(Vec3::ZERO);
        assert!((eye - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-5);
    }
}
