//! `vcuts`: precomputed visibility-cut rendering from the command line. Run with no arguments
//! for help.

use clap::Parser;

/// Precomputed visibility-cut rendering: photo-real lighting of dynamic scenes under
/// environment light, objects moved and materials edited live.
#[derive(Parser)]
#[command(name = "vcuts", version, arg_required_else_help = true)]
struct Cli {
    #[command(flatten)]
    global: vcuts::GlobalArgs,
    #[command(subcommand)]
    command: vcuts::Command,
}

fn main() {
    vcuts::quiet_on_broken_pipe();
    let cli = Cli::parse();
    vcuts::exit_on_error(cli.global.init().and_then(|()| vcuts::run(cli.command)));
}
