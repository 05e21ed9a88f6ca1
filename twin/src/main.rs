//! `twin`: runs the rover's real firmware in the emulator behind a pseudo-terminal, so that
//! `hostctl`, or any program written for the real rover, opens it like the Uno's serial port.
//!
//! The first line of stdout is the pty path. The emulation is paced to real time (a program
//! on the other end sees real-time replies and timeouts); the twin reports its spare speed
//! as a ratio to real time.

use clap::Parser;
use harness::{Avr, HostEvent, Pty};
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Command line of the twin.
#[derive(Parser, Debug)]
#[command(version, about = "Run the emulated rover behind a serial port (pty)")]
struct Args {
    /// Keep a symlink to the pty at this path (removed on exit).
    #[arg(long)]
    link: Option<PathBuf>,
    /// Directory holding master.elf (default: target/firmware of this workspace).
    #[arg(long)]
    firmware_dir: Option<PathBuf>,
    /// Stop after this many seconds of emulated time (default: run until interrupted).
    #[arg(long)]
    seconds: Option<f64>,
    /// Run as fast as the host allows instead of pacing to real time.
    #[arg(long)]
    unpaced: bool,
    /// Print the speed ratio to real time on stderr every N seconds (0: never).
    #[arg(long, default_value_t = 0.0)]
    stats: f64,
}

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: nix::libc::c_int) {
    STOP.store(true, Ordering::SeqCst);
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("twin: {e}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> Result<(), Box<dyn std::error::Error>> {
    use nix::sys::signal::{signal, SigHandler, Signal};
    for s in [Signal::SIGINT, Signal::SIGTERM, Signal::SIGHUP] {
        // SAFETY: the handler only stores to an atomic, which is async-signal-safe.
        unsafe { signal(s, SigHandler::Handler(on_signal)) }?;
    }
    let mut master = match &args.firmware_dir {
        Some(dir) => Avr::load(&dir.join("master.elf"))?,
        None => Avr::firmware("master")?,
    };
    let mut pty = Pty::open()?;
    if let Some(link) = &args.link {
        pty.link(link)?;
    }
    println!("{}", pty.path().display());
    std::io::stdout().flush()?;

    const SLICE_US: u64 = 500;
    let wall_start = Instant::now();
    let emu_start = master.micros();
    let mut busy = Duration::ZERO;
    let mut last_stats = Instant::now();
    while !STOP.load(Ordering::SeqCst) {
        let t0 = Instant::now();
        if pty.host_event() == Some(HostEvent::Opened) {
            // The Uno resets when a program opens its port (DTR auto-reset).
            master.reset();
            master.uart_take();
        }
        pty.pump(&mut master)?;
        master.run_us(SLICE_US);
        pty.pump(&mut master)?;
        busy += t0.elapsed();
        let emu = Duration::from_micros(master.micros() - emu_start);
        if let Some(limit) = args.seconds {
            if emu.as_secs_f64() >= limit {
                break;
            }
        }
        if !args.unpaced {
            let wall = wall_start.elapsed();
            if emu > wall {
                std::thread::sleep(emu - wall);
            }
        }
        if args.stats > 0.0 && last_stats.elapsed().as_secs_f64() >= args.stats {
            last_stats = Instant::now();
            eprintln!(
                "twin: {:.1} s emulated, speed {:.2}x real time",
                emu.as_secs_f64(),
                emu.as_secs_f64() / busy.as_secs_f64().max(1e-9)
            );
        }
    }
    Ok(())
}
