//! The process's interrupt request (Ctrl-C, `kill`): `turf run` installs a handler for SIGINT
//! and SIGTERM ([`install`]). The first signal sets a flag that long engines poll between steps
//! ([`requested`]) — the continuum stage after each converged increment, the discrete stage after
//! each checkpointed strain step, the pipeline between stages — so that the run stops with what
//! it has and `summary.json` records the interrupted stage (`complete = false`). The handler then
//! restores the default action, so a second signal ends the process at once.
//!
//! Without [`install`] (the library in tests and in other programs) the flag is never set and
//! the engines run as before. Unix only; elsewhere [`install`] does nothing and Ctrl-C ends the
//! process as it always did.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the first SIGINT or SIGTERM once [`install`] has run.
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Why an engine stopped early when [`requested`] is true (ends up in `summary.json`).
pub const REASON: &str = "interrupted by a signal (SIGINT or SIGTERM)";

/// Whether an interrupt has been requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Install the handler for SIGINT and SIGTERM.
#[cfg(unix)]
pub fn install() {
    /// Set the flag, say so on stderr and restore the default action. Only async-signal-safe
    /// calls (an atomic store, `write`, `signal`).
    extern "C" fn on_signal(signal: libc::c_int) {
        REQUESTED.store(true, Ordering::SeqCst);
        const MESSAGE: &[u8] = b"\nturf: interrupted: stopping after the current step and keeping \
what is done (interrupt again to stop at once)\n";
        // SAFETY: write(2) and signal(2) are async-signal-safe (POSIX.1-2008, signal-safety(7));
        // the buffer is a static byte string.
        unsafe {
            libc::write(2, MESSAGE.as_ptr().cast(), MESSAGE.len());
            libc::signal(signal, libc::SIG_DFL);
        }
    }
    let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
    // SAFETY: the handler only performs async-signal-safe operations (above).
    unsafe {
        libc::signal(libc::SIGINT, handler);
        libc::signal(libc::SIGTERM, handler);
    }
}

/// Install the handler: nothing to do off Unix.
#[cfg(not(unix))]
pub fn install() {}
