//! Buffer views and accessors, checked and read by hand: the gltf crate's own readers index
//! slices without bounds checks and panic on malformed files, so every byte range is checked
//! here before it is touched.

use gltf::accessor::{DataType, Dimensions};
use gltf::json::accessor::IndexComponentType;
use gltf::json::validation::Checked;

/// Checks every buffer and buffer view against the data they stand for.
pub(super) fn check_views(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
) -> Result<(), String> {
    for buffer in doc.buffers() {
        let have = buffers.get(buffer.index()).map_or(0, |d| d.0.len());
        // Buffers read from URIs are padded to 4 bytes by the gltf crate; more than that is a
        // declared length that disagrees with the file.
        let external = matches!(buffer.source(), gltf::buffer::Source::Uri(_));
        if have < buffer.length() || (external && have > buffer.length().div_ceil(4) * 4) {
            return Err(format!(
                "buffer {}: byteLength {} but the data has {have} bytes",
                buffer.index(),
                buffer.length()
            ));
        }
    }
    let json = doc.as_json();
    for view in doc.views() {
        let end = view.offset().checked_add(view.length());
        if view.length() == 0 || end.is_none_or(|e| e > view.buffer().length()) {
            return Err(format!(
                "bufferView {}: bytes {}..+{} outside buffer {} ({} bytes)",
                view.index(),
                view.offset(),
                view.length(),
                view.buffer().index(),
                view.buffer().length()
            ));
        }
        if let Some(stride) = json.buffer_views[view.index()].byte_stride {
            if view.target() == Some(gltf::buffer::Target::ElementArrayBuffer) {
                return Err(format!(
                    "bufferView {}: index data with a byteStride",
                    view.index()
                ));
            }
            if !(4..=252).contains(&stride.0) || stride.0 % 4 != 0 || stride.0 > view.length() {
                return Err(format!(
                    "bufferView {}: byteStride {} (must be a multiple of 4 in 4..=252, at most byteLength)",
                    view.index(),
                    stride.0
                ));
            }
        }
    }
    Ok(())
}

/// Reads every accessor once, so bad ranges, floats, sparse indices and min/max bounds are
/// caught even in accessors the renderer never draws (the file is broken either way).
/// Accessors over buffers from `zero_buffers` on had no data in the file: their bounds are not
/// compared (as the validator does not).
pub(super) fn check_accessors(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    zero_buffers: usize,
) -> Result<(), String> {
    for acc in doc.accessors() {
        let values =
            read_raw(doc, &acc, buffers).map_err(|e| format!("accessor {}: {e}", acc.index()))?;
        if acc.view().is_none_or(|v| v.buffer().index() < zero_buffers) {
            check_bounds(&acc, &values).map_err(|e| format!("accessor {}: {e}", acc.index()))?;
        }
    }
    Ok(())
}

/// Components an accessor without a bufferView (all zeros before sparse substitution) may hold:
/// 2^20 (8 MiB as f64), a 350,000-vertex position accessor.
pub(super) const MAX_ZERO_COMPONENTS: usize = 1 << 20;

pub(super) fn component_count(d: Dimensions) -> usize {
    d.multiplicity()
}

/// The accessor's values as f32, integer components normalized to 0..1 or -1..1 when the
/// accessor says `normalized`.
pub(super) fn read_f32(
    doc: &gltf::Document,
    acc: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
) -> Result<Vec<f32>, String> {
    let raw = read_raw(doc, acc, buffers)?;
    let ty = acc.data_type();
    Ok(if acc.normalized() {
        raw.into_iter().map(|v| normalize(ty, v)).collect()
    } else {
        raw.into_iter().map(|v| v as f32).collect()
    })
}

/// An index accessor's values (the caller checked its type is unsigned).
pub(super) fn read_u32(
    doc: &gltf::Document,
    acc: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
) -> Result<Vec<u32>, String> {
    Ok(read_raw(doc, acc, buffers)?
        .into_iter()
        .map(|v| v as u32)
        .collect())
}

fn normalize(ty: DataType, v: f64) -> f32 {
    // glTF's rules: unsigned c / max, signed max(c / max, -1).
    let r = match ty {
        DataType::U8 => v / 255.0,
        DataType::U16 => v / 65535.0,
        DataType::I8 => (v / 127.0).max(-1.0),
        DataType::I16 => (v / 32767.0).max(-1.0),
        DataType::U32 => v / u32::MAX as f64,
        DataType::F32 => v,
    };
    r as f32
}

