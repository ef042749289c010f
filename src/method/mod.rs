//! The displacement methods relief implements: one table holding each method's stable id, name,
//! source paper, the maps it needs and its default budget. Adding a method is one GLSL file in
//! `shaders/methods/` plus one row here.

mod maps;

pub use maps::{build_method_map, build_method_map_with, BuiltMethodMap, MapBuilder};

use std::fmt;
use std::str::FromStr;

use serde::Serialize;

/// A precomputed map a method reads besides the height field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MapKind {
    /// The max pyramid in the height image's mip chain.
    MaxPyramid,
    /// Per texel a, b, c and height of an unbounding cone + revolved parabola (paper 004).
    Quadric,
    /// Per texel the ratio of the widest cone the bilinear bound's box surface stays outside of,
    /// and that surface's height.
    ConservativeCone,
    /// Per texel the ratio of the widest cone a ray enters the bilinear bound's box surface
    /// through at most once, and that surface's height.
    RelaxedCone,
}

impl MapKind {
    /// Whether the map is bound apart from the height image (binding 3): every kind but the
    /// pyramid, which lives in the height image's mip levels.
    pub fn is_method_map(self) -> bool {
        self != MapKind::MaxPyramid
    }

    /// The name reports use.
    pub fn name(self) -> &'static str {
        match self {
            MapKind::MaxPyramid => "max_pyramid",
            MapKind::Quadric => "quadric_map",
            MapKind::ConservativeCone => "cone_map",
            MapKind::RelaxedCone => "relaxed_cone_map",
        }
    }
}

/// How a method with a leaf stage finds the hit once its traversal has closed in on it
/// (specialization constant 2, `BUDGET_LEAF_EXACT` in `conventions.glsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Leaf {
    /// The paper's own refinement: linear search or interpolation at half- or one-texel spacing,
    /// binary search, or stopping on the box surface. It misses slivers of surface thinner than
    /// its sampling.
    Paper,
    /// The exact intersection of the ray with the bilinear patches it crosses (the shaders'
    /// default, which the surface pass relies on).
    Exact,
}

impl Leaf {
    /// The value of specialization constant 2.
    pub fn spec_value(self) -> u32 {
        match self {
            Leaf::Paper => 0,
            Leaf::Exact => 1,
        }
    }

    /// The name the CLI and reports use.
    pub fn name(self) -> &'static str {
        match self {
            Leaf::Paper => "paper",
            Leaf::Exact => "exact",
        }
    }
}

impl fmt::Display for Leaf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Iteration cap, refinement steps and leaf (specialization constants 0, 1 and 2 of every
/// method). Methods without a leaf stage ignore `leaf`; their table rows say `Paper`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Budget {
    pub max_steps: u32,
    pub refine_steps: u32,
    pub leaf: Leaf,
}

/// One row of the method table.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct MethodInfo {
    pub id: &'static str,
    pub name: &'static str,
    pub paper: &'static str,
    pub needs: &'static [MapKind],
    pub default_budget: Budget,
    /// Whether `Budget::leaf` chooses between the paper's refinement and the exact leaf; the
    /// other methods ignore it (a search with no leaf, or maxmip, whose paper's leaf is exact).
    pub leaf_choice: bool,
}

