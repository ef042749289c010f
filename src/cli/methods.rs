//! `relief methods`: the displacement methods as a table (id, method, what it reads besides the
//! heights, default budget, source), or as JSON with each method's needs and default budget.

use clap::Args;
use relief::method::{Budget, Leaf, Method, MethodInfo};

#[derive(Args)]
pub struct MethodsArgs {
    /// Print a JSON list of {id, name, paper, needs, default_budget, fixed_step, leaf_choice}.
    #[arg(long)]
    json: bool,
}

/// A budget as the table says it: "32 steps", "16 + 5", "256, exact leaf, grows with the ray".
fn budget_text(info: &MethodInfo) -> String {
    let Budget {
        max_steps,
        refine_steps,
        leaf,
        extent_limit,
    } = info.default_budget;
    let mut text = match (refine_steps, max_steps) {
        (0, 1) => "1 step".to_owned(),
        (0, n) => format!("{n} steps"),
        (r, n) => format!("{n} + {r}"),
    };
    if info.leaf_choice && leaf == Leaf::Exact {
        text.push_str(", exact leaf");
    }
    if extent_limit > 0 {
        text.push_str(&format!(", + texels crossed up to {extent_limit}"));
    }
    text
}

fn reads_text(info: &MethodInfo) -> String {
    if info.needs.is_empty() {
        return "nothing".to_owned();
    }
    let names: Vec<&str> = info.needs.iter().map(|k| k.name()).collect();
    names.join(", ")
}

pub fn run(args: &MethodsArgs) -> anyhow::Result<()> {
    if args.json {
        let list: Vec<_> = Method::all()
            .map(|m| {
                let i = m.info();
                serde_json::json!({
                    "id": i.id,
                    "name": i.name,
                    "paper": i.paper,
                    "needs": i.needs,
                    "default_budget": i.default_budget,
                    "fixed_step": i.fixed_step,
                    "leaf_choice": i.leaf_choice,
                })
            })
            .collect();
        println!("{}", serde_json::to_string(&list)?);
        return Ok(());
    }
    let rows: Vec<[String; 5]> = Method::all()
        .map(|m| {
            let i = m.info();
            [
                i.id.to_owned(),
                i.name.to_owned(),
                reads_text(i),
                budget_text(i),
                i.paper.to_owned(),
            ]
        })
        .collect();
    let header = [
        "id",
        "method",
        "reads besides the heights",
        "default budget",
        "source",
    ];
    let mut widths = header.map(str::len);
    for row in &rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |cells: [&str; 5]| {
        let padded: Vec<String> = cells
            .iter()
            .zip(widths)
            .map(|(c, w)| format!("{c:<w$}"))
            .collect();
        println!("{}", padded.join("  ").trim_end());
    };
    line(header);
    for row in &rows {
        line([&row[0], &row[1], &row[2], &row[3], &row[4]]);
    }
    Ok(())
}
