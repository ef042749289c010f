//! Skins and the JOINTS_n/WEIGHTS_n attributes, checked as glTF 2.0 and the Khronos validator
//! define them. Meshes are drawn unskinned, but a file whose skins break the spec is broken, so
//! it is rejected with the skin, node, mesh or accessor and the rule it breaks.
//!
//! The node graph was checked to be a forest (`gltf_nodes::check_graph`) before this runs.

use std::collections::{HashMap, HashSet};

use gltf::accessor::{DataType, Dimensions};
use gltf::json::mesh::Semantic;
use gltf::json::validation::Checked;

use super::gltf_accessor;
use super::gltf_animation_check::{accessor, format_of, has_data};

/// Largest distance from 1 of a vertex's weight sum (the validator's normalization tolerance).
const SUM_TOLERANCE: f64 = 0.0005;
/// Largest distance of an inverse bind matrix's last row from (0, 0, 0, 1).
const AFFINE_TOLERANCE: f32 = 1e-6;

/// The node forest: each node's top root, and preorder intervals for ancestor tests.
struct Forest {
    root: Vec<usize>,
    enter: Vec<usize>,
    leave: Vec<usize>,
}

impl Forest {
    fn of(json: &gltf::json::Root) -> Forest {
        let n = json.nodes.len();
        let mut parent = vec![None; n];
        for (i, node) in json.nodes.iter().enumerate() {
            for c in node.children.iter().flatten() {
                if let Some(p) = parent.get_mut(c.value()) {
                    *p = Some(i);
                }
            }
        }
        let (mut root, mut enter, mut leave) = (vec![0; n], vec![0; n], vec![0; n]);
        let mut clock = 0;
        for top in (0..n).filter(|&i| parent[i].is_none()) {
            // (node, whether its children were pushed): iterative, so deep trees cannot overflow.
            let mut stack = vec![(top, false)];
            while let Some((i, done)) = stack.pop() {
                if done {
                    leave[i] = clock;
                    continue;
                }
                root[i] = top;
                enter[i] = clock;
                clock += 1;
                stack.push((i, true));
                for c in json.nodes[i].children.iter().flatten() {
                    if c.value() < n {
                        stack.push((c.value(), false));
                    }
                }
            }
        }
        Forest { root, enter, leave }
    }

    /// Whether `a` is `b` or one of its ancestors.
    fn contains(&self, a: usize, b: usize) -> bool {
        self.enter[a] <= self.enter[b] && self.enter[b] < self.leave[a]
    }
}

/// Every skin, every node with a skin, and every primitive's joints and weights.
pub(super) fn check_skins(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    zero_buffers: usize,
) -> Result<(), String> {
    let json = doc.as_json();
    let n = json.nodes.len();
    let forest = Forest::of(json);
    for (s, skin) in json.skins.iter().enumerate() {
        let joints: Vec<usize> = skin.joints.iter().map(|j| j.value()).collect();
        if let Some(&j) = joints.iter().find(|&&j| j >= n) {
            return Err(format!("skin {s}: joint node {j} does not exist"));
        }
        if let Some((&first, &other)) = joints.first().and_then(|f| {
            Some((
                f,
                joints
                    .iter()
                    .find(|&&j| forest.root[j] != forest.root[*f])?,
            ))
        }) {
            return Err(format!(
                "skin {s}: joints {first} and {other} have no common root (they are in different node trees)"
            ));
        }
        if let Some(sk) = skin.skeleton.map(|k| k.value()) {
            if sk >= n {
                return Err(format!("skin {s}: skeleton node {sk} does not exist"));
            }
            if let Some(j) = joints.iter().find(|&&j| !forest.contains(sk, j)) {
                return Err(format!(
                    "skin {s}: skeleton node {sk} is not a common root of the joints (joint {j} is not below it)"
                ));
            }
        }
        if let Some(ibm) = skin.inverse_bind_matrices {
            check_ibm(doc, ibm.value(), joints.len(), buffers, zero_buffers).map_err(|e| {
                format!(
                    "skin {s}: inverseBindMatrices accessor {}: {e}",
                    ibm.value()
                )
            })?;
        }
    }
    // The fewest joints among the skins each mesh is drawn with: joint indices must be below.
    let mut joint_limit: Vec<Option<usize>> = vec![None; json.meshes.len()];
    for (i, node) in json.nodes.iter().enumerate() {
        let Some(s) = node.skin.map(|s| s.value()) else {
            continue;
        };
        let skin = json
            .skins
            .get(s)
            .ok_or_else(|| format!("node {i}: skin {s} does not exist"))?;
        let Some(m) = node.mesh.map(|m| m.value()) else {
            return Err(format!("node {i}: skin {s} without a mesh"));
        };
        let mesh = json
            .meshes
            .get(m)
            .ok_or_else(|| format!("node {i}: mesh {m} does not exist"))?;
        let joints0 = Checked::Valid(Semantic::Joints(0));
        if !mesh
            .primitives
            .iter()
            .any(|p| p.attributes.contains_key(&joints0))
        {
            return Err(format!(
                "node {i}: has skin {s} but mesh {m} has no JOINTS_0/WEIGHTS_0 data to skin"
            ));
        }
        let limit = &mut joint_limit[m];
        *limit = Some(limit.map_or(skin.joints.len(), |l| l.min(skin.joints.len())));
    }
    check_scenes(json, &forest)?;
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            check_primitive(doc, prim, joint_limit[m], buffers, zero_buffers)
                .map_err(|e| format!("mesh {m} primitive {p}: {e}"))?;
        }
    }
    Ok(())
}

