//! The method table: for every displacement method its stable id, shader file, the maps it reads,
//! its budgets and leaf modes, and the role the bench gives it. Every other place that needs one of
//! these facts (build.rs, the plan, the bench, the report, `relief methods`) reads it from here.
//!
//! Plain data and `const fn`s over it, with no dependency on the rest of the crate nor on other
//! crates: `build.rs` compiles this same file (`#[path]`) to decide which shader variants to build
//! and which of them bind the method map. Library-only traits (serde, `FromStr`) live in `mod.rs`.

/// A precomputed map a method reads besides the height field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MapKind {
    /// The max pyramid in the height image's mip chain.
    MaxPyramid,
    /// Per texel a, b, c and height of an unbounding cone + revolved parabola (Kiglics et al.).
    Quadric,
    /// Per texel the ratio of the widest cone the bilinear bound's box surface stays outside of,
    /// and that surface's height.
    ConservativeCone,
    /// Per texel the ratio of the widest cone a ray enters the bilinear bound's box surface
    /// through at most once, and that surface's height.
    RelaxedCone,
}

impl MapKind {
    /// Every kind, in the order reports list them.
    pub const ALL: [MapKind; 4] = [
        MapKind::MaxPyramid,
        MapKind::ConservativeCone,
        MapKind::RelaxedCone,
        MapKind::Quadric,
    ];

    /// Whether the map is bound apart from the height image (binding 3): every kind but the
    /// pyramid, which lives in the height image's mip levels.
    pub const fn is_method_map(self) -> bool {
        !matches!(self, MapKind::MaxPyramid)
    }

    /// The name reports use.
    pub const fn name(self) -> &'static str {
        match self {
            MapKind::MaxPyramid => "max_pyramid",
            MapKind::Quadric => "quadric_map",
            MapKind::ConservativeCone => "cone_map",
            MapKind::RelaxedCone => "relaxed_cone_map",
        }
    }

    /// The name `relief methods --json` lists under `needs`.
    pub const fn json_name(self) -> &'static str {
        match self {
            MapKind::MaxPyramid => "max_pyramid",
            MapKind::Quadric => "quadric",
            MapKind::ConservativeCone => "conservative_cone",
            MapKind::RelaxedCone => "relaxed_cone",
        }
    }
}

/// How a method with a leaf stage finds the hit once its traversal has closed in on it
/// (specialization constant 2, `BUDGET_LEAF_EXACT` in `conventions.glsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
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
    /// Both leaves, in the order of their specialization values.
    pub const ALL: [Leaf; 2] = [Leaf::Paper, Leaf::Exact];

    /// The value of specialization constant 2.
    pub const fn spec_value(self) -> u32 {
        match self {
            Leaf::Paper => 0,
            Leaf::Exact => 1,
        }
    }

    /// The name the CLI and reports use.
    pub const fn name(self) -> &'static str {
        match self {
            Leaf::Paper => "paper",
            Leaf::Exact => "exact",
        }
    }
}

/// Iteration cap, refinement steps, leaf and how far the cap may grow with the ray
/// (specialization constants 0 to 3 of every method). Methods without a leaf stage ignore
/// `leaf`; their table rows say `Paper`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budget {
    /// The iteration cap of the method's main loop (specialization constant 0).
    pub max_steps: u32,
    /// Steps of the refinement after the main loop, for the methods that refine (constant 1).
    pub refine_steps: u32,
    /// How the hit is found once the traversal has closed in on it (constant 2).
    pub leaf: Leaf,
    /// 0: `max_steps` is the cap. Otherwise the cap of each ray is `max_steps` plus the number of
    /// texels its path crosses from the top plane to the bottom plane, up to this many steps: a
    /// grazing ray over a deep field crosses thousands of texels, and a tree walk that meets a
    /// spike in every coarse node (sparse spikes) needs a step per few of them, so a fixed cap
    /// cannot be exact there while rays that finish early never pay for it.
    pub extent_limit: u32,
}

/// The most steps a default budget grows to. Lavapipe ends every loop of an invocation after
/// 65535 iterations in all, and a tree walk's steps also run leaf solves; the worst ray measured
/// (pdm, sparse spikes, 0.5 degrees, depth scale 2, 256^2) needs 6863.
pub const EXTENT_LIMIT: u32 = 8192;

