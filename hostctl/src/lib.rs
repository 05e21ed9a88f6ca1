//! `hostctl`: the host-side command-line tool of the Blodwen rover.
//!
//! It sits on the PC end of the master's USB-serial link (or the twin's
//! pty) and speaks the PC–master protocol of reference §4 with the frame
//! codec, register tables and value mapping from `shared`, so it uses the
//! same definitions as both firmwares. Subcommands write one register, read
//! one register, configure a read set, watch a read set live, and run a script
//! of the original PC library's calls over one connection ([`cmd::run`]). With
//! no port given it uses the rover twin, joining or starting it ([`twin`]).
//!
//! The flow is the same for every subcommand: the command line is checked
//! and turned into frames first ([`plan`]), so bad input is refused before
//! the port is even opened; then the link is opened, the `Ready` banner
//! awaited, and the frames exchanged ([`execute`]).
//!
//! Read set 7 is reserved for `hostctl read`, which overwrites it on every
//! call.

pub mod banner;
pub mod cli;
pub mod cmd;
pub mod error;
pub mod exception;
#[cfg(test)]
mod fake;
pub mod interrupt;
pub mod json;
pub mod link;
pub mod meaning;
pub mod port;
pub mod resolve;
pub mod suggest;
pub mod table;
pub mod term;
#[cfg(test)]
mod tests;
pub mod twin;

use std::io::Write;

pub use cli::{Cli, Command};
pub use error::HostError;
use link::Link;
use port::Port;
use table::Screen;

/// A checked command, with its frames built.
#[derive(Debug)]
pub enum Plan {
    /// See [`cmd::write`].
    Write(cmd::write::Plan),
    /// See [`cmd::read`].
    Read(cmd::read::Plan),
    /// See [`cmd::readset`].
    Readset(cmd::readset::Plan),
    /// See [`cmd::watch`].
    Watch(cmd::watch::Plan),
    /// See [`cmd::run`].
    Run(cmd::run::Plan),
}

/// Checks a command line and builds its frames. Nothing is sent.
pub fn plan(command: &Command) -> Result<Plan, HostError> {
    Ok(match command {
        Command::Write(a) => Plan::Write(cmd::write::plan(a)?),
        Command::Read(a) => Plan::Read(cmd::read::plan(a)?),
        Command::Readset(a) => Plan::Readset(cmd::readset::plan(a)?),
        Command::Watch(a) => Plan::Watch(cmd::watch::plan(a)?),
        Command::Run(a) => Plan::Run(cmd::run::plan(a)?),
    })
}

/// How results are printed.
#[derive(Debug, Clone, Copy)]
pub struct Style {
    /// JSON lines instead of text.
    pub json: bool,
    /// Redraw `watch` tables in place (stdout is a terminal).
    pub in_place: bool,
    /// The terminal's width, asked at each redraw ([`term::stdout_width`]).
    pub width: fn() -> Option<usize>,
}

/// Runs a plan over a connected link, writing results to `out`.
pub fn execute<P: Port>(
    plan: &Plan,
    link: &mut Link<P>,
    style: Style,
    out: &mut dyn Write,
) -> Result<(), HostError> {
    execute_with_clock(plan, link, style, out, &mut cmd::run::WallClock::new())
}

/// [`execute`], with `run`'s pauses and live views timed by `clock` (a twin's emulated
/// time, see [`twin::TwinClock`]).
pub fn execute_with_clock<P: Port>(
    plan: &Plan,
    link: &mut Link<P>,
    style: Style,
    out: &mut dyn Write,
    clock: &mut dyn cmd::run::Clock,
) -> Result<(), HostError> {
    let text = match plan {
        Plan::Write(p) => cmd::write::run(p, link, style.json)?,
        Plan::Read(p) => cmd::read::run(p, link, style.json)?,
        Plan::Readset(p) => cmd::readset::run(p, link, style.json)?,
        Plan::Run(p) => {
            let mut output = cmd::run::Output {
                out,
                in_place: style.in_place && !style.json,
                json: style.json,
                width: style.width,
            };
            return cmd::run::run(p, link, clock, &mut output);
        }
        Plan::Watch(p) => {
            let mut screen = Screen::new(style.in_place && !style.json, style.width);
            return cmd::watch::run(p, link, clock, &mut |round| {
                let text = if style.json {
                    let mut lines = cmd::watch::json_lines(round).join("\n");
                    lines.push('\n');
                    lines
                } else {
                    screen.frame(&cmd::watch::table_lines(round))
                };
                out.write_all(text.as_bytes()).map_err(HostError::Output)?;
                out.flush().map_err(HostError::Output)?;
                Ok(())
            });
        }
    };
    writeln!(out, "{text}").map_err(HostError::Output)?;
    Ok(())
}

/// Picks the port: `--port`, else `BLODWEN_PORT` (passed in as `env`).
pub fn port_path(flag: Option<&str>, env: Option<String>) -> Result<String, HostError> {
    match flag {
        Some("") => Err(HostError::EmptyPort),
        Some(p) => Ok(p.to_owned()),
        None => env.filter(|p| !p.is_empty()).ok_or(HostError::NoPort),
    }
}

