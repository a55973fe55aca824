//! One lock for the work of every GL device in the process, so that threads sharing one wait
//! for each other instead of panicking inside wgpu.
//!
//! wgpu's GL backend keeps its context behind a lock of its own that panics after waiting
//! six seconds ("Could not lock adapter context. This is most-likely a deadlock."), and
//! llvmpipe holds it longer than that while it compiles a large shader (the interpreter's:
//! minutes without Mesa's shader cache). A second thread using the device meanwhile (the
//! live path's background build, the interpreter's warm-up of `sdfc render --live --watch`,
//! tests sharing a renderer) then panicked. Under this lock such a thread waits as long as
//! it must. Vulkan needs none: its devices take work from any thread.
//!
//! The lock is re-entrant per thread, so the renderer's functions that call each other may
//! each take it; each takes it before any other lock of the renderer (the pipeline cache's
//! slots), so no two threads can wait for each other. It is taken where device work begins
//! and held until its wgpu objects are dropped: a frame (`render_text`,
//! `render_bytecode_cut`, which cover `dispatch` and `map_and_wait`), an evaluation
//! (`eval_gpu`), a pipeline's build (`Pipelines::get`), a health check, forgetting pipelines
//! and losing the device.

use std::cell::Cell;
use std::sync::{Mutex, MutexGuard};

static GL_WORK: Mutex<()> = Mutex::new(());

thread_local! {
    /// Whether this thread holds [`GL_WORK`].
    static HELD: Cell<bool> = const { Cell::new(false) };
}

/// Whether a device's work is serialised: true for a GL device.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Serial {
    pub(crate) gl: bool,
}

/// Held while a thread works on a GL device; nothing for other devices, or where this
/// thread holds the lock already.
#[must_use]
pub(crate) struct Held(Option<MutexGuard<'static, ()>>);

impl Serial {
    /// Takes the lock for a GL device (waiting for any other thread's work on one).
    pub(crate) fn hold(self) -> Held {
        if !self.gl || HELD.with(Cell::get) {
            return Held(None);
        }
        // A thread that panicked while holding it left nothing half-done that the lock
        // guards (the lock guards no data): go on.
        let guard = GL_WORK.lock().unwrap_or_else(|e| e.into_inner());
        HELD.with(|h| h.set(true));
        Held(Some(guard))
    }
}

impl Drop for Held {
    fn drop(&mut self) {
        if self.0.is_some() {
            HELD.with(|h| h.set(false));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    #[test]
    fn a_second_thread_waits_for_the_first_and_a_thread_may_take_it_again() {
        let gl = Serial { gl: true };
        let outer = gl.hold();
        // Re-entrant: the same thread takes it again without waiting for itself.
        let inner = gl.hold();
        assert!(outer.0.is_some() && inner.0.is_none());
        let done = Arc::new(AtomicBool::new(false));
        let other = {
            let done = done.clone();
            std::thread::spawn(move || {
                let start = Instant::now();
                let _held = gl.hold();
                done.store(true, Ordering::SeqCst);
                start.elapsed()
            })
        };
        std::thread::sleep(Duration::from_millis(150));
        assert!(
            !done.load(Ordering::SeqCst),
            "the other thread did not wait"
        );
        drop(inner);
        // Still held by `outer`.
        std::thread::sleep(Duration::from_millis(50));
        assert!(!done.load(Ordering::SeqCst), "released by the inner hold");
        drop(outer);
        let waited = other.join().expect("the other thread");
        assert!(done.load(Ordering::SeqCst));
        assert!(waited >= Duration::from_millis(150), "{waited:?}");
        // Released: this thread takes it afresh.
        assert!(gl.hold().0.is_some());
    }

    #[test]
    fn other_devices_take_nothing() {
        let vulkan = Serial { gl: false };
        let a = vulkan.hold();
        let b = std::thread::spawn(move || vulkan.hold().0.is_none())
            .join()
            .expect("thread");
        assert!(a.0.is_none() && b);
    }
}
