//! The `eapbd` command line: the interactive viewer, simulate scenes, render them headless,
//! benchmark the solvers.

mod cli;

use clap::Parser;

fn main() -> anyhow::Result<()> {
    let args = cli::Cli::parse();
    let command = match args.command {
        Some(c) => c,
        // `eapbd` alone: the viewer on the hanging cloth.
        None => cli::Cli::try_parse_from(["eapbd", "view", "--scene", "cloth"])?
            .command
            .ok_or_else(|| anyhow::anyhow!("the default view command did not parse"))?,
    };
    match command {
        cli::Command::View(a) => cli::view::run(&a),
        cli::Command::Simulate(a) => cli::simulate::run(&a),
        cli::Command::Render(a) => cli::render::run(&a),
        cli::Command::Report(a) => cli::report::run(&a),
        cli::Command::Bench(a) => cli::bench::run(&a),
    }
}
