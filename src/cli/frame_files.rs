//! The files each frame of `relief render` leaves: its image (8- or 16-bit PNG, or OpenEXR) and
//! the sidecars the flags ask for (a Radiance `.hdr`, an OpenEXR with the render outputs, 16-bit
//! PNGs of the scalar outputs, the camera as JSON). Each is written whole under a hidden temporary name beside its place and renamed
//! into it, so a run killed mid-frame leaves no truncated file for `--resume` to take as done.

use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::{Args, ValueEnum};
use relief::render::{FrameOutput, ToneMapping};
use relief::scene::Camera;

use super::aov::{Layer, LayerSource};
use super::camera_sidecar::camera_json;
use super::cost_map::{cost_map_png, CostMap};
use super::exr_out::{encode_exr, is_exr};
use super::frame_encoders;
use super::usage;

/// Where `relief render` writes each frame, and in what form.
#[derive(Args, Clone, Debug)]
pub struct FileArgs {
    /// Output PNG, or OpenEXR (FILE.exr: the channels --exr-out writes); with --frames N > 1,
    /// frame k is written as STEM_000k.png (.exr) beside it.
    #[arg(long, default_value = "frame.png")]
    pub out: PathBuf,
    /// Bits per channel of the PNG: 8 (the GPU's tone-mapped frame) or 16 (tone mapped on the
    /// CPU from the read-back linear radiance with the same curve and exposure).
    #[arg(long, value_name = "8|16", default_value_t = 8, value_parser = bit_depth)]
    pub bit_depth: u8,
    /// Also write each frame's linear radiance (before exposure and tone mapping) as a
    /// Radiance .hdr file, named like the PNGs.
    #[arg(long, value_name = "FILE.hdr")]
    pub hdr_out: Option<PathBuf>,
    /// Also write each frame as an OpenEXR file, named like the PNGs: the linear radiance (R, G,
    /// B, A) and the render outputs --aov chooses (default all): Z (linear view depth of the
    /// displaced hit, along the camera's axis; infinite where nothing was drawn), P.X, P.Y, P.Z
    /// (world position), N.X, N.Y, N.Z (world shading normal), uv.U, uv.V (texture coordinates at
    /// the hit), albedo.R, albedo.G, albedo.B, material, id (scene mesh index + 1, 0 for none),
    /// steps (the view ray's steps through its height field), shadow, ao, coverage, motion.X,
    /// motion.Y (pixels since the previous frame). The header holds the camera.
    #[arg(long, value_name = "FILE.exr")]
    pub exr_out: Option<PathBuf>,
    /// What the OpenEXR files' R, G, B hold: linear (the scene's radiance, before exposure and
    /// tone mapping) or tone-mapped (the curve and exposure applied, display-referred but not
    /// sRGB-encoded, as compositors expect linear values).
    #[arg(long, value_name = "linear|tone-mapped", default_value = "linear")]
    pub exr_beauty: ExrBeauty,
    /// The render outputs the OpenEXR files (and --aov-png) hold, comma-separated: depth,
    /// position, normal, uv, albedo, material, object, steps, shadow, ao, coverage, motion.
    #[arg(long, value_name = "LAYERS", value_delimiter = ',', value_enum)]
    pub aov: Vec<Layer>,
    /// Also write each scalar render output (depth, material, object, steps, shadow, ao,
    /// coverage) as a 16-bit greyscale PNG beside the image, named STEM.LAYER.png.
    #[arg(long)]
    pub aov_png: bool,
    /// Also write each frame's camera as JSON, named like the PNGs: view, projection and
    /// view-projection matrices, camera-to-world, eye, near and far planes, lens and image size.
    #[arg(long, value_name = "FILE.json")]
    pub camera_out: Option<PathBuf>,
    /// Skip the frames whose files are all there already (a sequence stopped part way picks up
    /// where it stopped); the others are drawn and written as usual.
    #[arg(long)]
    pub resume: bool,
    /// Write the sequence's work as a timeline (Chrome trace-event JSON, which ui.perfetto.dev
    /// and chrome://tracing open): the host's recording, submission and retiring on one track,
    /// every pass of every frame on another with its invocation counts, on one clock. Works
    /// with --no-write.
    #[arg(long, value_name = "FILE.json")]
    pub timeline: Option<PathBuf>,
    /// Also write each frame's cost as a heat map PNG beside it, STEM.cost-steps.png and
    /// STEM.cost-fragments.png: per pixel the relief steps traced, or the relief fragments
    /// traced (overdraw after culling); black none, white the frame's most, with the colour bar
    /// on the right. Counts the frame's work, as --count-work.
    #[arg(long, value_name = "steps|fragments", value_delimiter = ',')]
    pub cost_map: Vec<CostMap>,
}