/// Inverse bind matrices: MAT4 float, at least one per joint, each affine.
fn check_ibm(
    doc: &gltf::Document,
    index: usize,
    joints: usize,
    buffers: &[gltf::buffer::Data],
    zero_buffers: usize,
) -> Result<(), String> {
    let acc = accessor(doc, index)?;
    if acc.dimensions() != Dimensions::Mat4 || acc.data_type() != DataType::F32 || acc.normalized()
    {
        return Err(format!("is {} but must be Mat4 F32", format_of(&acc)));
    }
    if acc.count() < joints {
        return Err(format!(
            "has {} matrices for {joints} joints (needs at least one per joint)",
            acc.count()
        ));
    }
    if !has_data(&acc, zero_buffers) {
        return Ok(());
    }
    let values = gltf_accessor::read_f32(doc, &acc, buffers)?;
    for (k, m) in values.chunks_exact(16).enumerate() {
        // Column-major: the last row is components 3, 7, 11 and 15.
        for (c, want) in [(3, 0.0), (7, 0.0), (11, 0.0), (15, 1.0)] {
            if (m[c] - want).abs() > AFFINE_TOLERANCE {
                return Err(format!(
                    "matrix {k} has {} at component {c}, but inverse bind matrices must be affine (last row 0 0 0 1)",
                    m[c]
                ));
            }
        }
    }
    Ok(())
}

/// A node drawn with a skin needs that skin's joints in the same scene. Linear in the scene
/// lists plus, for each skin and scene it is drawn in, the skin's joints.
fn check_scenes(json: &gltf::json::Root, forest: &Forest) -> Result<(), String> {
    let roots: Vec<HashSet<usize>> = json
        .scenes
        .iter()
        .map(|scene| scene.nodes.iter().map(|r| r.value()).collect())
        .collect();
    let mut scenes_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, scene) in json.scenes.iter().enumerate() {
        for r in &scene.nodes {
            scenes_of.entry(r.value()).or_default().push(k);
        }
    }
    let mut checked = HashSet::new();
    for (i, node) in json.nodes.iter().enumerate() {
        let Some(s) = node.skin.map(|s| s.value()) else {
            continue;
        };
        let joints = json.skins.get(s).map_or(&[][..], |s| &s.joints[..]);
        for &k in scenes_of.get(&forest.root[i]).into_iter().flatten() {
            if !checked.insert((k, s)) {
                continue;
            }
            if let Some(j) = joints
                .iter()
                .map(|j| j.value())
                .find(|&j| forest.root.get(j).is_none_or(|r| !roots[k].contains(r)))
            {
                return Err(format!(
                    "scene {k}: node {i} is drawn with skin {s}, but its joint node {j} is not in the scene"
                ));
            }
        }
    }
    Ok(())
}

/// JOINTS_n and WEIGHTS_n: in pairs, in their formats, with equal counts; where their data is
/// in the file, joint indices below `joint_limit`, no joint twice with weight, weights
/// non-negative and summing to 1.
fn check_primitive(
    doc: &gltf::Document,
    prim: &gltf::json::mesh::Primitive,
    joint_limit: Option<usize>,
    buffers: &[gltf::buffer::Data],
    zero_buffers: usize,
) -> Result<(), String> {
    let (sets, count) = skin_sets(doc, prim)?;
    let read = |acc: &gltf::Accessor| -> Result<Option<Vec<f32>>, String> {
        if has_data(acc, zero_buffers) {
            gltf_accessor::read_f32(doc, acc, buffers)
                .map(Some)
                .map_err(|e| format!("accessor {}: {e}", acc.index()))
        } else {
            Ok(None)
        }
    };
    let mut data = Vec::with_capacity(sets.len());
    for (k, joints, weights) in &sets {
        data.push((*k, read(joints)?, read(weights)?));
    }
    check_vertices(&data, count.unwrap_or(0), joint_limit)
}

