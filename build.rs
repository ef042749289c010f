//! Compiles every shader entry point and variant under `shaders/` to SPIR-V with glslang and
//! writes `shaders.rs` into OUT_DIR, which embeds them. A compile error fails the build with the
//! shader's file:line and glslang's message.
//!
//! Variants: each of the method passes (`surface.frag`, `shadow_caster.frag`, `trace.comp`) once per row of the method
//! table, `src/method/table.rs`, which this script compiles as a module of its own: the row names
//! the method's file (reached through the virtual include "method.glsl") and whether the variant
//! binds the method map (binding 3); `surface.frag` also once per row with level of detail
//! (`surface.frag:<id>:lod`, RELIEF_LOD), once per row shading height-blended layers
//! (`surface.frag:<id>:layers`, TERRAIN_LAYERS, and `:lod:layers` with both) and once plain (no relief), as is
//! `shadow_caster.frag` and `occluders.frag`; `mesh.vert` also as the shadow pass's (`mesh.vert:shadow`); `lighting.comp` also with ray-traced shadows (`lighting.comp:traced`); `passes/pyramid.comp` and
//! `passes/mean_pyramid.comp` once per storage format (`pyramid.comp` also for four-channel
//! terrain layers), `passes/blended_pyramid.comp` and `passes/brush.comp` per height format; every other file under
//! `passes/` once. A file in
//! `shaders/methods/` that no row names fails the build.
//!
//! Shared facts: `src/render/shader_interface/` (bindings, specialization ids, array sizes, mode
//! values, push-constant layouts), also compiled here as a module of its own, becomes the virtual
//! include "interface.glsl", so the shaders and the library read each fact from the same line;
//! a push-constant block, uniform block or storage record whose Rust offsets are not where its
//! std430 or std140 rules put them fails the build (`build/interface_header.rs`).
//!
//! The shader library (`src/shader_library/`, `build/shader_library.rs`): its files embedded in
//! the crate, its generated `relief_ids.glsl`, and the shaders that include it (a check of every
//! file, and the `shader_library` example's) compiled with an include resolver that knows only
//! the library's files.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// glslang compiles the variants, the shader library's check and its example's shaders.
#[cfg(feature = "compile-shaders")]
#[path = "build/compile.rs"]
mod compile;
/// The git commit and dirty flag that `results.json` records.
#[path = "build/git_commit.rs"]
mod git_commit;
/// "interface.glsl", written from `shader_interface`, and the layouts' check.
#[path = "build/interface_header.rs"]
mod interface_header;
/// SPIR-V made elsewhere (a packaged crate's): read back with its sources' fingerprint checked.
#[path = "build/prebuilt.rs"]
mod prebuilt;
/// The facts shaders and library share, the same files the library compiles.
#[allow(dead_code)]
#[path = "src/render/shader_interface/mod.rs"]
mod shader_interface;
/// The shader library's generated files and its example's shaders.
#[path = "build/shader_library.rs"]
mod shader_library;
/// The shader library's file list, the same file the library compiles.
#[allow(dead_code)]
#[path = "src/shader_library/files.rs"]
mod shader_library_files;
/// The method table, the same file the library compiles; build.rs reads only part of it.
#[allow(dead_code)]
#[path = "src/method/table.rs"]
mod table;

/// One SPIR-V module to produce.
struct Variant {
    key: String,
    file: PathBuf,
    stage: Stage,
    defines: Vec<(String, String)>,
    method_file: Option<PathBuf>,
}

/// A shader's stage, by its file's extension.
#[derive(Clone, Copy, Debug)]
enum Stage {
    Vertex,
    Fragment,
    Compute,
}

fn stage_of(path: &Path) -> Option<Stage> {
    match path.extension()?.to_str()? {
        "vert" => Some(Stage::Vertex),
        "frag" => Some(Stage::Fragment),
        "comp" => Some(Stage::Compute),
        _ => None,
    }
}

fn sorted_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

/// The method whose search curved relief bends (`surface.frag:relief:curved`, and the shadow
/// pass's `shadow_caster.frag:relief:curved`), and whose bindings and self-shadows prism shells
/// use (`:shells`).
const CURVED_METHOD: &str = "relief";

