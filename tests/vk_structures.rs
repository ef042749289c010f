//! Acceleration structures in `relief::vk`: built over triangles and boxes, instanced in a top
//! level, sized and timed; bad geometry refused; every buffer they hold returned after they
//! drop; and a device without ray queries (or with them switched off) says so instead of
//! building.

mod common;

use relief::bench::{measure_scene_shadows, SceneShadowConfig};
use relief::scene::ShadowScene;
use relief::vk::{AccelerationStructure, ContextOptions, Geometry, Instance, VkError, IDENTITY};

fn triangles(ctx: &std::sync::Arc<relief::vk::Context>) -> AccelerationStructure {
    let positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let indices = [0, 1, 2, 2, 1, 3];
    let geometry = Geometry::Triangles {
        positions: &positions,
        indices: &indices,
    };
    AccelerationStructure::bottom_level(ctx, geometry, "test triangles").expect("built")
}

#[test]
fn structures_build_and_return_every_buffer_when_dropped() {
    let Some(ctx) =
        common::ray_query_device("structures_build_and_return_every_buffer_when_dropped")
    else {
        return;
    };
    ctx.wait_idle().expect("idle");
    let before = ctx.alive();
    {
        let tris = triangles(&ctx);
        let boxes = [
            [0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            [2.0, 0.0, 0.0, 3.0, 1.0, 1.0],
        ];
        let prisms = AccelerationStructure::bottom_level(&ctx, Geometry::Boxes(&boxes), "boxes")
            .expect("built");
        assert_eq!((tris.primitives(), prisms.primitives()), (2, 2));
        let placed = [
            Instance {
                structure: &tris,
                transform: IDENTITY,
                custom_index: 0,
            },
            Instance {
                structure: &prisms,
                transform: [
                    [1.0, 0.0, 0.0, 5.0],
                    [0.0, 1.0, 0.0, 0.0],
                    [0.0, 0.0, 1.0, 0.0],
                ],
                custom_index: 7,
            },
        ];
        let top = AccelerationStructure::top_level(&ctx, &placed, "top").expect("built");
        assert_eq!(top.primitives(), 2);
        for s in [&tris, &prisms, &top] {
            assert!(s.bytes() > 0, "{s:?}");
            assert!(s.build_ms() > 0.0 && s.build_ms() < 10_000.0, "{s:?}");
        }
        // The top level keeps what it instances: dropping the bottom levels first is safe.
        drop(tris);
        drop(prisms);
        let empty = AccelerationStructure::top_level(&ctx, &[], "empty top").expect("built");
        assert_eq!(empty.primitives(), 0);
        drop(top);
    }
    ctx.wait_idle().expect("idle");
    let after = ctx.alive();
    assert_eq!(after.buffers, before.buffers, "{before:?} -> {after:?}");
    assert_eq!(after.allocated_bytes, before.allocated_bytes);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn bad_geometry_is_refused_by_name() {
    let Some(ctx) = common::ray_query_device("bad_geometry_is_refused_by_name") else {
        return;
    };
    let positions = [[0.0f32; 3]; 3];
    for (indices, why) in [
        (&[0u32, 1][..], "indices"),
        (&[0, 1, 3][..], "indices"),
        (&[][..], "over nothing"),
    ] {
        let geometry = Geometry::Triangles {
            positions: &positions,
            indices,
        };
        let err =
            AccelerationStructure::bottom_level(&ctx, geometry, "bad mesh").expect_err("refused");
        let text = err.to_string();
        assert!(matches!(err, VkError::Invalid(_)), "{text}");
        assert!(text.contains("bad mesh") && text.contains(why), "{text}");
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn without_ray_queries_the_traced_path_says_why() {
    let options = ContextOptions::default().with_without_ray_queries(true);
    let Some(ctx) = common::device_with("without_ray_queries_the_traced_path_says_why", &options)
    else {
        return;
    };
    assert!(!ctx.info().ray_query);
    let err = AccelerationStructure::top_level(&ctx, &[], "no rays").expect_err("refused");
    assert!(err.to_string().contains("has no ray queries"), "{err}");
    let config = SceneShadowConfig {
        scene: Some(ShadowScene::BoxOverPlane),
        width: 32,
        height: 18,
        traced: true,
        ..SceneShadowConfig::default()
    };
    let err = measure_scene_shadows(&ctx, &config).expect_err("refused");
    assert!(err.to_string().contains("has no ray queries"), "{err}");
    // The raster path stays: the same measurement without the traced rays runs.
    let config = SceneShadowConfig {
        traced: false,
        ..config
    };
    assert!(measure_scene_shadows(&ctx, &config).is_ok());
    common::assert_no_validation_errors(&ctx);
}
