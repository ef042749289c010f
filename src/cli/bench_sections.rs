//! Which of `relief bench`'s sections a run asks for. `--sections LIST` names them; without it,
//! flags that narrow the sweep (`--methods`, `--fields`, `--heightmap`, `--sizes`, `--angles`,
//! `--azimuths`, `--depth-scales`, `--budgets`) run only the sections they narrow (the main
//! sweep, the stability matrix over the chosen methods, and blending over the chosen methods and
//! angles), since a user who asks for two methods at one size expects their table, not every
//! section at its own settings. The `--no-X` and `--X-only` flags apply on top.

use clap::ValueEnum;
use relief::bench::{
    plan_jobs, stiff_cases, AoConfig, SectionsRun, ShadingConfig, SkippedSection, SweepConfig,
    SweepSections,
};
use relief::vk::Context;

use super::bench_args::BenchArgs;

/// A section of the sweep, as `--sections` names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SectionName {
    /// The error-against-time sweep with its scaling, matched-scaling and depth-scale parts.
    Main,
    Stability,
    Shading,
    Lod,
    Edits,
    Blending,
    SceneShadows,
    FrameFeatures,
    Silhouettes,
    FrameCosts,
}

impl SectionName {
    /// Every section, in the report's order.
    pub const ALL: [SectionName; 10] = [
        SectionName::Main,
        SectionName::Stability,
        SectionName::Shading,
        SectionName::Lod,
        SectionName::Edits,
        SectionName::Blending,
        SectionName::SceneShadows,
        SectionName::FrameFeatures,
        SectionName::Silhouettes,
        SectionName::FrameCosts,
    ];

    /// The name `--sections` takes.
    pub fn name(self) -> &'static str {
        match self {
            SectionName::Main => "main",
            SectionName::Stability => "stability",
            SectionName::Shading => "shading",
            SectionName::Lod => "lod",
            SectionName::Edits => "edits",
            SectionName::Blending => "blending",
            SectionName::SceneShadows => "scene-shadows",
            SectionName::FrameFeatures => "frame-features",
            SectionName::Silhouettes => "silhouettes",
            SectionName::FrameCosts => "frame-costs",
        }
    }

    /// Whether the sweep's narrowing flags apply to it.
    fn narrowed_by_sweep_flags(self) -> bool {
        matches!(
            self,
            SectionName::Main | SectionName::Stability | SectionName::Blending
        )
    }
}

/// What the flags ask of the sections, before `--no-X` and `--X-only`.
pub struct SectionChoice {
    listed: Vec<SectionName>,
    narrowing: Vec<&'static str>,
}

impl SectionChoice {
    /// The choice `args` make.
    pub fn of(args: &BenchArgs) -> SectionChoice {
        let given = [
            ("--methods", !args.methods.is_empty()),
            ("--fields", !args.fields.is_empty()),
            ("--heightmap", !args.heightmap.is_empty()),
            ("--sizes", !args.sizes.is_empty()),
            ("--angles", !args.angles.is_empty()),
            ("--azimuths", !args.azimuths.is_empty()),
            ("--depth-scales", !args.depth_scales.is_empty()),
            ("--budgets", !args.budgets.is_empty()),
        ];
        SectionChoice {
            listed: args.sections.clone(),
            narrowing: given.iter().filter(|g| g.1).map(|g| g.0).collect(),
        }
    }

    /// Why `section` is left out by `--sections` or the narrowing flags; `None` when they let
    /// it run.
    pub fn left_out(&self, section: SectionName) -> Option<String> {
        if !self.listed.is_empty() {
            let listed: Vec<&str> = self.listed.iter().map(|s| s.name()).collect();
            return (!self.listed.contains(&section))
                .then(|| format!("--sections {} leaves it out", listed.join(",")));
        }
        (!self.narrowing.is_empty() && !section.narrowed_by_sweep_flags()).then(|| {
            format!(
                "the sweep is narrowed by {}, which it does not take; name it in --sections to run it",
                self.narrowing.join(", ")
            )
        })
    }

    /// The record of the run: `ran(section)` says whether each section was measured, and a
    /// section left out by none of this choice's reasons was left out by a `--no-X` or
    /// `--X-only` flag.
    pub fn record(&self, ran: impl Fn(SectionName) -> bool) -> SectionsRun {
        let mut record = SectionsRun::default();
        for section in SectionName::ALL {
            if ran(section) {
                record.ran.push(section.name().to_owned());
            } else {
                let why = self.left_out(section).unwrap_or_else(|| {
                    "left out by a --no-X or --X-only flag, or it has nothing to measure here"
                        .to_owned()
                });
                record.skipped.push(SkippedSection {
                    section: section.name().to_owned(),
                    why,
                });
            }
        }
        record
    }
}