fn variants(root: &Path) -> Vec<Variant> {
    let mut out = Vec::new();
    for file in sorted_files(&root.join("passes")) {
        let Some(stage) = stage_of(&file) else {
            continue;
        };
        let base = file
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default()
            .to_owned();
        let plain =
            |key: String, defines: Vec<(String, String)>, method_file: Option<PathBuf>| Variant {
                key,
                file: file.clone(),
                stage,
                defines,
                method_file,
            };
        if base == "surface.frag" || base == "shadow_caster.frag" || base == "occluders.frag" {
            // Surfaces without relief: no method, no height bindings, early depth testing.
            let defines = vec![("PLAIN_SURFACE".into(), "1".into())];
            out.push(plain(format!("{base}:plain"), defines, None));
        }
        if base == "lighting.comp" {
            // The deferred frame's lighting with every shadow-casting light tested by ray
            // queries through the scene's acceleration structure.
            let defines = vec![("TRACED_SHADOWS".into(), "1".into())];
            out.push(plain(format!("{base}:traced"), defines, None));
        }
        if base == "mesh.vert" || base == "shell.vert" {
            // The shadow pass's: placed by the shadow view the draw renders into.
            let defines = vec![("SHADOW_CASTER".into(), "1".into())];
            out.push(plain(format!("{base}:shadow"), defines, None));
        }
        if table::METHOD_PASSES.contains(&base.as_str()) {
            for m in table::METHODS {
                let (defines, method_file) = method_variant(root, m);
                if base == "surface.frag" {
                    let lod = lod_defines(m, &defines);
                    let key = format!("{base}:{}:lod", m.id);
                    out.push(plain(key, lod.clone(), Some(method_file.clone())));
                    let layers = ("TERRAIN_LAYERS".to_owned(), "1".to_owned());
                    let key = format!("{base}:{}:layers", m.id);
                    let defines_with = |mut d: Vec<(String, String)>| {
                        d.push(layers.clone());
                        d
                    };
                    out.push(plain(
                        key,
                        defines_with(defines.clone()),
                        Some(method_file.clone()),
                    ));
                    let key = format!("{base}:{}:lod:layers", m.id);
                    out.push(plain(key, defines_with(lod), Some(method_file.clone())));
                }
                if m.id == CURVED_METHOD && base != "trace.comp" {
                    // Curved relief: the method's linear and binary search on a bent ray.
                    let mut curved = defines.clone();
                    curved.push(("CURVED".into(), "1".into()));
                    let key = format!("{base}:{}:curved", m.id);
                    out.push(plain(key, curved, Some(method_file.clone())));
                }
                if m.id == CURVED_METHOD && base != "trace.comp" {
                    // Prism shells: relief's own structures stand in for nothing; the march is
                    // shells.glsl's, with relief's self-shadows and bindings.
                    let mut shells = defines.clone();
                    shells.push(("SHELLS".into(), "1".into()));
                    let key = format!("{base}:{}:shells", m.id);
                    out.push(plain(key, shells, Some(method_file.clone())));
                }
                out.push(plain(
                    format!("{base}:{}", m.id),
                    defines,
                    Some(method_file),
                ));
            }
        } else if base == "pyramid.comp" || base == "mean_pyramid.comp" {
            for (fmt, qualifier) in [("r16", "r16"), ("r32f", "r32f")] {
                let defines = vec![("HEIGHT_FORMAT".into(), qualifier.into())];
                out.push(plain(format!("{base}:{fmt}"), defines, None));
            }
            if base == "pyramid.comp" {
                // A terrain's layers and weights, four channels in one image.
                for fmt in ["rgba16", "rgba32f"] {
                    let defines = vec![("HEIGHT_FORMAT".into(), fmt.into())];
                    out.push(plain(format!("{base}:{fmt}"), defines, None));
                }
            }
        } else if base == "blended_pyramid.comp" || base == "brush.comp" {
            for fmt in ["r16", "r32f"] {
                let defines = vec![("HEIGHT_FORMAT".into(), fmt.into())];
                out.push(plain(format!("{base}:{fmt}"), defines, None));
            }
        } else {
            out.push(plain(base, vec![], None));
        }
    }
    out
}

/// The defines and the method file of a method variant, from the method's table row.
fn method_variant(root: &Path, m: &table::MethodInfo) -> (Vec<(String, String)>, PathBuf) {
    let mut defines = vec![("METHOD_TRACE".into(), format!("trace_{}", m.id))];
    // Only methods whose row names a method map get binding 3 (bindings.glsl).
    if m.method_map().is_some() {
        defines.push((table::METHOD_MAP_DEFINE.into(), "1".into()));
    }
    (defines, root.join(m.shader))
}

/// A surface variant with level of detail (shaders/include/lod.glsl): methods that read the max
/// pyramid also bind the averaged one (binding 4); fixed-step searches scale their sample count.
fn lod_defines(m: &table::MethodInfo, defines: &[(String, String)]) -> Vec<(String, String)> {
    let mut lod = defines.to_vec();
    lod.push(("RELIEF_LOD".into(), "1".into()));
    if m.reads_pyramid() {
        lod.push(("LOD_MEAN_PYRAMID".into(), "1".into()));
    } else if m.fixed_step {
        lod.push(("LOD_LINEAR_SEARCH".into(), "1".into()));
    }
    lod
}

