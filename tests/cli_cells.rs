//! `relief cells` through the binary: a closed glTF mesh and a procedural shape become cell complexes whose hits
//! match the mesh; open meshes and bad arguments give one error line and exit 1.

mod common;

use std::path::Path;
use std::process::Output;

use common::cli::relief;

use common::mesh_gltf::{write_mesh, TETRAHEDRON, TETRAHEDRON_FACES};
use serde_json::Value;

/// `relief cells MESH --out OUT EXTRA...`.
fn cells_of(mesh: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "cells",
        mesh.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    relief(&args)
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn stats(dir: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(dir.join("cells.json")).expect("cells.json"))
        .expect("json")
}

#[test]
fn a_closed_gltf_mesh_becomes_cells_that_hit_where_it_does() {
    let dir = common::scratch_dir("cells-tetrahedron");
    let mesh = write_mesh(&dir, "tetrahedron", &TETRAHEDRON, &TETRAHEDRON_FACES);
    let out_dir = dir.join("out");
    let out = cells_of(
        &mesh,
        &out_dir,
        &["--resolution", "32", "--rays", "32", "--dump"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = stats(&out_dir);
    assert_eq!(s["triangles"], 4);
    assert!(s["grey_cells"].as_u64().unwrap() >= 1);
    let hits = &s["hits"];
    assert!(hits["solid"].as_u64().unwrap() > 100, "{hits}");
    assert_eq!(hits["missed_solid"], 0, "{hits}");
    // Sharp edges are where projection lines cross the surface twice (the overlap the grid's doubling bounds):
    // past the first crossing a line counts as inside, so a ray passing just outside an edge stops up to a cell
    // early. On this tetrahedron that costs a tenth of a cell on average (against 0.0002 on the sphere).
    assert!(hits["mean_error"].as_f64().unwrap() < 0.15, "{hits}");
    assert!(hits["max_error"].as_f64().unwrap() < 1.1, "{hits}");
    assert!(out_dir.join("maps.png").is_file());
    // 32 x 32 rays of 4 floats after the header.
    let dump = std::fs::read(out_dir.join("rays.npy")).expect("rays.npy");
    assert!(dump.len() > 32 * 32 * 4 * 4);
}

#[test]
fn the_torus_shape_chooses_its_grid_and_rebuilds_a_mesh() {
    let dir = common::scratch_dir("cells-torus");
    let obj = dir.join("torus.obj");
    let out = relief(&[
        "cells",
        "--shape",
        "torus",
        "--out",
        dir.to_str().unwrap(),
        "--resolution",
        "16",
        "--rays",
        "24",
        "--mesh-out",
        obj.to_str().unwrap(),
        "--mesh-level",
        "1",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = stats(&dir);
    // One cell sees the inner and outer walls along one line; the paper's doubling stops where that ends.
    assert!(s["grid"].as_u64().unwrap() >= 2, "{s}");
    assert!(s["overlap_ratio"].as_f64().unwrap() <= 0.05, "{s}");
    assert_eq!(s["hits"]["missed_solid"], 0);
    // The lookup table lists every grey cell with its case and every domain face's atlas tile.
    let lookup: Value =
        serde_json::from_slice(&std::fs::read(dir.join("lookup.json")).expect("lookup.json"))
            .expect("json");
    let grey = lookup["grey_cells"].as_array().expect("grey cells");
    assert_eq!(grey.len() as u64, s["grey_cells"].as_u64().unwrap());
    let faces: usize = grey
        .iter()
        .map(|c| c["faces"].as_array().unwrap().len())
        .sum();
    assert_eq!(faces as u64, s["domain_faces"].as_u64().unwrap());
    assert!(grey
        .iter()
        .all(|c| c["case"].is_string() && c["projection"]["kind"].is_string()));
    let obj = std::fs::read_to_string(&obj).expect("obj written");
    assert!(obj.lines().filter(|l| l.starts_with("f ")).count() > 100);
    assert!(text(&out.stdout).contains("rebuilt mesh"));
}

#[test]
fn the_torus_renders_through_its_cells_as_it_does_rasterised() {
    if common::device("the_torus_renders_through_its_cells_as_it_does_rasterised").is_none() {
        return;
    }
    let dir = common::scratch_dir("cells-torus-render");
    let out = relief(&[
        "cells",
        "--shape",
        "torus",
        "--out",
        dir.to_str().unwrap(),
        "--resolution",
        "16",
        "--rays",
        "0",
        "--render",
        "128x96",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let r = &stats(&dir)["render"];
    assert!(r["covered_pixels"].as_u64().unwrap() > 1500, "{r}");
    assert!(r["cells_ms"].as_f64().unwrap() > 0.0, "{r}");
    assert!(r["mean_channel_difference"].as_f64().unwrap() <= 3.0, "{r}");
    assert!(
        r["mean_channel_difference_on_mesh"].as_f64().unwrap() <= 3.0,
        "{r}"
    );
    for image in ["cells.png", "raster.png", "diff.png"] {
        let size = image::image_dimensions(dir.join(image)).expect("a PNG");
        assert_eq!(size, (128, 96), "{image}");
    }
    assert!(text(&out.stdout).contains("mean channel difference"));
}

#[test]
fn an_open_mesh_is_refused_with_one_line() {
    let dir = common::scratch_dir("cells-open");
    let mesh = write_mesh(&dir, "open", &TETRAHEDRON, &TETRAHEDRON_FACES[..3]);
    let out = cells_of(&mesh, &dir.join("out"), &[]);
    common::cli::assert_clean_failure(&out, &["open.gltf", "is open", "closed mesh"]);
}

#[test]
fn bad_arguments_are_refused_with_one_line() {
    let dir = common::scratch_dir("cells-args");
    let out_dir = dir.join("out");
    let out_dir = out_dir.to_str().unwrap();
    let out = relief(&[
        "cells", "--shape", "sphere", "--out", out_dir, "--dir", "0,0,0",
    ]);
    common::cli::assert_clean_failure(&out, &["--dir"]);
    let out = relief(&[
        "cells",
        "--shape",
        "sphere",
        "--out",
        out_dir,
        "--resolution",
        "0",
    ]);
    common::cli::assert_clean_failure(&out, &["--resolution"]);
    let out = relief(&[
        "cells", "--shape", "sphere", "--out", out_dir, "--render", "640",
    ]);
    common::cli::assert_clean_failure(&out, &["--render", "WxH"]);
    let out = relief(&[
        "cells",
        &dir.join("missing.gltf").to_string_lossy(),
        "--out",
        out_dir,
    ]);
    common::cli::assert_clean_failure(&out, &["missing.gltf"]);
    // Maps that would not fit in memory are refused before any is sampled.
    let out = relief(&[
        "cells",
        "--shape",
        "sphere",
        "--out",
        out_dir,
        "--grid",
        "128",
        "--resolution",
        "1024",
    ]);
    common::cli::assert_clean_failure(&out, &["sphere", "MiB", "--grid"]);
}

#[test]
fn corpus_meshes_are_built_or_refused_cleanly() {
    let Some(gltf) = common::corpus::corpus("corpus_meshes_are_built_or_refused_cleanly") else {
        return;
    };
    let dir = common::scratch_dir("cells-corpus");
    let helmet = gltf.join("gltf/FlightHelmet/FlightHelmet.gltf");
    if helmet.is_file() {
        let out = cells_of(&helmet, &dir, &[]);
        common::cli::assert_clean_failure(&out, &["FlightHelmet.gltf", "is open"]);
    }
    let sphere = gltf.join("gltf/blender-io-roundtrip/01_textured_sphere/01_textured_sphere.gltf");
    if sphere.is_file() {
        let out = cells_of(&sphere, &dir, &["--resolution", "32", "--rays", "32"]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let hits = &stats(&dir)["hits"];
        assert_eq!(hits["missed_solid"], 0, "{hits}");
        assert!(hits["mean_error"].as_f64().unwrap() < 0.01, "{hits}");
    }
}
