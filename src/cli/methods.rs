//! `relief methods`: the displacement methods, one id per line, or JSON with names and papers.

use clap::Args;
use relief::method::Method;

#[derive(Args)]
pub struct MethodsArgs {
    /// Print a JSON list of {id, name, paper, needs}.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &MethodsArgs) -> anyhow::Result<()> {
    if args.json {
        let list: Vec<_> = Method::all()
            .map(|m| {
                let i = m.info();
                serde_json::json!({ "id": i.id, "name": i.name, "paper": i.paper, "needs": i.needs })
            })
            .collect();
        println!("{}", serde_json::to_string(&list)?);
    } else {
        for m in Method::all() {
            println!("{}", m.id());
        }
    }
    Ok(())
}
