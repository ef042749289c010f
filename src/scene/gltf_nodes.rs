//! The node graph: checked to be a forest before it is walked, so a cyclic or shared node
//! gives an error instead of a hang or a stack overflow.

use glam::{Mat4, Quat, Vec3};

/// Every node must have at most one parent, no node may be its own ancestor, scene roots must
/// be roots, and transforms must be finite, affine and not given twice (matrix and TRS).
pub(super) fn check_graph(doc: &gltf::Document) -> Result<(), String> {
    let json = doc.as_json();
    let n = json.nodes.len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for (i, node) in json.nodes.iter().enumerate() {
        for child in node.children.iter().flatten() {
            let c = child.value();
            if c >= n {
                return Err(format!("node {i}: child {c} does not exist"));
            }
            if let Some(p) = parent[c] {
                return Err(format!("node {c} is a child of both node {p} and node {i}"));
            }
            parent[c] = Some(i);
        }
        check_transform(node).map_err(|e| format!("node {i}: {e}"))?;
        if let (Some(w), Some(mesh)) = (&node.weights, node.mesh) {
            let targets = json.meshes[mesh.value()]
                .primitives
                .first()
                .and_then(|p| p.targets.as_ref())
                .map_or(0, Vec::len);
            if w.len() != targets {
                return Err(format!(
                    "node {i}: {} morph weights for {targets} morph targets",
                    w.len()
                ));
            }
        }
    }
    // With one parent each, a cycle shows as a walk up that meets itself. Walks stop at nodes
    // an earlier walk cleared, so the whole pass is linear in the node count.
    let mut walk_of: Vec<Option<usize>> = vec![None; n];
    for start in 0..n {
        let mut at = Some(start);
        while let Some(node) = at {
            match walk_of[node] {
                Some(w) if w == start => return Err(format!("node {node} is its own ancestor")),
                Some(_) => break,
                None => walk_of[node] = Some(start),
            }
            at = parent[node];
        }
    }
    for scene in doc.scenes() {
        let mut seen = std::collections::HashSet::new();
        for node in scene.nodes() {
            if let Some(p) = parent[node.index()] {
                return Err(format!(
                    "scene {}: node {} is listed as a root but is a child of node {p}",
                    scene.index(),
                    node.index()
                ));
            }
            if !seen.insert(node.index()) {
                return Err(format!(
                    "scene {}: node {} is listed twice",
                    scene.index(),
                    node.index()
                ));
            }
        }
    }
    Ok(())
}

fn check_transform(node: &gltf::json::Node) -> Result<(), String> {
    if let Some(m) = node.matrix {
        if node.translation.is_some() || node.rotation.is_some() || node.scale.is_some() {
            return Err("has both matrix and translation/rotation/scale".into());
        }
        if m.iter().any(|v| !v.is_finite())
            || m[3] != 0.0
            || m[7] != 0.0
            || m[11] != 0.0
            || m[15] != 1.0
        {
            return Err("matrix is not a finite affine transform".into());
        }
    }
    let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
    if !node.translation.is_none_or(|t| finite(&t)) || !node.scale.is_none_or(|s| finite(&s)) {
        return Err("translation or scale is not finite".into());
    }
    if let Some(r) = node.rotation {
        let len = Quat::from_array(r.0).length();
        if !finite(&r.0) || (len - 1.0).abs() > 1e-3 {
            return Err(format!("rotation is not a unit quaternion (length {len})"));
        }
    }
    Ok(())
}

/// The scene's nodes in depth-first order (parents before children, in document order) with
/// their world matrices. Relies on [`check_graph`]; the visit limit is a second guard.
pub(super) fn walk<'a>(
    scene: &gltf::Scene<'a>,
    limit: usize,
) -> Result<Vec<(gltf::Node<'a>, Mat4)>, String> {
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node<'a>, Mat4)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    stack.reverse();
    while let Some((node, parent)) = stack.pop() {
        if out.len() >= limit {
            return Err("the node graph visits more nodes than the file has (a cycle?)".into());
        }
        let world = parent * local(&node);
        let first_child = stack.len();
        stack.extend(node.children().map(|c| (c, world)));
        stack[first_child..].reverse();
        out.push((node, world));
    }
    Ok(out)
}

/// The node's local transform (matrix, or translation * rotation * scale).
pub(super) fn local(node: &gltf::Node) -> Mat4 {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => Mat4::from_cols_array_2d(&matrix),
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => Mat4::from_scale_rotation_translation(
            Vec3::from(scale),
            Quat::from_array(rotation).normalize(),
            Vec3::from(translation),
        ),
    }
}