fn component_value(ty: DataType, b: &[u8]) -> f64 {
    match ty {
        DataType::I8 => b[0] as i8 as f64,
        DataType::U8 => b[0] as f64,
        DataType::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
        DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
        DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
    }
}

/// Where `count` elements of `elem` bytes, `stride` apart, start in the buffers, after checking
/// that they lie inside `view` and are aligned to the component size.
fn locate<'b>(
    view: &gltf::buffer::View,
    offset: usize,
    count: usize,
    elem: usize,
    stride: usize,
    align: usize,
    buffers: &'b [gltf::buffer::Data],
) -> Result<&'b [u8], String> {
    if offset % align != 0 || (view.offset() + offset) % align != 0 {
        return Err(format!(
            "byteOffset {offset} in bufferView {} is not a multiple of the component size {align}",
            view.index()
        ));
    }
    let len = count
        .checked_sub(1)
        .and_then(|n| n.checked_mul(stride))
        .and_then(|n| n.checked_add(elem))
        .and_then(|n| n.checked_add(offset));
    match len {
        Some(len) if len <= view.length() => {}
        _ => {
            return Err(format!(
                "{count} elements of {elem} bytes (stride {stride}) from byteOffset {offset} overrun bufferView {} ({} bytes)",
                view.index(),
                view.length()
            ))
        }
    }
    let data = &buffers
        .get(view.buffer().index())
        .ok_or_else(|| format!("buffer {} has no data", view.buffer().index()))?
        .0;
    let start = view.offset() + offset;
    data.get(start..view.offset() + view.length())
        .ok_or_else(|| format!("bufferView {} lies outside its buffer", view.index()))
}

/// How an element's components lie in its bytes: matrix columns of 1- and 2-byte components are
/// padded to 4 bytes (glTF's alignment rule); everything else is one tightly packed column.
#[derive(Clone, Copy)]
struct Layout {
    ty: DataType,
    cols: usize,
    rows: usize,
    col_bytes: usize,
}

impl Layout {
    fn of(ty: DataType, dims: Dimensions) -> Layout {
        let (cols, rows) = match dims {
            Dimensions::Mat2 => (2, 2),
            Dimensions::Mat3 => (3, 3),
            Dimensions::Mat4 => (4, 4),
            other => (1, other.multiplicity()),
        };
        let packed = rows * ty.size();
        let col_bytes = if cols > 1 {
            packed.next_multiple_of(4)
        } else {
            packed
        };
        Layout {
            ty,
            cols,
            rows,
            col_bytes,
        }
    }

    fn elem(&self) -> usize {
        self.cols * self.col_bytes
    }

    /// Bytes the last element needs: the last column's padding may be missing.
    fn extent(&self) -> usize {
        (self.cols - 1) * self.col_bytes + self.rows * self.ty.size()
    }
}

fn read_elements(bytes: &[u8], count: usize, stride: usize, l: Layout, out: &mut Vec<f64>) {
    let csize = l.ty.size();
    for i in 0..count {
        for c in 0..l.cols {
            for r in 0..l.rows {
                let at = i * stride + c * l.col_bytes + r * csize;
                out.push(component_value(l.ty, &bytes[at..at + csize]));
            }
        }
    }
}

/// Every component of every element, sparse substitution applied, as f64 (exact for all
/// component types).
fn read_raw(
    doc: &gltf::Document,
    acc: &gltf::Accessor,
    buffers: &[gltf::buffer::Data],
) -> Result<Vec<f64>, String> {
    let ty = acc.data_type();
    let csize = ty.size();
    let comps = component_count(acc.dimensions());
    let count = acc.count();
    if count == 0 {
        return Err("count is 0".into());
    }
    if acc.normalized() && matches!(ty, DataType::F32 | DataType::U32) {
        return Err(format!("normalized is set on {ty:?} components"));
    }
    let layout = Layout::of(ty, acc.dimensions());
    let elem = layout.elem();
    // Reserved only once the data is known to be there: `count` is the file's word, and an
    // accessor claiming 2^32 elements over a few bytes must not reserve gigabytes first.
    let mut out = Vec::new();
    match acc.view() {
        Some(view) => {
            let stride = view.stride().unwrap_or(elem);
            if stride < elem {
                return Err(format!(
                    "byteStride {stride} is smaller than an element ({elem} bytes)"
                ));
            }
            let bytes = locate(
                &view,
                acc.offset(),
                count,
                layout.extent(),
                stride,
                csize,
                buffers,
            )?;
            out.reserve_exact(count * comps);
            read_elements(bytes, count, stride, layout, &mut out);
        }
        None => {
            // Without a view the values are zeros (sparse substitution may follow) that no byte
            // of the file stands for, so their number is capped outright.
            let total = count
                .checked_mul(comps)
                .filter(|&n| n <= MAX_ZERO_COMPONENTS)
                .ok_or_else(|| {
                    format!(
                        "count {count} with no bufferView is more than the \
                         {MAX_ZERO_COMPONENTS} zero components read"
                    )
                })?;
            out.resize(total, 0.0);
        }
    }
    if ty == DataType::F32 && out.iter().any(|v| !v.is_finite()) {
        return Err("holds NaN or infinite floats".into());
    }
    if let Some(sparse) = &doc.as_json().accessors[acc.index()].sparse {
        apply_sparse(doc, sparse, count, layout, &mut out, buffers)?;
    }
    Ok(out)
}