/// What one `relief bench` measures, from its flags: the sweep's jobs and which other sections
/// run, with their settings.
pub(super) fn sections(args: &BenchArgs, cfg: &SweepConfig, ctx: &Context) -> SweepSections {
    let choice = SectionChoice::of(args);
    let asked = |s: SectionName| choice.left_out(s).is_none();
    let only_other = args.shading_only
        || args.lod_only
        || args.stability_only
        || args.scene_shadows_only
        || args.frame_features_only
        || args.silhouettes_only
        || args.frame_costs_only;
    let jobs = if only_other || !asked(SectionName::Main) {
        Vec::new()
    } else {
        plan_jobs(cfg)
    };
    let shading_wanted = (args.shading_only || asked(SectionName::Shading))
        && !(args.no_shading
            || args.lod_only
            || args.stability_only
            || args.scene_shadows_only
            || args.frame_features_only
            || args.silhouettes_only
            || args.frame_costs_only);
    let shading = shading_wanted.then(|| {
        if cfg.quick {
            ShadingConfig::quick()
        } else {
            ShadingConfig::full()
        }
    });
    let largest = if cfg.quick {
        1024
    } else {
        8192.min(ctx.info().max_image_dimension_2d)
    };
    let cases = if cfg.stability
        && (args.stability_only || asked(SectionName::Stability))
        && !(args.shading_only
            || args.lod_only
            || args.scene_shadows_only
            || args.frame_features_only
            || args.silhouettes_only
            || args.frame_costs_only)
    {
        stiff_cases(largest, cfg.quick)
    } else {
        Vec::new()
    };
    let ao = if cfg.quick {
        AoConfig::quick()
    } else {
        AoConfig::full()
    };
    let edits_wanted = asked(SectionName::Edits) && !(args.no_edits || only_other);
    SweepSections {
        jobs,
        shadow_stability: shading.is_some() && cfg.stability,
        shading,
        cases,
        ao,
        lod: (args.lod_only || asked(SectionName::Lod))
            && !(args.no_lod
                || args.shading_only
                || args.stability_only
                || args.scene_shadows_only
                || args.frame_features_only
                || args.silhouettes_only
                || args.frame_costs_only),
        edit_sizes: if edits_wanted {
            edit_sizes(args, cfg)
        } else {
            Vec::new()
        },
        blending: asked(SectionName::Blending) && !(args.no_blending || only_other),
        scene_shadows: args.scene_shadows_only
            || (asked(SectionName::SceneShadows) && !(args.no_scene_shadows || only_other)),
        frame_features: args.frame_features_only
            || (asked(SectionName::FrameFeatures) && !(args.no_frame_features || only_other)),
        silhouettes: args.silhouettes_only
            || (asked(SectionName::Silhouettes) && !(args.no_silhouettes || only_other)),
        frame_costs: args.frame_costs_only
            || (asked(SectionName::FrameCosts) && !(args.no_frame_costs || only_other)),
    }
}

/// Which sections `sections` runs and why the others are left out.
pub(super) fn sections_record(args: &BenchArgs, sections: &SweepSections) -> SectionsRun {
    SectionChoice::of(args).record(|s| match s {
        SectionName::Main => !sections.jobs.is_empty(),
        SectionName::Stability => !sections.cases.is_empty(),
        SectionName::Shading => sections.shading.is_some(),
        SectionName::Lod => sections.lod,
        SectionName::Edits => !sections.edit_sizes.is_empty(),
        SectionName::Blending => sections.blending,
        SectionName::SceneShadows => sections.scene_shadows,
        SectionName::FrameFeatures => sections.frame_features,
        SectionName::Silhouettes => sections.silhouettes,
        SectionName::FrameCosts => sections.frame_costs,
    })
}

/// The terrain-edit section's field sides: --edit-sizes, else 1024 and 4096 (quick: 256 and 1024).
fn edit_sizes(args: &BenchArgs, cfg: &SweepConfig) -> Vec<u32> {
    if !args.edit_sizes.is_empty() {
        args.edit_sizes.clone()
    } else if cfg.quick {
        vec![256, 1024]
    } else {
        vec![1024, 4096]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn choice(listed: &[SectionName], narrowing: &[&'static str]) -> SectionChoice {
        SectionChoice {
            listed: listed.to_vec(),
            narrowing: narrowing.to_vec(),
        }
    }

    #[test]
    fn narrowing_flags_keep_only_the_sections_they_narrow() {
        let c = choice(&[], &["--methods", "--sizes"]);
        assert_eq!(c.left_out(SectionName::Main), None);
        assert_eq!(c.left_out(SectionName::Stability), None);
        assert_eq!(c.left_out(SectionName::Blending), None);
        let why = c.left_out(SectionName::FrameCosts).expect("left out");
        assert!(why.contains("--methods, --sizes"), "{why}");
        let all = choice(&[], &[]);
        assert!(SectionName::ALL.iter().all(|&s| all.left_out(s).is_none()));
    }

    #[test]
    fn listed_sections_run_whatever_narrows_the_sweep() {
        let c = choice(&[SectionName::Main, SectionName::Edits], &["--methods"]);
        assert_eq!(c.left_out(SectionName::Edits), None);
        assert!(c
            .left_out(SectionName::Stability)
            .is_some_and(|w| w.contains("--sections main,edits")));
        let record = c.record(|s| s == SectionName::Main);
        assert_eq!(record.ran, ["main"]);
        assert_eq!(record.skipped.len(), 9);
        assert!(
            record.skipped[3].why.contains("--no-X"),
            "edits was asked for"
        );
    }
}
