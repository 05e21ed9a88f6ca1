//! The command line: global options and one variant per subcommand.

use clap::{Parser, Subcommand};

use crate::cmd;

/// The longest `--settle-ms`: a minute, far beyond the slaves' reboot, so a typo cannot
/// hang hostctl.
pub const MAX_SETTLE_MS: u64 = 60_000;
/// The longest pause between two `watch` rounds: an hour, as for a script's `wait`.
pub const MAX_INTERVAL_MS: u64 = 3_600_000;

/// Talk to the Blodwen rover (or its twin) over the master's serial link.
///
/// Devices: 0 is the master, 1..9 the controllers (DS drive/steer boards
/// 1, 2, 4, 5, 7, 8; LL lift boards 3, 6, 9). Registers are named as in
/// docs/registers.md (case-insensitive, with or without the REG…_ prefix) or
/// given by number. Values are in engineering units.
#[derive(Debug, Parser)]
#[command(name = "hostctl", version)]
pub struct Cli {
    /// Serial device of the master, or a twin's pty [default: $BLODWEN_PORT, else the
    /// rover twin at $XDG_RUNTIME_DIR/blodwen-twin/port (/tmp/blodwen-twin/port), which
    /// hostctl joins if it runs and starts otherwise; it exits after 10 minutes unused].
    #[arg(long, global = true, value_name = "PATH")]
    pub port: Option<String>,

    /// Print one JSON object per line instead of text for people. A failure is a last
    /// line `{"command":…,"error":…}` (a script's also with its `line` and `text`; a run
    /// that ended with the rover stopped with its `faults`; one stopped by Ctrl-C or SIGTERM
    /// with `interrupted` and the `line`), as well as the error on stderr and exit status 1
    /// (3 for that run, 130 and 143 for those).
    #[arg(long, global = true)]
    pub json: bool,

    /// Milliseconds to wait after the master's `Ready` before the first frame,
    /// while the slaves it has just reset reboot (at most 60000).
    #[arg(
        long,
        global = true,
        value_name = "MS",
        default_value_t = 2000,
        value_parser = clap::value_parser!(u64).range(..=MAX_SETTLE_MS)
    )]
    pub settle_ms: u64,

    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands, one file each under `cmd/`.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Write one register: VALUE (engineering units) is mapped to its raw
    /// value and sent as one write frame; the master must answer 00.
    Write(cmd::write::Args),

    /// Read one register: configures read set 7 (reserved for hostctl's
    /// one-off reads) with that register, reads it and prints the value in
    /// units and raw.
    Read(cmd::read::Args),

    /// Configure a read set (0..7) with up to 24 registers; the master must
    /// answer with the count.
    ///
    /// The set is gone when this command ends: closing the port resets the master, which
    /// empties every read set (reference §4.1), as every command's opening does, so a
    /// later `hostctl watch --readset N` cannot use it. Give `watch` the registers itself
    /// (`hostctl watch --readset N REG...`), or use `run` for a sequence in one session.
    Readset(cmd::readset::Args),

    /// Poll a read set and show a table that refreshes in place (JSON lines
    /// with --json). Sets 0, 1 and 2 have standard contents when no
    /// registers are named.
    Watch(cmd::watch::Args),

    /// Run a script of rover commands in one session of the serial link
    ///
    /// Each opening of the port resets the master, so a sequence that must act on one boot
    /// belongs in one script.
    ///
    /// A line is one command; `#` starts a comment at a line's start or alone after a space
    /// (`drive all 100 # forward`; `say Wheel #1` prints `Wheel #1`):
    ///   reset                   the library's resetExceptions(): every fitted board leaves its
    ///                           exception (after the port opens, each is in its boot state)
    ///   calibrate               the library's calibrate(), every running board held stopped
    ///                           meanwhile: each steer and lift then holds where it stands on
    ///                           the new calibration, each drive aims for 0
    ///   write DEV REG VALUE     one register, VALUE in engineering units
    ///   drive W|all SPEED       a drive demand, ticks/s (W: wheel 1..6)
    ///   steer W|all DEG         a steer demand
    ///   lift W|all DEG          a lift demand
    ///   turn DEG                the library's turn: steers 1, 2 to DEG, 5, 6 to -DEG, 3, 4 to 0
    ///   pointturn               steers to the point turn's angles (the operator's `pt`)
    ///   rotate SPEED            drives 1, 5 at -SPEED, 2, 6 at SPEED, 3 and 4 at -SPEED/1.8
    ///                           and SPEED/1.8: the spin after a pointturn (`rot`)
    ///   stop                    every motor unpowered at once, then the library's emergency
    ///                           stop (gains and demands 0); a board that ignores it fails
    ///   wait SECONDS            a live view of required against actual per wheel, redrawn in
    ///                           place (to a file or pipe: the last view only)
    ///   watch SECONDS [EVERY]   the same view kept as a log, one every EVERY s (1 by
    ///                           default; 0: every update, for a step response)
    ///   show DEV REG…           adds registers (`show 1 drive_control drive_error`) to
    ///                           every later view
    ///   say TEXT                prints TEXT
    ///
    /// The whole script is checked before anything is sent: drive, steer, lift, turn,
    /// pointturn and rotate against the library's limits (steer and lift: the calibration
    /// less 10°), `write` only against the register's range, as the original library checks
    /// its own register writes.
    ///
    /// The first write waits until 5 s after the master's banner, when the master starts
    /// watching the controllers. The rover stops when the script ends (closing the port
    /// reboots it), so end with a `wait` for a demand to act.
    ///
    /// Ctrl-C (or SIGTERM) stops the script after the line in progress (a `wait` or `watch`
    /// ends at once, drawing its view once more; a `calibrate` leaves the boards it stopped
    /// stopped), also while hostctl waits for the master or the twin, and hostctl closes
    /// the port, which stops the rover; a second one ends hostctl at once.
    ///
    /// Exit status: 0 done; 1 an error (a line refused, the link failed); 3 the script ran
    /// to its end with the rover stopped (a board in an exception other than its boot state,
    /// one seen rebooted back into its boot state, or a controller not answering, at the
    /// last view or at one more update() when frames went out after it); 130 stopped by
    /// Ctrl-C; 143 by SIGTERM.
    #[command(verbatim_doc_comment)]
    Run(cmd::run::Args),
}

impl Command {
    /// The subcommand's name, as typed.
    pub fn name(&self) -> &'static str {
        match self {
            Command::Write(_) => "write",
            Command::Read(_) => "read",
            Command::Readset(_) => "readset",
            Command::Watch(_) => "watch",
            Command::Run(_) => "run",
        }
    }
}
