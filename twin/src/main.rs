//! `twin`: the rover twin behind a pseudo-terminal.
//!
//! `twin [--link PATH] …` builds the emulated rover (the real master and slave images on one
//! I²C bus, with physics, temperature sensors and an RC receiver), prints the pty path on its
//! first line, and serves it paced to real time until interrupted (SIGINT, SIGTERM, SIGHUP),
//! `--seconds` of emulated time have passed, or (with `--idle-exit`) no program has had the
//! port open for a while; then it removes its link and control socket. Opening the port
//! resets the master, as the Uno's DTR auto-reset does, and so does closing it with HUPCL
//! set (the port's default: DTR drops); bytes not yet taken by the master die with the
//! reset. Faults are injected at start
//! (`--fault`) or while it runs (`twin inject CMD…`, over the control socket `<link>.ctl`).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use clap::{Parser, Subcommand};
use harness::Pty;
use twin::command::Command;
use twin::control::{self, ControlSocket};
use twin::serve::{Limits, Server, Stopped};
use twin::{paths, Config, Rover, TwinError};

/// Run the emulated Blodwen rover behind a serial port (pty), or steer a running one.
#[derive(Parser, Debug)]
#[command(version, args_conflicts_with_subcommands = true)]
struct Args {
    #[command(flatten)]
    run: RunArgs,
    #[command(subcommand)]
    sub: Option<Sub>,
}

#[derive(clap::Args, Debug)]
struct RunArgs {
    /// Keep a symlink to the pty at PATH (removed on exit); the control socket is PATH.ctl.
    #[arg(long, value_name = "PATH")]
    link: Option<PathBuf>,
    /// Control socket path [default: LINK.ctl, or one named after this process].
    #[arg(long, value_name = "PATH")]
    control: Option<PathBuf>,
    /// Directory holding master.elf, slave-drive.elf and slave-lift.elf
    /// [default: target/firmware of this workspace].
    #[arg(long, value_name = "DIR")]
    firmware_dir: Option<PathBuf>,
    /// Stop after this many seconds of emulated time [default: run until interrupted].
    #[arg(long, value_name = "S")]
    seconds: Option<f64>,
    /// Run as fast as the host allows instead of pacing to real time.
    #[arg(long)]
    unpaced: bool,
    /// Print the speed on stderr every SECS seconds (0: never): paced, the compute headroom
    /// over real time; unpaced, the speed it runs at.
    #[arg(long, value_name = "SECS", default_value_t = 0.0)]
    stats: f64,
    /// Exit after SECS seconds during which no program had the port open (0: never).
    #[arg(long, value_name = "SECS", default_value_t = 0.0)]
    idle_exit: f64,
    /// Turn the RC receiver on at start (it is off unless asked for).
    #[arg(long)]
    rc: bool,
    /// A fault to inject at start, as `twin inject` takes it (e.g. "stall 3 on"); repeatable.
    #[arg(long, value_name = "CMD")]
    fault: Vec<String>,
    /// The bus's lock-step quantum, µs of emulated time, 1..=50 (at most the physics slice:
    /// within a quantum a slave lags the master by up to the quantum).
    #[arg(long, value_name = "US", default_value_t = twin::DEFAULT_QUANTUM_US,
          value_parser = clap::value_parser!(u64).range(1..=50))]
    quantum_us: u64,
    /// Threads the chips run on, 1..=10 (1: all on one thread) [default: the available
    /// parallelism, at most 4].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u8).range(1..=10))]
    threads: Option<u8>,
}

