//! A comparison as text: the terminal's aligned table and the same content as Markdown.

use std::fmt::Write as _;

use super::{rank_devices, CellComparison, Comparison, RatioInterval, Side, CONFIDENCE};

/// A titled table of text cells.
struct Table {
    headers: Vec<&'static str>,
    rows: Vec<Vec<String>>,
}

/// What a report is made of, rendered one way for the terminal and one for Markdown.
enum Block {
    Heading(String),
    Line(String),
    Table(Table),
}

/// The comparison for a terminal: aligned columns.
pub fn terminal_report(c: &Comparison) -> String {
    let mut out = String::new();
    for block in blocks(c) {
        match block {
            Block::Heading(text) => {
                let _ = writeln!(out, "\n{text}");
            }
            Block::Line(text) => {
                let _ = writeln!(out, "{text}");
            }
            Block::Table(t) => out.push_str(&aligned(&t)),
        }
    }
    out
}

/// The comparison as a Markdown page.
pub fn markdown_report(c: &Comparison) -> String {
    let mut out = String::from("# relief bench compare\n\n");
    for block in blocks(c) {
        match block {
            Block::Heading(text) => {
                let _ = writeln!(out, "\n## {text}\n");
            }
            Block::Line(text) => {
                let _ = writeln!(out, "{text}\n");
            }
            Block::Table(t) => {
                let _ = writeln!(out, "| {} |", t.headers.join(" | "));
                let _ = writeln!(out, "|{}", "---|".repeat(t.headers.len()));
                for row in &t.rows {
                    let cells: Vec<String> = row.iter().map(|c| c.replace('|', "\\|")).collect();
                    let _ = writeln!(out, "| {} |", cells.join(" | "));
                }
                out.push('\n');
            }
        }
    }
    out
}

fn aligned(t: &Table) -> String {
    let mut widths: Vec<usize> = t.headers.iter().map(|h| h.chars().count()).collect();
    for row in &t.rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |cells: &mut dyn Iterator<Item = &str>| {
        let padded: Vec<String> = cells
            .zip(&widths)
            .map(|(c, w)| format!("{c:<w$}"))
            .collect();
        padded.join("  ").trim_end().to_owned() + "\n"
    };
    let mut out = line(&mut t.headers.iter().copied());
    for row in &t.rows {
        out.push_str(&line(&mut row.iter().map(String::as_str)));
    }
    out
}

fn describe(side: &Side) -> String {
    let dirty = if side.relief.dirty { " (dirty)" } else { "" };
    let short = side.relief.commit.get(..10).unwrap_or(&side.relief.commit);
    format!(
        "{} ({}), relief {} at {short}{dirty}, {}",
        side.device.name, side.device.driver, side.relief.version, side.date
    )
}

fn blocks(c: &Comparison) -> Vec<Block> {
    let mut blocks = vec![
        Block::Line(format!("BASE: {}", describe(&c.base))),
        Block::Line(format!("NEW:  {}", describe(&c.new))),
    ];
    for o in &c.option_changes {
        blocks.push(Block::Line(format!(
            "option {}: {} -> {}",
            o.name, o.base, o.new
        )));
    }
    if !c.same_device {
        blocks.push(Block::Heading(
            "Different devices: each method's devices ranked (no verdicts)".into(),
        ));
        blocks.push(Block::Table(device_table(c)));
    } else {
        blocks.push(Block::Heading(format!(
            "Methods: median NEW/BASE over their cells, {:.0}% interval",
            100.0 * CONFIDENCE
        )));
        blocks.push(Block::Table(method_table(c)));
    }
    blocks.push(Block::Heading(format!(
        "Cells: NEW/BASE of the median GPU frame, {:.0}% interval",
        100.0 * CONFIDENCE
    )));
    blocks.push(Block::Table(cell_table(c)));
    let few = |i: &RatioInterval| !i.full_coverage;
    let methods_few = c.same_device && c.methods.iter().any(|m| few(&m.interval));
    if methods_few || c.cells.iter().any(|x| x.interval.as_ref().is_some_and(few)) {
        blocks.push(Block::Line(format!(
            "* fewer than 6 frames on a side (or cells, for a method): the interval is their whole \
             range and covers less than {:.0}%; time more frames (--frames) for a firmer verdict",
            100.0 * CONFIDENCE
        )));
    }
    if c.same_device && c.alone() > 0 {
        blocks.push(Block::Line(
            "alone: the cell's own interval is beyond the band but its method did not move; on a \
             shared machine one cell's frames can all fall in a moment of contention, so such a \
             cell is not counted as a change"
                .into(),
        ));
    }
    blocks.extend(one_sided("Only in BASE", &c.only_base));
    blocks.extend(one_sided("Only in NEW", &c.only_new));
    blocks.push(Block::Line(summary(c)));
    blocks
}

/// One line of totals.
pub(super) fn summary(c: &Comparison) -> String {
    let [faster, slower, within] = c.counts();
    let sides = format!(
        "{} only in BASE, {} only in NEW",
        c.only_base.len(),
        c.only_new.len()
    );
    if c.same_device {
        format!(
            "{} cells: {slower} slower, {faster} faster, {within} within noise ({} of them beyond \
             the band alone) (band +-{:.0}%); {sides}",
            c.cells.len(),
            c.alone(),
            100.0 * c.min_effect
        )
    } else {
        format!("{} cells on two devices; {sides}", c.cells.len())
    }
}

