//! Triangle primitives to [`Mesh`]es: attribute formats checked against glTF's rules, data
//! read through the bounds-checked accessor reader, missing normals and tangents derived.

use glam::{Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Semantic;

use super::gltf_accessor::{read_f32, read_u32};
use super::{tangents, HeightSource, Material, Mesh, TextureSlot, Vertex};

/// Every primitive of every mesh in the document, in object space (identity transform) with
/// `material` the glTF material index or `usize::MAX` for none; `None` for primitives that are
/// not triangle lists. Meshes no node uses are converted too, since a broken mesh makes a
/// broken file whether or not this scene shows it.
pub(super) fn convert_meshes(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    materials: &[Material],
) -> Result<Vec<Vec<Option<Mesh>>>, String> {
    let fallback = Material::default();
    doc.meshes()
        .map(|mesh| {
            let name = mesh
                .name()
                .map_or_else(|| format!("mesh {}", mesh.index()), str::to_owned);
            check_morphs(doc, &mesh).map_err(|e| format!("mesh {name:?}: {e}"))?;
            mesh.primitives()
                .map(|prim| {
                    let material = prim.material().index();
                    let def = material.and_then(|m| materials.get(m)).unwrap_or(&fallback);
                    convert_primitive(doc, buffers, &prim, &name, def)
                        .map(|m| {
                            m.map(|mut m| {
                                m.material = material.unwrap_or(usize::MAX);
                                m
                            })
                        })
                        .map_err(|e| format!("mesh {name:?}: primitive {}: {e}", prim.index()))
                })
                .collect()
        })
        .collect()
}

/// `mesh` placed by a node's world matrix: winding is reversed under a mirroring transform so
/// front faces stay counter-clockwise in world space.
pub(super) fn place(mesh: &Mesh, transform: Mat4) -> Mesh {
    let mut m = mesh.clone();
    m.transform = transform;
    if transform.determinant() < 0.0 {
        for tri in m.indices.chunks_exact_mut(3) {
            tri.swap(1, 2);
        }
    }
    m
}

/// Morph targets are not applied, but their accessors must fit the primitive they morph.
fn check_morphs(doc: &gltf::Document, mesh: &gltf::Mesh) -> Result<(), String> {
    let json = &doc.as_json().meshes[mesh.index()];
    let accessors = &doc.as_json().accessors;
    let mut target_count = None;
    for (p, prim) in json.primitives.iter().enumerate() {
        let targets = prim.targets.as_deref().unwrap_or(&[]);
        if target_count.is_some_and(|n| n != targets.len()) {
            return Err("primitives have different numbers of morph targets".into());
        }
        target_count = Some(targets.len());
        let base = |s: gltf::json::mesh::Semantic| {
            prim.attributes
                .get(&gltf::json::validation::Checked::Valid(s))
        };
        let Some(position) = base(Semantic::Positions) else {
            continue;
        };
        let count = accessors[position.value()].count.0;
        for (t, target) in targets.iter().enumerate() {
            let attrs = [
                (target.positions, Semantic::Positions),
                (target.normals, Semantic::Normals),
                (target.tangents, Semantic::Tangents),
            ];
            for (acc, semantic) in attrs {
                let Some(acc) = acc else { continue };
                let a = &accessors[acc.value()];
                if base(semantic.clone()).is_none() || a.count.0 != count {
                    return Err(format!(
                        "primitive {p}: morph target {t}: {} has no base attribute or a different count",
                        semantic_name(&semantic)
                    ));
                }
                if semantic == Semantic::Positions && (a.min.is_none() || a.max.is_none()) {
                    return Err(format!(
                        "primitive {p}: morph target {t}: POSITION has no min/max"
                    ));
                }
            }
        }
    }
    if json
        .weights
        .as_ref()
        .is_some_and(|w| w.len() != target_count.unwrap_or(0))
    {
        return Err("weights do not match the number of morph targets".into());
    }
    Ok(())
}

/// The mesh of one primitive, or `None` for a primitive that is not triangles (points, lines,
/// strips and fans are not drawn).
fn convert_primitive(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    prim: &gltf::Primitive,
    name: &str,
    material: &Material,
) -> Result<Option<Mesh>, String> {
    if prim.mode() != gltf::mesh::Mode::Triangles {
        return Ok(None);
    }
    let attr = |semantic: Semantic, formats: &[(Dimensions, DataType, bool)]| {
        attribute(doc, buffers, prim, semantic, formats)
    };
    let float3 = [(Dimensions::Vec3, DataType::F32, false)];
    let Some(acc) = prim.get(&Semantic::Positions) else {
        return Err("has no POSITION".into());
    };
    if acc.min().is_none() || acc.max().is_none() {
        return Err("POSITION accessor has no min/max".into());
    }
    let positions = attr(Semantic::Positions, &float3)?.unwrap_or_default();
    let count = positions.len() / 3;
    let normals = attr(Semantic::Normals, &float3)?;
    let tangents = attr(
        Semantic::Tangents,
        &[(Dimensions::Vec4, DataType::F32, false)],
    )?;
    let uv_formats = [
        (Dimensions::Vec2, DataType::F32, false),
        (Dimensions::Vec2, DataType::U8, true),
        (Dimensions::Vec2, DataType::U16, true),
    ];
    let uv0 = attr(Semantic::TexCoords(0), &uv_formats)?;
    let uv1 = attr(Semantic::TexCoords(1), &uv_formats)?;
    let mut color_formats = Vec::new();
    for dims in [Dimensions::Vec3, Dimensions::Vec4] {
        color_formats.extend([
            (dims, DataType::F32, false),
            (dims, DataType::U8, true),
            (dims, DataType::U16, true),
        ]);
    }
    let colors = attr(Semantic::Colors(0), &color_formats)?;
    let color_width = prim
        .get(&Semantic::Colors(0))
        .map_or(4, |a| a.dimensions().multiplicity());
    check_attribute_sets(prim, count, material)?;

    let mut indices = match prim.indices() {
        None => (0..count as u32).collect(),
        Some(acc) => read_indices(doc, buffers, &acc, count)?,
    };
    indices.truncate(indices.len() / 3 * 3);

    let v2 = |data: &Option<Vec<f32>>, i: usize| data.as_ref().map(|d| [d[2 * i], d[2 * i + 1]]);
    let mut vertices: Vec<Vertex> = (0..count)
        .map(|i| {
            let uv = v2(&uv0, i).unwrap_or([0.0; 2]);
            let color = colors.as_ref().map_or([1.0; 4], |c| {
                let s = &c[i * color_width..(i + 1) * color_width];
                [s[0], s[1], s[2], if color_width == 4 { s[3] } else { 1.0 }]
            });
            Vertex {
                position: [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]],
                normal: normals
                    .as_ref()
                    .map_or([0.0; 3], |n| unit3(&n[3 * i..3 * i + 3])),
                uv,
                uv1: v2(&uv1, i).unwrap_or(uv),
                tangent: tangents.as_ref().map_or([0.0; 4], |t| {
                    let [x, y, z] = unit3(&t[4 * i..4 * i + 3]);
                    [x, y, z, if t[4 * i + 3] < 0.0 { -1.0 } else { 1.0 }]
                }),
                color,
            }
        })
        .collect();
    if normals.is_none() {
        flat_normals(&mut vertices, &mut indices);
    }
    if tangents.is_none() || normals.is_none() {
        // Supplied tangents go with supplied normals; new normals need new tangents.
        tangents::generate(&mut vertices, &mut indices, uv0.is_some());
    }
    Ok(Some(Mesh {
        name: name.to_owned(),
        vertices,
        indices,
        material: 0,
        transform: Mat4::IDENTITY,
    }))
}

