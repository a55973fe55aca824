//! A note on stderr when a render outlasts a few seconds, so that a long wait does not read as
//! a hang: the driver's build of a large scene's specialised pipeline can take minutes (more
//! than four for the 5 000-shape union on NVIDIA's driver, 83 to 108 s on lavapipe:
//! docs/performance.md), and `sdfc render` prints nothing else until it is done.

use crate::out::say;
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::time::Duration;

/// What the note says.
pub const NOTE: &str = "sdfc: still rendering: the device's driver is most likely building the \
scene's pipeline, which can take minutes for thousands of shapes; `--live` draws a preview \
meanwhile, and `--interpreted` renders without that build";

/// How long a render runs before the note: 5 s, or `SDFC_NOTE_AFTER_MS` (the tests set 0,
/// which says it at once).
fn delay() -> Duration {
    std::env::var("SDFC_NOTE_AFTER_MS")
        .ok()
        .and_then(|v| v.parse().ok())
        .map_or(Duration::from_secs(5), Duration::from_millis)
}

/// Runs `work`, saying [`NOTE`] once if it has not finished after the delay.
pub fn unless_quick<T>(work: impl FnOnce() -> T) -> T {
    let delay = delay();
    if delay.is_zero() {
        say!("{NOTE}");
        return work();
    }
    let (done, finished) = channel::<()>();
    std::thread::scope(|s| {
        s.spawn(move || {
            // Disconnected, when `done` is dropped below: finished in time, nothing to say.
            if finished.recv_timeout(delay) == Err(RecvTimeoutError::Timeout) {
                say!("{NOTE}");
            }
        });
        let out = work();
        drop(done);
        out
    })
}
