//! Brush strokes on the GPU (`brush.comp`) with the pyramid rebuilt only where they touched:
//! after 100 random strokes every level equals a full rebuild bit for bit; the strokes match
//! their CPU formulas; bad strokes change nothing and say why in one line.

mod common;

use relief::heightfield::{Address, Generator};
use relief::render::{EditError, ElevationEditor, HeightFormat};
use relief::terrain::{BrushKind, Stroke};

/// Deterministic strokes over a `w` x `h` map, some hanging over its edges.
fn random_strokes(count: usize, w: u32, h: u32, seed: u64) -> Vec<Stroke> {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let kinds = [
        BrushKind::Raise,
        BrushKind::Lower,
        BrushKind::Flatten,
        BrushKind::Crater,
    ];
    (0..count)
        .map(|_| Stroke {
            kind: kinds[(next() * 4.0) as usize % 4],
            x: next() * (w as f32 + 8.0) - 4.0,
            y: next() * (h as f32 + 8.0) - 4.0,
            radius: 1.0 + next() * 30.0,
            strength: next() * 0.3,
            target: next(),
            layer: 0,
        })
        .collect()
}

#[test]
fn a_hundred_strokes_rebuilt_in_place_equal_a_full_rebuild() {
    let Some(ctx) = common::device("a_hundred_strokes_rebuilt_in_place") else {
        return;
    };
    let (w, h) = (97, 64);
    let elevation = Generator::Fbm.generate(w, h, 5);
    let strokes = random_strokes(100, w, h, 11);
    for format in [HeightFormat::R32Float, HeightFormat::R16Unorm] {
        for address in [Address::Repeat, Address::Clamp] {
            let what = format!("{format:?} {address:?}");
            let mut incremental = ElevationEditor::new(&ctx, &elevation, format, address).unwrap();
            let mut full = ElevationEditor::new(&ctx, &elevation, format, address).unwrap();
            let mut touched = 0;
            for batch in strokes.chunks(7) {
                let report = incremental.apply(batch).expect("strokes apply");
                touched += report.texels_per_level[1];
                full.apply(batch).expect("strokes apply");
            }
            full.rebuild_all().unwrap();
            let (a, b) = (
                incremental.read_levels().unwrap(),
                full.read_levels().unwrap(),
            );
            assert_ne!(
                a[0],
                elevation.data(),
                "{what}: the strokes changed the elevation"
            );
            for (level, (x, y)) in a.iter().zip(&b).enumerate() {
                let same = x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits());
                assert!(same, "{what}: level {level} differs from the full rebuild");
            }
            // Partial: level 1 has 49x32 nodes, 100 rebuilds of all of them would be 156,800.
            assert!(
                touched < 100 * 49 * 32 / 2,
                "{what}: {touched} nodes rebuilt"
            );
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn strokes_on_the_gpu_follow_their_cpu_formulas() {
    let Some(ctx) = common::device("strokes_on_the_gpu_follow_their_cpu_formulas") else {
        return;
    };
    let elevation = Generator::Fbm.generate(64, 48, 2);
    let strokes = random_strokes(12, 64, 48, 3);
    let mut editor =
        ElevationEditor::new(&ctx, &elevation, HeightFormat::R32Float, Address::Clamp).unwrap();
    editor.apply(&strokes).unwrap();
    let gpu = &editor.read_levels().unwrap()[0];
    let mut cpu = elevation.data().to_vec();
    for s in &strokes {
        for j in 0..48 {
            for i in 0..64 {
                let k = (j * 64 + i) as usize;
                cpu[k] = s.apply(i, j, cpu[k]);
            }
        }
    }
    let worst = gpu
        .iter()
        .zip(&cpu)
        .map(|(g, c)| (g - c).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "the GPU's strokes are {worst} off the CPU's");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn bad_strokes_change_nothing_and_say_why() {
    let Some(ctx) = common::device("bad_strokes_change_nothing_and_say_why") else {
        return;
    };
    let elevation = Generator::Fbm.generate(32, 32, 1);
    let mut editor =
        ElevationEditor::new(&ctx, &elevation, HeightFormat::R32Float, Address::Repeat).unwrap();
    let good = Stroke {
        kind: BrushKind::Raise,
        x: 16.0,
        y: 16.0,
        radius: 4.0,
        strength: 0.1,
        target: 0.0,
        layer: 0,
    };
    for (bad, needle) in [
        (
            Stroke {
                x: f32::NAN,
                ..good
            },
            "x is NaN",
        ),
        (
            Stroke {
                radius: 0.0,
                ..good
            },
            "radius 0",
        ),
        (
            Stroke {
                radius: 1e6,
                ..good
            },
            "radius",
        ),
        (Stroke { x: 500.0, ..good }, "misses the 32x32 map"),
    ] {
        let err = editor.apply(&[good, bad]).expect_err("refused");
        assert!(matches!(err, EditError::Stroke(_)), "{err:?}");
        let message = err.to_string();
        assert!(
            message.contains("stroke 1") && message.contains(needle),
            "{message}"
        );
    }
    assert_eq!(
        editor.read_levels().unwrap()[0],
        elevation.data(),
        "nothing was applied"
    );
    common::assert_no_validation_errors(&ctx);
}
