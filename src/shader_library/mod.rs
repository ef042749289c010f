//! relief's displacement methods as a GLSL shader library, free of relief's own bindings: the
//! methods, the self-shadows and curved relief over a height image the includer binds and names.
//! An engine writes the files into a folder its shader compiler includes from
//! ([`write_to`]), defines three names and includes [`ENTRY`] and the methods it wants; the
//! maps the methods read come from the CPU builders in [`crate::heightfield`]
//! (`MaxPyramid::build_bilinear_bound`, `cone_map`, `quadric_map`). docs/shader-library.md holds
//! the contract; `examples/shader_library/` draws a relief quad with nothing else.

mod files;

use std::path::{Path, PathBuf};

use crate::method::{Budget, Method};
pub use files::{DEFAULT_SPEC_ID_BASE, ENTRY};

include!(concat!(env!("OUT_DIR"), "/shader_library.rs"));

/// One file of the library.
#[derive(Clone, Copy, Debug)]
pub struct LibraryFile {
    /// Its name in the library's folder, as `#include` names it.
    pub name: &'static str,
    /// Its GLSL.
    pub source: &'static str,
}

/// Every file of the library: [`ENTRY`], the files it includes, the methods (one per method,
/// [`method_file`]), `shadows.glsl`, `relief_frame.glsl`, `curved.glsl` and the generated
/// `relief_ids.glsl`.
pub fn files() -> impl Iterator<Item = LibraryFile> {
    LIBRARY_SOURCES
        .iter()
        .map(|&(name, source)| LibraryFile { name, source })
}

/// The GLSL of the library file `name`.
pub fn source(name: &str) -> Option<&'static str> {
    files().find(|f| f.name == name).map(|f| f.source)
}

/// Writes every library file into `dir` (created when missing) and returns their paths: the
/// folder to put on the shader compiler's include path.
pub fn write_to(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    files()
        .map(|f| {
            let path = dir.join(f.name);
            std::fs::write(&path, f.source)?;
            Ok(path)
        })
        .collect()
}

/// The library file that defines `method`'s `Hit trace_<id>(Ray, Budget)`.
pub fn method_file(method: Method) -> &'static str {
    files::method_file_name(method.info().shader)
}

/// A specialization constant the library declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpecConstant {
    /// Its id's name in `relief_ids.glsl` (`SPEC_BUDGET_MAX_STEPS`).
    pub name: &'static str,
    /// Its id minus `RELIEF_SPEC_ID_BASE`.
    pub offset: u32,
}

/// Every specialization constant the library declares. Each has a default in the GLSL, so an
/// includer sets only those it wants to change.
pub fn spec_constants() -> impl Iterator<Item = SpecConstant> {
    files::SPEC_CONSTANTS.iter().map(|&name| SpecConstant {
        name,
        offset: offset_of(name),
    })
}

fn offset_of(name: &str) -> u32 {
    crate::render::shader_interface::SPEC_IDS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, id)| id)
        // build.rs checked every name when it wrote relief_ids.glsl.
        .unwrap_or_else(|| unreachable!("{name} is in SPEC_IDS"))
}

/// The (id, value) pairs that give `method` the budget relief's own passes give it (its
/// table row's default budget), for ids from `base` (`RELIEF_SPEC_ID_BASE`).
pub fn budget_constants(method: Method, base: u32) -> [(u32, u32); 4] {
    let Budget {
        max_steps,
        refine_steps,
        leaf,
        extent_limit,
    } = method.info().default_budget;
    [
        ("SPEC_BUDGET_MAX_STEPS", max_steps),
        ("SPEC_BUDGET_REFINE_STEPS", refine_steps),
        ("SPEC_BUDGET_LEAF_EXACT", leaf.spec_value()),
        ("SPEC_BUDGET_EXTENT_LIMIT", extent_limit),
    ]
    .map(|(name, value)| (base + offset_of(name), value))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_has_its_file_in_the_library() {
        for method in Method::all() {
            let file = method_file(method);
            let text = source(file).unwrap_or_else(|| panic!("{file} is in the library"));
            assert!(
                text.contains(&format!(
                    "Hit trace_{}(Ray ray, Budget budget)",
                    method.id()
                )),
                "{file} defines trace_{}",
                method.id()
            );
        }
    }

    #[test]
    fn every_file_has_its_own_name() {
        let mut names: Vec<&str> = files().map(|f| f.name).collect();
        let all = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all, "two library files share a name");
    }

    #[test]
    fn ids_header_offsets_match_the_interface() {
        let ids = source(files::IDS_FILE).expect("generated ids are embedded");
        for c in spec_constants() {
            let line = format!("#define {} (RELIEF_SPEC_ID_BASE + {})", c.name, c.offset);
            assert!(ids.contains(&line), "{line} in relief_ids.glsl");
        }
    }

    #[test]
    fn budget_constants_carry_the_table_budget() {
        let qdm = Method::QDM;
        let pairs = budget_constants(qdm, 200);
        assert_eq!(pairs[0], (200, qdm.info().default_budget.max_steps));
        assert!(pairs.iter().all(|&(id, _)| id >= 200));
    }

    #[test]
    fn write_to_writes_every_file() {
        let dir =
            std::env::temp_dir().join(format!("relief-shader-library-{}", std::process::id()));
        let written = write_to(&dir).expect("temp dir is writable");
        assert_eq!(written.len(), files().count());
        assert_eq!(
            std::fs::read_to_string(dir.join(ENTRY)).expect("entry written"),
            source(ENTRY).expect("entry embedded")
        );
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }
}
