//! Ctrl-C during `hostctl run`: the first SIGINT (or SIGTERM) asks the script to stop
//! where it is, after drawing the view it was showing, so output sent to a file or a pipe
//! keeps the rover's last state instead of nothing; a second one ends hostctl at once (the
//! default action, which the first restores). Either way the port closes, which reboots
//! the master and so stops every motor.
//!
//! The handler only sets a flag; the script's clock ([`crate::cmd::run::Clock`]) reads it
//! between its short sleeps.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the signal handler.
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Whether Ctrl-C (or SIGTERM) has come since [`install`].
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// Catches the next SIGINT and SIGTERM (once each: the handler resets to the default, so
/// a second Ctrl-C kills hostctl). Nothing is caught if the handler cannot be installed:
/// the signal then ends hostctl as before, which also closes the port.
#[cfg(unix)]
pub fn install() {
    use nix::sys::signal::{sigaction, SaFlags, SigAction, SigHandler, SigSet, Signal};
    let action = SigAction::new(
        SigHandler::Handler(on_signal),
        SaFlags::SA_RESETHAND | SaFlags::SA_RESTART,
        SigSet::empty(),
    );
    for signal in [Signal::SIGINT, Signal::SIGTERM] {
        // SAFETY: the handler only stores to an atomic, which is async-signal-safe.
        let _ = unsafe { sigaction(signal, &action) };
    }
}

/// Elsewhere signals keep their default action.
#[cfg(not(unix))]
pub fn install() {}

#[cfg(unix)]
extern "C" fn on_signal(_: nix::libc::c_int) {
    REQUESTED.store(true, Ordering::Relaxed);
}
