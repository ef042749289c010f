//! The bench's silhouette section: relief on curved meshes (a sphere, a torus, an open cylinder
//! and a curved wall, both lying so that no view looks into them, and any mesh the caller
//! brings, such as one from a glTF file) against the displaced-geometry reference, for each way
//! of drawing it (flat
//! relief mapping and flat QDM under the polygons, curved relief mapping, prism shells), depth scales from
//! shallow to deep and views from 30 to 75 degrees: silhouette agreement and colour difference
//! against GPU time, the numbers a material's choice follows.

use std::f32::consts::{FRAC_PI_2, PI, TAU};
use std::fmt::Write as _;
use std::sync::Arc;

use glam::{Mat4, Vec3};
use serde::{Deserialize, Serialize};

use super::frame_timing::{time_steady_frames, MapRate};
use crate::displaced_reference::{
    compare_with_reference, coverage, displaced_scene, iou, DisplacedReferenceError,
};
use crate::heightfield::{Address, Generator, Heightfield};
use crate::method::Method;
use crate::render::{render, RenderError, RenderOptions};
use crate::scene::{
    cylinder_mesh, sphere_mesh, torus_mesh, Camera, Light, Material, Mesh, Relief, Scene,
    Silhouettes,
};
use crate::shells::{self, scene_shells, SceneShellsError};
use crate::vk::Context;

/// Why the section could not run.
#[derive(Debug, thiserror::Error)]
pub enum SilhouetteError {
    /// The caller's mesh cannot carry relief.
    #[error(
        "mesh {0:?} has no triangle with usable texture coordinates to hang a height map from"
    )]
    NoUvs(String),
    /// A frame could not be rendered.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The reference could not be built.
    #[error(transparent)]
    Reference(#[from] DisplacedReferenceError),
    /// The prism shells could not be built.
    #[error(transparent)]
    Shells(#[from] SceneShellsError),
}

/// One mesh, depth, view and way of drawing it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SilhouetteCell {
    /// "sphere", "torus", "open cylinder", "curved wall" or the caller's mesh's name.
    pub mesh: String,
    /// The relief's world depth as a fraction of the mesh's radius.
    pub depth: f32,
    /// The view's elevation above the mesh's equator, in degrees.
    pub view_deg: f32,
    /// "flat relief", "flat qdm", "curved relief" or "shells" (prism shells drawn by the GPU).
    pub option: String,
    /// Silhouette agreement with the reference (intersection over union of covered pixels).
    pub iou: f64,
    /// Mean channel difference over the image, 8-bit levels.
    pub mean_difference: f64,
    /// The same within two pixels of the reference's outline.
    pub band_difference: f64,
    /// Median GPU ms of the surface pass.
    pub surface_ms: f64,
}

/// Prism shells' outline for one mesh, depth and view, from the CPU march that defines them:
/// which pixels the shells cover against the reference's, to set beside the GPU's.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShellCoverage {
    /// As [`SilhouetteCell::mesh`].
    pub mesh: String,
    /// As [`SilhouetteCell::depth`].
    pub depth: f32,
    /// As [`SilhouetteCell::view_deg`].
    pub view_deg: f32,
    /// Silhouette agreement with the reference (intersection over union of covered pixels).
    pub iou: f64,
    /// Prisms in the shell.
    pub prisms: usize,
    /// Wall-clock seconds of the march over the image, on every core.
    pub cpu_seconds: f64,
}

/// The whole section.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SilhouetteSection {
    /// Image size.
    pub size: [u32; 2],
    /// Frames timed per cell (after one untimed frame).
    pub frames: u32,
    /// Every cell.
    pub cells: Vec<SilhouetteCell>,
    /// Prism shells' coverage per mesh, depth and view (absent from files written before it).
    #[serde(default)]
    pub shells: Vec<ShellCoverage>,
    /// Per mesh, its first depth and view drawn every way beside the reference (not in
    /// results.json: `relief bench` writes them as PNG files).
    #[serde(skip)]
    pub strips: Vec<SilhouetteStrip>,
}

