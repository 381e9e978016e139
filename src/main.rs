//! The `eapbd` command line: the interactive viewer, simulate scenes, render them headless,
//! benchmark the solvers.

mod cli;

use clap::{CommandFactory, FromArgMatches, Parser};

fn main() -> anyhow::Result<()> {
    let matches = cli::Cli::command().get_matches_from(cli::scene_file::expand(std::env::args_os())?);
    let args = cli::Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    let sub = matches.subcommand().map(|(_, m)| m);
    let command = match args.command {
        Some(c) => c,
        // `eapbd` alone: the viewer on the main demo.
        None => {
            let (scene, substeps, iterations) = eapbd::scene::MAIN_DEMO;
            let (substeps, iterations) = (substeps.to_string(), iterations.to_string());
            let args = ["eapbd", "view", "--scene", scene, "--substeps", &substeps, "--iterations", &iterations];
            cli::Cli::try_parse_from(args)?
                .command
                .ok_or_else(|| anyhow::anyhow!("the default view command did not parse"))?
        }
    };
    match command {
        cli::Command::View(a) => {
            sub.map(|m| a.scene.save(m)).transpose()?;
            cli::view::run(&a)
        }
        cli::Command::Simulate(a) => {
            sub.map(|m| a.scene.save(m)).transpose()?;
            cli::simulate::run(&a)
        }
        cli::Command::Render(a) => {
            sub.map(|m| a.scene.save(m)).transpose()?;
            cli::render::run(&a)
        }
        cli::Command::Report(a) => cli::report::run(&a),
        cli::Command::Bench(a) => cli::bench::run(&a),
    }
}
