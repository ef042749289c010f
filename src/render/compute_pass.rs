//! A compute pipeline built from one embedded shader (its SPIR-V key), the descriptor set layout
//! of its bindings, a push-constant size and specialization constants: the one way every compute
//! pass of the renderer makes its pipeline, so a pass file holds only what is its own (bindings,
//! push constants, what it dispatches).

use std::sync::Arc;

use ash::vk;

use crate::shaders;
use crate::vk::{
    compute_pipeline, Context, DescriptorLayout, DescriptorSet, Pipeline, Recording, SpecConstants,
    VkError, VkResult,
};

/// The pipeline of one compute kernel with the layout of its set 0.
pub(in crate::render) struct ComputePass {
    // Declared first so it is destroyed before the layout it was created with.
    pipeline: Pipeline,
    layout: DescriptorLayout,
}

impl ComputePass {
    /// The pipeline of shader `key` with set 0 holding `bindings`, `push_bytes` of push
    /// constants and `spec`; `name` names the pipeline and its layout in validation messages.
    pub fn new(
        ctx: &Arc<Context>,
        key: &str,
        bindings: &[(u32, vk::DescriptorType)],
        push_bytes: u32,
        spec: &SpecConstants,
        name: &str,
    ) -> VkResult<ComputePass> {
        let spirv =
            shaders::spirv(key).ok_or_else(|| VkError::Invalid(format!("no shader {key}")))?;
        let layout = DescriptorLayout::new(
            ctx,
            bindings,
            vk::ShaderStageFlags::COMPUTE,
            &format!("{name} layout"),
        )?;
        let pipeline = compute_pipeline(ctx, spirv, &[&layout], push_bytes, spec, name)?;
        Ok(ComputePass { pipeline, layout })
    }

    /// [`ComputePass::new`] with no specialization constants.
    pub fn plain(
        ctx: &Arc<Context>,
        key: &str,
        bindings: &[(u32, vk::DescriptorType)],
        push_bytes: u32,
        name: &str,
    ) -> VkResult<ComputePass> {
        ComputePass::new(
            ctx,
            key,
            bindings,
            push_bytes,
            &SpecConstants::default(),
            name,
        )
    }

    /// The layout sets for this pass are allocated with.
    pub fn layout(&self) -> &DescriptorLayout {
        &self.layout
    }

    /// The pipeline, for passes that bind once and dispatch many times.
    pub fn pipeline(&self) -> &Pipeline {
        &self.pipeline
    }

    /// Records a bind of the pipeline and `set`, a push of `push` and a dispatch of `groups`
    /// workgroups; the barrier after it is the caller's, which knows what reads the result.
    pub fn dispatch(
        &self,
        rec: &Recording,
        set: &DescriptorSet,
        push: &[u8],
        groups: [u32; 3],
    ) -> VkResult<()> {
        self.pipeline.bind(rec, Some(set));
        if !push.is_empty() {
            self.pipeline.push(rec, push)?;
        }
        rec.dispatch(groups);
        Ok(())
    }
}
