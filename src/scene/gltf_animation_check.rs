//! Animations, checked as glTF 2.0 and the Khronos validator define them. Only the one that
//! moves the camera is played (`gltf_camera_path`), but a file whose animations break the spec
//! is broken, so it is rejected with the animation, sampler or channel and the rule it breaks.
//!
//! Accessor data is read with `gltf_accessor`'s bounds-checked readers, and each accessor's
//! data is read at most once here, so the work is linear in the file's size.

use std::collections::{HashMap, HashSet};

use gltf::accessor::{DataType, Dimensions};
use gltf::json::animation::{Interpolation, Property};
use gltf::json::validation::Checked;

use super::gltf_accessor;

/// Largest distance from 1 of a rotation key's length (the validator's unit-length tolerance).
const UNIT_TOLERANCE: f64 = 0.0005;

/// Accessor `index`, or an error if there is none.
pub(super) fn accessor(doc: &gltf::Document, index: usize) -> Result<gltf::Accessor<'_>, String> {
    doc.accessors()
        .nth(index)
        .ok_or_else(|| format!("accessor {index} does not exist"))
}

/// Whether the accessor's values come from the file (as the validator does, data checks skip
/// accessors without a bufferView: the loader gives those a zero fill from `zero_buffers` on).
pub(super) fn has_data(acc: &gltf::Accessor, zero_buffers: usize) -> bool {
    acc.view().is_none_or(|v| v.buffer().index() < zero_buffers)
}

/// The accessor's element format for messages, e.g. `Vec4 F32` or `Vec4 U8 normalized`.
pub(super) fn format_of(acc: &gltf::Accessor) -> String {
    let norm = if acc.normalized() { " normalized" } else { "" };
    format!("{:?} {:?}{norm}", acc.dimensions(), acc.data_type())
}

/// Float, or (u)byte/(u)short normalized: the formats rotation and weights outputs allow.
fn float_or_normalized(acc: &gltf::Accessor) -> bool {
    match acc.data_type() {
        DataType::F32 => !acc.normalized(),
        DataType::I8 | DataType::U8 | DataType::I16 | DataType::U16 => acc.normalized(),
        DataType::U32 => false,
    }
}

fn path_name(p: Property) -> &'static str {
    match p {
        Property::Translation => "translation",
        Property::Rotation => "rotation",
        Property::Scale => "scale",
        Property::MorphTargetWeights => "weights",
    }
}

/// Every animation's samplers and channels.
pub(super) fn check_animations(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    zero_buffers: usize,
) -> Result<(), String> {
    let json = doc.as_json();
    let mut inputs_read = HashSet::new();
    let mut rotations_read = HashSet::new();
    for (a, anim) in json.animations.iter().enumerate() {
        check_samplers(doc, a, anim, buffers, zero_buffers, &mut inputs_read)?;
        let mut targets: HashMap<(usize, &str), usize> = HashMap::new();
        for (c, channel) in anim.channels.iter().enumerate() {
            let here = || format!("animation {a} channel {c}");
            let n = channel.target.node.value();
            let node = json
                .nodes
                .get(n)
                .ok_or_else(|| format!("{}: target node {n} does not exist", here()))?;
            // An unknown path is only a warning to the validator: nothing to check it against.
            let Checked::Valid(path) = channel.target.path else {
                continue;
            };
            let name = path_name(path);
            if let Some(first) = targets.insert((n, name), c) {
                return Err(format!(
                    "animation {a}: channels {first} and {c} both target node {n} {name}"
                ));
            }
            if path != Property::MorphTargetWeights && node.matrix.is_some() {
                return Err(format!(
                    "{}: targets the {name} of node {n}, which has a matrix (only TRS nodes can be animated)",
                    here()
                ));
            }
            let morphs = node
                .mesh
                .and_then(|m| json.meshes.get(m.value()))
                .and_then(|m| m.primitives.first())
                .and_then(|p| p.targets.as_ref())
                .map_or(0, Vec::len);
            if path == Property::MorphTargetWeights && morphs == 0 {
                return Err(format!(
                    "{}: targets the weights of node {n}, whose mesh has no morph targets",
                    here()
                ));
            }
            let s = channel.sampler.value();
            let sampler = anim
                .samplers
                .get(s)
                .ok_or_else(|| format!("{}: sampler {s} does not exist", here()))?;
            let cubic = sampler.interpolation == Checked::Valid(Interpolation::CubicSpline);
            let keys = accessor(doc, sampler.input.value())?.count();
            let output = accessor(doc, sampler.output.value())?;
            let o = output.index();
            let (ok, want) = output_format(path, &output);
            if !ok {
                return Err(format!(
                    "{} (sampler {s}): output accessor {o} is {} but {name} needs {want}",
                    here(),
                    format_of(&output)
                ));
            }
            let per_key = if cubic { 3 } else { 1 } * morphs.max(1);
            if keys.checked_mul(per_key) != Some(output.count()) {
                let cubic_note = if cubic { " x3 for CUBICSPLINE" } else { "" };
                let morph_note = if path == Property::MorphTargetWeights {
                    format!(" x{morphs} morph targets")
                } else {
                    String::new()
                };
                return Err(format!(
                    "{} (sampler {s}): output accessor {o} has {} elements; {keys} keyframes{cubic_note}{morph_note} need exactly {}",
                    here(),
                    output.count(),
                    keys.saturating_mul(per_key)
                ));
            }
            if path == Property::Rotation
                && has_data(&output, zero_buffers)
                && rotations_read.insert((o, cubic))
            {
                check_rotations(doc, &output, cubic, buffers)
                    .map_err(|e| format!("{} (sampler {s}): output accessor {o}: {e}", here()))?;
            }
        }
    }
    Ok(())
}