/// Reads one attribute if present, after checking its format is one glTF allows for it.
/// Normals and tangents must be unit length and tangent w must be +-1 (a tolerance allows for
/// quantised exporters).
fn attribute(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    prim: &gltf::Primitive,
    semantic: Semantic,
    formats: &[(Dimensions, DataType, bool)],
) -> Result<Option<Vec<f32>>, String> {
    let Some(acc) = prim.get(&semantic) else {
        return Ok(None);
    };
    let what = format!("{} accessor {}", semantic_name(&semantic), acc.index());
    let format = (acc.dimensions(), acc.data_type(), acc.normalized());
    if !formats.contains(&format) {
        return Err(format!(
            "{what}: {:?} of {:?}{} is not allowed here",
            format.0,
            format.1,
            if format.2 { " normalized" } else { "" }
        ));
    }
    let data = read_f32(doc, &acc, buffers).map_err(|e| format!("{what}: {e}"))?;
    let width = acc.dimensions().multiplicity();
    if matches!(semantic, Semantic::Colors(_)) && data.iter().any(|c| !(0.0..=1.0).contains(c)) {
        return Err(format!("{what}: colour components outside 0..1"));
    }
    if matches!(semantic, Semantic::Normals | Semantic::Tangents) {
        for (i, v) in data.chunks_exact(width).enumerate() {
            let len = Vec3::from_slice(&v[..3]).length();
            if (len - 1.0).abs() > 1e-2 {
                return Err(format!("{what}: element {i} has length {len}, not 1"));
            }
            if width == 4 && (v[3].abs() - 1.0).abs() > 1e-3 {
                return Err(format!("{what}: element {i} has w = {}, not 1 or -1", v[3]));
            }
        }
    }
    Ok(Some(data))
}

