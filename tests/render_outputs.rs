//! The render outputs of the G-buffer checked against what is known without it: a rotated box's
//! depth and positions against exact ray-box intersections through each pixel's centre, its
//! coverage 1 inside, 0 outside and fractional on its outline under MSAA; a lit ground's
//! albedo, ambient occlusion and shadow against its material and the blocker above it; the
//! motion of a known sideways camera move against the pinhole model; and a relief quad's steps
//! and hits against the trace pass (`relief trace`'s compute path) for the very same rays.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use relief::heightfield::{Address, Generator};
use relief::method::Method;
use relief::render::{
    render, trace_on_gpu, FrameRequest, GBufferChannels, HeightFormat, RenderOptions, Renderer,
    TraceRequest,
};
use relief::scene::{
    box_mesh, quad_mesh, Camera, Light, LightKind, Material, Projection, Relief, Scene,
};
use relief::vk::Context;

const WIDTH: u32 = 96;
const HEIGHT: u32 = 64;

fn options(msaa: u32) -> RenderOptions {
    RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT)
        .with_msaa(msaa)
        .with_gbuffer(true)
}

fn gbuffer(ctx: &Arc<Context>, scene: &Scene, opts: &RenderOptions) -> GBufferChannels {
    let frame = render(ctx, scene, None, opts).expect("renders");
    frame.gbuffer.expect("the G-buffer was asked for")
}

/// A unit-half-extent box turned 30 degrees about y and 20 about x, seen from 5 units away.
fn box_scene() -> Scene {
    let mut cube = box_mesh("box", Vec3::ONE, 0);
    cube.transform = box_transform();
    Scene {
        meshes: vec![cube],
        materials: vec![Material::default()],
        camera: Some(Camera::look_at(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::ZERO,
            45f32.to_radians(),
            0.1,
            50.0,
        )),
        ..Scene::default()
    }
}

fn box_transform() -> Mat4 {
    Mat4::from_rotation_x(20f32.to_radians()) * Mat4::from_rotation_y(30f32.to_radians())
}

/// Where a world ray first meets the box, by the slab method in the box's own frame.
fn box_hit(origin: Vec3, dir: Vec3) -> Option<Vec3> {
    let to_box = box_transform().inverse();
    let o = to_box.transform_point3(origin);
    let d = to_box.transform_vector3(dir);
    let (mut enter, mut leave) = (f32::NEG_INFINITY, f32::INFINITY);
    for axis in 0..3 {
        let (a, b) = ((-1.0 - o[axis]) / d[axis], (1.0 - o[axis]) / d[axis]);
        enter = enter.max(a.min(b));
        leave = leave.min(a.max(b));
    }
    (enter <= leave && enter > 0.0).then(|| origin + dir * enter)
}

