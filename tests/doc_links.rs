//! Every link between the project's Markdown files lands: the file exists, and a `#anchor` names a
//! heading of it, as GitHub makes anchors (lowercase, punctuation dropped, spaces to hyphens,
//! repeats numbered).

use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// GitHub's anchor for a heading's text.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a Markdown file's headings (outside code blocks).
fn anchors(text: &str) -> HashSet<String> {
    let mut seen = HashSet::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced || !line.starts_with('#') {
            continue;
        }
        let base = anchor(line.trim_start_matches('#'));
        let mut name = base.clone();
        let mut k = 1;
        while seen.contains(&name) {
            name = format!("{base}-{k}");
            k += 1;
        }
        seen.insert(name);
    }
    seen
}

/// Every `](target)` of a Markdown file outside code blocks, with its line number.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut fenced = false;
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            out.push((n + 1, after[..end].to_owned()));
            rest = &after[end..];
        }
    }
    out
}

fn markdown_files(root: &Path) -> Vec<PathBuf> {
    // src/guide.md is the crate's rustdoc guide: its links are rustdoc's, checked by `cargo doc`.
    let mut files = vec![root.join("README.md")];
    let entries = std::fs::read_dir(root.join("docs")).expect("docs/");
    files.extend(
        entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|x| x == "md")),
    );
    files.sort();
    files
}

#[test]
fn every_link_between_the_docs_lands() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut broken = Vec::new();
    for file in markdown_files(root) {
        let text = std::fs::read_to_string(&file).expect("readable");
        for (line, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (path, fragment) = match target.split_once('#') {
                Some((p, f)) => (p, Some(f)),
                None => (target.as_str(), None),
            };
            let linked = if path.is_empty() {
                file.clone()
            } else {
                file.parent().expect("in a folder").join(path)
            };
            let place = format!("{}:{line}: {target}", file.display());
            if !linked.exists() {
                broken.push(format!("{place} (no such file)"));
                continue;
            }
            let Some(fragment) = fragment else { continue };
            if linked.extension().is_some_and(|x| x == "md") {
                let linked_text = std::fs::read_to_string(&linked).expect("readable");
                if !anchors(&linked_text).contains(fragment) {
                    broken.push(format!("{place} (no such heading)"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn anchors_follow_github() {
    assert_eq!(
        anchor(" Prism shells: `--silhouettes shells`"),
        "prism-shells---silhouettes-shells"
    );
    assert_eq!(
        anchor(" Mesa 22.3.6 against 25.0.7"),
        "mesa-2236-against-2507"
    );
    let twice = anchors("# A\n## A\n```\n# not a heading\n```\n");
    assert!(twice.contains("a") && twice.contains("a-1") && !twice.contains("not-a-heading"));
}