/// The primitive's JOINTS_n and WEIGHTS_n accessors as `(n, joints, weights)`, checked for
/// pairing, format and equal counts, with that count (`None` without skinning attributes).
fn skin_sets<'d>(
    doc: &'d gltf::Document,
    prim: &gltf::json::mesh::Primitive,
) -> Result<SkinSets<'d>, String> {
    let mut joint_sets = Vec::new();
    let mut weight_sets = Vec::new();
    for (semantic, index) in &prim.attributes {
        match semantic {
            Checked::Valid(Semantic::Joints(k)) => joint_sets.push((*k, index.value())),
            Checked::Valid(Semantic::Weights(k)) => weight_sets.push((*k, index.value())),
            _ => {}
        }
    }
    if joint_sets.len() != weight_sets.len() {
        return Err(format!(
            "{} JOINTS_n attributes but {} WEIGHTS_n (they come in pairs)",
            joint_sets.len(),
            weight_sets.len()
        ));
    }
    if joint_sets.is_empty() {
        return Ok((Vec::new(), None));
    }
    joint_sets.sort_unstable();
    weight_sets.sort_unstable();
    let mut sets = Vec::new();
    let mut count = None;
    for (&(jk, ji), &(wk, wi)) in joint_sets.iter().zip(&weight_sets) {
        if jk != wk {
            return Err(format!(
                "JOINTS_{jk} is paired with WEIGHTS_{wk} (each JOINTS_n needs its WEIGHTS_n)"
            ));
        }
        let joints = accessor(doc, ji)?;
        let weights = accessor(doc, wi)?;
        if joints.dimensions() != Dimensions::Vec4
            || !matches!(joints.data_type(), DataType::U8 | DataType::U16)
            || joints.normalized()
        {
            return Err(format!(
                "JOINTS_{jk} accessor {ji} is {} but must be Vec4 U8 or U16",
                format_of(&joints)
            ));
        }
        let weights_ok = match weights.data_type() {
            DataType::F32 => !weights.normalized(),
            DataType::U8 | DataType::U16 => weights.normalized(),
            _ => false,
        };
        if weights.dimensions() != Dimensions::Vec4 || !weights_ok {
            return Err(format!(
                "WEIGHTS_{wk} accessor {wi} is {} but must be Vec4 F32 or normalized U8/U16",
                format_of(&weights)
            ));
        }
        for acc in [&joints, &weights] {
            if *count.get_or_insert(acc.count()) != acc.count() {
                return Err(format!(
                    "accessor {} of JOINTS_{jk}/WEIGHTS_{jk} has {} elements, the other sets {}",
                    acc.index(),
                    acc.count(),
                    count.unwrap_or(0)
                ));
            }
        }
        sets.push((jk, joints, weights));
    }
    Ok((sets, count))
}

/// The skinning accessors of a primitive, `(n, JOINTS_n, WEIGHTS_n)`, and their element count.
type SkinSets<'d> = (
    Vec<(u32, gltf::Accessor<'d>, gltf::Accessor<'d>)>,
    Option<usize>,
);

/// One skinning set's `n` with its joints and weights as read (`None` without data in the file).
type SetData = (u32, Option<Vec<f32>>, Option<Vec<f32>>);

/// Each of `vertices` vertices: joints below `joint_limit`, no joint twice with weight, weights
/// non-negative and (when every set has its data) summing to 1.
fn check_vertices(
    data: &[SetData],
    vertices: usize,
    joint_limit: Option<usize>,
) -> Result<(), String> {
    let all_weights = data.iter().all(|d| d.2.is_some());
    let mut used: Vec<u32> = Vec::new();
    for v in 0..vertices {
        used.clear();
        let mut sum = 0.0f64;
        for (k, joints, weights) in data {
            for c in 0..4 {
                let at = v * 4 + c;
                let joint = joints.as_ref().map(|j| j[at] as u32);
                let weight = weights.as_ref().map_or(0.0, |w| w[at]);
                if let (Some(j), Some(limit)) = (joint, joint_limit) {
                    if j as usize >= limit {
                        return Err(format!(
                            "JOINTS_{k} vertex {v} uses joint {j} but its skin has {limit} joints"
                        ));
                    }
                }
                if weight < 0.0 {
                    return Err(format!(
                        "WEIGHTS_{k} vertex {v} has negative weight {weight}"
                    ));
                }
                sum += weight as f64;
                if let (Some(j), true) = (joint, weight != 0.0) {
                    if used.contains(&j) {
                        return Err(format!(
                            "JOINTS_{k} vertex {v} uses joint {j} twice with non-zero weight"
                        ));
                    }
                    used.push(j);
                }
            }
        }
        if all_weights && (sum - 1.0).abs() > SUM_TOLERANCE {
            return Err(format!(
                "vertex {v}'s weights sum to {sum}, but they must sum to 1"
            ));
        }
    }
    Ok(())
}
