//! glTF 2.0 (.gltf with external or embedded buffers, .glb) to a [`Scene`]: one scene's node
//! tree with transforms, its triangle meshes, materials with textures and relief, images,
//! cameras and KHR_lights_punctual lights.
//!
//! Malformed files are rejected with an error rather than trusted: the JSON is checked (by
//! `gltf_prepass` and the gltf crate's validator), and buffer views, accessors, the node graph,
//! cameras and lights are checked here before anything is read, because the gltf crate's own
//! readers panic on out-of-range data. Animations are checked (`gltf_animation_check`) and the one
//! that moves the chosen camera becomes [`Scene::camera_path`] (`gltf_camera_path`); skins and
//! joint/weight attributes are not used, but are checked too (`gltf_skin_check`).
//! Primitives that are not triangle lists are skipped and counted in
//! [`LoadReport::skipped_primitives`].

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

use super::camera::Projection;
use super::gltf_mesh::{convert_meshes, place};
use super::gltf_prepass::{self, Parsed};
use super::light_extras::parse_light_extras;
use super::{
    gltf_accessor, gltf_animation_check, gltf_camera_path, gltf_image, gltf_material, gltf_nodes,
    gltf_skin_check,
};
use super::{Camera, Light, LightKind, Material, Scene};

/// Why a scene file could not be used. Every message starts with the file's path.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file itself could not be read.
    #[error("scene {path:?}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Why it could not be read.
        source: std::io::Error,
    },
    /// The file is not glTF 2.0 the loader can use; `what` says where and why.
    #[error("scene {path:?}: {what}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Where in it and why.
        what: String,
    },
}

/// Which scene and camera of a file to use.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SceneOptions {
    /// Index of the glTF scene; `None`: the file's default scene, else scene 0.
    pub scene: Option<usize>,
    /// Index among the cameras met walking the chosen scene's nodes; `None`: the first.
    pub camera: Option<usize>,
}

/// What was loaded but left out.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LoadReport {
    /// Primitives that are points, lines, strips or fans (only triangle lists are drawn).
    pub skipped_primitives: usize,
    /// Cameras met walking the chosen scene's nodes (what [`SceneOptions::camera`] counts).
    pub cameras: usize,
}

/// Loads a glTF file with its buffers and images.
pub fn load_gltf(path: &Path, opts: &SceneOptions) -> Result<Scene, SceneError> {
    load_gltf_with_report(path, opts).map(|(scene, _)| scene)
}

/// [`load_gltf`], also saying what was skipped.
pub fn load_gltf_with_report(
    path: &Path,
    opts: &SceneOptions,
) -> Result<(Scene, LoadReport), SceneError> {
    let bytes = std::fs::read(path).map_err(|source| SceneError::Read {
        path: path.to_owned(),
        source,
    })?;
    let invalid = |what: String| SceneError::Invalid {
        path: path.to_owned(),
        what,
    };
    let Parsed {
        doc,
        raw,
        blob,
        zero_buffers,
    } = gltf_prepass::parse(&bytes).map_err(invalid)?;
    let base = path.parent().unwrap_or_else(|| Path::new("."));
    let buffers = load_buffers(&doc, base, blob).map_err(invalid)?;
    gltf_accessor::check_views(&doc, &buffers).map_err(invalid)?;
    gltf_nodes::check_graph(&doc).map_err(invalid)?;
    check_cameras(&doc).map_err(invalid)?;
    let images = gltf_image::load_images(&doc, base, &buffers).map_err(invalid)?;
    let mut scene = Scene {
        materials: gltf_material::convert_materials(&doc, &raw).map_err(invalid)?,
        images,
        ..Scene::default()
    };
    let (report, camera_node) = build(&doc, &buffers, opts, &mut scene).map_err(invalid)?;
    super::bake_vertex_color_weights(&mut scene)
        .map_err(|e| invalid(format!("vertex-colour layer weights: {e}")))?;
    // Last, so errors in what is drawn name their mesh: the rest of the accessors (animation,
    // skins, unused) are checked too, since a file with broken data is broken either way.
    gltf_accessor::check_accessors(&doc, &buffers, zero_buffers).map_err(invalid)?;
    // Animations are checked whole before the camera's is read; skins are checked, not used.
    gltf_animation_check::check_animations(&doc, &buffers, zero_buffers).map_err(invalid)?;
    gltf_skin_check::check_skins(&doc, &buffers, zero_buffers).map_err(invalid)?;
    if let (Some(node), Some(camera)) = (camera_node, scene.camera) {
        scene.camera_path =
            gltf_camera_path::camera_path(&doc, &buffers, zero_buffers, node, camera.projection)
                .map_err(invalid)?;
    }
    Ok((scene, report))
}