/// Every method file is some row's, and every row's file exists: a method is one GLSL file plus
/// one row, and neither compiles alone.
fn check_table(root: &Path) -> Result<(), String> {
    let named: Vec<PathBuf> = table::METHODS.iter().map(|m| root.join(m.shader)).collect();
    let mut problems: Vec<String> = named
        .iter()
        .filter(|p| !p.is_file())
        .map(|p| {
            format!(
                "the method table names {}, which does not exist",
                p.display()
            )
        })
        .collect();
    problems.extend(
        sorted_files(&root.join("methods"))
            .into_iter()
            .filter(|p| p.extension().is_some_and(|e| e == "glsl") && !named.contains(p))
            .map(|p| {
                format!(
                    "{} has no row in src/method/table.rs (add one, or delete the file)",
                    p.display()
                )
            }),
    );
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("\n"))
    }
}

/// One SPIR-V module: its file under OUT_DIR, and the variant key the library looks it up by
/// (none for the example's shaders, which the example includes by file).
pub struct Module {
    out_name: String,
    key: Option<String>,
    bytes: Vec<u8>,
}

/// Exits the build with `message` on stderr: a plain exit keeps cargo's output to the message
/// (glslang's, for a shader), without a backtrace.
fn fail(message: &str) -> ! {
    eprintln!("{message}");
    std::process::exit(1);
}

fn main() {
    let manifest =
        PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let root = manifest.join("shaders");
    println!("cargo:rerun-if-changed=shaders");
    println!("cargo:rerun-if-changed=src/method/table.rs");
    println!("cargo:rerun-if-changed=src/render/shader_interface");
    println!("cargo:rerun-if-changed=src/shader_library/files.rs");
    println!("cargo:rerun-if-changed=examples/shader_library");
    println!("cargo:rerun-if-changed={}", shader_library::CHECK_SHADER);
    if cfg!(not(feature = "compile-shaders")) {
        // Only a build that reads the folder watches it: a missing path would rerun every build.
        println!("cargo:rerun-if-changed={}", prebuilt::DIR);
    }
    println!("cargo:rerun-if-env-changed={}", prebuilt::WRITE_ENV);
    git_commit::emit(&manifest);
    if let Err(message) = check_table(&root) {
        fail(&message);
    }
    let mismatches = interface_header::layout_mismatches();
    if !mismatches.is_empty() {
        fail(&format!(
            "layouts whose Rust fields are not where GLSL puts them (src/render/shader_interface):\n{}",
            mismatches.join("\n")
        ));
    }
    let interface = interface_header::interface_header();
    std::fs::write(out_dir.join("interface.glsl"), &interface).expect("OUT_DIR is writable");
    let ids = shader_library::ids_header().unwrap_or_else(|m| fail(&m));
    let variants = variants(&root);
    let fingerprint = prebuilt::fingerprint(&manifest, &[&interface, &ids], &variants);
    let modules = spirv_modules(&manifest, &interface, &ids, &variants, &fingerprint);
    let mut table = String::from("// Generated by build.rs: SPIR-V of every shader variant.\n");
    table.push_str("pub(crate) static SHADERS: &[(&str, &Aligned<[u8]>)] = &[\n");
    for m in &modules {
        let file = out_dir.join(&m.out_name);
        if let Some(parent) = file.parent() {
            std::fs::create_dir_all(parent).expect("OUT_DIR is writable");
        }
        std::fs::write(&file, &m.bytes).expect("OUT_DIR is writable");
        if let Some(key) = &m.key {
            let _ = writeln!(table, "    ({key:?}, &Aligned(*include_bytes!({file:?}))),");
        }
    }
    table.push_str("];\n");
    std::fs::write(out_dir.join("shaders.rs"), table).expect("OUT_DIR is writable");
    if let Err(message) = shader_library::write_tables(&manifest, &out_dir, &ids) {
        fail(&message);
    }
    if let Some(dir) = std::env::var_os(prebuilt::WRITE_ENV) {
        let dir = PathBuf::from(dir);
        if let Err(e) = prebuilt::write(&dir, &fingerprint, &modules) {
            fail(&format!(
                "writing prebuilt SPIR-V into {}: {e}",
                dir.display()
            ));
        }
    }
}

/// Every module, compiled by glslang.
#[cfg(feature = "compile-shaders")]
fn spirv_modules(
    manifest: &Path,
    interface: &str,
    ids: &str,
    variants: &[Variant],
    _fingerprint: &str,
) -> Vec<Module> {
    compile::all(manifest, interface, ids, variants).unwrap_or_else(|m| fail(&m))
}

/// Every module, from the prebuilt SPIR-V a packaged crate carries, checked to be made from
/// these very sources.
#[cfg(not(feature = "compile-shaders"))]
fn spirv_modules(
    manifest: &Path,
    _interface: &str,
    _ids: &str,
    variants: &[Variant],
    fingerprint: &str,
) -> Vec<Module> {
    prebuilt::read(manifest, fingerprint, variants).unwrap_or_else(|m| fail(&m))
}

/// The file under OUT_DIR (and the prebuilt folder) of variant `key`.
fn variant_file(key: &str) -> String {
    format!("{}.spv", key.replace([':', '.'], "_"))
}