/// What an OpenEXR frame's colour channels hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ExrBeauty {
    Linear,
    ToneMapped,
}

/// The files one frame writes, in the order they are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FileKind {
    Image,
    Hdr,
    Exr,
    LayerPng(Layer),
    Camera,
    CostMap(CostMap),
}

/// What a frame's files are made from besides its pixels.
pub struct FrameView<'a> {
    /// The camera it was drawn through.
    pub camera: Camera,
    /// The tone curve and exposure the GPU applied.
    pub tone: ToneMapping,
    /// Each scene mesh's material index (the material layer).
    pub mesh_materials: &'a [usize],
}

impl FileArgs {
    /// Refuses combinations that cannot be written, before any device is made.
    pub fn check(&self, no_write: bool, supersampled: bool) -> anyhow::Result<()> {
        let exr_out = is_exr(&self.out);
        if exr_out && self.bit_depth != 8 {
            return Err(usage(format!(
                "--bit-depth {} sets a PNG's bits; {} is an OpenEXR file (32-bit float)",
                self.bit_depth,
                self.out.display()
            )));
        }
        if (exr_out || self.exr_out.is_some()) && supersampled {
            return Err(usage(
                "OpenEXR frames hold the G-buffer at the frame's size, one entry per pixel; leave out --supersample",
            ));
        }
        let sidecars = [
            ("--hdr-out", &self.hdr_out, "hdr", "Radiance"),
            ("--exr-out", &self.exr_out, "exr", "OpenEXR"),
            ("--camera-out", &self.camera_out, "json", "JSON"),
        ];
        for (flag, path, extension, kind) in sidecars {
            let Some(path) = path else { continue };
            let fits = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case(extension));
            if !fits {
                return Err(usage(format!(
                    "{flag} writes {kind} .{extension} files; {} does not end in .{extension}",
                    path.display()
                )));
            }
            if no_write {
                return Err(usage(format!(
                    "{flag} writes a file for every frame; leave out --no-write"
                )));
            }
        }
        if let Some(path) = &self.timeline {
            if !path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("json"))
            {
                return Err(usage(format!(
                    "--timeline writes trace-event JSON; {} does not end in .json",
                    path.display()
                )));
            }
        }
        let exr = exr_out || self.exr_out.is_some();
        if !self.aov.is_empty() && !exr && !self.aov_png {
            return Err(usage(
                "--aov chooses the layers of OpenEXR frames and --aov-png; give --exr-out FILE.exr, --out FILE.exr or --aov-png",
            ));
        }
        if self.aov_png && !self.layers().iter().any(|l| l.scalar()) {
            return Err(usage(
                "--aov-png writes the scalar layers (depth, material, object, steps, shadow, ao, coverage); --aov chose none",
            ));
        }
        if self.exr_beauty != ExrBeauty::Linear && !exr {
            return Err(usage(
                "--exr-beauty sets what OpenEXR frames hold; give --exr-out FILE.exr or --out FILE.exr",
            ));
        }
        if self.aov_png && supersampled {
            return Err(usage(
                "--aov-png reads the G-buffer at the frame's size, one entry per pixel; leave out --supersample",
            ));
        }
        if self.aov_png && no_write {
            return Err(usage(
                "--aov-png writes files for every frame; leave out --no-write",
            ));
        }
        if !self.cost_map.is_empty() && no_write {
            return Err(usage(
                "--cost-map writes a heat map for every frame; leave out --no-write (--count-work counts without files)",
            ));
        }
        if self.resume && no_write {
            return Err(usage(
                "--resume skips frames whose files are written; --no-write writes none",
            ));
        }
        Ok(())
    }

    /// Whether frames must read back their linear radiance.
    pub fn needs_radiance(&self) -> bool {
        self.hdr_out.is_some() || self.needs_gbuffer() || self.bit_depth == 16
    }

    /// Whether frames must keep and read back the G-buffer.
    pub fn needs_gbuffer(&self) -> bool {
        self.exr_out.is_some() || is_exr(&self.out) || self.aov_png
    }

    /// The render outputs chosen: --aov's, in the documented order, or every one.
    fn layers(&self) -> Vec<Layer> {
        if self.aov.is_empty() {
            return Layer::ALL.to_vec();
        }
        let mut layers = self.aov.clone();
        layers.sort_unstable();
        layers.dedup();
        layers
    }

    /// Every file frame `index` (0-based) of `frames` writes.
    pub fn paths(&self, index: u32, frames: u32) -> Vec<PathBuf> {
        self.kinds()
            .into_iter()
            .map(|(kind, base)| file_path(kind, base, index, frames))
            .collect()
    }

    /// Whether every file of frame `index` is already there (for `--resume`).
    pub fn written(&self, index: u32, frames: u32) -> bool {
        self.paths(index, frames).iter().all(|p| p.is_file())
    }

    /// These outputs with `tag` joined to every file's stem (`frame.png` -> `frame_TAG.png`):
    /// one scene's or one camera's files in a batch.
    pub fn tagged(&self, tag: &str) -> FileArgs {
        let tag_path = |p: &Path| {
            let stem = p
                .file_stem()
                .map_or("frame".into(), |s| s.to_string_lossy());
            let name = match p.extension() {
                Some(ext) => format!("{stem}_{tag}.{}", ext.to_string_lossy()),
                None => format!("{stem}_{tag}"),
            };
            p.with_file_name(name)
        };
        FileArgs {
            out: tag_path(&self.out),
            hdr_out: self.hdr_out.as_deref().map(tag_path),
            exr_out: self.exr_out.as_deref().map(tag_path),
            camera_out: self.camera_out.as_deref().map(tag_path),
            timeline: self.timeline.as_deref().map(tag_path),
            ..self.clone()
        }
    }

    /// Writes every file of frame `index` of `frames`.
    pub fn write(
        &self,
        frame: &FrameOutput,
        index: u32,
        frames: u32,
        view: &FrameView,
    ) -> anyhow::Result<()> {
        let layers = self.layers();
        let tone_mapped = self.exr_beauty == ExrBeauty::ToneMapped;
        let exr = || encode_exr(frame, &layers, view, tone_mapped);
        for (kind, base) in self.kinds() {
            let bytes = match kind {
                FileKind::Image if is_exr(base) => exr()?,
                FileKind::Image if self.bit_depth == 16 => {
                    frame_encoders::png16(frame, &view.tone)?
                }
                FileKind::Image => frame_encoders::png8(frame)?,
                FileKind::Hdr => frame_encoders::hdr(frame)?,
                FileKind::Exr => exr()?,
                FileKind::LayerPng(layer) => {
                    let values = frame.gbuffer.as_ref().and_then(|gbuffer| {
                        let source = LayerSource {
                            gbuffer,
                            camera: &view.camera,
                            mesh_materials: view.mesh_materials,
                        };
                        source.png_values(layer)
                    });
                    match values {
                        Some(v) => Some(frame_encoders::grey16(&v, frame.width, frame.height)?),
                        None => None,
                    }
                }
                FileKind::CostMap(map) => match &frame.work {
                    Some(counts) => Some(cost_map_png(map, counts)?),
                    None => None,
                },
                FileKind::Camera => {
                    let value = camera_json(&view.camera, index + 1, frame.width, frame.height);
                    let mut text = value.to_string();
                    text.push('\n');
                    Some(text.into_bytes())
                }
            };
            if let Some(bytes) = bytes {
                write_whole(&file_path(kind, base, index, frames), &bytes)?;
            }
        }
        Ok(())
    }

    /// Each file a frame writes, with the path its name is made from.
    fn kinds(&self) -> Vec<(FileKind, &Path)> {
        let mut kinds = vec![(FileKind::Image, self.out.as_path())];
        kinds.extend(self.hdr_out.as_deref().map(|p| (FileKind::Hdr, p)));
        kinds.extend(self.exr_out.as_deref().map(|p| (FileKind::Exr, p)));
        if self.aov_png {
            let scalar = self.layers().into_iter().filter(|l| l.scalar());
            kinds.extend(scalar.map(|l| (FileKind::LayerPng(l), self.out.as_path())));
        }
        kinds.extend(self.camera_out.as_deref().map(|p| (FileKind::Camera, p)));
        let mut maps = self.cost_map.clone();
        maps.sort_by_key(|m| m.name());
        maps.dedup();
        kinds.extend(
            maps.into_iter()
                .map(|m| (FileKind::CostMap(m), self.out.as_path())),
        );
        kinds
    }
}