fn cell_table(c: &Comparison) -> Table {
    let mut headers = vec![
        "cell",
        "BASE ms",
        "NEW ms",
        "NEW/BASE",
        "interval",
        "frames",
        "error change",
    ];
    if c.same_device {
        headers.push("verdict");
    }
    let rows = c
        .cells
        .iter()
        .map(|cell| {
            let mut row = vec![
                cell.key.to_string(),
                format!("{:.4}", cell.base_ms),
                format!("{:.4}", cell.new_ms),
                ratio_text(cell),
                interval_text(cell),
                format!("{}/{}", cell.frames[0], cell.frames[1]),
                error_text(cell),
            ];
            if c.same_device {
                row.push(if cell.alone() {
                    format!("{} ({} alone)", cell.verdict, cell.own)
                } else {
                    cell.verdict.to_string()
                });
            }
            row
        })
        .collect();
    Table { headers, rows }
}

fn method_table(c: &Comparison) -> Table {
    let rows = c
        .methods
        .iter()
        .map(|m| {
            vec![
                m.method.clone(),
                m.cells.to_string(),
                format!("{:.3}x", m.interval.ratio),
                bounds(&m.interval),
                m.verdict.to_string(),
            ]
        })
        .collect();
    Table {
        headers: vec!["method", "cells", "NEW/BASE", "interval", "verdict"],
        rows,
    }
}

fn ratio_text(cell: &CellComparison) -> String {
    cell.interval
        .map_or("-".into(), |i| format!("{:.3}x", i.ratio))
}

fn interval_text(cell: &CellComparison) -> String {
    cell.interval.as_ref().map_or("no time".into(), bounds)
}

fn bounds(i: &RatioInterval) -> String {
    let mark = if i.full_coverage { "" } else { "*" };
    format!("[{:.3}, {:.3}]{mark}", i.low, i.high)
}

fn error_text(cell: &CellComparison) -> String {
    let change = cell.error_change();
    if change == 0.0 {
        "same".into()
    } else {
        format!(
            "{change:+.4} tx ({:.4} -> {:.4})",
            cell.error[0], cell.error[1]
        )
    }
}

fn device_table(c: &Comparison) -> Table {
    let rows = rank_devices(&c.cells)
        .into_iter()
        .map(|r| {
            let names = [&c.base.device.name, &c.new.device.name];
            let first = r.fastest();
            vec![
                r.method.clone(),
                r.cells.to_string(),
                format!("{:.4}", r.ms[0]),
                format!("{:.4}", r.ms[1]),
                format!("{:.3}x", r.ratio()),
                format!("{:.4}", r.error[0]),
                format!("{:.4}", r.error[1]),
                format!("1. {}, 2. {}", names[first], names[1 - first]),
            ]
        })
        .collect();
    Table {
        headers: vec![
            "method",
            "cells",
            "BASE ms (geo mean)",
            "NEW ms",
            "NEW/BASE",
            "BASE error tx",
            "NEW error tx",
            "ranking",
        ],
        rows,
    }
}

fn one_sided(title: &str, keys: &[super::CellKey]) -> Vec<Block> {
    if keys.is_empty() {
        return Vec::new();
    }
    let mut blocks = vec![Block::Heading(format!("{title}: {} cells", keys.len()))];
    blocks.extend(keys.iter().map(|k| Block::Line(format!("  {k}"))));
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::compare::compare;
    use crate::bench::results_fixture::{device, results, run};

    #[test]
    fn reports_show_every_cell_its_verdict_and_the_one_sided_cells() {
        let base = results(
            device("gpu"),
            vec![
                run("pom", 30.0, &[1.0, 1.01, 0.99], 0.1),
                run("pom", 10.0, &[1.0], 0.1),
            ],
        );
        let new = results(
            device("gpu"),
            vec![run("pom", 30.0, &[2.0, 2.02, 1.98], 0.1)],
        );
        let c = compare(&base, &new, 0.05);
        for text in [terminal_report(&c), markdown_report(&c)] {
            assert!(
                text.contains("error_vs_time pom fbm 64x64 d0.1 30/30deg"),
                "{text}"
            );
            assert!(text.contains("2.000x") && text.contains("slower"), "{text}");
            assert!(text.contains("Only in BASE: 1 cells"), "{text}");
            assert!(text.contains("10/30deg"), "{text}");
            assert!(
                text.contains("]*") && text.contains("fewer than 6 frames"),
                "{text}"
            );
            assert!(
                text.contains("1 cells: 1 slower, 0 faster, 0 within noise"),
                "{text}"
            );
            assert!(text.contains("Methods: median NEW/BASE"), "{text}");
        }
        assert!(markdown_report(&c).contains("| cell | BASE ms |"));
    }

    #[test]
    fn different_devices_get_a_ranking_and_no_verdicts() {
        let base = results(device("laptop"), vec![run("pom", 30.0, &[2.0], 0.1)]);
        let new = results(device("desktop"), vec![run("pom", 30.0, &[1.0], 0.1)]);
        let text = terminal_report(&compare(&base, &new, 0.05));
        assert!(text.contains("Different devices"), "{text}");
        assert!(text.contains("1. desktop, 2. laptop"), "{text}");
        assert!(
            !text.contains("  verdict") && !text.contains("within noise"),
            "{text}"
        );
    }
}
