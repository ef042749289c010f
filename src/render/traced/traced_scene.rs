//! A scene's occluders in acceleration structures: plain triangles (and, in the flat world, relief
//! polygons) opaque in one bottom level, relief prisms as boxes in another, with their frames in a
//! storage buffer and their height map with its max pyramid; one top level over both.

use std::sync::Arc;

use ash::vk;

use super::prism_records::PrismRecord;
use crate::heightfield::{Address, Heightfield};
use crate::render::heights::height_resources::HeightResources;
use crate::render::kit::gpu_heightfield::HeightFormat;
use crate::render::kit::render_error::RenderError;
use crate::shadow_reference::{Occluder, SceneOccluders};
use crate::vk::{AccelerationStructure, Buffer, Context, Geometry, Instance, IDENTITY};

/// The custom index of the prisms' instance: prism k's record is at this plus k.
const PRISM_BASE: u32 = 0;

/// What a traced scene holds and what building it cost.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TracedSceneStats {
    /// Opaque triangles in the triangle structure.
    pub triangles: usize,
    /// Relief prisms, one box each.
    pub prisms: usize,
    /// Bytes of all the structures (the top level and one or two bottom levels).
    pub structure_bytes: u64,
    /// GPU ms of all their builds.
    pub build_ms: f64,
}

/// A scene's occluders on the GPU, ready for ray queries.
pub struct TracedScene {
    // Declared first: the top level goes before the bottom levels it names.
    top: AccelerationStructure,
    bottoms: Vec<AccelerationStructure>,
    records: Buffer,
    heights: HeightResources,
    address: Address,
    stats: TracedSceneStats,
}

impl TracedScene {
    /// Builds the structures of `occluders`. Every relief prism must read the same height map
    /// (the frame's, as the scene-shadow scenes have it): the traversal binds one.
    pub fn new(ctx: &Arc<Context>, occluders: &SceneOccluders) -> Result<TracedScene, RenderError> {
        if !ctx.info().ray_query {
            return Err(RenderError::NoRayQueries {
                device: ctx.info().name.clone(),
            });
        }
        let mut positions: Vec<[f32; 3]> = Vec::new();
        let mut records = Vec::new();
        let mut boxes = Vec::new();
        let mut map: Option<(Arc<Heightfield>, Address)> = None;
        for occluder in occluders.occluders() {
            match occluder {
                Occluder::Triangle(corners) => positions.extend(corners.map(|c| c.to_array())),
                Occluder::Relief(shell) => {
                    match &map {
                        None => map = Some((shell.heights().clone(), shell.address())),
                        Some((h, a)) => {
                            if !Arc::ptr_eq(h, shell.heights()) || *a != shell.address() {
                                return Err(RenderError::Traced(
                                    "relief materials read different height maps; ray queries bind one".into(),
                                ));
                            }
                        }
                    }
                    records.push(PrismRecord::from(&shell.frame()));
                    let b = shell.bounds();
                    boxes.push([b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z]);
                }
            }
        }
        let indices: Vec<u32> = (0..positions.len() as u32).collect();
        let mut bottoms = Vec::new();
        let mut instances_of = Vec::new();
        if !indices.is_empty() {
            let geometry = Geometry::Triangles {
                positions: &positions,
                indices: &indices,
            };
            bottoms.push(AccelerationStructure::bottom_level(
                ctx,
                geometry,
                "traced triangles",
            )?);
            instances_of.push(0);
        }
        if !boxes.is_empty() {
            bottoms.push(AccelerationStructure::bottom_level(
                ctx,
                Geometry::Boxes(&boxes),
                "traced prisms",
            )?);
            instances_of.push(PRISM_BASE);
        }
        let instances: Vec<Instance> = bottoms
            .iter()
            .zip(&instances_of)
            .map(|(structure, &custom_index)| Instance {
                structure,
                transform: IDENTITY,
                custom_index,
            })
            .collect();
        let top = AccelerationStructure::top_level(ctx, &instances, "traced scene")?;
        // A storage buffer is never empty: a scene without relief binds one unused record.
        let placeholder = [<PrismRecord as bytemuck::Zeroable>::zeroed()];
        let bytes: &[u8] = if records.is_empty() {
            bytemuck::cast_slice(&placeholder)
        } else {
            bytemuck::cast_slice(&records)
        };
        let records_buffer = Buffer::with_data(
            ctx,
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            "traced prism records",
        )?;
        let (field, address) = match map {
            Some((h, a)) => (h, a),
            None => (
                Arc::new(Heightfield::new(1, 1, vec![1.0])?),
                Address::Repeat,
            ),
        };
        let heights = upload_heights(ctx, &field, address)?;
        let all = || std::iter::once(&top).chain(&bottoms);
        let stats = TracedSceneStats {
            triangles: indices.len() / 3,
            prisms: records.len(),
            structure_bytes: all().map(AccelerationStructure::bytes).sum(),
            build_ms: all().map(AccelerationStructure::build_ms).sum(),
        };
        Ok(TracedScene {
            top,
            bottoms,
            records: records_buffer,
            heights,
            address,
            stats,
        })
    }

    /// Replaces the relief's height map (an edit, or a map of another size) and returns the host
    /// milliseconds it took. A prism's box spans its whole depth range and its frame comes from
    /// its triangle, so neither depends on the heights: no structure is rebuilt or refitted, and
    /// the next trace reads the new map (and its max pyramid, built here).
    pub fn set_heights(
        &mut self,
        ctx: &Arc<Context>,
        heights: &Heightfield,
    ) -> Result<f64, RenderError> {
        let start = std::time::Instant::now();
        self.heights = upload_heights(ctx, heights, self.address)?;
        Ok(start.elapsed().as_secs_f64() * 1e3)
    }

    /// What the scene holds and what building it cost.
    pub fn stats(&self) -> TracedSceneStats {
        self.stats
    }

    pub(in crate::render) fn top(&self) -> &AccelerationStructure {
        &self.top
    }

    pub(in crate::render) fn records(&self) -> &Buffer {
        &self.records
    }

    pub(in crate::render) fn heights(&self) -> &HeightResources {
        &self.heights
    }

    /// How many bottom levels the top level instances.
    pub fn bottom_levels(&self) -> usize {
        self.bottoms.len()
    }
}

/// `field` on the GPU, quantized to unorm16 as the reference reads it, with its max pyramid built.
fn upload_heights(
    ctx: &Arc<Context>,
    field: &Heightfield,
    address: Address,
) -> Result<HeightResources, RenderError> {
    let heights = HeightResources::new(
        ctx,
        field,
        HeightFormat::R16Unorm,
        address,
        None,
        // A traversal reads nothing of the uniforms but the height info, filled in here.
        bytemuck::Zeroable::zeroed(),
    )?;
    ctx.one_shot(|rec| heights.record_pyramid(rec))?;
    Ok(heights)
}
