use super::super::distance_map::choose_grid;
use super::super::measure::{measure_hits, HitAgreement};
use super::super::mesh::shapes::{bumpy_sphere, icosphere, torus};
use super::*;
use crate::heightfield::rng::SplitMix64;

fn mesh(shape: (Vec<[f64; 3]>, Vec<[u32; 3]>), name: &str) -> ClosedMesh {
    ClosedMesh::new(name, &shape.0, &shape.1).expect("closed")
}

fn assert_close(what: &str, m: &HitAgreement) {
    eprintln!("{what}: {m:?}");
    assert!(m.both > m.rays / 8, "{what}: too few rays hit ({m:?})");
    assert!(
        m.mean_error < 0.01,
        "{what}: mean error {} cell sides",
        m.mean_error
    );
    assert!(
        m.max_error < 1.0,
        "{what}: a hit {} cell sides off",
        m.max_error
    );
    assert_eq!(m.missed_solid, 0, "{what}: rays through the solid missed");
    assert!(
        m.graze_max_error < 1.0,
        "{what}: a grazing hit {} cell sides off",
        m.graze_max_error
    );
    assert!(
        m.false_hit_max_distance < 0.1,
        "{what}: a hit where the mesh has none, {} cell sides from it",
        m.false_hit_max_distance
    );
}

#[test]
fn rays_through_sphere_cells_meet_the_sphere() {
    let sphere = mesh(icosphere([0.1, -0.2, 0.3], 1.0, 3), "sphere");
    for n in [1, 4] {
        let grid = CellGrid::classify(&sphere, n);
        let maps = CellMaps::sample(&sphere, &grid, 24);
        for dir in [[0.3, -0.5, -1.0], [1.0, 0.0, 0.0], [-0.7, 0.7, 0.1]] {
            let (m, _) = measure_hits(&sphere, &grid, &maps, dir, 24);
            assert_close(&format!("sphere, n = {n}, dir {dir:?}"), &m);
        }
    }
}

#[test]
fn rays_through_torus_cells_meet_the_torus() {
    let ring = mesh(torus([0.0, 0.2, 0.0], 1.0, 0.4, 32, 16), "torus");
    let (grid, maps) = choose_grid(&ring, 24, 0.05, 16);
    assert!(grid.n() > 1);
    // Down the hole, and edge on.
    for dir in [[0.1, -0.2, -1.0], [1.0, 0.3, 0.2]] {
        let (m, _) = measure_hits(&ring, &grid, &maps, dir, 24);
        assert_close(&format!("torus, n = {}, dir {dir:?}", grid.n()), &m);
    }
}

#[test]
fn inside_agrees_with_the_winding_number_away_from_the_surface() {
    let ring = mesh(torus([0.0; 3], 1.0, 0.4, 32, 16), "torus");
    let (grid, maps) = choose_grid(&ring, 24, 0.05, 16);
    let complex = CellComplex::new(&grid, &maps);
    let mut rng = SplitMix64::new(7);
    let mut checked = 0;
    for _ in 0..2000 {
        let mut unit = || f64::from(rng.next_f32());
        let p = [unit() * 3.0 - 1.5, unit() * 3.0 - 1.5, unit() - 0.5];
        // Distance to the torus's tube circle (the mesh's facets lie within a few hundredths of the tube).
        let ring_distance = ((p[0] * p[0] + p[1] * p[1]).sqrt() - 1.0).hypot(p[2]);
        if (ring_distance - 0.4).abs() < 0.06 {
            continue;
        }
        checked += 1;
        let expected = ring.winding_number(p).abs() > 0.5;
        assert_eq!(complex.inside(p), expected, "at {p:?}");
    }
    assert!(checked > 1000);
}

#[test]
fn rays_that_miss_the_grid_or_start_past_it_miss() {
    let sphere = mesh(icosphere([0.0; 3], 1.0, 2), "sphere");
    let grid = CellGrid::classify(&sphere, 2);
    let maps = CellMaps::sample(&sphere, &grid, 8);
    let complex = CellComplex::new(&grid, &maps);
    let settings = MarchSettings::default();
    assert_eq!(
        complex.march([5.0, 5.0, 5.0], [0.0, 0.0, 1.0], settings),
        None
    );
    assert_eq!(
        complex.march([0.0, 0.0, 5.0], [0.0, 0.0, 1.0], settings),
        None,
        "pointing away"
    );
    let hit = complex
        .march([0.0, 0.0, 5.0], [0.0, 0.0, -1.0], settings)
        .expect("straight at it");
    assert!((hit.t - 4.0).abs() < 0.05, "{hit:?}");
}

#[test]
fn rays_through_bumpy_sphere_cells_meet_its_folds() {
    let blob = mesh(bumpy_sphere([0.0; 3], 1.0, 4, 0.2, 6.0), "bumpy sphere");
    // Star-shaped from its centre: the paper's choice keeps one cell. Four a side see the folds from their sides.
    let (chosen, _) = choose_grid(&blob, 24, 0.05, 16);
    assert_eq!(chosen.n(), 1);
    for n in [1, 4] {
        let grid = CellGrid::classify(&blob, n);
        let maps = CellMaps::sample(&blob, &grid, 24);
        let (m, _) = measure_hits(&blob, &grid, &maps, [0.3, -0.5, -1.0], 24);
        assert_close(&format!("bumpy sphere, n = {n}"), &m);
    }
}