/// Where a file of `kind` made from `base` goes for frame `index` of `frames`: a layer's PNG is
/// `STEM.LAYER.png` beside the frame's image.
fn file_path(kind: FileKind, base: &Path, index: u32, frames: u32) -> PathBuf {
    let path = frame_path(base, index, frames);
    let suffix = match kind {
        FileKind::LayerPng(layer) => layer.to_string(),
        FileKind::CostMap(map) => format!("cost-{}", map.name()),
        _ => return path,
    };
    let stem = path
        .file_stem()
        .map_or("frame".into(), |s| s.to_string_lossy());
    path.with_file_name(format!("{stem}.{suffix}.png"))
}

/// The file frame `index` (0-based) of `frames` is written to: `out` itself for one frame, else
/// `STEM_000k.EXT` beside it.
pub fn frame_path(out: &Path, index: u32, frames: u32) -> PathBuf {
    if frames == 1 {
        return out.to_path_buf();
    }
    let stem = out
        .file_stem()
        .map_or("frame".into(), |s| s.to_string_lossy());
    let ext = out
        .extension()
        .map_or("png".into(), |e| e.to_string_lossy());
    out.with_file_name(format!("{stem}_{:04}.{ext}", index + 1))
}

/// The hidden name `path` is written under until it is whole.
pub fn partial_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or("frame".into(), |n| n.to_string_lossy());
    path.with_file_name(format!(".{name}.partial"))
}