/// One mesh, depth and view as the reference and every option draw it, side by side (RGBA8):
/// the picture beside the section's numbers.
#[derive(Debug, Clone, Default)]
pub struct SilhouetteStrip {
    /// File name to write it under: `silhouettes-<mesh>.png`.
    pub file: String,
    /// Width and height in pixels.
    pub size: [u32; 2],
    /// Its pixels.
    pub rgba: Vec<u8>,
}

/// `silhouettes-<mesh>.png`, the mesh's name kept to letters and digits.
fn strip_file(mesh: &str) -> String {
    let name: String = mesh
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    format!("silhouettes-{name}.png")
}

/// Lays `images` (each `size`, RGBA8) side by side.
fn side_by_side(images: &[Vec<u8>], size: [u32; 2]) -> Vec<u8> {
    let (w, h) = (size[0] as usize * 4, size[1] as usize);
    let mut out = vec![0u8; w * h * images.len()];
    for (k, image) in images.iter().enumerate() {
        for (y, row) in image.chunks_exact(w).enumerate() {
            let at = (y * images.len() + k) * w;
            out[at..at + w].copy_from_slice(row);
        }
    }
    out
}

/// A test mesh, how long one depth unit is on it (at its widest), its radius, and where the
/// camera looks from (horizontal direction) and at.
struct Subject {
    name: String,
    mesh: Mesh,
    depth_unit: f32,
    radius: f32,
    facing: Vec3,
    target: Vec3,
    distance: f32,
    /// The camera's near and far planes.
    clip: [f32; 2],
}

/// The open meshes lie with their axis along x, so that no view of the section looks into their
/// open ends: there a one-sided mesh shows its inside, which no method under its polygons can.
fn lying(mut mesh: Mesh, turn_about_y: f32) -> Mesh {
    mesh.transform = Mat4::from_rotation_z(FRAC_PI_2) * Mat4::from_rotation_y(turn_about_y);
    mesh
}

fn subjects(quick: bool) -> Vec<Subject> {
    // The wall spans 1.5 radians; turned so that its middle faces +x, then laid down (+y).
    let wall_arc = 1.5f32;
    let mut all = vec![
        Subject {
            name: "sphere".into(),
            mesh: sphere_mesh("sphere", 1.0, 16, 32, 0),
            depth_unit: PI * 2f32.sqrt(),
            radius: 1.0,
            facing: Vec3::Z,
            target: Vec3::ZERO,
            distance: 3.0,
            clip: [0.1, 20.0],
        },
        Subject {
            name: "torus".into(),
            mesh: torus_mesh("torus", 1.0, 0.35, 48, 24, 0),
            depth_unit: TAU * (1.35f32 * 0.35).sqrt(),
            radius: 1.0,
            facing: Vec3::Z,
            target: Vec3::ZERO,
            distance: 3.2,
            clip: [0.1, 20.0],
        },
    ];
    if !quick {
        all.push(Subject {
            name: "open cylinder".into(),
            mesh: lying(cylinder_mesh("cylinder", 1.0, 2.0, TAU, 48, 4, 0), 0.0),
            depth_unit: (TAU * 2.0f32).sqrt(),
            radius: 1.0,
            facing: Vec3::Z,
            target: Vec3::ZERO,
            distance: 4.2,
            clip: [0.1, 20.0],
        });
        all.push(Subject {
            name: "curved wall".into(),
            mesh: lying(
                cylinder_mesh("wall", 2.0, 1.5, wall_arc, 24, 2, 0),
                -0.5 * wall_arc,
            ),
            depth_unit: (wall_arc * 2.0 * 1.5).sqrt(),
            radius: 2.0,
            facing: Vec3::Z,
            target: Vec3::Y * 2.0,
            distance: 3.0,
            clip: [0.1, 20.0],
        });
    }
    all
}