/// The part a method plays in the bench report's comparisons (sections 2 and 3): the fixed-step
/// method and the tree method that the report sets side by side at matched error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BenchRole {
    /// The fixed-step method whose cap is grown until it matches the tree method's error.
    StepBaseline,
    /// The tree method, at its default budget, that the step baseline is matched against.
    TreeBaseline,
}

/// One row of the method table.
#[derive(Debug, Clone, Copy)]
pub struct MethodInfo {
    /// Stable id: the CLI's name, the shader variants' key suffix, `trace_<id>` in GLSL.
    pub id: &'static str,
    /// Its full name, for reports and `relief methods`.
    pub name: &'static str,
    /// The paper it comes from (authors, title, year).
    pub paper: &'static str,
    /// Its GLSL file, relative to `shaders/`: it defines `Hit trace_<id>(Ray, Budget)`.
    pub shader: &'static str,
    /// The maps it reads, at most one of them a method map (binding 3).
    pub needs: &'static [MapKind],
    /// The budget used when none is asked for.
    pub default_budget: Budget,
    /// Whether `Budget::leaf` chooses between the paper's refinement and the exact leaf; the
    /// other methods ignore it (a search with no leaf, or maxmip, whose paper's leaf is exact).
    pub leaf_choice: bool,
    /// Whether its cost is a fixed number of steps along the ray, so a larger cap buys accuracy
    /// (the bench tries each of its caps on these).
    pub fixed_step: bool,
    /// The part it plays in the bench report's matched-error comparison, if any.
    pub bench_role: Option<BenchRole>,
}

impl MethodInfo {
    /// The map it reads through binding 3, if any.
    pub const fn method_map(&self) -> Option<MapKind> {
        let mut i = 0;
        while i < self.needs.len() {
            if self.needs[i].is_method_map() {
                return Some(self.needs[i]);
            }
            i += 1;
        }
        None
    }

    /// Whether it reads the max pyramid in the height image's mip chain.
    pub const fn reads_pyramid(&self) -> bool {
        let mut i = 0;
        while i < self.needs.len() {
            if matches!(self.needs[i], MapKind::MaxPyramid) {
                return true;
            }
            i += 1;
        }
        false
    }
}

/// The entry points compiled once per method (with the method's file as "method.glsl"); a
/// variant's key is `<pass>:<id>`.
pub const METHOD_PASSES: [&str; 3] = ["surface.frag", "shadow_caster.frag", "trace.comp"];

/// The `#define` that gives a method variant binding 3 (`bindings.glsl`).
pub const METHOD_MAP_DEFINE: &str = "USES_METHOD_MAP";

/// Budget of a fixed-step search without refinement.
const fn steps(max_steps: u32) -> Budget {
    Budget {
        max_steps,
        refine_steps: 0,
        leaf: Leaf::Paper,
        extent_limit: 0,
    }
}

/// Budget of a method that ends in the exact leaf by default: an accurate method, whose cap
/// grows with the ray's extent.
const fn exact(max_steps: u32, refine_steps: u32) -> Budget {
    Budget {
        max_steps,
        refine_steps,
        leaf: Leaf::Exact,
        extent_limit: EXTENT_LIMIT,
    }
}

