//! `programmer-sim`: serves an emulated STK500 v1 programmer on a new pseudo-terminal.
//!
//! Prints the terminal's path as the first line of standard output, serves one avrdude
//! session, then writes `flash.bin`, `eeprom.bin` and `log.json` to `--out`.

use clap::{Parser, ValueEnum};
use nix::sys::signal::{sigaction, SaFlags, SigAction, SigHandler, SigSet, Signal};
use programmer_sim::{output, pty, serve, Mode, Programmer, SimError};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

static STOP: AtomicBool = AtomicBool::new(false);

/// Which programmer to play.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum ModeArg {
    /// The Uno's serial bootloader, as `avrdude -c arduino` expects (the master board).
    Bootloader,
    /// An ArduinoISP-style ICSP programmer, as `avrdude -c stk500v1` expects (slave boards).
    Isp,
}

/// Emulated STK500 v1 programmer (ATmega328P target) on a pseudo-terminal.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    /// Directory for flash.bin, eeprom.bin and log.json (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Programmer to play.
    #[arg(long, value_enum, default_value = "isp")]
    mode: ModeArg,
    /// Seconds without traffic after which the session ends and the images are saved.
    #[arg(long, default_value_t = 30)]
    idle_timeout: u64,
}

extern "C" fn request_stop(_: nix::libc::c_int) {
    STOP.store(true, Ordering::SeqCst);
}

fn install_stop_handler() -> Result<(), SimError> {
    let action = SigAction::new(
        SigHandler::Handler(request_stop),
        SaFlags::empty(),
        SigSet::empty(),
    );
    for sig in [Signal::SIGTERM, Signal::SIGINT] {
        // SAFETY: the handler only stores to an atomic, which is async-signal-safe, and no
        // other code in this process installs handlers for these signals.
        unsafe { sigaction(sig, &action) }.map_err(SimError::Signal)?;
    }
    Ok(())
}

fn run(args: Args) -> Result<(), SimError> {
    install_stop_handler()?;
    let mode = match args.mode {
        ModeArg::Bootloader => Mode::Bootloader,
        ModeArg::Isp => Mode::Isp,
    };
    let mut port = pty::open_raw()?;
    {
        let mut stdout = std::io::stdout().lock();
        writeln!(stdout, "{}", port.path.display()).map_err(SimError::PtyIo)?;
        stdout.flush().map_err(SimError::PtyIo)?;
    }
    let mut prog = Programmer::new(mode);
    let idle = Duration::from_secs(args.idle_timeout);
    let end = serve(&mut port.master, &mut prog, idle, &STOP)?;
    output::save(&args.out, &prog, end)?;
    let r = prog.record();
    eprintln!(
        "programmer-sim: {} ({}): {} flash and {} EEPROM bytes written, {} refusals; saved to {}",
        end.name(),
        mode.name(),
        r.bytes_written(programmer_sim::Memory::Flash),
        r.bytes_written(programmer_sim::Memory::Eeprom),
        r.refusals.len(),
        args.out.display()
    );
    Ok(())
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("programmer-sim: {e}");
            ExitCode::FAILURE
        }
    }
}
