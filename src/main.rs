//! The `relief` command-line tool: render, maps, devices.

mod cli;

fn main() -> std::process::ExitCode {
    cli::run()
}
