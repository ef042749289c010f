//! The frame as a small graph of passes. Each node names its pass, the resources it reads and
//! writes, and how often it runs; [`FrameGraph::build`] checks that every read has a writer
//! before it, drops the nodes whose writes reach nothing the frame hands on, and keeps the rest
//! in an order that respects every read. The renderer records the nodes in that order, and
//! `--explain` prints them with what was dropped and why.

use std::fmt;

use serde::Serialize;

use super::pass::Pass;

/// What passes hand each other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrameResource {
    /// Every height map's max pyramid (built once; kept across frames).
    HeightPyramids,
    /// The texture-space AO maps (built once; kept across frames).
    AoMaps,
    /// The shadow-map atlas (kept across frames until a view or a caster changes).
    ShadowAtlas,
    /// Per pixel, the farthest depth the nearest opaque surface can reach.
    OccluderBounds,
    /// The scene's depth.
    Depth,
    /// The linear radiance the scene is drawn into.
    Radiance,
    /// The G-buffer's channels, drawn beside the radiance.
    GBuffer,
    /// The deferred frame's shading inputs, drawn beside the G-buffer.
    ShadingInputs,
    /// The tone-mapped frame: what is presented or read back.
    Frame,
}

impl fmt::Display for FrameResource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FrameResource::HeightPyramids => "height pyramids",
            FrameResource::AoMaps => "ao maps",
            FrameResource::ShadowAtlas => "shadow atlas",
            FrameResource::OccluderBounds => "occluder bounds",
            FrameResource::Depth => "depth",
            FrameResource::Radiance => "radiance",
            FrameResource::GBuffer => "g-buffer",
            FrameResource::ShadingInputs => "shading inputs",
            FrameResource::Frame => "frame",
        })
    }
}

/// How often a node runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PassRate {
    /// In the first frame only: what it writes never changes.
    FirstFrame,
    /// When what it depends on changed (a view, a caster, an edit).
    WhenChanged,
    /// In every frame.
    EveryFrame,
}

/// One pass and what it touches.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct GraphNode {
    /// The pass recorded.
    pub pass: Pass,
    /// What it reads, each written by a node before it (or in an earlier frame, for what is
    /// kept).
    pub reads: Vec<FrameResource>,
    /// What it writes.
    pub writes: Vec<FrameResource>,
    /// How often it runs.
    pub rate: PassRate,
}

impl GraphNode {
    /// A node of `pass` at `rate` reading `reads` and writing `writes`.
    pub fn new(
        pass: Pass,
        rate: PassRate,
        reads: &[FrameResource],
        writes: &[FrameResource],
    ) -> GraphNode {
        GraphNode {
            pass,
            reads: reads.to_vec(),
            writes: writes.to_vec(),
            rate,
        }
    }
}

/// A node left out, and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct DroppedPass {
    /// The pass left out.
    pub pass: Pass,
    /// Why, one line.
    pub why: String,
}

/// The nodes a frame records, in order, and those it left out.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct FrameGraph {
    /// The nodes, in recording order.
    pub nodes: Vec<GraphNode>,
    /// The nodes left out, with why.
    pub dropped: Vec<DroppedPass>,
}

/// A graph that cannot be recorded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GraphError {
    /// A node reads what no node writes.
    #[error("the {pass} pass reads the {resource}, which no pass writes")]
    Unwritten {
        /// The reader.
        pass: Pass,
        /// What it reads.
        resource: FrameResource,
    },
    /// The reads go round in a circle.
    #[error("the passes {passes} read each other's writes in a circle")]
    Cycle {
        /// The passes in the circle, and any waiting on them.
        passes: String,
    },
}

impl FrameGraph {
    /// Orders `nodes` so each comes after the writers of what it reads (otherwise keeping the
    /// given order), and drops those whose writes reach none of `outputs`, directly or through
    /// the nodes that read them.
    pub fn build(
        nodes: Vec<GraphNode>,
        outputs: &[FrameResource],
    ) -> Result<FrameGraph, GraphError> {
        for node in &nodes {
            for &resource in &node.reads {
                let written = nodes
                    .iter()
                    .any(|n| n.pass != node.pass && n.writes.contains(&resource));
                if !written {
                    return Err(GraphError::Unwritten {
                        pass: node.pass,
                        resource,
                    });
                }
            }
        }
        let (kept, dropped) = Self::needed(nodes, outputs);
        Ok(FrameGraph {
            nodes: Self::ordered(kept)?,
            dropped,
        })
    }

    /// Splits `nodes` into those whose writes reach an output and the others.
    fn needed(
        nodes: Vec<GraphNode>,
        outputs: &[FrameResource],
    ) -> (Vec<GraphNode>, Vec<DroppedPass>) {
        let mut wanted: Vec<FrameResource> = outputs.to_vec();
        let mut needed = vec![false; nodes.len()];
        // Walk back from the outputs: a node writing a wanted resource is needed, and what it
        // reads is wanted in turn.
        loop {
            let mut grew = false;
            for (k, node) in nodes.iter().enumerate() {
                if !needed[k] && node.writes.iter().any(|w| wanted.contains(w)) {
                    needed[k] = true;
                    grew = true;
                    for &read in &node.reads {
                        if !wanted.contains(&read) {
                            wanted.push(read);
                        }
                    }
                }
            }
            if !grew {
                break;
            }
        }
        let mut kept = Vec::new();
        let mut dropped = Vec::new();
        for (node, needed) in nodes.into_iter().zip(needed) {
            if needed {
                kept.push(node);
            } else {
                let writes: Vec<String> =
                    node.writes.iter().map(FrameResource::to_string).collect();
                dropped.push(DroppedPass {
                    pass: node.pass,
                    why: format!(
                        "nothing the frame hands on reads what it writes ({})",
                        writes.join(", ")
                    ),
                });
            }
        }
        (kept, dropped)
    }