const METHODS: &[MethodInfo] = &[
    MethodInfo {
        id: "parallax",
        name: "parallax mapping with offset limiting",
        paper: "Welsh 2004 (cited in papers 000, 001)",
        needs: &[],
        default_budget: Budget {
            max_steps: 1,
            refine_steps: 0,
            leaf: Leaf::Paper,
        },
        leaf_choice: false,
    },
    MethodInfo {
        id: "steep",
        name: "steep parallax mapping",
        paper: "McGuire 2005 (papers 000, 003)",
        needs: &[],
        default_budget: Budget {
            max_steps: 32,
            refine_steps: 0,
            leaf: Leaf::Paper,
        },
        leaf_choice: false,
    },
    MethodInfo {
        id: "relief",
        name: "relief mapping: linear search + binary search",
        paper: "Policarpo et al. 2005 (paper 001 section 1.3.1)",
        needs: &[],
        // Bevy's defaults: 16 linear steps, 5 binary steps.
        default_budget: Budget {
            max_steps: 16,
            refine_steps: 5,
            leaf: Leaf::Paper,
        },
        leaf_choice: false,
    },
    MethodInfo {
        id: "pom",
        name: "parallax occlusion mapping with linear-approximation refinement",
        paper: "Tatarchuk 2006 (paper 001, Listing 1.1)",
        needs: &[],
        default_budget: Budget {
            max_steps: 32,
            refine_steps: 0,
            leaf: Leaf::Paper,
        },
        leaf_choice: false,
    },
    MethodInfo {
        id: "csm",
        name: "cone step mapping on a cone map conservative for the bilinear surface, exact leaf",
        paper: "Dummer 2006 (papers 001, 004)",
        needs: &[MapKind::ConservativeCone],
        default_budget: Budget {
            max_steps: 256,
            refine_steps: 0,
            leaf: Leaf::Exact,
        },
        leaf_choice: true,
    },
    MethodInfo {
        id: "rcsm",
        name: "relaxed cone stepping + binary refinement on a relaxed cone map, exact leaf",
        paper: "Policarpo & Oliveira 2007 (papers 001, 004)",
        needs: &[MapKind::RelaxedCone],
        default_budget: Budget {
            max_steps: 256,
            refine_steps: 8,
            leaf: Leaf::Exact,
        },
        leaf_choice: true,
    },
    MethodInfo {
        id: "qrm",
        name: "quadtree relief mapping (Algorithm 1: quadrant trick, half-texel delta), exact leaf",
        paper: "Schroders & van Gulik 2006 (paper 000)",
        needs: &[MapKind::MaxPyramid],
        // Its traversal never climbs back up, so a ray grazing the surface pays a step per leaf
        // node it passes: a 5-degree view of fbm 1024^2 takes up to 512 steps (1 degree: ~1500).
        // The cap only bounds stragglers.
        default_budget: Budget {
            max_steps: 1024,
            refine_steps: 0,
            leaf: Leaf::Exact,
        },
        leaf_choice: true,
    },
    MethodInfo {
        id: "pdm",
        name: "pyramidal displacement mapping: node crossing, exact leaf",
        paper: "Oh et al. 2006, Ki & Oh (paper 003)",
        needs: &[MapKind::MaxPyramid],
        // Its traversal never climbs back up, so a ray grazing the surface pays a step per leaf
        // node it passes: a 5-degree view of fbm 1024^2 takes up to 512 steps (1 degree: ~1500).
        // The cap only bounds stragglers.
        default_budget: Budget {
            max_steps: 1024,
            refine_steps: 0,
            leaf: Leaf::Exact,
        },
        leaf_choice: true,
    },
    MethodInfo {
        id: "qdm",
        name: "quadtree displacement mapping: one-level ascent on crossing, exact leaf",
        paper: "Drobot 2010 (paper 001, Listing 1.3)",
        needs: &[MapKind::MaxPyramid],
        // A 1-degree view of fbm 128^2 takes up to ~215 steps; the cap only bounds stragglers.
        default_budget: Budget {
            max_steps: 256,
            refine_steps: 0,
            leaf: Leaf::Exact,
        },
        leaf_choice: true,
    },
    MethodInfo {
        id: "maxmip",
        name: "maximum-mipmap traversal with exact ray/bilinear-patch intersection at the leaf",
        paper: "Tevs, Ihrke, Seidel 2008 (beyond the papers)",
        needs: &[MapKind::MaxPyramid],
        // A 1-degree view of fbm 128^2 takes up to ~215 steps; the cap only bounds stragglers.
        default_budget: Budget {
            max_steps: 256,
            refine_steps: 0,
            leaf: Leaf::Exact,
        },
        leaf_choice: false,
    },
    MethodInfo {
        id: "quadric",
        name: "quadratic displacement maps: cone + revolved parabola per texel, stable solver, exact leaf",
        paper: "Kiglics, Valasek, Balint, Ban (paper 004, Algorithms 1 and 2)",
        needs: &[MapKind::Quadric],
        default_budget: Budget {
            max_steps: 256,
            refine_steps: 8,
            leaf: Leaf::Exact,
        },
        leaf_choice: true,
    },
];

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

    /// The key of its surface shader variant.
    pub fn surface_shader_key(self) -> String {
        format!("surface.frag:{}", self.id())
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
            .find(|l| l.contains("constant_id = 2"))
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
}
