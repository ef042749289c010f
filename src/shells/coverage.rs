//! Which pixels of a view the shells cover: one ray through each pixel's centre, as the raster
//! pass samples it, traced on every core. What a silhouette is measured by, without a GPU.

use glam::{DVec3, Vec4};

use super::prism::Shell;
use crate::scene::Camera;

/// Row-major coverage of a `size` image seen through `camera`: true where a pixel's ray meets
/// the relief inside some shell.
pub fn coverage(shells: &[Shell], camera: &Camera, size: [u32; 2]) -> Vec<bool> {
    let [width, height] = size;
    let inverse = camera
        .view_projection(width as f32 / height.max(1) as f32)
        .inverse();
    let ray = |x: u32, y: u32| {
        // Vulkan clip space: y down like the image's rows, depth 0 at the near plane.
        let ndc_x = (x as f32 + 0.5) / width as f32 * 2.0 - 1.0;
        let ndc_y = (y as f32 + 0.5) / height as f32 * 2.0 - 1.0;
        let near = inverse * Vec4::new(ndc_x, ndc_y, 0.0, 1.0);
        let far = inverse * Vec4::new(ndc_x, ndc_y, 1.0, 1.0);
        let (near, far) = (
            (near.truncate() / near.w).as_dvec3(),
            (far.truncate() / far.w).as_dvec3(),
        );
        (near, far - near)
    };
    let covered = |x: u32, y: u32| {
        let (origin, dir): (DVec3, DVec3) = ray(x, y);
        shells
            .iter()
            .any(|s| s.trace(origin, dir).is_some_and(|h| h.t <= 1.0))
    };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u32;
    let mut out = vec![false; (width * height) as usize];
    std::thread::scope(|scope| {
        let rows_each = height.div_ceil(threads.max(1)).max(1);
        for (k, chunk) in out
            .chunks_mut((rows_each * width).max(1) as usize)
            .enumerate()
        {
            let covered = &covered;
            scope.spawn(move || {
                for (i, px) in chunk.iter_mut().enumerate() {
                    let i = i as u32 + k as u32 * rows_each * width;
                    *px = covered(i % width, i / width);
                }
            });
        }
    });
    out
}
