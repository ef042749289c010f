//! The chosen camera's glTF animation as a [`CameraPath`]: the first animation with a
//! translation, rotation or scale channel on the camera's node or one of its ancestors moves
//! the camera; every other node on that chain keeps its rest transform.
//!
//! Runs after `gltf_animation_check`, so channels, samplers, output formats and counts are
//! known good; the data is still read with `gltf_accessor`'s bounds-checked readers, and a
//! track that fails [`Track::new`] becomes an error, not a panic.

use glam::{Quat, Vec3};
use gltf::json::animation::{Channel, Interpolation as GltfInterpolation, Property};
use gltf::json::validation::Checked;

use super::camera_path::{CameraPath, Interpolation, Keyed, Keyframe, NodeMotion, Track};
use super::gltf_animation_check::{accessor, has_data};
use super::{gltf_accessor, gltf_nodes, Projection};

/// What one loader call reads from.
struct Source<'a> {
    doc: &'a gltf::Document,
    buffers: &'a [gltf::buffer::Data],
    zero_buffers: usize,
}

/// The camera path of the camera on node `camera_node`, or `None` when no animation moves it.
pub(super) fn camera_path(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    zero_buffers: usize,
    camera_node: usize,
    projection: Projection,
) -> Result<Option<CameraPath>, String> {
    let chain = chain_to(doc, camera_node)?;
    let moves_chain = |c: &Channel| {
        chain.contains(&c.target.node.value()) && transform_path(c.target.path).is_some()
    };
    let json = doc.as_json();
    let Some(a) = json
        .animations
        .iter()
        .position(|anim| anim.channels.iter().any(moves_chain))
    else {
        return Ok(None);
    };
    let src = Source {
        doc,
        buffers,
        zero_buffers,
    };
    let nodes = chain
        .iter()
        .map(|&n| node_motion(&src, a, n))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Some(CameraPath::new(nodes, projection)))
}

/// Node indices from the scene root down to `node`. The graph was checked to be a forest, and
/// the walk stops after as many steps as there are nodes all the same.
fn chain_to(doc: &gltf::Document, node: usize) -> Result<Vec<usize>, String> {
    let json = doc.as_json();
    let mut parent = vec![None; json.nodes.len()];
    for (i, n) in json.nodes.iter().enumerate() {
        for child in n.children.iter().flatten() {
            if let Some(p) = parent.get_mut(child.value()) {
                *p = Some(i);
            }
        }
    }
    let mut chain = vec![node];
    while let Some(&Some(p)) = parent.get(chain[chain.len() - 1]) {
        if chain.len() > json.nodes.len() {
            return Err(format!("node {node}: its ancestors form a cycle"));
        }
        chain.push(p);
    }
    chain.reverse();
    Ok(chain)
}

/// The transform part a channel path animates; `None` for morph weights and unknown paths.
fn transform_path(path: Checked<Property>) -> Option<Property> {
    match path {
        Checked::Valid(p @ (Property::Translation | Property::Rotation | Property::Scale)) => {
            Some(p)
        }
        _ => None,
    }
}

/// Node `n`'s local transform under animation `a`: fixed when no channel of `a` moves it.
fn node_motion(src: &Source, a: usize, n: usize) -> Result<NodeMotion, String> {
    let json = src.doc.as_json();
    let node = json
        .nodes
        .get(n)
        .ok_or_else(|| format!("node {n} does not exist"))?;
    let channels: Vec<(usize, Property)> = json.animations[a]
        .channels
        .iter()
        .enumerate()
        .filter(|(_, c)| c.target.node.value() == n)
        .filter_map(|(c, ch)| transform_path(ch.target.path).map(|p| (c, p)))
        .collect();
    if channels.is_empty() {
        let local = src.doc.nodes().nth(n).map(|node| gltf_nodes::local(&node));
        return local
            .map(NodeMotion::Fixed)
            .ok_or_else(|| format!("node {n} does not exist"));
    }
    let mut translation = Keyed::Rest(node.translation.map_or(Vec3::ZERO, Vec3::from));
    let mut rotation = Keyed::Rest(
        node.rotation
            .map_or(Quat::IDENTITY, |r| Quat::from_array(r.0)),
    );
    let mut scale = Keyed::Rest(node.scale.map_or(Vec3::ONE, Vec3::from));
    for (c, property) in channels {
        let here = |e: String| format!("animation {a} channel {c}: {e}");
        match property {
            Property::Translation => set(&mut translation, read_track(src, a, c, vec3)),
            Property::Rotation => set(&mut rotation, read_track(src, a, c, quat)),
            Property::Scale => set(&mut scale, read_track(src, a, c, vec3)),
            Property::MorphTargetWeights => Ok(()),
        }
        .map_err(here)?;
    }
    Ok(NodeMotion::Animated {
        translation,
        rotation,
        scale,
    })
}

/// Puts a track that was read in place of the rest value; `None` (no data) keeps the rest.
fn set<T>(keyed: &mut Keyed<T>, track: Result<Option<Track<T>>, String>) -> Result<(), String> {
    if let Some(track) = track? {
        *keyed = Keyed::Track(track);
    }
    Ok(())
}

fn vec3(v: &[f32]) -> Option<Vec3> {
    Some(Vec3::new(*v.first()?, *v.get(1)?, *v.get(2)?))
}

fn quat(v: &[f32]) -> Option<Quat> {
    Some(Quat::from_xyzw(
        *v.first()?,
        *v.get(1)?,
        *v.get(2)?,
        *v.get(3)?,
    ))
}

/// Channel `c` of animation `a` as a track of values `read` makes from `width` floats each.
/// Keyframe times in a buffer the file left without data are a zero fill the validator does
/// not check, not times: such a channel gives `None` and the node keeps its rest value.
fn read_track<T: Keyframe>(
    src: &Source,
    a: usize,
    c: usize,
    read: fn(&[f32]) -> Option<T>,
) -> Result<Option<Track<T>>, String> {
    let anim = &src.doc.as_json().animations[a];
    let s = anim.channels[c].sampler.value();
    let sampler = anim
        .samplers
        .get(s)
        .ok_or_else(|| format!("sampler {s} does not exist"))?;
    let input = accessor(src.doc, sampler.input.value())?;
    let output = accessor(src.doc, sampler.output.value())?;
    if !has_data(&input, src.zero_buffers) {
        return Ok(None);
    }
    let interpolation = match sampler.interpolation {
        Checked::Valid(GltfInterpolation::Step) => Interpolation::Step,
        Checked::Valid(GltfInterpolation::Linear) => Interpolation::Linear,
        Checked::Valid(GltfInterpolation::CubicSpline) => Interpolation::CubicSpline,
        Checked::Invalid => return Err(format!("sampler {s}: unknown interpolation")),
    };
    let times = gltf_accessor::read_f32(src.doc, &input, src.buffers)
        .map_err(|e| format!("input accessor {}: {e}", input.index()))?;
    let width = gltf_accessor::component_count(output.dimensions());
    let values = gltf_accessor::read_f32(src.doc, &output, src.buffers)
        .map_err(|e| format!("output accessor {}: {e}", output.index()))?
        .chunks_exact(width)
        .map(read)
        .collect::<Option<Vec<T>>>()
        .ok_or_else(|| format!("output accessor {} has too few components", output.index()))?;
    Track::new(interpolation, times, values)
        .map(Some)
        .map_err(|e| format!("sampler {s}: {e}"))
}