/// Animation `a`'s samplers: their accessors exist and their inputs are keyframe times. Inputs
/// shared with earlier samplers (`inputs_read`) are not read again.
fn check_samplers(
    doc: &gltf::Document,
    a: usize,
    anim: &gltf::json::Animation,
    buffers: &[gltf::buffer::Data],
    zero_buffers: usize,
    inputs_read: &mut HashSet<usize>,
) -> Result<(), String> {
    for (s, sampler) in anim.samplers.iter().enumerate() {
        let cubic = sampler.interpolation == Checked::Valid(Interpolation::CubicSpline);
        let input = accessor(doc, sampler.input.value())
            .map_err(|e| format!("animation {a} sampler {s}: input {e}"))?;
        accessor(doc, sampler.output.value())
            .map_err(|e| format!("animation {a} sampler {s}: output {e}"))?;
        let read = has_data(&input, zero_buffers) && inputs_read.insert(input.index());
        check_input(doc, &input, cubic, read, buffers).map_err(|e| {
            format!(
                "animation {a} sampler {s}: input accessor {}: {e}",
                input.index()
            )
        })?;
    }
    Ok(())
}

/// Whether `output` has the element format a channel animating `path` reads, and that format
/// for the message.
fn output_format(path: Property, output: &gltf::Accessor) -> (bool, &'static str) {
    match path {
        Property::Translation | Property::Scale => (
            output.dimensions() == Dimensions::Vec3
                && output.data_type() == DataType::F32
                && !output.normalized(),
            "Vec3 F32",
        ),
        Property::Rotation => (
            output.dimensions() == Dimensions::Vec4 && float_or_normalized(output),
            "Vec4 F32 or normalized (u)byte/(u)short",
        ),
        Property::MorphTargetWeights => (
            output.dimensions() == Dimensions::Scalar && float_or_normalized(output),
            "Scalar F32 or normalized (u)byte/(u)short",
        ),
    }
}

/// Keyframe times: float scalars with min and max, at least two for CUBICSPLINE, and (when
/// `read`) non-negative and strictly increasing.
fn check_input(
    doc: &gltf::Document,
    input: &gltf::Accessor,
    cubic: bool,
    read: bool,
    buffers: &[gltf::buffer::Data],
) -> Result<(), String> {
    if input.dimensions() != Dimensions::Scalar
        || input.data_type() != DataType::F32
        || input.normalized()
    {
        return Err(format!(
            "is {} but keyframe times must be Scalar F32",
            format_of(input)
        ));
    }
    if input.min().is_none() || input.max().is_none() {
        return Err("keyframe times need min and max".into());
    }
    if cubic && input.count() < 2 {
        return Err(format!(
            "CUBICSPLINE needs at least 2 keyframes, found {}",
            input.count()
        ));
    }
    if !read {
        return Ok(());
    }
    let times = gltf_accessor::read_f32(doc, input, buffers)?;
    for (i, &t) in times.iter().enumerate() {
        if t < 0.0 {
            return Err(format!("keyframe time {i} is negative ({t})"));
        }
        if i > 0 && t <= times[i - 1] {
            return Err(format!(
                "keyframe time {i} ({t}) is not greater than time {} ({}): times must strictly increase",
                i - 1,
                times[i - 1]
            ));
        }
    }
    Ok(())
}

/// Rotation keys must be unit quaternions (for CUBICSPLINE, the values between the tangents).
fn check_rotations(
    doc: &gltf::Document,
    output: &gltf::Accessor,
    cubic: bool,
    buffers: &[gltf::buffer::Data],
) -> Result<(), String> {
    let values = gltf_accessor::read_f32(doc, output, buffers)?;
    for (k, q) in values.chunks_exact(4).enumerate() {
        if cubic && k % 3 != 1 {
            continue;
        }
        let len = q
            .iter()
            .map(|&v| (v as f64) * (v as f64))
            .sum::<f64>()
            .sqrt();
        if (len - 1.0).abs() > UNIT_TOLERANCE {
            return Err(format!(
                "rotation element {k} has length {len}, but quaternions must be unit length"
            ));
        }
    }
    Ok(())
}