pub const METHODS: &[MethodInfo] = &[
    MethodInfo {
        id: "parallax",
        name: "parallax mapping with offset limiting",
        paper: "Welsh 2004",
        shader: "methods/parallax.glsl",
        needs: &[],
        default_budget: steps(1),
        leaf_choice: false,
        // One offset, no search: a larger cap changes nothing.
        fixed_step: false,
        bench_role: None,
    },
    MethodInfo {
        id: "steep",
        name: "steep parallax mapping",
        paper: "McGuire 2005",
        shader: "methods/steep.glsl",
        needs: &[],
        default_budget: steps(32),
        leaf_choice: false,
        fixed_step: true,
        bench_role: None,
    },
    MethodInfo {
        id: "relief",
        name: "relief mapping: linear search + binary search",
        paper: "Policarpo et al. 2005",
        shader: "methods/relief.glsl",
        needs: &[],
        // Bevy's defaults: 16 linear steps, 5 binary steps.
        default_budget: Budget {
            max_steps: 16,
            refine_steps: 5,
            leaf: Leaf::Paper,
            extent_limit: 0,
        },
        leaf_choice: false,
        fixed_step: true,
        bench_role: None,
    },
    MethodInfo {
        id: "pom",
        name: "parallax occlusion mapping with linear-approximation refinement",
        paper: "Tatarchuk 2006",
        shader: "methods/pom.glsl",
        needs: &[],
        default_budget: steps(32),
        leaf_choice: false,
        fixed_step: true,
        // What engines ship: the baseline of Drobot's comparisons.
        bench_role: Some(BenchRole::StepBaseline),
    },
    MethodInfo {
        id: "csm",
        name: "cone step mapping on a cone map conservative for the bilinear surface, exact leaf",
        paper: "Dummer 2006",
        shader: "methods/csm.glsl",
        needs: &[MapKind::ConservativeCone],
        default_budget: exact(256, 0),
        leaf_choice: true,
        fixed_step: false,
        bench_role: None,
    },
    MethodInfo {
        id: "rcsm",
        name: "relaxed cone stepping + binary refinement on a relaxed cone map, exact leaf",
        paper: "Policarpo & Oliveira 2007",
        shader: "methods/rcsm.glsl",
        needs: &[MapKind::RelaxedCone],
        default_budget: exact(256, 8),
        leaf_choice: true,
        fixed_step: false,
        bench_role: None,
    },
    MethodInfo {
        id: "qrm",
        name: "quadtree relief mapping (Algorithm 1: quadrant trick, half-texel delta), exact leaf",
        paper: "Schroders & van Gulik 2006",
        shader: "methods/qrm.glsl",
        needs: &[MapKind::MaxPyramid],
        // Its traversal never climbs back up, so a ray grazing the surface pays a step per leaf
        // node it passes: a 5-degree view of fbm 1024^2 takes up to 512 steps (1 degree: ~1500).
        // The cap only bounds stragglers.
        default_budget: exact(1024, 0),
        leaf_choice: true,
        fixed_step: false,
        bench_role: None,
    },
    MethodInfo {
        id: "pdm",
        name: "pyramidal displacement mapping: node crossing, exact leaf",
        paper: "Oh et al. 2006, Ki & Oh",
        shader: "methods/pdm.glsl",
        needs: &[MapKind::MaxPyramid],
        // Never climbs back up either: the same budget as qrm, for the same reason.
        default_budget: exact(1024, 0),
        leaf_choice: true,
        fixed_step: false,
        bench_role: None,
    },
    MethodInfo {
        id: "qdm",
        name: "quadtree displacement mapping: one-level ascent on crossing, exact leaf",
        paper: "Drobot 2010",
        shader: "methods/qdm.glsl",
        needs: &[MapKind::MaxPyramid],
        // A 1-degree view of fbm 128^2 takes up to ~215 steps; the cap only bounds stragglers.
        default_budget: exact(256, 0),
        leaf_choice: true,
        fixed_step: false,
        // Paper 001's own tree method, set against POM there.
        bench_role: Some(BenchRole::TreeBaseline),
    },
    MethodInfo {
        id: "maxmip",
        name: "maximum-mipmap traversal with exact ray/bilinear-patch intersection at the leaf",
        paper: "Tevs, Ihrke, Seidel 2008",
        shader: "methods/maxmip.glsl",
        needs: &[MapKind::MaxPyramid],
        // A 1-degree view of fbm 128^2 takes up to ~215 steps; the cap only bounds stragglers.
        default_budget: exact(256, 0),
        leaf_choice: false,
        fixed_step: false,
        bench_role: None,
    },
    MethodInfo {
        id: "quadric",
        name: "quadratic displacement maps: cone + revolved parabola per texel, stable solver, exact leaf",
        paper: "Kiglics, Valasek, Balint, Ban",
        shader: "methods/quadric.glsl",
        needs: &[MapKind::Quadric],
        default_budget: exact(256, 8),
        leaf_choice: true,
        fixed_step: false,
        bench_role: None,
    },
];
