//! The `eapbd` command line: simulate scenes, render them headless, benchmark the solvers.

mod cli;

use clap::Parser;

fn main() -> anyhow::Result<()> {
    let args = cli::Cli::parse();
    match args.command {
        cli::Command::Simulate(a) => cli::simulate::run(&a),
        cli::Command::Render(a) => cli::render::run(&a),
        cli::Command::Report(a) => cli::report::run(&a),
        cli::Command::Bench(a) => cli::bench::run(&a),
    }
}
