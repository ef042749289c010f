//! The frame's graph: one node per pass the renderer built, with what it reads and writes and how
//! often it runs, ordered and pruned by [`FrameGraph::build`]. The renderer records the nodes in
//! the graph's order; background, blended draws and tone mapping run inside the surface pass's
//! rendering (lavapipe writes a timestamp recorded inside a rendering only when the rendering is
//! flushed, so they are timed within its scope).

use crate::render::kit::graph::{FrameGraph, FrameResource as R, GraphError, GraphNode, PassRate};
use crate::render::kit::pass::Pass;

/// What the renderer built, which decides the frame's nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameParts {
    /// Some height map's pyramid (max or averaged) is built on the GPU.
    pub pyramids: bool,
    /// Some material's AO map is built on the GPU.
    pub ao_maps: bool,
    /// Some light has a shadow map.
    pub shadow_maps: bool,
    /// The occluder pass runs.
    pub occluders: bool,
    /// Meshes are drawn through cell complexes.
    pub cells: bool,
    /// The sky is drawn behind the scene.
    pub background: bool,
    /// The surface pass writes the G-buffer, which frames read back.
    pub gbuffer: bool,
    /// The depth is read back (the shadow probe).
    pub depth: bool,
    /// The frame is lit deferred: the surface pass writes the G-buffer and the shading inputs,
    /// the lighting pass reads them.
    pub deferred: bool,
}

/// The graph of the passes `parts` needs.
pub fn frame_graph(parts: FrameParts) -> Result<FrameGraph, GraphError> {
    let when = |built: bool, resource: R| built.then_some(resource);
    let pyramids = when(parts.pyramids, R::HeightPyramids);
    let ao_maps = when(parts.ao_maps, R::AoMaps);
    let atlas = when(parts.shadow_maps, R::ShadowAtlas);
    let bounds = when(parts.occluders, R::OccluderBounds);
    let gbuffer = when(parts.gbuffer || parts.deferred, R::GBuffer);
    let inputs = when(parts.deferred, R::ShadingInputs);
    let list = |items: &[Option<R>]| -> Vec<R> { items.iter().flatten().copied().collect() };
    let mut nodes = Vec::new();
    let mut add = |pass: Pass, rate: PassRate, reads: Vec<R>, writes: Vec<R>| {
        nodes.push(GraphNode::new(pass, rate, &reads, &writes));
    };
    if parts.pyramids {
        add(
            Pass::Pyramid,
            PassRate::FirstFrame,
            vec![],
            vec![R::HeightPyramids],
        );
    }
    if parts.ao_maps {
        add(
            Pass::AmbientOcclusion,
            PassRate::FirstFrame,
            list(&[pyramids]),
            vec![R::AoMaps],
        );
    }
    if parts.shadow_maps {
        add(
            Pass::ShadowMaps,
            PassRate::WhenChanged,
            list(&[pyramids]),
            vec![R::ShadowAtlas],
        );
    }
    if parts.occluders {
        add(
            Pass::Occluders,
            PassRate::EveryFrame,
            vec![],
            vec![R::OccluderBounds],
        );
    }
    if parts.cells {
        add(
            Pass::Cells,
            PassRate::EveryFrame,
            list(&[atlas]),
            vec![R::Radiance, R::Depth],
        );
    }
    add(
        Pass::Surface,
        PassRate::EveryFrame,
        list(&[pyramids, ao_maps, atlas, bounds]),
        list(&[Some(R::Radiance), Some(R::Depth), gbuffer, inputs]),
    );
    if parts.deferred {
        add(
            Pass::Lighting,
            PassRate::EveryFrame,
            list(&[atlas, gbuffer, inputs]),
            vec![R::Radiance],
        );
    }
    if parts.background {
        add(
            Pass::Background,
            PassRate::EveryFrame,
            vec![R::Depth],
            vec![R::Radiance],
        );
    }
    add(
        Pass::ToneMap,
        PassRate::EveryFrame,
        vec![R::Radiance],
        vec![R::Frame],
    );
    let kept = when(parts.gbuffer, R::GBuffer);
    let handed_on = list(&[Some(R::Frame), kept, parts.depth.then_some(R::Depth)]);
    FrameGraph::build(nodes, &handed_on)
}
