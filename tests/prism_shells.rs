//! Prism shells (`Silhouettes::Shells`) against the displaced-geometry reference: the CPU
//! march's outline and the GPU's drawing cover what the displaced sphere, torus and open cylinder
//! cover (silhouette IoU >= 0.98, mean channel difference <= 3 levels, closer than flat relief),
//! and no pixel inside the outline is left uncovered where prisms meet, face-on to grazing. On
//! failure the images are left under `target/test-output/displaced-reference/`.

mod common;

use common::displaced::{
    displaced, draw, mean_difference, save, scene, sphere_and_torus, HEIGHT, WIDTH,
};
use glam::Vec3;
use relief::displaced_reference::{coverage, iou};
use relief::heightfield::{Address, Generator};
use relief::method::Method;
use relief::render::{render, RenderOptions};
use relief::scene::{cylinder_mesh, Silhouettes};
use relief::shells::scene_shells;

#[test]
fn prism_shells_cover_what_the_displaced_mesh_covers() {
    let Some(ctx) = common::device("prism_shells_cover_what_the_displaced_mesh_covers") else {
        return;
    };
    let heights = Generator::Fbm.generate(64, 64, 3);
    // Open, lying along x so that no view looks into it: its ends are an open boundary the
    // displaced surface leaves inward.
    let mut cylinder = cylinder_mesh("open cylinder", 1.0, 2.0, std::f32::consts::TAU, 48, 4, 0);
    cylinder.transform = glam::Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2);
    let cylinder_depth = 0.05 / (std::f32::consts::TAU * 2.0).sqrt();
    let meshes =
        sphere_and_torus()
            .into_iter()
            .chain([("open cylinder", cylinder, cylinder_depth)]);
    for (name, mesh, depth) in meshes {
        for (eye, view) in [
            (Vec3::new(0.0, 1.5, 2.6) * 1.2, "30 degrees"),
            (Vec3::new(0.0, 2.9, 0.78) * 1.2, "75 degrees"),
        ] {
            let mut flat = scene(mesh.clone(), depth, eye);
            if let Some(relief) = flat.materials[0].relief.as_mut() {
                relief.method = Method::RELIEF;
            }
            let reference = draw(&ctx, &displaced(&flat, &heights, 1.0), None);
            let truth = coverage(&reference);
            let shells = scene_shells(&flat, Some(&heights), Address::Repeat).expect("shells");
            let camera = flat.camera.expect("a camera");
            let marched = relief::shells::coverage(&shells, &camera, [WIDTH, HEIGHT]);
            let flat_image = draw(&ctx, &flat, Some(&heights));
            let mut shelled = flat.clone();
            if let Some(relief) = shelled.materials[0].relief.as_mut() {
                relief.silhouettes = Silhouettes::Shells;
            }
            let gpu = draw(&ctx, &shelled, Some(&heights));
            let (cpu_iou, gpu_iou, flat_iou) = (
                iou(&marched, &truth),
                iou(&coverage(&gpu), &truth),
                iou(&coverage(&flat_image), &truth),
            );
            let gpu_diff = mean_difference(&gpu, &reference, |_| true);
            let flat_diff = mean_difference(&flat_image, &reference, |_| true);
            eprintln!(
                "{name}, {view}: silhouette IoU shells {gpu_iou:.4} (CPU march {cpu_iou:.4}), flat {flat_iou:.4}; mean channel difference shells {gpu_diff:.2}, flat {flat_diff:.2}"
            );
            let stem = format!("{name}_{}", view.replace(' ', "_"));
            if gpu_iou < 0.98 || gpu_diff > 3.0 {
                save(&format!("{stem}_shells"), &gpu);
                save(&format!("{stem}_reference"), &reference);
            }
            assert!(
                cpu_iou >= 0.99 && cpu_iou > flat_iou,
                "{name}, {view}: the CPU march's outline agrees {cpu_iou:.4} (flat {flat_iou:.4})"
            );
            assert!(
                gpu_iou >= 0.98 && gpu_iou > flat_iou,
                "{name}, {view}: the GPU shells' outline agrees {gpu_iou:.4} (flat {flat_iou:.4})"
            );
            assert!(
                gpu_diff <= 3.0 && gpu_diff < flat_diff,
                "{name}, {view}: the GPU shells differ by {gpu_diff:.2} levels (flat {flat_diff:.2})"
            );
        }
    }
}

/// Pixels `truth` covers that `rgba` leaves to the background while covering all eight
/// neighbours: holes inside the outline.
fn holes(rgba: &[u8], truth: &[bool], width: usize, height: usize) -> Vec<(usize, usize)> {
    let covered = coverage(rgba);
    (1..height - 1)
        .flat_map(|y| (1..width - 1).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            truth[y * width + x]
                && !covered[y * width + x]
                && (0..9).all(|k| covered[(y + k / 3 - 1) * width + x + k % 3 - 1] || k == 4)
        })
        .collect()
}

#[test]
fn prism_shells_leave_no_holes_where_prisms_meet() {
    let Some(ctx) = common::device("prism_shells_leave_no_holes_where_prisms_meet") else {
        return;
    };
    let heights = Generator::Fbm.generate(64, 64, 3);
    let (width, height) = (400, 300);
    for (_, mesh, depth) in sphere_and_torus() {
        // Face-on to nearly edge-on over the torus's ring.
        for elevation in [30.0f32, 75.0, 88.0] {
            let e = elevation.to_radians();
            let eye = Vec3::new(0.0, e.sin(), e.cos()) * 3.6;
            let mut shelled = scene(mesh.clone(), depth, eye);
            if let Some(relief) = shelled.materials[0].relief.as_mut() {
                relief.method = Method::RELIEF;
            }
            let opts = RenderOptions::default()
                .with_width(width)
                .with_height(height);
            let reference = displaced(&shelled, &heights, 1.0);
            let truth = coverage(&render(&ctx, &reference, None, &opts).expect("renders").rgba);
            if let Some(relief) = shelled.materials[0].relief.as_mut() {
                relief.silhouettes = Silhouettes::Shells;
            }
            let frame = render(&ctx, &shelled, Some(&heights), &opts).expect("renders");
            common::assert_no_validation_errors(&ctx);
            let found = holes(&frame.rgba, &truth, width as usize, height as usize);
            eprintln!("{}, {elevation} degrees: holes at {found:?}", mesh.name);
            assert!(
                found.is_empty(),
                "{}, {elevation} degrees: holes between prisms",
                mesh.name
            );
        }
    }
}