#[test]
fn a_boxs_depth_and_positions_are_its_exact_ray_hits() {
    let Some(ctx) = common::device("a_boxs_depth_and_positions_are_its_exact_ray_hits") else {
        return;
    };
    let scene = box_scene();
    let camera = scene.camera.expect("camera");
    let g = gbuffer(&ctx, &scene, &options(1));
    let positions = g.positions(&camera);
    let axis = -camera.view.row(2).truncate();
    let (mut inside, mut worst_depth, mut worst_position, mut disagree) = (0, 0f32, 0f32, 0);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let k = (y * WIDTH + x) as usize;
            let (origin, dir) = pixel_ray_at(&camera, x as f32 + 0.5, y as f32 + 0.5);
            match box_hit(origin, dir) {
                Some(hit) if g.coverage[k] == 1.0 => {
                    inside += 1;
                    let depth = (hit - camera.eye()).dot(axis);
                    worst_depth = worst_depth.max((g.depth[k] - depth).abs());
                    worst_position = worst_position.max(Vec3::from(positions[k]).distance(hit));
                    assert_eq!(g.mesh[k], 1, "pixel ({x}, {y}) shows the box");
                }
                None if g.coverage[k] == 0.0 => {
                    assert!(g.depth[k].is_infinite(), "pixel ({x}, {y}): nothing drawn");
                    assert_eq!(g.mesh[k], 0);
                }
                // A pixel centre within rounding of the outline.
                _ => disagree += 1,
            }
        }
    }
    eprintln!(
        "{inside} box pixels: depth within {worst_depth:.2e}, position within {worst_position:.2e}; {disagree} on the outline disagree"
    );
    assert!(inside > 1000, "the box fills part of the frame: {inside}");
    assert!(worst_depth < 1e-3, "depth off by {worst_depth}");
    assert!(worst_position < 2e-3, "position off by {worst_position}");
    assert!(disagree <= 4, "{disagree} pixels disagree on the outline");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn coverage_is_whole_inside_empty_outside_and_fractional_on_the_outline() {
    let Some(ctx) = common::device("coverage_is_whole_inside_empty_outside") else {
        return;
    };
    let scene = box_scene();
    let camera = scene.camera.expect("camera");
    let g = gbuffer(&ctx, &scene, &options(4));
    let mut fractional = 0;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let k = (y * WIDTH + x) as usize;
            // Whether the pixel's corners and centre all see the box, or none does.
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)];
            let seen = corners
                .iter()
                .filter(|(dx, dy)| {
                    let (o, d) = pixel_ray_at(&camera, x as f32 + dx, y as f32 + dy);
                    box_hit(o, d).is_some()
                })
                .count();
            let c = g.coverage[k];
            match seen {
                5 => assert_eq!(c, 1.0, "pixel ({x}, {y}) lies inside the box"),
                0 => assert_eq!(c, 0.0, "pixel ({x}, {y}) lies outside the box"),
                _ => fractional += usize::from(c > 0.0 && c < 1.0),
            }
        }
    }
    assert!(
        fractional > 40,
        "only {fractional} outline pixels are partly covered"
    );
    common::assert_no_validation_errors(&ctx);
}

/// The ray through the point (px, py) of the framebuffer, in pixels from its top-left corner.
fn pixel_ray_at(camera: &Camera, px: f32, py: f32) -> (Vec3, Vec3) {
    let inverse = camera
        .view_projection(WIDTH as f32 / HEIGHT as f32)
        .inverse();
    let ndc = Vec3::new(
        px / WIDTH as f32 * 2.0 - 1.0,
        py / HEIGHT as f32 * 2.0 - 1.0,
        0.0,
    );
    let near = inverse.project_point3(ndc);
    let far = inverse.project_point3(ndc.with_z(1.0));
    (near, (far - near).normalize())
}