/// Like `gltf::import_buffers`, but the error says which buffer (lengths are checked later).
fn load_buffers(
    doc: &gltf::Document,
    base: &Path,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<gltf::buffer::Data>, String> {
    doc.buffers()
        .map(|b| {
            gltf::buffer::Data::from_source_and_blob(b.source(), Some(base), &mut blob).map_err(
                |e| match b.source() {
                    gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => {
                        format!("buffer {} ({uri}): {e}", b.index())
                    }
                    _ => format!("buffer {}: {e}", b.index()),
                },
            )
        })
        .collect()
}

/// Fills `scene` from the chosen glTF scene; also returns the chosen camera's node.
fn build(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    opts: &SceneOptions,
    scene: &mut Scene,
) -> Result<(LoadReport, Option<usize>), String> {
    let mut report = LoadReport::default();
    let meshes = convert_meshes(doc, buffers, &scene.materials)?;
    let count = doc.scenes().len();
    let chosen = match opts.scene {
        Some(i) if i >= count => {
            return Err(format!(
                "scene {i} requested but the file has {count} scenes"
            ));
        }
        Some(i) => doc.scenes().nth(i),
        None => doc.default_scene().or_else(|| doc.scenes().next()),
    };
    let Some(root) = chosen else {
        return Ok((report, None));
    };
    let mut default_material = None;
    let mut cameras = Vec::new();
    for (node, world) in gltf_nodes::walk(&root, doc.nodes().len())? {
        if let Some(mesh) = node.mesh() {
            for converted in &meshes[mesh.index()] {
                let Some(m) = converted else {
                    report.skipped_primitives += 1;
                    continue;
                };
                let mut placed = place(m, world);
                if placed.material == usize::MAX {
                    placed.material = *default_material.get_or_insert_with(|| {
                        scene.materials.push(Material::default());
                        scene.materials.len() - 1
                    });
                }
                scene.meshes.push(placed);
            }
        }
        if let Some(cam) = node.camera() {
            cameras.push((node.index(), convert_camera(&cam, world)));
        }
        if let Some(light) = node.light() {
            scene.lights.push(convert_light(&light, world)?);
        }
    }
    let chosen = match opts.camera {
        Some(i) if i >= cameras.len() => {
            return Err(format!(
                "camera {i} requested but the scene has {} cameras",
                cameras.len()
            ));
        }
        Some(i) => Some(cameras[i]),
        None => cameras.first().copied(),
    };
    scene.camera = chosen.map(|(_, camera)| camera);
    report.cameras = cameras.len();
    Ok((report, chosen.map(|(node, _)| node)))
}

/// Cameras whose projection is degenerate (zero extent, far not beyond near) are rejected:
/// they would give a singular projection matrix.
fn check_cameras(doc: &gltf::Document) -> Result<(), String> {
    for cam in doc.cameras() {
        let ok = match cam.projection() {
            gltf::camera::Projection::Perspective(p) => {
                p.yfov() > 0.0
                    && p.yfov() < std::f32::consts::PI
                    && p.znear() > 0.0
                    && p.zfar().is_none_or(|f| f > p.znear() && f.is_finite())
                    && p.aspect_ratio().is_none_or(|a| a > 0.0 && a.is_finite())
            }
            gltf::camera::Projection::Orthographic(o) => {
                o.xmag() != 0.0
                    && o.ymag() != 0.0
                    && o.xmag().is_finite()
                    && o.ymag().is_finite()
                    && o.znear() >= 0.0
                    && o.zfar() > o.znear()
                    && o.zfar().is_finite()
            }
        };
        if !ok {
            return Err(format!("camera {}: degenerate projection", cam.index()));
        }
    }
    Ok(())
}

fn convert_camera(cam: &gltf::Camera, world: Mat4) -> Camera {
    let projection = match cam.projection() {
        gltf::camera::Projection::Perspective(p) => Projection::Perspective {
            yfov: p.yfov(),
            aspect: p.aspect_ratio(),
            znear: p.znear(),
            // glTF's infinite projection; a far plane far away stands in for it.
            zfar: p.zfar().unwrap_or(p.znear() * 1e4),
        },
        gltf::camera::Projection::Orthographic(o) => Projection::Orthographic {
            xmag: o.xmag(),
            ymag: o.ymag(),
            znear: o.znear(),
            zfar: o.zfar(),
        },
    };
    Camera {
        view: world.inverse(),
        projection,
    }
}

fn convert_light(light: &gltf::khr_lights_punctual::Light, world: Mat4) -> Result<Light, String> {
    use gltf::khr_lights_punctual::Kind;
    let what = || format!("light {}", light.index());
    let intensity = light.intensity();
    let color = Vec3::from(light.color());
    let valid = intensity.is_finite()
        && intensity >= 0.0
        && color.is_finite()
        && color.min_element() >= 0.0;
    if !valid {
        return Err(format!(
            "{}: negative or non-finite colour or intensity",
            what()
        ));
    }
    if light.range().is_some_and(|r| !(r > 0.0 && r.is_finite())) {
        return Err(format!("{}: range must be > 0", what()));
    }
    let kind = match light.kind() {
        Kind::Directional => LightKind::Directional,
        Kind::Point => LightKind::Point,
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            if !(0.0 <= inner_cone_angle
                && inner_cone_angle < outer_cone_angle
                && outer_cone_angle <= std::f32::consts::FRAC_PI_2)
            {
                return Err(format!(
                    "{}: spot cone angles must satisfy 0 <= inner < outer <= pi/2",
                    what()
                ));
            }
            LightKind::Spot {
                inner_cone: inner_cone_angle,
                outer_cone: outer_cone_angle,
            }
        }
    };
    let extras = light.extras().as_ref().map(|raw| raw.get());
    let settings = parse_light_extras(extras, kind).map_err(|e| format!("{}: {e}", what()))?;
    Ok(Light {
        kind,
        radius: settings.radius,
        shadow_map_size: settings.shadow_map_size,
        shadow_cascades: settings.shadow_cascades,
        position: world.transform_point3(Vec3::ZERO),
        direction: world
            .transform_vector3(Vec3::NEG_Z)
            .normalize_or(Vec3::NEG_Z),
        color: color * intensity,
        range: light.range(),
        casts_shadows: true,
    })
}
