//! The shell march against the exact height-field tracer on a flat quad, against the really
//! displaced mesh on a curved one, and on the properties that make a shell worth having: rays
//! through edges two prisms share find the relief, and rays that cross the shell beside a sunken
//! relief pass it by.

use std::sync::Arc;

use glam::{DVec2, DVec3, Vec3};

use super::march::ray_triangle;
use super::*;
use crate::displaced_reference::{displace, levels_for, subdivide};
use crate::geometry::Mesh;
use crate::heightfield::reference::{trace, RefRay, SurfaceModel};
use crate::heightfield::synthetic::Generator;
use crate::heightfield::{Address, Heightfield};
use crate::scene::{cylinder_mesh, quad_mesh, sphere_mesh, HeightLookup, HeightUv};

fn lookup(heights: Heightfield) -> HeightLookup {
    HeightLookup {
        heights: Arc::new(heights.quantized_unorm16()),
        address: Address::Repeat,
        uv: HeightUv::IDENTITY,
    }
}

/// The nearest crossing of the ray with the mesh's front faces (world space: identity
/// transform), as the raster pass culls the back ones.
fn nearest_on_mesh(mesh: &Mesh, origin: DVec3, dir: DVec3) -> Option<f64> {
    let p = |k: u32| Vec3::from(mesh.vertices[k as usize].position).as_dvec3();
    mesh.indices
        .chunks_exact(3)
        .map(|t| [p(t[0]), p(t[1]), p(t[2])])
        .filter(|[a, b, c]| (*b - *a).cross(*c - *a).dot(dir) < 0.0)
        .filter_map(|tri| ray_triangle(origin, dir, tri))
        .min_by(f64::total_cmp)
}

/// A small deterministic sequence in [0, 1).
fn halton(i: u32, base: u32) -> f64 {
    let (mut f, mut r, mut i) = (1.0, 0.0, i + 1);
    while i > 0 {
        f /= f64::from(base);
        r += f * f64::from(i % base);
        i /= base;
    }
    r
}

#[test]
fn a_flat_quads_shell_finds_the_exact_height_field_hits() {
    // 1 x 1 in xz, facing +y, u along +x and v along +z: one depth unit is one world unit.
    let quad = quad_mesh("quad", 1.0, 1.0, 1.0, 0);
    let heights = lookup(Generator::Fbm.generate(32, 32, 7));
    let s = 0.1;
    let shell = Shell::new(&quad, &heights, s as f32).expect("a shell");
    let (mut compared, mut worst) = (0, 0.0f64);
    for i in 0..200 {
        let (u0, v0) = (0.25 + 0.5 * halton(i, 2), 0.25 + 0.5 * halton(i, 3));
        // From face-on to 80 degrees off the normal, all round.
        let tilt = 80f64.to_radians() * halton(i, 5);
        let turn = std::f64::consts::TAU * halton(i, 7);
        let (dx, dy, dz) = (tilt.sin() * turn.cos(), tilt.sin() * turn.sin(), tilt.cos());
        let exact = trace(
            &heights.heights,
            &RefRay { u0, v0, dx, dy, dz },
            s,
            SurfaceModel::Bilinear,
            Address::Repeat,
        );
        if !(0.0..=1.0).contains(&exact.u) || !(0.0..=1.0).contains(&exact.v) {
            continue; // It hits beyond the quad, where the shell ends.
        }
        let dir = DVec3::new(dx, -dz, dy);
        let entry = DVec3::new(u0 - 0.5, 0.0, v0 - 0.5);
        let hit = shell
            .trace(entry - dir * 2.0, dir)
            .expect("the relief under the quad");
        worst = worst.max((hit.depth * s - exact.z).abs());
        assert!(
            (hit.uv - DVec2::new(exact.u, exact.v)).length() < 1e-6,
            "ray {i}: {:?} against {exact:?}",
            hit.uv
        );
        compared += 1;
    }
    assert!(compared > 150, "{compared} rays stayed on the quad");
    assert!(worst < 1e-7, "worst depth error {worst}");
}