/// Writes `bytes` to `path` through its partial name, flushed to the disk before the rename, so
/// `path` holds either nothing (or its old contents) or all of `bytes`.
pub fn write_whole(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let partial = partial_path(path);
    let written = fs::File::create(&partial).and_then(|mut file| {
        file.write_all(bytes)?;
        file.sync_all()
    });
    if let Err(e) = written.and_then(|()| fs::rename(&partial, path)) {
        // What was written so far is useless; the error is about `path`, not the leftover.
        let _ = fs::remove_file(&partial);
        return Err(e).with_context(|| format!("writing {}", path.display()));
    }
    Ok(())
}

/// `--bit-depth`'s value.
fn bit_depth(text: &str) -> Result<u8, String> {
    match text {
        "8" => Ok(8),
        "16" => Ok(16),
        _ => Err("PNGs are written with 8 or 16 bits per channel".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(out: &str) -> FileArgs {
        FileArgs {
            out: out.into(),
            bit_depth: 8,
            hdr_out: Some("radiance/frame.hdr".into()),
            exr_out: None,
            camera_out: Some("frame.json".into()),
            aov: vec![Layer::Shadow, Layer::Normal, Layer::Depth],
            aov_png: true,
            exr_beauty: ExrBeauty::Linear,
            resume: false,
            timeline: Some("trace.json".into()),
            cost_map: Vec::new(),
        }
    }

    #[test]
    fn a_sequence_numbers_its_files_beside_the_output() {
        let out = Path::new("shots/frame.png");
        assert_eq!(frame_path(out, 0, 1), PathBuf::from("shots/frame.png"));
        assert_eq!(
            frame_path(out, 0, 60),
            PathBuf::from("shots/frame_0001.png")
        );
        assert_eq!(
            frame_path(out, 59, 60),
            PathBuf::from("shots/frame_0060.png")
        );
    }

    #[test]
    fn a_tag_goes_into_every_files_stem() {
        let tagged = args("shots/frame.png").tagged("box");
        assert_eq!(
            tagged.paths(2, 10),
            [
                PathBuf::from("shots/frame_box_0003.png"),
                PathBuf::from("radiance/frame_box_0003.hdr"),
                PathBuf::from("shots/frame_box_0003.depth.png"),
                PathBuf::from("shots/frame_box_0003.shadow.png"),
                PathBuf::from("frame_box_0003.json"),
            ]
        );
        assert_eq!(tagged.timeline, Some(PathBuf::from("trace_box.json")));
    }

    #[test]
    fn a_file_is_whole_or_absent_and_no_partial_stays() {
        let dir = std::env::temp_dir().join(format!("relief-frame-files-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        let path = dir.join("sub").join("frame.png");
        write_whole(&path, b"first").expect("writes");
        write_whole(&path, b"second, longer").expect("replaces");
        assert_eq!(fs::read(&path).expect("reads"), b"second, longer");
        assert!(!partial_path(&path).exists());
        // A directory where the file should go: the rename fails, the partial is removed.
        let blocked = dir.join("blocked.png");
        fs::create_dir_all(blocked.join("inside")).expect("makes the obstacle");
        assert!(write_whole(&blocked, b"bytes").is_err());
        assert!(!partial_path(&blocked).exists());
        fs::remove_dir_all(&dir).expect("cleans up");
    }
}
