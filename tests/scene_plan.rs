//! Only what the scene needs: the plan derived from a scene, checked against what the frame
//! really created on the device (pipelines, images, allocations counted by the context).

mod common;

use relief::heightfield::Generator;
use relief::method::Method;
use relief::render::{render, Pass, Plan, RenderOptions};
use relief::scene::{quad_mesh, Light, Material, Relief, Scene};
use relief::vk::ObjectCounts;

fn one_material_scene(method: Method, light: Option<Light>) -> Scene {
    Scene {
        meshes: vec![quad_mesh("quad", 2.0, 2.0, 1.0, 0)],
        materials: vec![Material {
            name: "displaced".into(),
            relief: Some(Relief::new(0.05, method)),
            ..Material::default()
        }],
        lights: light.into_iter().collect(),
        ..Scene::default()
    }
}

fn render_counted(scene: &Scene) -> Option<(Plan, ObjectCounts)> {
    let ctx = common::device("scene_plan")?;
    let hf = Generator::Fbm.generate(64, 64, 3);
    let opts = RenderOptions::default().with_width(64).with_height(48);
    let before = ctx.created();
    let frame = render(&ctx, scene, Some(&hf), &opts).expect("renders");
    let created = ctx.created() - before;
    common::assert_no_validation_errors(&ctx);
    Some((frame.plan, created))
}

#[test]
fn one_pom_material_without_light_builds_one_pipeline_and_nothing_else() {
    let scene = one_material_scene(Method::POM, None);
    let Some((plan, created)) = render_counted(&scene) else {
        return;
    };
    assert_eq!(plan.pipelines.len(), 1, "{:?}", plan.pipelines);
    let pipeline = plan.pipelines[0];
    assert_eq!(pipeline.method, Some(Method::POM));
    assert!(!pipeline.shadows.mode.is_some(), "no light casts shadows");
    assert_eq!(plan.heights.len(), 1);
    assert!(!plan.heights[0].pyramid, "POM reads no pyramid");
    assert_eq!(
        plan.heights[0].map, None,
        "POM reads no cone or quadric map"
    );
    let passes: Vec<&str> = plan.passes.iter().map(|p| p.pass.name()).collect();
    assert_eq!(passes, ["surface"], "no pyramid pass, no shadow pass");
    let skipped: Vec<&str> = plan.skipped.iter().map(|s| s.what.as_str()).collect();
    for what in [
        "max_pyramid",
        "cone_map",
        "relaxed_cone_map",
        "quadric_map",
        "self-shadow rays",
        "surface.frag:plain",
    ] {
        assert!(
            skipped.contains(&what),
            "{what} not listed as skipped: {skipped:?}"
        );
    }
    // What the device saw: the surface pipeline and the tone-mapping pass's, no compute (no
    // pyramid build); images for the heights, the white texture and the three targets (radiance,
    // depth, frame), and no map image.
    assert_eq!(created.graphics_pipelines, 2, "{created:?}");
    assert_eq!(created.compute_pipelines, 0, "{created:?}");
    assert_eq!(created.images, 5, "{created:?}");
    assert_eq!(created.allocations, created.images + created.buffers);
}

#[test]
fn maps_and_shadow_work_appear_only_when_needed() {
    let csm = Method::all().find(|m| m.id() == "csm").expect("csm");
    let shadowed = Light {
        casts_shadows: true,
        radius: 0.0,
        ..Light::default_light()
    };
    let scene = one_material_scene(csm, Some(shadowed));
    let Some((plan, created)) = render_counted(&scene) else {
        return;
    };
    assert_eq!(plan.pipelines.len(), 1);
    assert!(
        plan.pipelines[0].shadows.mode.is_some(),
        "a shadow-casting light"
    );
    assert!(plan.passes.iter().any(|p| p.pass == Pass::SelfShadowRays));
    assert_eq!(
        plan.heights[0].map.map(|m| m.name()),
        Some("cone_map"),
        "csm reads a cone map"
    );
    // The surface pipeline, the same material casting into the light's shadow map, and the
    // tone-mapping pass.
    assert_eq!(plan.shadow_maps.len(), 1, "{:?}", plan.shadow_maps);
    assert!(plan.passes.iter().any(|p| p.pass == Pass::ShadowMaps));
    assert_eq!(created.graphics_pipelines, 3, "{created:?}");
    // The cone map is built on the GPU (render::cone_map_pass): its compute pipeline, and its
    // three buffers (heights in, pyramid, map out) besides the frame's own.
    assert_eq!(
        created.compute_pipelines, 1,
        "the cone map build: {created:?}"
    );
    // The cone map and the shadow atlas (its sampled depths and its depth test) are the three
    // images more than POM needs.
    assert_eq!(created.images, 8, "{created:?}");
}

#[test]
fn pyramid_methods_build_the_pyramid_on_the_gpu() {
    let qdm = Method::all().find(|m| m.id() == "qdm").expect("qdm");
    let Some((plan, created)) = render_counted(&one_material_scene(qdm, None)) else {
        return;
    };
    assert!(plan.heights[0].pyramid);
    assert_eq!(plan.heights[0].map, None);
    assert_eq!(
        created.compute_pipelines, 1,
        "the pyramid pass: {created:?}"
    );
    // The surface pipeline and the tone-mapping pass's.
    assert_eq!(created.graphics_pipelines, 2, "{created:?}");
}

#[test]
fn relief_without_any_height_map_is_a_clear_error() {
    let scene = one_material_scene(Method::POM, None);
    let err = Plan::derive(&scene, None).expect_err("no height map given");
    let text = err.to_string();
    assert!(
        text.contains("\"displaced\"") && text.contains("--heightmap"),
        "{text}"
    );
}