#[test]
fn an_open_cylinders_shell_meets_the_really_displaced_cylinder() {
    // Uniform stretch, so the shell's interpolated depth lengths are the reference's own.
    let wall = cylinder_mesh("cylinder", 1.0, 2.0, std::f32::consts::TAU, 24, 4, 0);
    let heights = lookup(Generator::Bricks.generate(32, 32, 3));
    let s = 0.02;
    let shell = Shell::new(&wall, &heights, s).expect("a shell");
    let reference = displace(&subdivide(&wall, 4), &heights, s);
    let depth = f64::from(s) * (std::f64::consts::TAU * 2.0).sqrt();
    let (mut both, mut disagree, mut worst) = (0, 0, 0.0f64);
    let mut errors = Vec::new();
    for i in 0..160 {
        // Across the whole outline, the rim and the inside seen through the open ends included.
        let x = -1.3 + 2.6 * halton(i, 2);
        let y = -1.2 + 2.4 * halton(i, 3);
        let origin = DVec3::new(x, y + 0.8, 4.0);
        let dir = DVec3::new(0.05, -0.2, -1.0).normalize();
        let exact = nearest_on_mesh(&reference, origin, dir);
        let hit = shell.trace(origin, dir);
        match (exact, hit) {
            (Some(t), Some(h)) => {
                both += 1;
                errors.push((h.t - t).abs());
                worst = worst.max((h.t - t).abs());
            }
            (None, None) => {}
            _ => disagree += 1,
        }
    }
    errors.sort_by(f64::total_cmp);
    let median = errors[errors.len() / 2];
    assert!(both > 60, "{both} rays hit both");
    // A ray within a fine triangle's width of the outline may go either way.
    assert!(disagree <= 3, "{disagree} rays hit one and not the other");
    assert!(
        median < 1e-3 * depth,
        "median distance {median} against depth {depth}"
    );
    assert!(
        worst < 0.01 * depth,
        "worst distance {worst} against depth {depth}"
    );
}

#[test]
fn rays_through_shared_edges_and_corners_find_the_relief() {
    let sphere = sphere_mesh("sphere", 1.0, 8, 16, 0);
    let level = Heightfield::new(2, 2, vec![0.5; 4]).expect("a field");
    let shell = Shell::new(&sphere, &lookup(level), 0.02).expect("a shell");
    let mut aimed = 0;
    for t in sphere.indices.chunks_exact(3) {
        let p = |k: usize| Vec3::from(sphere.vertices[t[k] as usize].position).as_dvec3();
        // Each corner and each edge's midpoint, exactly where two or more prisms meet.
        for target in [p(0), p(1), p(2), (p(0) + p(1)) * 0.5, (p(1) + p(2)) * 0.5] {
            let origin = target * 3.0 + DVec3::new(0.0, 0.0, 1e-3);
            let dir = -origin;
            let hit = shell.trace(origin, dir);
            let hit = hit.unwrap_or_else(|| panic!("a ray at {target} slipped through"));
            assert!((hit.depth - 0.5).abs() < 1e-4, "{hit:?}");
            aimed += 1;
        }
    }
    assert!(aimed > 1000);
}

#[test]
fn rays_beside_a_sunken_relief_pass_it_by() {
    let sphere = sphere_mesh("sphere", 1.0, 16, 32, 0);
    let floor = Heightfield::new(2, 2, vec![0.0; 4]).expect("a field");
    let shell = Shell::new(&sphere, &lookup(floor), 0.01).expect("a shell");
    // Seen from above the pole the outline is the equator: the polygon's, a 32-gon of radius 1,
    // and the sunken relief's, well inside it.
    let sunk = shell
        .prisms
        .iter()
        .flat_map(|p| p.bottom())
        .map(|q| q.x.hypot(q.z))
        .fold(0.0, f64::max);
    let polygon = (std::f64::consts::PI / 32.0).cos();
    assert!(
        sunk < polygon - 0.01,
        "the relief {sunk} must sink inside the polygon {polygon}"
    );
    for i in 0..64 {
        let miss = sunk + (polygon - sunk) * (0.1 + 0.8 * halton(i, 2));
        let turn = std::f64::consts::TAU * halton(i, 3);
        let dir = DVec3::new(0.0, -1.0, 0.0);
        let origin = DVec3::new(miss * turn.cos(), 5.0, miss * turn.sin());
        assert!(shell.trace(origin, dir).is_none(), "a ray at {miss} hit");
        let inside = DVec3::new(0.9 * sunk * turn.cos(), 5.0, 0.9 * sunk * turn.sin());
        let hit = shell
            .trace(inside, dir)
            .expect("a ray inside the relief's outline hits");
        assert!((hit.depth - 1.0).abs() < 1e-6, "{hit:?}");
    }
}

