//! `hostctl` binary: parses the command line, opens the serial link and
//! hands over to the library.

use std::io::IsTerminal;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use hostctl::{link, Cli, Style};

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => match hostctl::usage_error_json(&e, std::env::args_os()) {
            // `--json` promises a last JSON line and status 1 for every failure.
            Some(line) => {
                println!("{line}");
                let _ = e.print();
                return ExitCode::FAILURE;
            }
            None => e.exit(),
        },
    };
    // Ctrl-C stops a script after drawing its view once more, and a watch after its
    // round (see `interrupt`); other commands keep the default: they end at once, closing
    // the port.
    if matches!(
        cli.command,
        hostctl::Command::Run(_) | hostctl::Command::Watch(_)
    ) {
        hostctl::interrupt::install();
    }
    let style = Style {
        json: cli.json,
        in_place: std::io::stdout().is_terminal(),
        width: hostctl::term::stdout_width,
    };
    let settle = Duration::from_millis(cli.settle_ms);
    // The settle is waited here, in the twin's emulated time when the port is a twin's.
    let open = |path: &str| {
        let link = link::open_serial(path, Duration::ZERO)?;
        // Ctrl-C during a long settle stops a script before it starts.
        let mut clock = hostctl::twin::clock_for(path);
        hostctl::cmd::run::sleep_unless_interrupted(clock.as_mut(), settle);
        Ok(link)
    };
    let env = std::env::var("BLODWEN_PORT").ok();
    let mut stdout = std::io::stdout().lock();
    let twin = || hostctl::twin::join_or_start(&mut |note| eprintln!("{note}"));
    match hostctl::run_with(&cli, env, twin, open, style, &mut stdout) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            hostctl::exit_status(&e)
        }
    }
}
