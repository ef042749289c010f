//! The surface pass's draws: each draw the plan lists with its uploaded mesh (or prism shell),
//! its descriptor sets, push block, world bounds and roles (shaded, casting, occluding). Built once
//! per scene by the surface pass, which records them.

use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::draw_bounds::{mesh_bounds, world_bounds};
use super::material_set::MaterialSets;
use super::occluders::occludes;
use crate::render::kit::draw_push::DrawPush;
use crate::render::kit::mesh_buffers::mesh_buffers;
use crate::render::plan::frame_plan::{DrawPlan, DrawRole, PipelineKey, Plan};
use crate::render::shadows::shadow_plan::relief_pad;
use crate::render::shells::shell_upload::{upload_shell, BuiltShell};
use crate::render::terrain::layer_set::LayerSets;
use crate::scene::{Mesh, Scene};
use crate::vk::{Buffer, Context, DescriptorSet, VkError, VkResult};

/// A draw's set 0 per frame slot, its material's set and its layers' set.
type DrawSets = (Vec<DescriptorSet>, DescriptorSet, Option<DescriptorSet>);

pub(super) struct MeshDraw {
    /// The scene mesh it draws.
    pub(super) mesh: usize,
    pub(super) vertices: Buffer,
    pub(super) indices: Buffer,
    pub(super) index_count: u32,
    pub(super) pipeline: usize,
    /// Set 0 per frame slot.
    pub(super) frame_sets: Vec<DescriptorSet>,
    pub(super) material_set: DescriptorSet,
    /// Set 2 of layered materials.
    pub(super) layer_set: Option<DescriptorSet>,
    pub(super) push: DrawPush,
    pub(super) blend: bool,
    pub(super) center: Vec3,
    /// World-space bounds, to skip the draw when the view cannot see them.
    pub(super) bounds: (Vec3, Vec3),
    /// How far its relief may reach past `bounds`, in world units: a caster's shadow views test
    /// the bounds grown by it.
    pub(super) caster_pad: f32,
    /// Whether the surface pass shades it (else it only casts).
    pub(super) shaded: bool,
    /// Whether the occluder pass draws it: shaded, opaque, never cut away.
    pub(super) occludes: bool,
}

/// The draws `plan` lists, each with its uploaded mesh and its sets: set 0 per frame slot
/// (`height_sets[k]` for height map `k`, else `plain_sets`), the material's and its layers'; and the
/// meshes drawn as prism shells.
pub(super) fn mesh_draws(
    ctx: &Arc<Context>,
    scene: &Scene,
    plan: &Plan,
    height_sets: &[Vec<DescriptorSet>],
    plain_sets: &[DescriptorSet],
    materials: &MaterialSets,
    layers: &LayerSets,
) -> VkResult<(Vec<MeshDraw>, Vec<BuiltShell>)> {
    let mut draws = Vec::with_capacity(plan.draws.len());
    let mut shells = Vec::new();
    // Once for the scene: it reads every vertex.
    let caster_pad = relief_pad(scene);
    for d in &plan.draws {
        let mesh = &scene.meshes[d.mesh];
        let frame_sets = match d.heights {
            Some(k) => height_sets[k].clone(),
            None if !plain_sets.is_empty() => plain_sets.to_vec(),
            None => return Err(VkError::Invalid("no plain frame set".into())),
        };
        let material_set = materials
            .set(d.material)
            .ok_or_else(|| VkError::Invalid(format!("material {} has no set", d.material)))?;
        let layer_set = layers
            .set(d.material)
            .filter(|_| plan.pipelines[d.pipeline].layers);
        let key = &plan.pipelines[d.pipeline];
        let sets = (frame_sets, material_set, layer_set);
        let draw = if key.shells {
            let (draw, built) = MeshDraw::shell(ctx, scene, mesh, d, key, sets)?;
            // A caster-only draw of the same mesh shares its shell's description.
            if d.role == DrawRole::Surface {
                shells.push(built);
            }
            draw
        } else {
            MeshDraw::new(ctx, mesh, d, key, sets)?
        };
        let mut draw = draw.with_caster_pad(caster_pad);
        draw.occludes = plan.occluders && occludes(scene, d, key);
        draws.push(draw);
    }
    Ok((draws, shells))
}

impl MeshDraw {
    /// Uploads `mesh`'s vertices and indices for draw `d` with pipeline `key`.
    fn new(
        ctx: &Arc<Context>,
        mesh: &Mesh,
        d: &DrawPlan,
        key: &PipelineKey,
        (frame_sets, material_set, layer_set): DrawSets,
    ) -> VkResult<MeshDraw> {
        let (lo, hi) = mesh_bounds(&mesh.vertices);
        let (vertices, indices) = mesh_buffers(
            ctx,
            bytemuck::cast_slice(&mesh.vertices),
            &mesh.indices,
            &mesh.name,
        )?;
        Ok(MeshDraw {
            mesh: d.mesh,
            vertices,
            indices,
            index_count: mesh.indices.len() as u32,
            pipeline: d.pipeline,
            frame_sets,
            material_set,
            layer_set,
            push: DrawPush::of(mesh.transform).for_mesh(d.mesh),
            blend: key.blend,
            center: mesh.transform.transform_point3((lo + hi) * 0.5),
            bounds: world_bounds(mesh.transform, lo, hi),
            caster_pad: 0.0,
            shaded: d.role == DrawRole::Surface,
            occludes: false,
        })
    }

    /// Uploads `mesh`'s prism shell for draw `d` with pipeline `key` (a `:shells` variant), in
    /// world space, so the draw's transform is the identity.
    fn shell(
        ctx: &Arc<Context>,
        scene: &Scene,
        mesh: &Mesh,
        d: &DrawPlan,
        key: &PipelineKey,
        (frame_sets, material_set, layer_set): DrawSets,
    ) -> VkResult<(MeshDraw, BuiltShell)> {
        let shell = upload_shell(ctx, scene, mesh, d.material)?;
        let (lo, hi) = shell.bounds;
        let draw = MeshDraw {
            mesh: d.mesh,
            vertices: shell.vertices,
            indices: shell.indices,
            index_count: shell.index_count,
            pipeline: d.pipeline,
            frame_sets,
            material_set,
            layer_set,
            push: DrawPush::of(Mat4::IDENTITY).for_mesh(d.mesh),
            blend: key.blend,
            center: (lo + hi) * 0.5,
            bounds: (lo, hi),
            caster_pad: 0.0,
            shaded: d.role == DrawRole::Surface,
            occludes: false,
        };
        Ok((draw, shell.built))
    }

    /// The draw as a caster whose relief reaches `pad` past its bounds.
    fn with_caster_pad(mut self, pad: f32) -> MeshDraw {
        self.caster_pad = pad;
        self
    }
}
