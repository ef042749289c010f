//! What a material's relief reads, checked before anything is built: its height source (the
//! frame's map, an image's channel, blended layers), the address its sampler implies, and the
//! settings that cannot be drawn together; and the errors that say why a scene cannot be planned.

use super::frame_plan::HeightKey;
use crate::heightfield::{Address, Heightfield};
use crate::method::Method;
use crate::scene::{HeightSource, Material, Relief, Scene, Silhouettes, Wrap};

/// Why a scene cannot be planned.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    #[error("material {material:?} has relief from the frame's height map, but none was given (use --heightmap FILE)")]
    /// A material takes its relief from the frame's height map, and none was given.
    NoFrameHeights {
        /// The material's name.
        material: String,
    },
    #[error("mesh {mesh:?} names material {material}, but the scene has {count}")]
    /// A mesh names a material index the scene does not have.
    NoMaterial {
        /// The mesh's name.
        mesh: String,
        /// The material index it names.
        material: usize,
        /// How many materials the scene has.
        count: usize,
    },
    #[error("--cells {name:?}: the scene has no mesh of that name (its meshes: {names})")]
    /// `--cells` names no mesh of the scene.
    NoCellsMesh {
        /// The name given.
        name: String,
        /// The scene's mesh names, comma-separated.
        names: String,
    },
    #[error("--cells: the meshes named {name:?} use {count} materials; a cell complex is shaded with one")]
    /// The meshes `--cells` selects use more than one material.
    CellsMaterials {
        /// The name given.
        name: String,
        /// How many materials they use.
        count: usize,
    },
    #[error("material {material:?}: {silhouettes} silhouettes {why}")]
    /// A material asks for curved or shell silhouettes where they cannot be drawn.
    Silhouettes {
        /// The material's name.
        material: String,
        /// The option asked for.
        silhouettes: Silhouettes,
        /// What stands in the way.
        why: String,
    },
    #[error("material {material:?} has relief from its layers, but no layers")]
    /// A material takes its relief from its layers, and has none.
    NoLayers {
        /// The material's name.
        material: String,
    },
    #[error("material {material:?}: {source}")]
    /// A material's layers are unusable.
    Layers {
        /// The material's name.
        material: String,
        /// What is wrong with them.
        source: crate::scene::LayersError,
    },
    #[error(
        "material {material:?}: height texture names image {image}, but the scene has {count}"
    )]
    /// A material's height texture (or one of its layers' textures) names an image index the
    /// scene does not have.
    NoImage {
        /// The material's name.
        material: String,
        /// The image index it names.
        image: usize,
        /// How many images the scene has.
        count: usize,
    },
}

/// `material`'s layers, checked, with every texture they name in the scene.
fn checked_layers<'a>(
    scene: &Scene,
    material: &'a crate::scene::Material,
) -> Result<&'a crate::scene::Layers, PlanError> {
    let layers = material
        .layers
        .as_ref()
        .ok_or_else(|| PlanError::NoLayers {
            material: material.name.clone(),
        })?;
    layers.check().map_err(|source| PlanError::Layers {
        material: material.name.clone(),
        source,
    })?;
    let textures = layers.layers.iter().flat_map(|l| {
        [Some(l.height), l.albedo, l.normal, l.roughness]
            .into_iter()
            .flatten()
    });
    let splat = layers.splat().ok_or_else(|| PlanError::Layers {
        material: material.name.clone(),
        source: crate::scene::LayersError::Unbaked,
    })?;
    for t in textures.chain([*splat]) {
        if t.image >= scene.images.len() {
            return Err(PlanError::NoImage {
                material: material.name.clone(),
                image: t.image,
                count: scene.images.len(),
            });
        }
    }
    Ok(layers)
}

fn address_of(wrap: [Wrap; 2]) -> Address {
    if wrap.contains(&Wrap::ClampToEdge) {
        Address::Clamp
    } else {
        Address::Repeat
    }
}

/// Which height map a relief material reads (its relief's `height`), a name for it in messages, and its size.
pub(super) fn height_source(
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    material: &Material,
    material_index: usize,
    height: HeightSource,
) -> Result<(HeightKey, String, (u32, u32)), PlanError> {
    Ok(match height {
        HeightSource::Frame => {
            let hf = frame_heights.ok_or_else(|| PlanError::NoFrameHeights {
                material: material.name.clone(),
            })?;
            let size = (hf.width(), hf.height());
            (HeightKey::Frame, "frame height map".to_owned(), size)
        }
        HeightSource::Texture {
            texture,
            channel,
            invert,
        } => {
            let image = scene
                .images
                .get(texture.image)
                .ok_or_else(|| PlanError::NoImage {
                    material: material.name.clone(),
                    image: texture.image,
                    count: scene.images.len(),
                })?;
            let key = HeightKey::Image {
                image: texture.image,
                channel,
                invert,
                address: address_of([texture.sampler.wrap_u, texture.sampler.wrap_v]),
            };
            let size = (image.pixels.width(), image.pixels.height());
            (key, format!("image {}", image.name), size)
        }
        HeightSource::Layers => {
            let layers = checked_layers(scene, material)?;
            let n = layers.resolution;
            let source = format!(
                "{} layers of {:?} blended ({})",
                layers.layers.len(),
                material.name,
                layers.mode
            );
            let key = HeightKey::Layers {
                material: material_index,
            };
            (key, source, (n, n))
        }
    })
}

/// Curved relief bends relief mapping's linear search and prism shells walk their own prisms;
/// the other methods' structures bound straight rays in the polygon's texture space, and level
/// of detail and blended layers have no curved or shell variant.
pub(super) fn check_silhouettes(material: &Material, relief: &Relief) -> Result<(), PlanError> {
    if relief.silhouettes == Silhouettes::Flat {
        return Ok(());
    }
    let why = if relief.method != Method::RELIEF {
        let how = match relief.silhouettes {
            Silhouettes::Shells => {
                "walk their prisms with their own march and relief mapping's \
                                    self-shadows"
            }
            _ => "trace with relief mapping's linear and binary search",
        };
        format!(
            "{how} (method relief), not {}: the other methods' acceleration structures bound \
             straight rays under a flat polygon only",
            relief.method
        )
    } else if relief.lod.is_some() {
        "have no level-of-detail variant".to_owned()
    } else if relief.height == HeightSource::Layers {
        "have no blended-layers variant".to_owned()
    } else {
        return Ok(());
    };
    Err(PlanError::Silhouettes {
        material: material.name.clone(),
        silhouettes: relief.silhouettes,
        why,
    })
}
