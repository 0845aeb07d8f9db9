//! The signals that end the explorer from outside (`kill`, a closed terminal window): SIGTERM
//! and SIGHUP, and SIGINT sent by `kill -INT` (Ctrl-C itself is a key in raw mode). Their
//! handler only notes the signal; the interface loop sees it within one poll, stops the
//! workers and restores the terminal as `q` does, and the program exits `128 + signal`.

use std::sync::atomic::{AtomicI32, Ordering};

/// The last signal received, 0 for none.
static RECEIVED: AtomicI32 = AtomicI32::new(0);

#[cfg(unix)]
extern "C" fn note(signal: libc::c_int) {
    // Async-signal-safe: one atomic store.
    RECEIVED.store(signal, Ordering::SeqCst);
}

/// Routes SIGTERM, SIGHUP and SIGINT to [`received`] instead of ending the process.
pub fn install() {
    #[cfg(unix)]
    for signal in [libc::SIGTERM, libc::SIGHUP, libc::SIGINT] {
        // SAFETY: the handler does one atomic store, which is async-signal-safe; the
        // `sigaction` is zeroed then filled as the C interface asks.
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = note as extern "C" fn(libc::c_int) as libc::sighandler_t;
            action.sa_flags = libc::SA_RESTART;
            libc::sigemptyset(&mut action.sa_mask);
            libc::sigaction(signal, &action, std::ptr::null_mut());
        }
    }
}

/// The signal received since [`install`], if one was.
pub fn received() -> Option<i32> {
    match RECEIVED.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s),
    }
}