#[test]
fn a_shell_needs_a_depth_and_uvs() {
    let quad = quad_mesh("quad", 1.0, 1.0, 1.0, 0);
    let heights = lookup(Heightfield::new(1, 1, vec![0.5]).expect("a field"));
    for bad in [0.0, -0.1, f32::NAN, f32::INFINITY] {
        let err = Shell::new(&quad, &heights, bad).expect_err("no depth");
        assert!(
            err.to_string().contains("positive, finite depth scale"),
            "{err}"
        );
    }
    let mut flat_uv = quad.clone();
    for v in &mut flat_uv.vertices {
        v.uv = [0.5, 0.5];
    }
    let err = Shell::new(&flat_uv, &heights, 0.1).expect_err("no uvs");
    assert!(matches!(err, ShellError::NoUvs { .. }), "{err}");
}

#[test]
fn a_curved_walls_shell_draws_the_displaced_walls_outline() {
    // A 1.5-radian arc of radius 2, 1.5 high: its straight edges and ends are an open boundary
    // the displaced surface leaves inward, which nothing drawn inside the polygons can follow.
    let wall = cylinder_mesh("wall", 2.0, 1.5, 1.5, 24, 2, 0);
    let heights = lookup(Generator::Fbm.generate(64, 64, 11));
    let depth_length = (1.5f64 * 2.0 * 1.5).sqrt();
    let s = (0.1 / depth_length) as f32; // 0.05 of the radius at the deepest
    let shell = Shell::new(&wall, &heights, s).expect("a shell");
    let (levels, _) = levels_for(&wall, &heights.uv, [64, 64], 2.0);
    let reference = displace(&subdivide(&wall, levels), &heights, s);
    // Orthographic rays 30 degrees round from the arc's middle and 20 degrees down.
    let middle = DVec3::new(0.75f64.cos(), 0.0, -0.75f64.sin());
    let (yaw, pitch) = (30f64.to_radians(), 20f64.to_radians());
    let round = glam::DQuat::from_rotation_y(yaw) * -middle;
    let dir = (round * pitch.cos() - DVec3::Y * pitch.sin()).normalize();
    let right = dir.cross(DVec3::Y).normalize();
    let up = right.cross(dir);
    let centre = middle * 2.0;
    let (w, h) = (64u32, 48u32);
    let [mut shell_px, mut truth_px, mut polygon_px, mut both_shell, mut both_polygon] = [0; 5];
    for j in 0..h {
        for i in 0..w {
            let x = (f64::from(i) + 0.5) / f64::from(w) * 3.0 - 1.5;
            let y = (f64::from(j) + 0.5) / f64::from(h) * 2.25 - 1.125;
            let origin = centre + right * x + up * y - dir * 5.0;
            let truth = nearest_on_mesh(&reference, origin, dir).is_some();
            let shelled = shell.trace(origin, dir).is_some();
            let flat = nearest_on_mesh(&wall, origin, dir).is_some();
            truth_px += usize::from(truth);
            shell_px += usize::from(shelled);
            polygon_px += usize::from(flat);
            both_shell += usize::from(truth && shelled);
            both_polygon += usize::from(truth && flat);
        }
    }
    let iou = |mine: usize, both: usize| both as f64 / (mine + truth_px - both) as f64;
    let (shell_iou, polygon_iou) = (iou(shell_px, both_shell), iou(polygon_px, both_polygon));
    eprintln!(
        "curved wall, {w}x{h} rays: shell IoU {shell_iou:.4}, polygon IoU {polygon_iou:.4} \
         ({truth_px} covered by the displaced wall)"
    );
    assert!(
        truth_px > (w * h / 4) as usize,
        "the wall fills the view: {truth_px}"
    );
    assert!(shell_iou >= 0.99, "shell IoU {shell_iou}");
    assert!(polygon_iou < shell_iou, "polygon IoU {polygon_iou}");
}
