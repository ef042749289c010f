//! Scene shadows traced by ray query (`SceneShadowConfig::traced`) against the exact scene
//! reference: the same receivers and light rays, through the scene's acceleration structures,
//! relief prisms resolved by the exact height-field walk in the shader. Unlike the shadow maps'
//! figures, agreement is counted everywhere, the band around shadow edges included.

mod common;

use relief::bench::{measure_scene_shadows, SceneShadowConfig, SceneShadowRun};
use relief::scene::ShadowScene;

const SIZE: (u32, u32) = (160, 90);

fn traced(scene: ShadowScene, elevation_deg: f32, radius_deg: f32) -> SceneShadowConfig {
    SceneShadowConfig {
        scene: Some(scene),
        elevation_deg,
        radius_deg: Some(radius_deg),
        width: SIZE.0,
        height: SIZE.1,
        samples_per_side: 3,
        traced: true,
        ..SceneShadowConfig::default()
    }
}

fn run(ctx: &std::sync::Arc<relief::vk::Context>, config: &SceneShadowConfig) -> SceneShadowRun {
    let run = measure_scene_shadows(ctx, config).expect("measured");
    let t = run.traced.as_ref().expect("traced");
    eprintln!(
        "{} radius {}: traced {} | maps and own term {} | {} rays, {} prism tests, {} capped",
        run.scene,
        run.light_radius_deg,
        t.everywhere,
        run.everywhere,
        t.rays,
        t.prisms_tested,
        t.capped
    );
    run
}

#[test]
fn traced_hard_shadows_agree_with_the_exact_reference_everywhere() {
    let Some(ctx) = common::ray_query_device("traced_hard_shadows_agree_with_the_exact_reference")
    else {
        return;
    };
    for scene in ShadowScene::ALL {
        for elevation in [5.0, 25.0, 45.0] {
            let r = run(&ctx, &traced(scene, elevation, 0.0));
            let t = r.traced.as_ref().expect("traced");
            let a = &t.everywhere;
            assert!(a.pixels > 5000, "{}: {a}", r.scene);
            assert_eq!(a.excluded_band, 0, "{}: nothing left out", r.scene);
            assert!(a.hard_agreement >= 0.999, "{}: {a}", r.scene);
            assert_eq!(t.capped, 0, "{}: a walk ran out of budget", r.scene);
            assert_eq!(t.rays, a.pixels, "{}: one ray per lit-side pixel", r.scene);
            let relief = matches!(
                scene,
                ShadowScene::SlabOverPlane | ShadowScene::BoxOverRelief
            );
            assert_eq!(t.structures.prisms > 0, relief, "{}", r.scene);
            assert_eq!(t.prisms_tested > 0, relief, "{}", r.scene);
            // Rays do what the maps cannot: the band the maps' figures leave out.
            assert!(
                a.hard_agreement >= r.everywhere.hard_agreement,
                "{}: traced {a}, maps {}",
                r.scene,
                r.everywhere
            );
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn traced_soft_shadows_follow_the_reference_sample_for_sample() {
    let Some(ctx) = common::ray_query_device("traced_soft_shadows_follow_the_reference") else {
        return;
    };
    for scene in [ShadowScene::SlabOverPlane, ShadowScene::BoxOverRelief] {
        let r = run(&ctx, &traced(scene, 25.0, 3.0));
        let t = r.traced.as_ref().expect("traced");
        // The same nine rays per pixel as the reference: a pixel differs only where one ray's
        // verdict does, by a ninth.
        assert!(t.rays >= 9 * t.everywhere.pixels / 2, "{}", r.scene);
        assert!(
            t.everywhere.mean_abs_error <= 0.001,
            "{}: {}",
            r.scene,
            t.everywhere
        );
        assert!(
            t.everywhere.mean_abs_error < r.everywhere.mean_abs_error,
            "{}: traced {}, maps {}",
            r.scene,
            t.everywhere,
            r.everywhere
        );
    }
    common::assert_no_validation_errors(&ctx);
}
