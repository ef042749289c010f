//! Compiling with glslang (feature `compile-shaders`): every variant against relief's own
//! includes, and the shader library's check and example against the library's files alone.

use std::path::{Path, PathBuf};

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage,
    SpirvVersion, Target, VulkanVersion,
};

use crate::shader_library::{library_files, CHECK_SHADER, EXAMPLE_DIR, EXAMPLE_SHADERS};
use crate::shader_library_files::IDS_FILE;
use crate::{variant_file, Module, Stage, Variant};

/// Every variant and the shader library's example shaders as modules; the library's check is
/// compiled and dropped. Every failing shader is reported, not just the first.
pub fn all(
    manifest: &Path,
    interface: &str,
    ids: &str,
    variants: &[Variant],
) -> Result<Vec<Module>, String> {
    let compiler = Compiler::acquire().expect("glslang initialises once per process");
    let root = manifest.join("shaders");
    let mut modules = Vec::new();
    let mut failures = Vec::new();
    for v in variants {
        match compile(compiler, &root, interface, v) {
            Ok(words) => modules.push(Module {
                out_name: variant_file(&v.key),
                key: Some(v.key.clone()),
                bytes: to_bytes(&words),
            }),
            Err(message) => failures.push(message),
        }
    }
    if !failures.is_empty() {
        for f in &failures {
            println!("cargo:warning={}", f.lines().next().unwrap_or_default());
        }
        return Err(format!(
            "{} shader(s) failed to compile:\n\n{}",
            failures.len(),
            failures.join("\n\n")
        ));
    }
    modules.extend(library_shaders(compiler, manifest, ids)?);
    Ok(modules)
}

fn to_bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

fn glslang_stage(stage: Stage) -> ShaderStage {
    match stage {
        Stage::Vertex => ShaderStage::Vertex,
        Stage::Fragment => ShaderStage::Fragment,
        Stage::Compute => ShaderStage::Compute,
    }
}

/// Resolves `#include` against `shaders/include/`, "method.glsl" to the variant's method and
/// "interface.glsl" to the header written from `shader_interface`.
struct Includes<'a> {
    root: PathBuf,
    method_file: Option<PathBuf>,
    interface: &'a str,
}

impl IncludeHandler for Includes<'_> {
    fn include(&mut self, _: IncludeType, name: &str, _: &str, _: usize) -> Option<IncludeResult> {
        if name == "interface.glsl" {
            return Some(IncludeResult {
                name: "interface.glsl (src/render/shader_interface)".into(),
                data: self.interface.to_owned(),
            });
        }
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

fn compile(
    compiler: &Compiler,
    root: &Path,
    interface: &str,
    v: &Variant,
) -> Result<Vec<u32>, String> {
    let mut includes = Includes {
        root: root.to_owned(),
        method_file: v.method_file.clone(),
        interface,
    };
    let method = v
        .method_file
        .as_ref()
        .map(|m| format!(" (method {})", m.display()))
        .unwrap_or_default();
    let source = Source {
        key: &format!("{}{method}", v.key),
        file: &v.file,
        shown_from: root.parent().unwrap_or(root),
        stage: v.stage,
        defines: &v.defines,
    };
    compile_source(compiler, &source, &mut includes)
}

/// One GLSL file to compile, and how its errors name it.
struct Source<'a> {
    key: &'a str,
    file: &'a Path,
    /// Error messages show the file relative to this folder.
    shown_from: &'a Path,
    stage: Stage,
    defines: &'a [(String, String)],
}

fn compile_source(
    compiler: &Compiler,
    s: &Source,
    includes: &mut dyn IncludeHandler,
) -> Result<Vec<u32>, String> {
    let shown = s
        .file
        .strip_prefix(s.shown_from)
        .unwrap_or(s.file)
        .display()
        .to_string();
    let text = std::fs::read_to_string(s.file).map_err(|e| format!("{shown}: {e}"))?;
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
    let defines: Vec<(&str, Option<&str>)> = s
        .defines
        .iter()
        .map(|(k, val)| (k.as_str(), Some(val.as_str())))
        .collect();
    let name_errors = |e: glslang::error::GlslangError| {
        // glslang numbers the top-level string 0; say which file that is.
        let text = e
            .to_string()
            .replace("ERROR: 0:", &format!("ERROR: {shown}:"));
        format!("shader {}:\n{text}", s.key)
    };
    let input = ShaderInput::new(
        &source,
        glslang_stage(s.stage),
        &options,
        Some(&defines),
        Some(includes),
    )
    .map_err(name_errors)?;
    let shader = compiler.create_shader(input).map_err(name_errors)?;
    shader.compile().map_err(name_errors)
}

/// Resolves `#include` among the shader library's files only.
struct LibraryIncludes {
    files: Vec<(String, PathBuf)>,
    ids: String,
}

impl IncludeHandler for LibraryIncludes {
    fn include(&mut self, _: IncludeType, name: &str, _: &str, _: usize) -> Option<IncludeResult> {
        let data = if name == IDS_FILE {
            self.ids.clone()
        } else {
            let (_, path) = self.files.iter().find(|(n, _)| n == name)?;
            std::fs::read_to_string(path).ok()?
        };
        Some(IncludeResult {
            name: format!("shader library {name}"),
            data,
        })
    }
}

/// The library's check (every file in one shader, compiled and dropped) and the example's
/// shaders, compiled with [`LibraryIncludes`]: a library file that reaches for relief's own
/// bindings or interface fails here.
fn library_shaders(compiler: &Compiler, manifest: &Path, ids: &str) -> Result<Vec<Module>, String> {
    let mut includes = LibraryIncludes {
        files: library_files(&manifest.join("shaders"), Path::new(IDS_FILE)),
        ids: ids.to_owned(),
    };
    let check = manifest.join(CHECK_SHADER);
    let every_file = Source {
        key: CHECK_SHADER,
        file: &check,
        shown_from: manifest,
        stage: Stage::Fragment,
        defines: &[],
    };
    compile_source(compiler, &every_file, &mut includes)?;
    let mut modules = Vec::new();
    for shader in EXAMPLE_SHADERS {
        let file = manifest.join(EXAMPLE_DIR).join(shader.file);
        let defines: Vec<(String, String)> = shader
            .define
            .iter()
            .map(|d| (d.to_string(), "1".to_owned()))
            .collect();
        let source = Source {
            key: &format!("{EXAMPLE_DIR}/{} ({})", shader.file, shader.spirv),
            file: &file,
            shown_from: manifest,
            stage: shader.stage,
            defines: &defines,
        };
        let words = compile_source(compiler, &source, &mut includes)?;
        modules.push(Module {
            out_name: format!("shader_library_example/{}", shader.spirv),
            key: None,
            bytes: to_bytes(&words),
        });
    }
    Ok(modules)
}