fn apply_sparse(
    doc: &gltf::Document,
    sparse: &gltf::json::accessor::sparse::Sparse,
    count: usize,
    layout: Layout,
    out: &mut [f64],
    buffers: &[gltf::buffer::Data],
) -> Result<(), String> {
    let n = sparse.count.0 as usize;
    if n == 0 || n > count {
        return Err(format!("sparse.count {n} is not in 1..={count}"));
    }
    let ity = match sparse.indices.component_type {
        Checked::Valid(IndexComponentType(t @ (DataType::U8 | DataType::U16 | DataType::U32))) => t,
        _ => return Err("sparse.indices.componentType must be an unsigned integer".into()),
    };
    let view_of = |i: usize| {
        doc.views()
            .nth(i)
            .ok_or_else(|| format!("sparse bufferView {i} does not exist"))
    };
    let iview = view_of(sparse.indices.buffer_view.value())?;
    let vview = view_of(sparse.values.buffer_view.value())?;
    if iview.stride().is_some() || vview.stride().is_some() {
        return Err("sparse bufferViews must not have byteStride".into());
    }
    let isize = ity.size();
    let ibytes = locate(
        &iview,
        sparse.indices.byte_offset.0 as usize,
        n,
        isize,
        isize,
        isize,
        buffers,
    )?;
    let mut indices = Vec::with_capacity(n);
    read_elements(
        ibytes,
        n,
        isize,
        Layout::of(ity, Dimensions::Scalar),
        &mut indices,
    );
    let (elem, comps) = (layout.elem(), layout.cols * layout.rows);
    let vbytes = locate(
        &vview,
        sparse.values.byte_offset.0 as usize,
        n,
        layout.extent(),
        elem,
        layout.ty.size(),
        buffers,
    )?;
    let mut values = Vec::with_capacity(n * comps);
    read_elements(vbytes, n, elem, layout, &mut values);
    if layout.ty == DataType::F32 && values.iter().any(|v| !v.is_finite()) {
        return Err("sparse values hold NaN or infinite floats".into());
    }
    let mut last = None;
    for (k, &i) in indices.iter().enumerate() {
        let i = i as usize;
        if i >= count || last.is_some_and(|l| i <= l) {
            return Err(format!(
                "sparse index {i} is out of range or not strictly increasing (count {count})"
            ));
        }
        last = Some(i);
        out[i * comps..(i + 1) * comps].copy_from_slice(&values[k * comps..(k + 1) * comps]);
    }
    Ok(())
}

/// Declared min/max must match the data exactly (the validator's rule): a wrong bound means
/// the writer and the data disagree about what the accessor holds.
fn check_bounds(acc: &gltf::Accessor, values: &[f64]) -> Result<(), String> {
    let comps = component_count(acc.dimensions());
    for (which, declared) in [("min", acc.min()), ("max", acc.max())] {
        let Some(declared) = declared else { continue };
        let list = declared
            .as_array()
            .filter(|a| a.len() == comps)
            .ok_or_else(|| format!("{which} must be an array of {comps} numbers"))?;
        for (c, d) in list.iter().enumerate() {
            let d = d
                .as_f64()
                .ok_or_else(|| format!("{which}[{c}] is not a number"))?;
            let column = values.iter().skip(c).step_by(comps).copied();
            let actual = if which == "min" {
                column.fold(f64::INFINITY, f64::min)
            } else {
                column.fold(f64::NEG_INFINITY, f64::max)
            };
            let same = if acc.data_type() == DataType::F32 {
                d as f32 == actual as f32
            } else {
                d == actual
            };
            if !same {
                return Err(format!(
                    "declared {which}[{c}] = {d} but the data's is {actual}"
                ));
            }
        }
    }
    Ok(())
}
