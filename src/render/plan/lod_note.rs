//! What the plan says about level of detail: the averaged height pyramid (Ki and Oh section 2.5)
//! is built only for LOD materials whose pyramid traversal can stop on it, and otherwise listed
//! as skipped with the reason (`relief render --explain`).

use super::frame_plan::{HeightPlan, PipelineKey};
use crate::method::Method;

/// The name the plan and `--explain` give the averaged pyramid.
pub const MEAN_PYRAMID: &str = "averaged_pyramid";

/// The note the pyramid pass's reason gets when averaged pyramids are built with it.
pub fn built(heights: &[HeightPlan]) -> String {
    match heights.iter().filter(|h| h.mean_pyramid).count() {
        0 => String::new(),
        n => format!(", and {n} averaged pyramid(s) for LOD materials"),
    }
}

/// Why no averaged pyramid is built, or `None` when one is.
pub fn skipped(pipelines: &[PipelineKey], heights: &[HeightPlan]) -> Option<String> {
    if heights.iter().any(|h| h.mean_pyramid) {
        return None;
    }
    let lod: Vec<&PipelineKey> = pipelines.iter().filter(|p| p.lod.is_some()).collect();
    if lod.is_empty() {
        return Some("no drawn material has LOD (extras.relief.lod, relief render --lod)".into());
    }
    if !lod.iter().any(|p| p.binds_mean_pyramid()) {
        let readers: Vec<&str> = Method::all()
            .filter(|m| m.info().reads_pyramid())
            .map(|m| m.id())
            .collect();
        return Some(format!(
            "the LOD materials' methods read no max pyramid to stop on (only {} do)",
            readers.join(", ")
        ));
    }
    Some(
        "the LOD materials have lod.average_below or lod.factor 0: they stop on the max pyramid"
            .into(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Generator;
    use crate::render::plan::frame_plan::Plan;
    use crate::scene::{quad_mesh, Lod, Material, Relief, Scene};

    fn plan(materials: &[(&str, Option<Lod>)]) -> Plan {
        let materials = materials
            .iter()
            .enumerate()
            .map(|(k, (id, lod))| Material {
                name: format!("m{k}"),
                relief: Some(Relief {
                    lod: *lod,
                    ..Relief::new(0.05, id.parse().expect("known id"))
                }),
                ..Material::default()
            })
            .collect::<Vec<_>>();
        let meshes = (0..materials.len())
            .map(|k| quad_mesh(&format!("q{k}"), 1.0, 1.0, 1.0, k))
            .collect();
        let scene = Scene {
            meshes,
            materials,
            ..Scene::default()
        };
        let hf = Generator::Fbm.generate(16, 16, 1);
        Plan::derive(&scene, Some(&hf)).expect("plans")
    }

    fn skipped_why(p: &Plan) -> Option<&str> {
        let s = p.skipped.iter().find(|s| s.what == MEAN_PYRAMID);
        s.map(|s| s.why.as_str())
    }

    #[test]
    fn averaged_pyramid_only_with_lod_on_a_pyramid_method() {
        let p = plan(&[("qdm", None)]);
        assert!(p.heights.iter().all(|h| !h.mean_pyramid && !h.mean_binding));
        assert!(skipped_why(&p).is_some_and(|w| w.contains("no drawn material has LOD")));
        assert!(p.pipelines.iter().all(|k| !k.shader().ends_with(":lod")));

        let p = plan(&[("qdm", Some(Lod::default()))]);
        assert_eq!(skipped_why(&p), None);
        assert!(p.heights[0].mean_pyramid && p.heights[0].mean_binding);
        assert_eq!(p.pipelines[0].shader(), "surface.frag:qdm:lod");
        let pyramid = p
            .passes
            .iter()
            .find(|x| x.pass == crate::render::Pass::Pyramid);
        assert!(pyramid.is_some_and(|x| x.why.contains("1 averaged pyramid(s)")));
    }

    #[test]
    fn skipped_reasons_name_the_cause() {
        let p = plan(&[("pom", Some(Lod::default()))]);
        assert!(p.heights.iter().all(|h| !h.mean_binding));
        assert!(skipped_why(&p).is_some_and(|w| w.contains("read no max pyramid")));
        let flat = Lod {
            average_below: 0,
            ..Lod::default()
        };
        let p = plan(&[("qdm", Some(flat))]);
        assert!(p.heights[0].mean_binding && !p.heights[0].mean_pyramid);
        assert!(skipped_why(&p).is_some_and(|w| w.contains("average_below")));
    }

    #[test]
    fn lod_and_full_detail_draws_of_one_map_get_separate_uploads() {
        // Their set 0 layouts differ in binding 4, so they cannot share descriptor sets.
        let p = plan(&[("qdm", Some(Lod::default())), ("qdm", None), ("pom", None)]);
        assert_eq!(p.heights.len(), 2);
        assert_ne!(p.draws[0].heights, p.draws[1].heights);
        assert_eq!(p.draws[1].heights, p.draws[2].heights);
        assert_eq!(p.pipelines.len(), 3);
    }
}
