//! Compiles every shader entry point and variant under `shaders/` to SPIR-V with glslang and
//! writes `shaders.rs` into OUT_DIR, which embeds them. A compile error fails the build with the
//! shader's file:line and glslang's message.
//!
//! Variants: `passes/surface.frag` once per method file in `shaders/methods/` (the method is
//! reached through the virtual include "method.glsl") and once plain (no relief), `passes/pyramid.comp` once per storage
//! format; every other file under `passes/` once.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage,
    SpirvVersion, Target, VulkanVersion,
};

/// One SPIR-V module to produce.
struct Variant {
    key: String,
    file: PathBuf,
    stage: ShaderStage,
    defines: Vec<(String, String)>,
    method_file: Option<PathBuf>,
}

/// Resolves `#include` against `shaders/include/`, and "method.glsl" to the variant's method.
struct Includes {
    root: PathBuf,
    method_file: Option<PathBuf>,
}

impl IncludeHandler for Includes {
    fn include(&mut self, _: IncludeType, name: &str, _: &str, _: usize) -> Option<IncludeResult> {
        let path = if name == "method.glsl" {
            self.method_file.clone()?
        } else {
            self.root.join("include").join(name)
        };
        let data = std::fs::read_to_string(&path).ok()?;
        let shown = path
            .strip_prefix(&self.root)
            .unwrap_or(&path)
            .display()
            .to_string();
        Some(IncludeResult { name: shown, data })
    }
}

fn stage_of(path: &Path) -> Option<ShaderStage> {
    match path.extension()?.to_str()? {
        "vert" => Some(ShaderStage::Vertex),
        "frag" => Some(ShaderStage::Fragment),
        "comp" => Some(ShaderStage::Compute),
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

fn variants(root: &Path) -> Vec<Variant> {
    let methods: Vec<PathBuf> = sorted_files(&root.join("methods"))
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "glsl"))
        .collect();
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
        if base == "surface.frag" {
            // Surfaces without relief: no method, no height bindings, early depth testing.
            let defines = vec![("PLAIN_SURFACE".into(), "1".into())];
            out.push(plain(format!("{base}:plain"), defines, None));
        }
        if matches!(base.as_str(), "surface.frag" | "trace.comp") {
            for m in &methods {
                let id = m.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
                let mut defines = vec![("METHOD_TRACE".into(), format!("trace_{id}"))];
                // Only methods that read a precomputed map get binding 3 (bindings.glsl).
                if reads_method_map(root, m) {
                    defines.push(("USES_METHOD_MAP".into(), "1".into()));
                }
                out.push(plain(format!("{base}:{id}"), defines, Some(m.clone())));
            }
        } else if base == "pyramid.comp" {
            for (fmt, qualifier) in [("r16", "r16"), ("r32f", "r32f")] {
                let defines = vec![("HEIGHT_FORMAT".into(), qualifier.into())];
                out.push(plain(format!("{base}:{fmt}"), defines, None));
            }
        } else {
            out.push(plain(base, vec![], None));
        }
    }
    out
}

/// Whether a method file, or an include it names, reads binding 3.
fn reads_method_map(root: &Path, method: &Path) -> bool {
    let source = std::fs::read_to_string(method).unwrap_or_default();
    let included = source.lines().filter_map(|l| {
        let name = l.trim().strip_prefix("#include")?.trim().trim_matches('"');
        std::fs::read_to_string(root.join("include").join(name)).ok()
    });
    std::iter::once(source.clone())
        .chain(included)
        .any(|text| text.contains("method_map"))
}

fn compile(compiler: &Compiler, root: &Path, v: &Variant) -> Result<Vec<u32>, String> {
    let shown = v
        .file
        .strip_prefix(root.parent().unwrap_or(root))
        .unwrap_or(&v.file)
        .display()
        .to_string();
    let text = std::fs::read_to_string(&v.file).map_err(|e| format!("{shown}: {e}"))?;
    let source = ShaderSource::from(text);
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan {
            version: VulkanVersion::Vulkan1_3,
            spirv_version: SpirvVersion::SPIRV1_6,
        },
        version_profile: None,
        messages: glslang::ShaderMessage::DEFAULT,
    };
    let defines: Vec<(&str, Option<&str>)> = v
        .defines
        .iter()
        .map(|(k, val)| (k.as_str(), Some(val.as_str())))
        .collect();
    let mut includes = Includes {
        root: root.to_owned(),
        method_file: v.method_file.clone(),
    };
    let name_errors = |e: glslang::error::GlslangError| {
        // glslang numbers the top-level string 0; say which file that is.
        let text = e
            .to_string()
            .replace("ERROR: 0:", &format!("ERROR: {shown}:"));
        let method = v
            .method_file
            .as_ref()
            .map(|m| format!(" (method {})", m.display()))
            .unwrap_or_default();
        format!("shader {}{method}:\n{text}", v.key)
    };
    let input = ShaderInput::new(
        &source,
        v.stage,
        &options,
        Some(&defines),
        Some(&mut includes),
    )
    .map_err(name_errors)?;
    let shader = compiler.create_shader(input).map_err(name_errors)?;
    shader.compile().map_err(name_errors)
}

fn main() {
    let manifest =
        PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let root = manifest.join("shaders");
    println!("cargo:rerun-if-changed=shaders");
    let compiler = Compiler::acquire().expect("glslang initialises once per process");
    let mut table = String::from("// Generated by build.rs: SPIR-V of every shader variant.\n");
    table.push_str("pub(crate) static SHADERS: &[(&str, &Aligned<[u8]>)] = &[\n");
    let mut failures = Vec::new();
    for v in variants(&root) {
        match compile(compiler, &root, &v) {
            Ok(words) => {
                let file = out_dir.join(format!("{}.spv", v.key.replace([':', '.'], "_")));
                let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                std::fs::write(&file, bytes).expect("OUT_DIR is writable");
                let _ = writeln!(
                    table,
                    "    ({:?}, &Aligned(*include_bytes!({:?}))),",
                    v.key, file
                );
            }
            Err(message) => failures.push(message),
        }
    }
    if !failures.is_empty() {
        for f in &failures {
            println!("cargo:warning={}", f.lines().next().unwrap_or_default());
        }
        // A plain exit keeps cargo's output to glslang's messages, without a backtrace.
        eprintln!(
            "{} shader(s) failed to compile:\n\n{}",
            failures.len(),
            failures.join("\n\n")
        );
        std::process::exit(1);
    }
    table.push_str("];\n");
    std::fs::write(out_dir.join("shaders.rs"), table).expect("OUT_DIR is writable");
}