#[test]
fn a_lit_grounds_albedo_ao_and_shadow_are_its_material_and_its_blocker() {
    let Some(ctx) = common::device("a_lit_grounds_albedo_ao_and_shadow") else {
        return;
    };
    let albedo = [0.6, 0.35, 0.2];
    let mut blocker = box_mesh("blocker", Vec3::new(1.0, 0.1, 1.0), 1);
    blocker.transform = Mat4::from_translation(Vec3::new(0.0, 1.5, 0.0));
    let scene = Scene {
        meshes: vec![quad_mesh("ground", 8.0, 8.0, 1.0, 0), blocker],
        materials: vec![
            Material {
                name: "ground".into(),
                base_color: [albedo[0], albedo[1], albedo[2], 1.0],
                ..Material::default()
            },
            Material::default(),
        ],
        lights: vec![Light {
            kind: LightKind::Directional,
            direction: Vec3::NEG_Y,
            casts_shadows: true,
            ..Light::default_light()
        }],
        camera: Some(Camera::look_at(
            Vec3::new(0.0, 7.0, 5.0),
            Vec3::ZERO,
            50f32.to_radians(),
            0.1,
            50.0,
        )),
        ..Scene::default()
    };
    let camera = scene.camera.expect("camera");
    let g = gbuffer(&ctx, &scene, &options(1));
    let positions = g.positions(&camera);
    let (mut under, mut open) = (0, 0);
    for (k, &[x, _, z]) in positions.iter().enumerate() {
        if g.mesh[k] != 1 {
            continue;
        }
        // The raster's uv: where the pixel's ray meets the ground plane, over its 8 x 8 units.
        let (px, py) = ((k as u32 % WIDTH) as f32, (k as u32 / WIDTH) as f32);
        let (origin, dir) = pixel_ray_at(&camera, px + 0.5, py + 0.5);
        let on_ground = origin - dir * (origin.y / dir.y);
        let uv = [on_ground.x / 8.0 + 0.5, on_ground.z / 8.0 + 0.5];
        assert!(
            (g.uv[k][0] - uv[0]).abs() < 1e-4 && (g.uv[k][1] - uv[1]).abs() < 1e-4,
            "pixel {k}: uv {:?}, the ground's {uv:?} there",
            g.uv[k]
        );
        for c in 0..3 {
            assert!(
                (g.albedo[k][c] - albedo[c]).abs() < 2e-3,
                "pixel {k}: albedo {:?}, the material's {albedo:?}",
                g.albedo[k]
            );
        }
        assert!((g.ao[k] - 1.0).abs() < 1e-3, "pixel {k}: ao {}", g.ao[k]);
        if x.abs() < 0.8 && z.abs() < 0.8 {
            under += 1;
            assert!(
                g.shadow[k] < 0.05,
                "({x}, {z}) under the blocker: {}",
                g.shadow[k]
            );
        } else if x.abs() > 1.3 || z.abs() > 1.3 {
            open += 1;
            assert!(
                g.shadow[k] > 0.95,
                "({x}, {z}) in the open: {}",
                g.shadow[k]
            );
        }
    }
    assert!(
        under > 50 && open > 500,
        "{under} pixels under, {open} open"
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn motion_is_the_screen_shift_of_a_known_camera_move() {
    let Some(ctx) = common::device("motion_is_the_screen_shift_of_a_known_camera_move") else {
        return;
    };
    // A wall facing the camera 5 units away; the camera steps 0.1 units to the right.
    let distance = 5.0;
    let step = 0.1;
    let yfov = 40f32.to_radians();
    let mut wall = quad_mesh("wall", 12.0, 12.0, 1.0, 0);
    wall.transform = Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let at = |x: f32| {
        Camera::look_at(
            Vec3::new(x, 0.0, distance),
            Vec3::new(x, 0.0, 0.0),
            yfov,
            0.1,
            50.0,
        )
    };
    let scene = Scene {
        meshes: vec![wall],
        materials: vec![Material::default()],
        camera: Some(at(0.0)),
        ..Scene::default()
    };
    let mut renderer = Renderer::new(&ctx, &scene, None, &options(1)).expect("renderer");
    let first = renderer
        .draw(&FrameRequest::new(at(0.0)))
        .expect("first frame");
    let still = first.gbuffer.expect("G-buffer");
    assert!(
        still.motion.iter().all(|m| m == &[0.0, 0.0]),
        "a first frame has no motion"
    );
    let second = renderer
        .draw(&FrameRequest::new(at(step)))
        .expect("second frame");
    let g = second.gbuffer.expect("G-buffer");
    // Pinhole: a point at depth d shifts by step * f / d pixels, f the focal length in pixels;
    // the camera moving right moves the wall left on screen.
    let focal = HEIGHT as f32 * 0.5 / (yfov * 0.5).tan();
    let expected = -step * focal / distance;
    let worst = g
        .motion
        .iter()
        .map(|m| (m[0] - expected).abs().max(m[1].abs()))
        .fold(0f32, f32::max);
    eprintln!("expected motion {expected:.4} px; worst error {worst:.2e}");
    assert!(expected.abs() > 1.0, "the move is visible: {expected}");
    assert!(worst < 0.02, "motion off by {worst} px");
    // Measured from a given camera instead of the last frame's: from the first frame's again.
    renderer.set_motion_origin(at(-step));
    let third = renderer
        .draw(&FrameRequest::new(at(step)))
        .expect("third frame");
    let doubled = third.gbuffer.expect("G-buffer");
    assert!(
        doubled
            .motion
            .iter()
            .all(|m| (m[0] - 2.0 * expected).abs() < 0.04),
        "motion from the given origin"
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn steps_and_hits_are_the_trace_passes_for_the_same_rays() {
    let Some(ctx) = common::device("steps_and_hits_are_the_trace_passes_for_the_same_rays") else {
        return;
    };
    // An orthographic view at 35 degrees of elevation: every pixel's ray is parallel, and the
    // 6 x 6 quad fills the frame exactly, so pixel (c, r) enters the relief at uv
    // ((c + 0.5) / W, (r + 0.5) / H), where the trace pass's ray (c, r) enters.
    let (side, elevation, depth_scale) = (6.0f32, 35f32.to_radians(), 0.05);
    let toward_eye = Vec3::new(0.0, elevation.sin(), elevation.cos());
    let camera = Camera {
        view: Mat4::look_at_rh(toward_eye * 10.0, Vec3::ZERO, Vec3::Y),
        projection: Projection::Orthographic {
            xmag: side / 2.0,
            ymag: side / 2.0 * elevation.sin(),
            znear: 1.0,
            zfar: 20.0,
        },
    };
    let heights = Generator::Bricks.generate(128, 128, 3).quantized_unorm16();
    let scene = Scene {
        meshes: vec![quad_mesh("relief", side, side, 1.0, 0)],
        materials: vec![Material {
            relief: Some(Relief::new(depth_scale, Method::QDM)),
            ..Material::default()
        }],
        camera: Some(camera),
        ..Scene::default()
    };
    let opts = options(1).with_width(64).with_height(64);
    let frame = render(&ctx, &scene, Some(&heights), &opts).expect("renders");
    let g = frame.gbuffer.expect("G-buffer");
    // The view ray in height space: u along +x, v along +z, down along -y.
    let view = -toward_eye;
    let dir = Vec3::new(view.x, view.z, -view.y).normalize();
    let req = TraceRequest {
        method: Method::QDM,
        dir: dir.to_array(),
        depth_scale,
        grid: (opts.width, opts.height),
        budget: Method::QDM.info().default_budget,
        address: Address::Repeat,
        format: HeightFormat::R16Unorm,
        map: None,
        shadow: None,
    };
    let traced = trace_on_gpu(&ctx, &heights, &req).expect("traces");
    let pixels = g.steps.len();
    let (mut same_steps, mut same_hit, mut worst_entry) = (0, 0, 0f32);
    assert_eq!(traced.hits.len(), pixels);
    for k in 0..pixels {
        let [u0, v0, _, _, _, u, v, _] = traced.hits[k];
        assert_eq!(g.mesh[k], 1, "pixel {k} missed the quad");
        same_steps += usize::from(g.steps[k] == traced.steps[k][0]);
        same_hit += usize::from((g.uv[k][0] - u).abs() < 1e-3 && (g.uv[k][1] - v).abs() < 1e-3);
        let entry = [(k % 64) as f32 + 0.5, (k / 64) as f32 + 0.5].map(|p| p / 64.0);
        worst_entry = worst_entry.max((u0 - entry[0]).abs().max((v0 - entry[1]).abs()));
    }
    let share = |n: usize| n as f64 / pixels as f64;
    eprintln!(
        "steps equal on {:.1}% of pixels, hits within 1e-3 uv on {:.1}%",
        100.0 * share(same_steps),
        100.0 * share(same_hit)
    );
    assert!(worst_entry < 1e-6, "the trace's grid is the pixels'");
    assert!(g.steps.iter().any(|&s| s > 4), "the rays took steps");
    // One method's code on the same rays: only float rounding of the entry may part them.
    assert!(share(same_steps) > 0.99, "steps differ on too many pixels");
    assert!(share(same_hit) > 0.99, "hits differ on too many pixels");
    common::assert_no_validation_errors(&ctx);
}
