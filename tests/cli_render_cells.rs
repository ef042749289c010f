//! `relief render --cells` through the binary: the plan builds the cells pass only when asked,
//! `--explain` lists the complexes, bad selections and meshes fail in one line, and the corpus's
//! textured sphere drawn through its cells matches the rasterised sphere.

mod common;

use std::path::Path;
use std::process::Output;

use common::cli::relief;

use common::mesh_gltf::{write_mesh, TETRAHEDRON, TETRAHEDRON_FACES};
use serde_json::Value;

/// `relief render SCENE --out OUT --width 96 --height 64 EXTRA...`.
fn render(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
    ];
    args.extend_from_slice(extra);
    relief(&args)
}

fn explain(scene: &Path, out: &Path, extra: &[&str]) -> Value {
    let run = render(scene, out, &[extra, &["--explain"]].concat());
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
    serde_json::from_slice(&run.stdout).expect("one JSON object")
}

fn names(list: &Value, key: &str) -> Vec<String> {
    list.as_array()
        .expect("a list")
        .iter()
        .filter_map(|v| v[key].as_str().map(str::to_owned))
        .collect()
}

#[test]
fn the_cells_pass_is_planned_only_when_asked_for() {
    if common::device("the_cells_pass_is_planned_only_when_asked_for").is_none() {
        return;
    }
    let dir = common::scratch_dir("render-cells-plan");
    let mesh = write_mesh(&dir, "tetrahedron", &TETRAHEDRON, &TETRAHEDRON_FACES);
    let out = dir.join("frame.png");

    let plain = explain(&mesh, &out, &[]);
    assert!(!names(&plain["passes"], "name").contains(&"cells".to_owned()));
    assert!(
        names(&plain["skipped"], "what").contains(&"cells".to_owned()),
        "{}",
        plain["skipped"]
    );
    assert_eq!(plain["cells"].as_array().map(Vec::len), Some(0));
    assert_eq!(plain["draws"], 1);

    let cells = explain(&mesh, &out, &["--cells", "all", "--cells-resolution", "16"]);
    assert!(names(&cells["passes"], "name").contains(&"cells".to_owned()));
    assert_eq!(cells["draws"], 0, "the mesh left the surface pass");
    let complexes = cells["cells"].as_array().expect("cells");
    assert_eq!(complexes.len(), 1);
    let c = &complexes[0];
    assert_eq!(c["triangles"], 4);
    assert_eq!(c["resolution"], 16);
    assert!(c["grey_cells"].as_u64().unwrap() >= 1, "{c}");
    assert!(c["domain_faces"].as_u64().unwrap() >= 1, "{c}");
    assert!(c["faces_drawn"].as_u64().unwrap() >= 4, "{c}");
    // The surface pass builds no pipeline: it has nothing left to draw.
    assert_eq!(
        cells["pipelines"].as_array().map(Vec::len),
        Some(0),
        "{}",
        cells["pipelines"]
    );

    // The same complex drawn to a file.
    let run = render(&mesh, &out, &["--cells", "all", "--cells-resolution", "16"]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let image = image::open(&out).expect("a PNG").to_rgba8();
    let background = *image.get_pixel(0, 0);
    let drawn = image.pixels().filter(|p| **p != background).count();
    assert!(
        drawn > 200,
        "only {drawn} pixels of the tetrahedron were drawn"
    );
}

#[test]
fn bad_selections_and_open_meshes_fail_in_one_line() {
    let dir = common::scratch_dir("render-cells-bad");
    let closed = write_mesh(&dir, "tetrahedron", &TETRAHEDRON, &TETRAHEDRON_FACES);
    let out = dir.join("frame.png");
    for (flag, value, needle) in [
        ("--cells-resolution", "0", "--cells-resolution"),
        ("--cells-overlap", "1.5", "--cells-overlap"),
        ("--cells-max-grid", "1000", "--cells-max-grid"),
    ] {
        let run = render(&closed, &out, &["--cells", "all", flag, value]);
        common::cli::assert_clean_failure(&run, &[needle]);
    }
    if common::device("bad_selections_and_open_meshes_fail_in_one_line").is_none() {
        return;
    }
    let run = render(&closed, &out, &["--cells", "teapot"]);
    common::cli::assert_clean_failure(&run, &["teapot", "tetrahedron"]);
    let open = write_mesh(&dir, "open", &TETRAHEDRON, &TETRAHEDRON_FACES[..3]);
    let run = render(&open, &out, &["--cells", "all"]);
    common::cli::assert_clean_failure(&run, &["open", "closed mesh"]);
}

#[test]
fn the_corpus_sphere_through_its_cells_matches_its_rasterised_self() {
    let Some(corpus) =
        common::corpus::corpus("the_corpus_sphere_through_its_cells_matches_its_rasterised_self")
    else {
        return;
    };
    if common::device("the_corpus_sphere_through_its_cells_matches_its_rasterised_self").is_none() {
        return;
    }
    let sphere =
        corpus.join("gltf/blender-io-roundtrip/01_textured_sphere/01_textured_sphere.gltf");
    if !sphere.is_file() {
        eprintln!("skipped: {} is not in the corpus", sphere.display());
        return;
    }
    let dir = common::scratch_dir("render-cells-corpus");
    let (raster, cells) = (dir.join("raster.png"), dir.join("cells.png"));
    for (out, extra) in [(&raster, &[][..]), (&cells, &["--cells", "all"][..])] {
        let mut args = vec![
            "render",
            sphere.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(&["--width", "240", "--height", "180"]);
        args.extend_from_slice(extra);
        let run = relief(&args);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
    let raster = image::open(&raster).unwrap().to_rgba8();
    let cells = image::open(&cells).unwrap().to_rgba8();
    let (mean, p99, diff) = common::golden::compare(cells.as_raw(), raster.as_raw());
    eprintln!("textured sphere: mean channel difference {mean:.3}, p99 {p99}");
    if mean > 3.0 {
        let evidence = common::evidence_dir("cells").join("corpus_sphere_diff.png");
        image::save_buffer(&evidence, &diff, 240, 180, image::ColorType::Rgba8).unwrap();
        panic!(
            "the sphere through its cells differs by {mean:.3} (max 3); difference in {}",
            evidence.display()
        );
    }
}