/// A mesh from outside (a glTF file's): seen from +z of its bounds' centre, at three times its
/// radius (the largest distance of a vertex from that centre), its depth unit the mesh's mean.
fn subject_of(mesh: &Mesh) -> Result<Subject, SilhouetteError> {
    let depth_unit = mesh
        .mean_depth_length()
        .ok_or_else(|| SilhouetteError::NoUvs(mesh.name.clone()))?;
    let world: Vec<Vec3> = mesh
        .vertices
        .iter()
        .map(|v| mesh.transform.transform_point3(v.position.into()))
        .collect();
    let (lo, hi) = world.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let centre = (lo + hi) * 0.5;
    let radius = world.iter().map(|p| p.distance(centre)).fold(0.0, f32::max);
    let mut mesh = mesh.clone();
    mesh.material = 0;
    Ok(Subject {
        name: mesh.name.clone(),
        mesh,
        depth_unit: depth_unit as f32,
        radius,
        facing: Vec3::Z,
        target: centre,
        distance: 3.0 * radius,
        clip: [0.03 * radius, 20.0 * radius],
    })
}

fn scene_of(subject: &Subject, depth: f32, view_deg: f32, option: &str) -> Scene {
    let (method, silhouettes) = match option {
        "flat qdm" => (Method::QDM, Silhouettes::Flat),
        "curved relief" => (Method::RELIEF, Silhouettes::Curved),
        "shells" => (Method::RELIEF, Silhouettes::Shells),
        _ => (Method::RELIEF, Silhouettes::Flat),
    };
    let relief = Relief {
        silhouettes,
        ..Relief::new(depth * subject.radius / subject.depth_unit, method)
    };
    let material = Material {
        name: "relief".into(),
        roughness: 0.6,
        relief: Some(relief),
        ..Material::default()
    };
    let light = Light {
        direction: Vec3::new(-0.5, -0.7, -0.5).normalize(),
        color: Vec3::splat(3.0),
        ..Light::default_light()
    };
    let e = view_deg.to_radians();
    let eye = subject.target + (subject.facing * e.cos() + Vec3::Y * e.sin()) * subject.distance;
    Scene {
        meshes: vec![subject.mesh.clone()],
        materials: vec![material],
        lights: vec![light],
        camera: Some(Camera::look_at(
            eye,
            subject.target,
            0.8,
            subject.clip[0],
            subject.clip[1],
        )),
        ..Scene::default()
    }
}

/// The ways of drawing relief the section compares.
pub const SILHOUETTE_OPTIONS: [&str; 4] = ["flat relief", "flat qdm", "curved relief", "shells"];

/// Runs the section; `quick` measures two meshes at one depth and view on a smaller image;
/// `extra`, a mesh of the caller's (with uvs for the height map), is measured after the built-in
/// ones.
pub fn run_silhouette_section(
    ctx: &Arc<Context>,
    quick: bool,
    extra: Option<&Mesh>,
    mut progress: impl FnMut(&str),
) -> Result<SilhouetteSection, SilhouetteError> {
    let (size, frames, depths, views): ([u32; 2], u32, &[f32], &[f32]) = if quick {
        ([160, 120], 2, &[0.05], &[30.0])
    } else {
        ([320, 240], 5, &[0.02, 0.05, 0.1], &[30.0, 75.0])
    };
    let heights: Heightfield = Generator::Fbm.generate(64, 64, 3);
    let opts = RenderOptions {
        width: size[0],
        height: size[1],
        ..RenderOptions::default()
    };
    let mut cells = Vec::new();
    let mut shell_cells = Vec::new();
    let mut strips = Vec::new();
    let mut all = subjects(quick);
    if let Some(mesh) = extra {
        all.push(subject_of(mesh)?);
    }
    for subject in all {
        for &depth in depths {
            for &view_deg in views {
                progress(&format!(
                    "silhouettes: {}, depth {depth}, {view_deg} degrees",
                    subject.name
                ));
                let base = scene_of(&subject, depth, view_deg, "flat relief");
                let reference = displaced_scene(&base, Some(&heights), Address::Repeat, 1.0)?;
                let truth = render(ctx, &reference.scene, None, &opts)?.rgba;
                let cell = (subject.name.clone(), depth, view_deg);
                shell_cells.push(shell_coverage(cell, &base, &heights, &truth, size)?);
                let pictured = depth == depths[0] && view_deg == views[0];
                let mut drawn = vec![truth.clone()];
                for option in SILHOUETTE_OPTIONS {
                    let scene = scene_of(&subject, depth, view_deg, option);
                    let image = render(ctx, &scene, Some(&heights), &opts)?.rgba;
                    if pictured {
                        drawn.push(image.clone());
                    }
                    let agreement = compare_with_reference(&image, &truth, size[0], size[1]);
                    let timed = time_steady_frames(
                        ctx,
                        &scene,
                        Some(&heights),
                        &opts,
                        frames,
                        MapRate::AsNeeded,
                    )?;
                    cells.push(SilhouetteCell {
                        mesh: subject.name.clone(),
                        depth,
                        view_deg,
                        option: option.to_owned(),
                        iou: agreement.iou,
                        mean_difference: agreement.mean_difference,
                        band_difference: agreement.band_difference,
                        surface_ms: timed.surface_ms,
                    });
                }
                if pictured {
                    strips.push(SilhouetteStrip {
                        file: strip_file(&subject.name),
                        size: [size[0] * drawn.len() as u32, size[1]],
                        rgba: side_by_side(&drawn, size),
                    });
                }
            }
        }
    }
    Ok(SilhouetteSection {
        size,
        frames,
        cells,
        shells: shell_cells,
        strips,
    })
}

