//! `hostctl` binary: parses the command line, opens the serial link and
//! hands over to the library.

use std::io::IsTerminal;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use hostctl::{link, Cli, Style};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let style = Style {
        json: cli.json,
        in_place: std::io::stdout().is_terminal(),
    };
    let settle = Duration::from_millis(cli.settle_ms);
    let open = |path: &str| link::open_serial(path, settle);
    let env = std::env::var("BLODWEN_PORT").ok();
    let mut stdout = std::io::stdout().lock();
    match hostctl::run(&cli, env, open, style, &mut stdout) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