/// The whole command: check the input, pick the port, open it with `open`
/// (which also waits for the banner), then run. Bad input returns before
/// `open` is called.
pub fn run<P: Port>(
    cli: &Cli,
    env_port: Option<String>,
    open: impl FnOnce(&str) -> Result<Link<P>, HostError>,
    style: Style,
    out: &mut dyn Write,
) -> Result<(), HostError> {
    run_with(cli, env_port, || Err(HostError::NoPort), open, style, out)
}

/// The exit status for a failure: 3 for a script that ran to its end with the rover in
/// exception ([`HostError::EndedInException`]), so a program can tell it from a script
/// that could not run; 130 for a script stopped by Ctrl-C and 143 by SIGTERM (as a shell
/// reports a program that signal ended); 1 for anything else (clap's usage errors are 2).
pub fn exit_status(error: &HostError) -> std::process::ExitCode {
    std::process::ExitCode::from(exit_code(error))
}

/// [`exit_status`]'s number.
pub fn exit_code(error: &HostError) -> u8 {
    match error {
        HostError::EndedInException { .. } | HostError::WatchEndedUnread { .. } => 3,
        HostError::Interrupted { signal, .. } => interrupt::exit_code(*signal),
        _ => 1,
    }
}

/// [`run`], with `fallback` naming the port when neither `--port` nor `BLODWEN_PORT` does
/// (the binary joins or starts the twin there, see [`twin`]). It is called only after the
/// input has been checked.
pub fn run_with<P: Port>(
    cli: &Cli,
    env_port: Option<String>,
    fallback: impl FnOnce() -> Result<String, HostError>,
    open: impl FnOnce(&str) -> Result<Link<P>, HostError>,
    style: Style,
    out: &mut dyn Write,
) -> Result<(), HostError> {
    let result = (|| {
        let mut plan = plan(&cli.command)?;
        if let Plan::Run(run) = &mut plan {
            run.settled = std::time::Duration::from_millis(cli.settle_ms);
        }
        let path = match port_path(cli.port.as_deref(), env_port) {
            Err(HostError::NoPort) => fallback()?,
            other => other?,
        };
        let mut link = open(&path)?;
        execute_with_clock(
            &plan,
            &mut link,
            style,
            &mut *out,
            &mut *twin::clock_for(&path),
        )
    })();
    // A program reading the JSON lines learns of the failure there too, not only on stderr.
    // A failure to print it (stdout gone) must not hide the error itself.
    if let (true, Err(e)) = (style.json, &result) {
        let _ = writeln!(out, "{}", error_json(&cli.command, e));
    }
    result
}

/// A command line clap refused, as the JSON line `--json` promises for every failure:
/// `Some` when `args` (the whole command line) ask for JSON and `error` is a failure, not
/// a request for help or the version. The command is the first subcommand named, if any.
pub fn usage_error_json<I, T>(error: &clap::Error, args: I) -> Option<String>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString>,
{
    use clap::error::ErrorKind;
    if matches!(
        error.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        return None;
    }
    let args: Vec<String> = args
        .into_iter()
        .skip(1)
        .map(|a| a.into().to_string_lossy().into_owned())
        .take_while(|a| a != "--")
        .collect();
    if !args.iter().any(|a| a == "--json") {
        return None;
    }
    let cli = <Cli as clap::CommandFactory>::command();
    let command = args
        .iter()
        .find(|a| cli.find_subcommand(a.as_str()).is_some())
        .map_or("", String::as_str);
    // The error's paragraph (what is missing comes on the lines after its first), not
    // the usage after it.
    let rendered = error.render().to_string();
    let paragraph: Vec<&str> = rendered
        .lines()
        .take_while(|l| !l.trim().is_empty())
        .map(str::trim)
        .collect();
    let words = paragraph.join(" ");
    let words = words.strip_prefix("error: ").unwrap_or(&words);
    Some(
        json::Object::new()
            .str("command", command)
            .str("error", words)
            .finish(),
    )
}

/// A failed command as one JSON line: the command, the error's words and, for a script
/// line, its number and text.
pub(crate) fn error_json(command: &Command, error: &HostError) -> String {
    let object = json::Object::new()
        .str("command", command.name())
        .str("error", &error.to_string());
    match error {
        HostError::ScriptStep { line, text, .. } | HostError::ScriptLine { line, text, .. } => {
            object
                .int("line", i64::try_from(*line).unwrap_or(i64::MAX))
                .str("text", text)
        }
        // Which signal, and the line it stopped the script at.
        HostError::Interrupted { signal, line, .. } => {
            let object = object.str("interrupted", interrupt::name(*signal));
            match line {
                Some(line) => object.int("line", i64::try_from(*line).unwrap_or(i64::MAX)),
                None => object,
            }
        }
        // What held the rover stopped, one entry per board or group of boards.
        HostError::EndedInException { faults, .. } => object.raw(
            "faults",
            &json::array(faults.iter().map(|f| json::string(f))),
        ),
        _ => object,
    }
    .finish()
}
