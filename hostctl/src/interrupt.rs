//! Ctrl-C (SIGINT) or SIGTERM during `hostctl run`: the first asks the script to stop
//! where it is, after the line in progress (a `wait` or `watch` ends at once and draws its
//! view once more, so output sent to a file or a pipe keeps the rover's last state); during
//! `hostctl watch`, it ends the watch after its round. A second one of either ends hostctl
//! at once (the handler restores both defaults). Either way the port closes, which reboots
//! the master and so stops every motor (the first way also drops DTR itself, which reaches
//! the master even while another program holds the port).
//!
//! The handler only records the signal; the script's clock
//! ([`crate::cmd::run::Clock::interrupted`]) and the waits before the script starts read it.

use std::sync::atomic::{AtomicI32, Ordering};

/// What follows a script stopped with the port open, for the end of its message.
pub const CLOSES: &str =
    "; hostctl closes the port, which reboots the master and so stops every motor";

/// The signal caught, 0 for none.
static CAUGHT: AtomicI32 = AtomicI32::new(0);

/// The signal caught since [`install`] (its number), if any.
pub fn caught() -> Option<i32> {
    match CAUGHT.load(Ordering::Relaxed) {
        0 => None,
        signal => Some(signal),
    }
}

/// How a message names `signal`.
pub fn name(signal: i32) -> &'static str {
    #[cfg(unix)]
    if signal == nix::libc::SIGTERM {
        return "SIGTERM";
    }
    let _ = signal;
    "Ctrl-C"
}

/// The exit status of a program `signal` stopped, as a shell reports it: 128 + its
/// number (130 for Ctrl-C, 143 for SIGTERM).
pub fn exit_code(signal: i32) -> u8 {
    u8::try_from(128 + signal).unwrap_or(u8::MAX)
}

/// Catches the next SIGINT or SIGTERM. Nothing is caught if the handler cannot be
/// installed: the signal then ends hostctl as before, which also closes the port.
#[cfg(unix)]
pub fn install() {
    use nix::sys::signal::{sigaction, SaFlags, SigAction, SigHandler, SigSet, Signal};
    let action = SigAction::new(
        SigHandler::Handler(on_signal),
        SaFlags::SA_RESTART,
        SigSet::empty(),
    );
    for signal in [Signal::SIGINT, Signal::SIGTERM] {
        // SAFETY: the handler calls only async-signal-safe functions (an atomic store and
        // signal()).
        let _ = unsafe { sigaction(signal, &action) };
    }
}

/// Elsewhere signals keep their default action.
#[cfg(not(unix))]
pub fn install() {}

#[cfg(unix)]
extern "C" fn on_signal(signal: nix::libc::c_int) {
    use nix::libc::{SIGINT, SIGTERM, SIG_DFL};
    let _ = CAUGHT.compare_exchange(0, signal, Ordering::Relaxed, Ordering::Relaxed);
    // The next one of either ends hostctl.
    // SAFETY: signal() is async-signal-safe; SIG_DFL is a valid disposition.
    unsafe {
        nix::libc::signal(SIGINT, SIG_DFL);
        nix::libc::signal(SIGTERM, SIG_DFL);
    }
}