#[derive(Subcommand, Debug)]
enum Sub {
    /// Send one command (a fault, or a question) to a running twin and print its reply
    ///
    /// Commands (W: wheel 1..6; N: controller 1..9; I: temperature sensor, 0 ambient, 1..9):
    ///   stall W [drive|steer|lift] on|off   block a wheel's motor (its drive unless named)
    ///   cut N                               take controller N off the I2C bus
    ///   restore N                           put it back
    ///   reboot N                            reset controller N, as a brown-out does
    ///   spike W drive|steer|lift AMPS MS    a current spike (0 < AMPS <= 10.24, 0 < MS <= 60000)
    ///   sensor I remove|restore             take sensor I off the OneWire bus, or put it back
    ///   temp I CELSIUS                      set what sensor I measures (-55..125)
    ///   drop-serial N [to-master|to-host]   lose the next N bytes on the serial line (to the
    ///                                       master unless told)
    ///   drop-serial clear                   cancel the losses still pending
    ///   rc on|off                           switch the RC receiver on or off
    ///   rc CH US                            an RC channel's pulse (CH 0 drive, 1 steer, 2 mode;
    ///                                       500..2500 µs)
    ///   status                              the faults in force, each sensor, each wheel's state,
    ///                                       and each board's LEDs and bridges
    ///   time                                emulated µs since power-up
    ///   dtr low|high                        the host's DTR line, which a pty cannot carry
    #[command(verbatim_doc_comment)]
    Inject {
        /// The running twin's pty link [default: the one hostctl uses].
        #[arg(long, value_name = "PATH")]
        link: Option<PathBuf>,
        /// The running twin's control socket [default: LINK.ctl].
        #[arg(long, value_name = "PATH")]
        control: Option<PathBuf>,
        /// The command, e.g. `stall 3 on`.
        #[arg(required = true, num_args = 1.., allow_hyphen_values = true)]
        words: Vec<String>,
    },
}

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: nix::libc::c_int) {
    STOP.store(true, Ordering::SeqCst);
}