/// The outline prism shells give `scene`'s relief meshes against the reference's frame `truth`,
/// for the cell `(mesh, depth, view_deg)`.
fn shell_coverage(
    (mesh, depth, view_deg): (String, f32, f32),
    scene: &Scene,
    heights: &Heightfield,
    truth: &[u8],
    size: [u32; 2],
) -> Result<ShellCoverage, SilhouetteError> {
    let built = scene_shells(scene, Some(heights), Address::Repeat)?;
    let camera = scene.camera.expect("the section's scenes have a camera");
    let started = std::time::Instant::now();
    let covered = shells::coverage(&built, &camera, size);
    let cpu_seconds = started.elapsed().as_secs_f64();
    Ok(ShellCoverage {
        mesh,
        depth,
        view_deg,
        iou: iou(&covered, &coverage(truth)),
        prisms: built.iter().map(|s| s.prisms.len()).sum(),
        cpu_seconds,
    })
}

/// The section's table in `report.md`.
pub fn report(md: &mut String, s: &SilhouetteSection) {
    let _ = writeln!(md, "\n## Silhouettes on curved meshes\n");
    let _ = writeln!(
        md,
        "Each way of drawing relief against the mesh really tessellated and displaced (edges of one \
         height texel), {}x{}, a 64x64 fBm map; depth is the relief's world depth over the \
         mesh's radius, view the elevation above its equator. IoU: silhouette agreement; \
         difference: mean channel difference over the image and within two pixels of the true \
         outline; time: median GPU ms of the surface pass over {} frames.\n",
        s.size[0], s.size[1], s.frames
    );
    let _ = writeln!(
        md,
        "| mesh | depth | view | option | IoU | difference | at the outline | surface ms |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    for c in &s.cells {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.4} | {:.2} | {:.2} | {:.3} |",
            c.mesh,
            c.depth,
            c.view_deg,
            c.option,
            c.iou,
            c.mean_difference,
            c.band_difference,
            c.surface_ms
        );
    }
    if !s.strips.is_empty() {
        let files: Vec<&str> = s.strips.iter().map(|p| p.file.as_str()).collect();
        let _ = writeln!(
            md,
            "\nPictures: {}, each mesh at the first depth and view above drawn as the reference, \
             then {}, side by side.",
            files.join(", "),
            SILHOUETTE_OPTIONS.join(", ")
        );
    }
    if s.shells.is_empty() {
        return;
    }
    let _ = writeln!(
        md,
        "\nPrism shells as the CPU march (their definition, in f64) traces them: one ray per \
         pixel centre, the covered pixels against the reference's, to set beside the GPU's \
         `shells` rows; no colour, no GPU time.\n"
    );
    let _ = writeln!(md, "| mesh | depth | view | prisms | IoU | CPU s |");
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    for c in &s.shells {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.4} | {:.2} |",
            c.mesh, c.depth, c.view_deg, c.prisms, c.iou, c.cpu_seconds
        );
    }
}
