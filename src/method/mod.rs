//! The displacement methods relief implements, by their rows in one table (`table.rs`): each
//! method's stable id, name, source paper, shader file, the maps it needs, its default budget and
//! leaf choice. Adding a method is one GLSL file in `shaders/methods/` plus one row there.
//!
//! This module is data: it imports nothing else of the crate, so every other module (and
//! build.rs) can read the table without a cycle.

mod table;

pub use table::{BenchRole, Budget, Leaf, MapKind, MethodInfo, METHOD_MAP_DEFINE, METHOD_PASSES};

use std::fmt;
use std::str::FromStr;

use serde::ser::SerializeStruct;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use table::METHODS;

const fn same_id(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The table row of `id`, checked at compile time for the named constants below.
const fn index_of(id: &str) -> usize {
    let mut i = 0;
    while i < METHODS.len() {
        if same_id(METHODS[i].id, id) {
            return i;
        }
        i += 1;
    }
    panic!("no such method id in the table")
}

/// A displacement method, by its stable id.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Method(usize);

impl Method {
    /// Parallax occlusion mapping, the renderer's default.
    pub const POM: Method = Method(index_of("pom"));
    /// Quadtree displacement mapping (Drobot), the default scene's.
    pub const QDM: Method = Method(index_of("qdm"));
    /// Relief mapping (Policarpo, Oliveira, Comba): linear then binary search; the method
    /// curved silhouettes bend.
    pub const RELIEF: Method = Method(index_of("relief"));
    /// Maximum-mipmap traversal with the exact bilinear leaf (Tevs, Ihrke, Seidel): the exact
    /// walk ray queries resolve relief prisms with.
    pub const MAXMIP: Method = Method(index_of("maxmip"));

    /// Every method, in table order.
    pub fn all() -> impl Iterator<Item = Method> {
        (0..METHODS.len()).map(Method)
    }

    /// The method's table row.
    pub fn info(self) -> &'static MethodInfo {
        &METHODS[self.0]
    }

    /// The stable id (`pom`, `qdm`, ...).
    pub fn id(self) -> &'static str {
        self.info().id
    }

    /// The key of its variant of `pass` (one of [`METHOD_PASSES`]), as build.rs names it.
    pub fn shader_key(self, pass: &str) -> String {
        format!("{pass}:{}", self.id())
    }

    /// The key of its surface shader variant.
    pub fn surface_shader_key(self) -> String {
        self.shader_key("surface.frag")
    }

    /// The method the table gives `role`, if any.
    pub fn with_role(role: BenchRole) -> Option<Method> {
        Method::all().find(|m| m.info().bench_role == Some(role))
    }
}

impl Serialize for MapKind {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.json_name())
    }
}

impl Serialize for Leaf {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl Serialize for Budget {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut b = s.serialize_struct("Budget", 4)?;
        b.serialize_field("max_steps", &self.max_steps)?;
        b.serialize_field("refine_steps", &self.refine_steps)?;
        b.serialize_field("leaf", &self.leaf)?;
        b.serialize_field("extent_limit", &self.extent_limit)?;
        b.end()
    }
}

/// Reads what [`Leaf`]'s `Serialize` writes: its name.
impl<'de> Deserialize<'de> for Leaf {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Leaf, D::Error> {
        String::deserialize(d)?
            .parse()
            .map_err(serde::de::Error::custom)
    }
}

/// [`Budget`]'s fields as `Serialize` writes them; `table.rs` stays free of serde (build.rs
/// compiles it too, without serde).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BudgetFields {
    max_steps: u32,
    refine_steps: u32,
    leaf: Leaf,
    extent_limit: u32,
}

impl<'de> Deserialize<'de> for Budget {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Budget, D::Error> {
        let f = BudgetFields::deserialize(d)?;
        Ok(Budget {
            max_steps: f.max_steps,
            refine_steps: f.refine_steps,
            leaf: f.leaf,
            extent_limit: f.extent_limit,
        })
    }
}