    /// A stable topological order: repeatedly the first node (in the given order) whose reads
    /// are all written by nodes already placed, or are resources kept from earlier frames whose
    /// writer comes later only because it runs at its own rate.
    fn ordered(mut pending: Vec<GraphNode>) -> Result<Vec<GraphNode>, GraphError> {
        let mut placed: Vec<GraphNode> = Vec::with_capacity(pending.len());
        while !pending.is_empty() {
            let ready = pending.iter().position(|node| {
                node.reads.iter().all(|r| {
                    placed.iter().any(|p| p.writes.contains(r))
                        || !pending
                            .iter()
                            .any(|p| p.pass != node.pass && p.writes.contains(r))
                })
            });
            let Some(k) = ready else {
                let passes: Vec<String> = pending.iter().map(|n| n.pass.to_string()).collect();
                return Err(GraphError::Cycle {
                    passes: passes.join(", "),
                });
            };
            placed.push(pending.remove(k));
        }
        Ok(placed)
    }

    /// The passes in recording order.
    pub fn passes(&self) -> impl Iterator<Item = Pass> + '_ {
        self.nodes.iter().map(|n| n.pass)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use FrameResource as R;

    fn forward() -> Vec<GraphNode> {
        vec![
            GraphNode::new(
                Pass::Surface,
                PassRate::EveryFrame,
                &[R::HeightPyramids, R::ShadowAtlas, R::OccluderBounds],
                &[R::Radiance, R::Depth],
            ),
            GraphNode::new(
                Pass::Pyramid,
                PassRate::FirstFrame,
                &[],
                &[R::HeightPyramids],
            ),
            GraphNode::new(
                Pass::ShadowMaps,
                PassRate::WhenChanged,
                &[R::HeightPyramids],
                &[R::ShadowAtlas],
            ),
            GraphNode::new(
                Pass::Occluders,
                PassRate::EveryFrame,
                &[R::HeightPyramids],
                &[R::OccluderBounds],
            ),
            GraphNode::new(
                Pass::ToneMap,
                PassRate::EveryFrame,
                &[R::Radiance],
                &[R::Frame],
            ),
        ]
    }

    #[test]
    fn writers_come_before_their_readers_and_the_given_order_holds_otherwise() {
        let graph = FrameGraph::build(forward(), &[R::Frame]).expect("a graph");
        let order: Vec<Pass> = graph.passes().collect();
        assert_eq!(
            order,
            [
                Pass::Pyramid,
                Pass::ShadowMaps,
                Pass::Occluders,
                Pass::Surface,
                Pass::ToneMap
            ]
        );
        assert!(graph.dropped.is_empty());
    }

    #[test]
    fn a_pass_whose_writes_nothing_reads_is_dropped_with_its_reason() {
        let mut nodes = forward();
        nodes.push(GraphNode::new(
            Pass::AmbientOcclusion,
            PassRate::FirstFrame,
            &[R::HeightPyramids],
            &[R::AoMaps],
        ));
        let graph = FrameGraph::build(nodes, &[R::Frame]).expect("a graph");
        assert_eq!(graph.dropped.len(), 1);
        assert_eq!(graph.dropped[0].pass, Pass::AmbientOcclusion);
        assert!(
            graph.dropped[0].why.contains("ao maps"),
            "{:?}",
            graph.dropped
        );
        // Handing the depth on keeps the surface pass for it alone too.
        let graph = FrameGraph::build(forward(), &[R::Depth]).expect("a graph");
        assert!(graph.passes().all(|p| p != Pass::ToneMap));
    }

    #[test]
    fn a_read_without_a_writer_and_a_circle_are_refused() {
        let nodes = vec![GraphNode::new(
            Pass::Surface,
            PassRate::EveryFrame,
            &[R::OccluderBounds],
            &[R::Radiance],
        )];
        assert_eq!(
            FrameGraph::build(nodes, &[R::Radiance]),
            Err(GraphError::Unwritten {
                pass: Pass::Surface,
                resource: R::OccluderBounds
            })
        );
        let circle = vec![
            GraphNode::new(
                Pass::Occluders,
                PassRate::EveryFrame,
                &[R::Radiance],
                &[R::OccluderBounds],
            ),
            GraphNode::new(
                Pass::Surface,
                PassRate::EveryFrame,
                &[R::OccluderBounds],
                &[R::Radiance],
            ),
        ];
        let err = FrameGraph::build(circle, &[R::Radiance]).expect_err("a circle");
        assert!(matches!(err, GraphError::Cycle { .. }), "{err}");
    }
}
