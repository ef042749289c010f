//! `relief render --hdr-out FILE.hdr`: the frame's linear radiance written beside its PNG, the
//! same pixels before tone mapping; a file name that is not .hdr is refused.

mod common;

use common::cli::relief;
use common::srgb;

#[test]
fn the_radiance_is_the_frame_before_tone_mapping() {
    if common::device("the_radiance_is_the_frame_before_tone_mapping").is_none() {
        return;
    }
    let dir = common::evidence_dir("cli-hdr-out");
    let (png, hdr) = (dir.join("frame.png"), dir.join("frame.hdr"));
    let run = relief(&[
        "render",
        "--width",
        "96",
        "--height",
        "54",
        "--tonemap",
        "none",
        "--msaa",
        "1",
        "--out",
        png.to_str().expect("utf-8"),
        "--hdr-out",
        hdr.to_str().expect("utf-8"),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let frame = image::open(&png).expect("the PNG").to_rgba8();
    let radiance = image::open(&hdr).expect("the .hdr").to_rgb32f();
    assert_eq!(radiance.dimensions(), (96, 54));
    let (mut checked, mut off) = (0, 0);
    for (p, r) in frame.pixels().zip(radiance.pixels()) {
        if p.0[..3].iter().any(|&c| c >= 250) {
            continue;
        }
        checked += 1;
        // Radiance files keep 8 bits of mantissa per pixel: a few levels after encoding.
        off += usize::from(
            (0..3).any(|c| (srgb::encode(f64::from(r.0[c])) - f64::from(p.0[c])).abs() > 3.0),
        );
    }
    eprintln!("{off} of {checked} pixels more than 3 levels from the PNG");
    assert!(
        checked > 96 * 54 / 2 && off * 100 <= checked,
        "{off} of {checked}"
    );
}

#[test]
fn only_hdr_files_are_written() {
    let run = relief(&["render", "--hdr-out", "frame.exr", "--out", "unused.png"]);
    common::cli::assert_usage_failure(&run, &["--hdr-out writes Radiance .hdr files"]);
    let run = relief(&["render", "--hdr-out", "f.hdr", "--no-write"]);
    common::cli::assert_usage_failure(&run, &["leave out --no-write"]);
}