fn main() -> ExitCode {
    let args = Args::parse();
    let result = match args.sub {
        Some(Sub::Inject {
            link,
            control,
            words,
        }) => inject(link, control, &words.join(" ")),
        None => run(&args.run),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("twin: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `twin inject`: one command to a running twin.
fn inject(
    link: Option<PathBuf>,
    control: Option<PathBuf>,
    line: &str,
) -> Result<ExitCode, Box<dyn std::error::Error>> {
    // A refused command, here or by the twin, is told the same way: `twin: ` on stderr and
    // exit 2 (a failure to reach the twin is exit 1, from main).
    let refused = |why: &str| {
        eprintln!("twin: {why}");
        ExitCode::from(2)
    };
    // Check the command here too, so a typo is reported without a running twin.
    if let Err(e) = Command::parse(line) {
        return Ok(refused(&e.to_string()));
    }
    let socket =
        control.unwrap_or_else(|| paths::control_of(&link.unwrap_or_else(paths::default_link)));
    let reply = control::send(&socket, line)?;
    // The control socket marks a refusal with `error: `.
    Ok(match reply.strip_prefix("error: ") {
        Some(why) => refused(why),
        None => {
            println!("{reply}");
            ExitCode::SUCCESS
        }
    })
}

fn install_signals() -> Result<(), nix::Error> {
    use nix::sys::signal::{signal, SigHandler, Signal};
    for s in [Signal::SIGINT, Signal::SIGTERM, Signal::SIGHUP] {
        // SAFETY: the handler only stores to an atomic, which is async-signal-safe.
        unsafe { signal(s, SigHandler::Handler(on_signal)) }?;
    }
    Ok(())
}

fn control_path(args: &RunArgs) -> PathBuf {
    match (&args.control, &args.link) {
        (Some(c), _) => c.clone(),
        (None, Some(link)) => paths::control_of(link),
        (None, None) => paths::default_dir().join(format!("twin-{}.ctl", std::process::id())),
    }
}

/// Makes the link's directory if it is missing.
fn prepare_link(link: &Path) -> Result<(), TwinError> {
    match link.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) => std::fs::create_dir_all(dir).map_err(|source| TwinError::Io {
            what: "cannot create the directory of",
            path: link.to_path_buf(),
            source,
        }),
        None => Ok(()),
    }
}

fn seconds(s: f64) -> Option<Duration> {
    (s > 0.0 && s.is_finite()).then(|| Duration::from_secs_f64(s))
}

/// `twin`: build the rover and serve it behind the pty.
fn run(args: &RunArgs) -> Result<ExitCode, Box<dyn std::error::Error>> {
    install_signals()?;
    let config = Config {
        firmware_dir: args.firmware_dir.clone(),
        quantum_us: args.quantum_us,
        threads: args
            .threads
            .map_or_else(twin::default_threads, usize::from)
            .max(1),
        ..Config::default()
    };
    let mut rover = Rover::with_config(&config)?;
    for line in &args.fault {
        let report = Command::parse(line)?.apply(&mut rover)?;
        eprintln!("twin: {report}");
    }
    if args.rc {
        rover.set_rc(true);
    }
    // Bind the control socket first: it refuses to start a second twin on the same link.
    let socket = ControlSocket::bind(&control_path(args))?;
    let mut pty = Pty::open()?;
    if let Some(link) = &args.link {
        prepare_link(link)?;
        pty.link(link).map_err(|source| TwinError::Io {
            what: "cannot make the pty link",
            path: link.clone(),
            source,
        })?;
    }
    println!("{}", pty.path().display());
    std::io::stdout().flush()?;
    eprintln!(
        "twin: serving {} ({}control socket {}; {} thread{})",
        pty.path().display(),
        args.link
            .as_ref()
            .map(|l| format!("link {}, ", l.display()))
            .unwrap_or_default(),
        socket.path().display(),
        rover.threads(),
        if rover.threads() == 1 { "" } else { "s" }
    );

    let paced = !args.unpaced;
    let mut server = Server::new(rover, pty, Some(socket), paced);
    let limits = Limits {
        emulated: args.seconds.and_then(seconds),
        idle: seconds(args.idle_exit),
    };
    let stats = seconds(args.stats);
    let mut last = std::time::Instant::now();
    let stopped = server.serve(
        limits,
        &|| STOP.load(Ordering::SeqCst),
        &mut |rover, emulated, wall| {
            if stats.is_some_and(|every| last.elapsed() >= every) {
                last = std::time::Instant::now();
                report_speed(rover, emulated, wall, paced);
            }
        },
    )?;
    if stopped == Stopped::Idle {
        eprintln!(
            "twin: no program used the port for {} s; exiting",
            args.idle_exit
        );
    }
    if stats.is_some() {
        eprintln!("twin: final: {}", server.rover().speed().describe(paced));
    }
    Ok(ExitCode::SUCCESS)
}

fn report_speed(rover: &Rover, emulated: Duration, wall: Duration, paced: bool) {
    eprintln!(
        "twin: {:.1} s emulated in {:.1} s, {}",
        emulated.as_secs_f64(),
        wall.as_secs_f64(),
        rover.speed().describe(paced)
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn inject_help_lists_every_form_of_every_command_on_a_line_of_its_own() {
        let mut cli = Args::command();
        let help = cli
            .find_subcommand_mut("inject")
            .expect("the inject subcommand")
            .render_long_help()
            .to_string();
        let forms: Vec<&str> = twin::command::USAGES
            .iter()
            .flat_map(|u| u.split("   (").next().unwrap_or(u).split(", or "))
            .collect();
        assert_eq!(forms.len(), 14, "{forms:?}");
        for form in forms {
            assert!(
                help.lines().any(|l| l
                    .strip_prefix("  ")
                    .and_then(|l| l.strip_prefix(form))
                    .is_some_and(|rest| rest.starts_with("  "))),
                "no line for `{form}` in:\n{help}"
            );
        }
        let summary = cli.render_help().to_string();
        let inject = summary
            .lines()
            .find(|l| l.trim_start().starts_with("inject "))
            .expect("inject in the command list");
        assert!(inject.len() < 100, "{inject}");
    }
}
