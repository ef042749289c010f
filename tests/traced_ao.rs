//! Ambient occlusion from the displaced scene by ray query against the brute-force CPU reference
//! (`relief::bench::measure_traced_ao`): the same cosine-weighted rays from each G-buffer pixel,
//! through every object and relief solid of the scene.

mod common;

use relief::bench::{measure_traced_ao, TracedAoConfig};
use relief::scene::ShadowScene;

#[test]
fn traced_ambient_occlusion_matches_the_brute_force_reference_ray_for_ray() {
    let Some(ctx) = common::ray_query_device("traced_ambient_occlusion_matches_the_reference")
    else {
        return;
    };
    for scene in [ShadowScene::BoxOverRelief, ShadowScene::SlabOverPlane] {
        let config = TracedAoConfig {
            scene: Some(scene),
            ..TracedAoConfig::default()
        };
        let run = measure_traced_ao(&ctx, &config).expect("measured");
        eprintln!(
            "{}: {} pixels, {} rays, mean |error| {:.5}, max {:.4}, {} differ; mean visibility {:.3}, {} occluded; {} prism tests, {:.2} ms",
            run.scene,
            run.pixels,
            run.rays,
            run.mean_abs_error,
            run.max_abs_error,
            run.differing_pixels,
            run.mean_visibility,
            run.occluded_pixels,
            run.prisms_tested,
            run.trace_ms
        );
        assert!(run.pixels > 5000, "{}", run.scene);
        assert_eq!(
            run.rays,
            16 * run.pixels,
            "{}: sixteen rays a receiver",
            run.scene
        );
        // Something occludes: the box the ground under it, the relief itself, the slab the
        // plane; a test where every share were 1 would mean nothing.
        assert!(run.occluded_pixels > run.pixels / 10, "{}", run.scene);
        assert!(run.mean_visibility < 0.97, "{}", run.scene);
        assert!(
            run.prisms_tested > 0,
            "{}: rays reach the relief",
            run.scene
        );
        // The same rays: pixels may differ only where one ray grazes a contact, by 1/16.
        assert!(run.mean_abs_error <= 0.0005, "{}", run.scene);
        assert!(run.differing_pixels * 200 <= run.pixels, "{}", run.scene);
        assert_eq!(run.capped, 0, "{}", run.scene);
    }
    common::assert_no_validation_errors(&ctx);
}
