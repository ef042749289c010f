//! Prebuilt SPIR-V: what a build with `compile-shaders` made, written to a folder
//! (`RELIEF_WRITE_PREBUILT_SPIRV=DIR`) and shipped in the packaged crate, so a dependent that
//! turns the feature off builds without glslang's C++. The folder's manifest carries a
//! fingerprint of every shader source, generated header and variant it was made from; a build
//! that reads it recomputes the fingerprint and refuses SPIR-V made from other sources.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::{Module, Variant};

/// The folder, at the package's root, that a packaged crate ships.
pub const DIR: &str = "prebuilt-spirv";
/// Set to a folder, a `compile-shaders` build writes its SPIR-V and manifest there.
pub const WRITE_ENV: &str = "RELIEF_WRITE_PREBUILT_SPIRV";
const MANIFEST: &str = "manifest.txt";

/// 64-bit FNV-1a: stable across Rust releases and platforms, unlike std's hasher.
struct Fnv(u64);

impl Fnv {
    fn add(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        // A separator, so that ("ab", "c") and ("a", "bc") differ.
        self.0 ^= 0xff;
        self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
    }
}

/// Every file under `dir`, recursively, sorted.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut pending = vec![dir.to_owned()];
    while let Some(d) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for path in entries.filter_map(|e| e.ok().map(|e| e.path())) {
            if path.is_dir() {
                pending.push(path);
            } else {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The fingerprint of what the SPIR-V is made from: the GLSL under `shaders/`, the shader
/// library's example and check shaders, the generated headers and every variant's definition.
pub fn fingerprint(manifest: &Path, generated: &[&str], variants: &[Variant]) -> String {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    let mut sources = files_under(&manifest.join("shaders"));
    let example = manifest.join(crate::shader_library::EXAMPLE_DIR);
    sources.extend(
        crate::shader_library::EXAMPLE_SHADERS
            .iter()
            .map(|shader| example.join(shader.file)),
    );
    sources.push(manifest.join(crate::shader_library::CHECK_SHADER));
    for path in sources {
        let relative = path.strip_prefix(manifest).unwrap_or(&path);
        h.add(relative.to_string_lossy().replace('\\', "/").as_bytes());
        h.add(&std::fs::read(&path).unwrap_or_default());
    }
    for shader in crate::shader_library::EXAMPLE_SHADERS {
        h.add(format!("{} {:?}", shader.spirv, shader.define).as_bytes());
    }
    for text in generated {
        h.add(text.as_bytes());
    }
    for v in variants {
        h.add(v.key.as_bytes());
        let method = v.method_file.as_deref().map(|m| m.strip_prefix(manifest));
        let file = v.file.strip_prefix(manifest);
        h.add(format!("{:?} {file:?} {method:?}", v.stage).as_bytes());
        for (name, value) in &v.defines {
            h.add(name.as_bytes());
            h.add(value.as_bytes());
        }
    }
    format!("{:016x}", h.0)
}

/// Writes `modules` and the manifest into `dir`.
pub fn write(dir: &Path, fingerprint: &str, modules: &[Module]) -> std::io::Result<()> {
    if dir.is_dir() {
        std::fs::remove_dir_all(dir)?;
    }
    let mut manifest = String::from(
        "# relief's prebuilt SPIR-V, written by a build with RELIEF_WRITE_PREBUILT_SPIRV set.\n",
    );
    let _ = writeln!(manifest, "fingerprint {fingerprint}");
    for m in modules {
        let path = dir.join(&m.out_name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        std::fs::write(&path, &m.bytes)?;
        let _ = writeln!(
            manifest,
            "{}\t{}",
            m.out_name,
            m.key.as_deref().unwrap_or("-")
        );
    }
    std::fs::write(dir.join(MANIFEST), manifest)
}

/// The modules of the package's prebuilt folder, when it was made from these very sources.
#[cfg_attr(feature = "compile-shaders", allow(dead_code))]
pub fn read(
    package: &Path,
    fingerprint: &str,
    variants: &[Variant],
) -> Result<Vec<Module>, String> {
    let dir = package.join(DIR);
    let text = std::fs::read_to_string(dir.join(MANIFEST)).map_err(|e| {
        format!(
            "relief is built without the `compile-shaders` feature, so it needs the prebuilt SPIR-V \
             a packaged relief carries, and {} cannot be read ({e}). In a checkout of relief, \
             build with `--features compile-shaders`, or write the folder first with \
             `{WRITE_ENV}=$PWD/{DIR} cargo build --lib`.",
            dir.join(MANIFEST).display()
        )
    })?;
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let made_from = lines
        .next()
        .and_then(|l| l.strip_prefix("fingerprint "))
        .ok_or_else(|| format!("{}: no fingerprint line", dir.join(MANIFEST).display()))?;
    if made_from != fingerprint {
        return Err(format!(
            "the prebuilt SPIR-V in {} was made from other shader sources (fingerprint {made_from}, \
             these sources {fingerprint}): rewrite it with `{WRITE_ENV}=$PWD/{DIR} cargo build \
             --lib`, or build with `--features compile-shaders`",
            dir.display()
        ));
    }
    let mut modules = Vec::new();
    for line in lines {
        let (out_name, key) = line
            .split_once('\t')
            .ok_or_else(|| format!("{}: bad line {line:?}", dir.join(MANIFEST).display()))?;
        let bytes = std::fs::read(dir.join(out_name))
            .map_err(|e| format!("{}: {e}", dir.join(out_name).display()))?;
        let key = (key != "-").then(|| key.to_owned());
        if key
            .as_deref()
            .is_some_and(|k| crate::variant_file(k) != out_name)
        {
            let manifest = dir.join(MANIFEST);
            return Err(format!(
                "{}: {out_name} does not hold {key:?}",
                manifest.display()
            ));
        }
        modules.push(Module {
            out_name: out_name.to_owned(),
            key,
            bytes,
        });
    }
    if let Some(v) = variants.iter().find(|v| {
        !modules
            .iter()
            .any(|m| m.key.as_deref() == Some(v.key.as_str()))
    }) {
        return Err(format!(
            "the prebuilt SPIR-V in {} has no {}",
            dir.display(),
            v.key
        ));
    }
    Ok(modules)
}