impl fmt::Display for Leaf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Parses `paper` or `exact`, so the CLI reads a leaf without an enum of its own.
impl FromStr for Leaf {
    type Err = String;

    fn from_str(s: &str) -> Result<Leaf, String> {
        Leaf::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("unknown leaf `{s}` (expected `paper` or `exact`)"))
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

/// An id that names no method.
#[derive(Debug, thiserror::Error)]
#[error("unknown method {given:?}; known methods: {known}")]
pub struct UnknownMethod {
    given: String,
    known: String,
}

impl FromStr for Method {
    type Err = UnknownMethod;

    fn from_str(s: &str) -> Result<Method, UnknownMethod> {
        Method::all()
            .find(|m| m.id() == s)
            .ok_or_else(|| UnknownMethod {
                given: s.to_owned(),
                known: Method::all().map(|m| m.id()).collect::<Vec<_>>().join(", "),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shader_default_leaf_is_the_tables() {
        // The surface pass sets only constants 0 and 1, so the GLSL default of constant 2 is the
        // leaf every method with a choice renders with: it must be the table's default.
        let glsl = include_str!("../../shaders/include/conventions.glsl");
        let line = glsl
            .lines()
            .find(|l| l.contains("constant_id = SPEC_BUDGET_LEAF_EXACT"))
            .expect("conventions.glsl declares constant 2");
        let default = line
            .trim_end_matches(';')
            .rsplit('=')
            .next()
            .and_then(|v| v.trim().parse::<u32>().ok())
            .expect("constant 2 has a numeric default");
        for m in Method::all().filter(|m| m.info().leaf_choice) {
            assert_eq!(m.info().default_budget.leaf.spec_value(), default, "{m}");
        }
    }

    #[test]
    fn ids_round_trip_and_have_shaders() {
        for m in Method::all() {
            assert_eq!(m.id().parse::<Method>().expect("own id parses"), m);
            assert!(
                crate::shaders::spirv(&m.surface_shader_key()).is_some(),
                "{m} has a surface shader"
            );
        }
        let err = "nope"
            .parse::<Method>()
            .expect_err("unknown id is rejected");
        assert!(
            err.to_string().contains("pom"),
            "the error lists the known ids: {err}"
        );
    }

    #[test]
    fn rows_are_consistent() {
        for m in Method::all() {
            let i = m.info();
            assert_eq!(Method::all().filter(|o| o.id() == i.id).count(), 1, "{m}");
            let maps = i.needs.iter().filter(|k| k.is_method_map()).count();
            assert!(maps <= 1, "{m} reads {maps} maps through binding 3");
            for pass in METHOD_PASSES {
                assert!(
                    crate::shaders::spirv(&m.shader_key(pass)).is_some(),
                    "{m} {pass}"
                );
            }
        }
        for role in [BenchRole::StepBaseline, BenchRole::TreeBaseline] {
            let n = Method::all()
                .filter(|m| m.info().bench_role == Some(role))
                .count();
            assert_eq!(n, 1, "{role:?} is one method's");
        }
        assert!(Method::with_role(BenchRole::StepBaseline).is_some_and(|m| m.info().fixed_step));
    }

    #[test]
    fn leaves_parse_and_facts_serialize_by_name() {
        for leaf in Leaf::ALL {
            assert_eq!(leaf.name().parse::<Leaf>(), Ok(leaf));
        }
        assert!("fast".parse::<Leaf>().is_err());
        let json = serde_json::to_string(&Budget {
            max_steps: 8,
            refine_steps: 2,
            leaf: Leaf::Exact,
            extent_limit: 0,
        })
        .expect("serializes");
        assert_eq!(
            json,
            r#"{"max_steps":8,"refine_steps":2,"leaf":"exact","extent_limit":0}"#
        );
        let kinds = serde_json::to_string(&MapKind::ALL).expect("serializes");
        assert_eq!(
            kinds,
            r#"["max_pyramid","conservative_cone","relaxed_cone","quadric"]"#
        );
    }
}