fn semantic_name(s: &Semantic) -> String {
    match s {
        Semantic::Positions => "POSITION".into(),
        Semantic::Normals => "NORMAL".into(),
        Semantic::Tangents => "TANGENT".into(),
        Semantic::TexCoords(n) => format!("TEXCOORD_{n}"),
        Semantic::Colors(n) => format!("COLOR_{n}"),
        other => format!("{other:?}"),
    }
}

/// Attributes must agree on the vertex count, texture coordinate sets must be numbered without
/// gaps, and every set the material reads must exist.
fn check_attribute_sets(
    prim: &gltf::Primitive,
    count: usize,
    material: &Material,
) -> Result<(), String> {
    let mut uv_sets = 0;
    let mut max_uv = None::<u32>;
    for (semantic, acc) in prim.attributes() {
        if acc.data_type() == DataType::U32 {
            return Err(format!(
                "{}: vertex attributes cannot be unsigned int",
                semantic_name(&semantic)
            ));
        }
        if acc.count() != count {
            return Err(format!(
                "{} has {} elements but POSITION has {count}",
                semantic_name(&semantic),
                acc.count()
            ));
        }
        if let Semantic::TexCoords(n) = semantic {
            uv_sets += 1;
            max_uv = max_uv.max(Some(n));
        }
    }
    if max_uv.is_some_and(|m| m + 1 != uv_sets) {
        return Err("TEXCOORD_n sets are not numbered 0, 1, ... without gaps".into());
    }
    let height = match material.relief.map(|r| r.height) {
        Some(HeightSource::Texture { texture, .. }) => Some(("relief height", texture)),
        _ => None,
    };
    let slots = TextureSlot::ALL
        .into_iter()
        .filter_map(|s| material.texture(s).map(|t| (s.name(), *t)));
    for (slot, t) in slots.chain(height) {
        if t.tex_coord >= uv_sets {
            return Err(format!(
                "material {:?} reads TEXCOORD_{} for {slot} but the primitive has {uv_sets} uv sets",
                material.name, t.tex_coord
            ));
        }
    }
    Ok(())
}

fn read_indices(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    acc: &gltf::Accessor,
    count: usize,
) -> Result<Vec<u32>, String> {
    let what = format!("indices accessor {}", acc.index());
    let restart = match (acc.dimensions(), acc.data_type(), acc.normalized()) {
        (Dimensions::Scalar, DataType::U8, false) => u8::MAX as u32,
        (Dimensions::Scalar, DataType::U16, false) => u16::MAX as u32,
        (Dimensions::Scalar, DataType::U32, false) => u32::MAX,
        (d, t, _) => {
            return Err(format!(
                "{what}: {d:?} of {t:?} (must be unsigned integer scalars, not normalized)"
            ))
        }
    };
    if acc.view().is_some_and(|v| v.stride().is_some()) {
        return Err(format!("{what}: its bufferView has a byteStride"));
    }
    let indices = read_u32(doc, acc, buffers).map_err(|e| format!("{what}: {e}"))?;
    if let Some(bad) = indices
        .iter()
        .find(|&&i| i as usize >= count || i == restart)
    {
        return Err(format!("{what}: index {bad} is out of range for {count} vertices (or a primitive restart value)"));
    }
    Ok(indices)
}

fn unit3(v: &[f32]) -> [f32; 3] {
    Vec3::from_slice(v).normalize_or(Vec3::Z).into()
}

/// glTF: without NORMAL, flat normals. Every triangle gets its own three vertices.
fn flat_normals(vertices: &mut Vec<Vertex>, indices: &mut Vec<u32>) {
    let mut flat = Vec::with_capacity(indices.len());
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| vertices[tri[k] as usize]);
        let p = |v: &Vertex| Vec3::from(v.position);
        let n = (p(&b) - p(&a)).cross(p(&c) - p(&a)).normalize_or(Vec3::Z);
        for mut v in [a, b, c] {
            v.normal = n.into();
            flat.push(v);
        }
    }
    *indices = (0..flat.len() as u32).collect();
    *vertices = flat;
}
