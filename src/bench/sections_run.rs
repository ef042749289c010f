//! Which of the bench's sections a run measured, and why each of the others was left out, so
//! that a narrowed run says what it holds instead of leaving readers to infer it from what is
//! missing.

use serde::{Deserialize, Serialize};

/// The sections of one run.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SectionsRun {
    /// The sections measured, in the report's order.
    pub ran: Vec<String>,
    /// The sections left out, each with why.
    pub skipped: Vec<SkippedSection>,
}

/// A section a run left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SkippedSection {
    /// The section's name, as `--sections` takes it.
    pub section: String,
    /// Why, one line.
    pub why: String,
}

impl SectionsRun {
    /// The record as one Markdown paragraph for the report.
    pub fn line(&self) -> String {
        // Sections left out for one reason are named together, in order of first mention.
        let mut reasons: Vec<(&str, Vec<&str>)> = Vec::new();
        for s in &self.skipped {
            match reasons.iter_mut().find(|(why, _)| *why == s.why) {
                Some((_, names)) => names.push(&s.section),
                None => reasons.push((&s.why, vec![&s.section])),
            }
        }
        let skipped: Vec<String> = reasons
            .iter()
            .map(|(why, names)| format!("{} ({why})", names.join(", ")))
            .collect();
        let ran = if self.ran.is_empty() {
            "none".to_owned()
        } else {
            self.ran.join(", ")
        };
        if skipped.is_empty() {
            format!("Sections: {ran}.")
        } else {
            format!("Sections: {ran}; left out: {}.", skipped.join("; "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_names_what_ran_and_why_the_rest_did_not() {
        let run = SectionsRun {
            ran: vec!["main".into(), "stability".into()],
            skipped: vec![SkippedSection {
                section: "edits".into(),
                why: "--no-edits".into(),
            }],
        };
        assert_eq!(
            run.line(),
            "Sections: main, stability; left out: edits (--no-edits)."
        );
        assert_eq!(SectionsRun::default().line(), "Sections: none.");
        let skip = |section: &str, why: &str| SkippedSection {
            section: section.into(),
            why: why.into(),
        };
        let grouped = SectionsRun {
            ran: vec!["main".into()],
            skipped: vec![
                skip("lod", "narrowed"),
                skip("edits", "--no-edits"),
                skip("shading", "narrowed"),
            ],
        };
        assert_eq!(
            grouped.line(),
            "Sections: main; left out: lod, shading (narrowed); edits (--no-edits)."
        );
    }
}
