//! `vcuts`: precomputed visibility-cut rendering from the command line. Run with no arguments
//! for help.

use clap::Parser;

fn main() {
    vcuts::quiet_on_broken_pipe();
    let cli = vcuts::Cli::parse();
    vcuts::exit_on_error(cli.global.init().and_then(|()| vcuts::run(cli.command)));
}
