//! The upload of every height map a plan lists, each with the precomputed map its method reads
//! (built once, here) and, for layered materials, the blended field, its pyramid and its painter.

use std::borrow::Cow;
use std::sync::Arc;

use super::renderer::FRAMES_IN_FLIGHT;
use super::single_frame::{planned_heights, BuiltMap, RenderOptions};
use crate::heightfield::{Address, Heightfield};
use crate::render::heights::height_resources::{HeightResources, HeightUpload};
use crate::render::kit::frame_uniforms::FrameUniforms;
use crate::render::kit::render_error::RenderError;
use crate::render::maps::map_builder::{build_method_map_with, MapBuilder};
use crate::render::plan::frame_plan::{HeightKey, Plan};
use crate::render::terrain::layer_paint::LayerPainter;
use crate::render::terrain::layered_heights::blended_heights;
use crate::scene::Scene;
use crate::vk::{Context, VkError};

/// Uploads every planned height map with its precomputed map (built once, here).
pub(in crate::render) fn upload_heights(
    ctx: &Arc<Context>,
    scene: &Scene,
    plan: &Plan,
    frame_heights: Option<&Heightfield>,
    opts: &RenderOptions,
    uniforms: FrameUniforms,
) -> Result<UploadedHeights, RenderError> {
    let mut heights = Vec::with_capacity(plan.heights.len());
    let mut painters = Vec::with_capacity(plan.heights.len());
    let mut maps = Vec::new();
    for hp in &plan.heights {
        let (stored, address, prebuilt) = match hp.key {
            HeightKey::Layers { material } => {
                let layers = scene.materials[material].layers.as_ref().ok_or_else(|| {
                    VkError::Invalid("the plan blends a material without layers".into())
                })?;
                let mut blended = blended_heights(
                    ctx,
                    scene,
                    layers,
                    opts.height_format,
                    opts.paintable_layers,
                )?;
                painters.push(blended.painter.take());
                maps.push(BuiltMap {
                    kind: "layer stack",
                    source: hp.source.clone(),
                    size: [hp.size.0, hp.size.1],
                    ms: blended.stack_ms,
                    on: "cpu",
                });
                maps.push(BuiltMap {
                    kind: "blended pyramid",
                    source: hp.source.clone(),
                    size: [hp.size.0, hp.size.1],
                    ms: blended.gpu_ms,
                    on: "gpu",
                });
                let level = blended.pyramid.level(0);
                let field = Heightfield::from_valid(level.width, level.height, level.data.clone());
                (Cow::Owned(field), Address::Clamp, Some(blended.pyramid))
            }
            HeightKey::Frame => {
                let stored = planned_heights(ctx, scene, hp, frame_heights, opts.height_format)?;
                painters.push(None);
                (stored, opts.address, None)
            }
            HeightKey::Image { address, .. } => {
                let stored = planned_heights(ctx, scene, hp, frame_heights, opts.height_format)?;
                painters.push(None);
                (stored, address, None)
            }
        };
        let map = match hp.map_method {
            Some(method) => build_method_map_with(method, &stored, address, MapBuilder::Gpu(ctx))?,
            None => None,
        };
        if let (Some(built), Some(kind)) = (&map, hp.map) {
            maps.push(BuiltMap {
                kind: kind.name(),
                source: hp.source.clone(),
                size: [built.data.width, built.data.height],
                ms: built.ms,
                on: built.on,
            });
        }
        let map_data = map.as_ref().map(|built| &built.data);
        let upload = HeightUpload {
            format: opts.height_format,
            address,
            map: map_data,
            pyramid: hp.pyramid,
            slots: FRAMES_IN_FLIGHT,
            mean_binding: hp.mean_binding,
            mean_pyramid: hp.mean_pyramid,
        };
        if let Some(pyramid) = &prebuilt {
            heights.push(HeightResources::upload_prebuilt(
                ctx, pyramid, &upload, uniforms,
            )?);
            continue;
        }
        heights.push(HeightResources::upload(ctx, &stored, &upload, uniforms)?);
    }
    Ok((heights, maps, painters))
}

/// Every planned height map uploaded, the maps built for them, and the painters of layered ones.
pub(in crate::render) type UploadedHeights = (
    Vec<HeightResources>,
    Vec<BuiltMap>,
    Vec<Option<LayerPainter>>,
);
