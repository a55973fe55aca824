//! `sdfc render --live --watch`: the live-editing loop. One device and one interpreter
//! pipeline for the whole session; each time the scene file's text changes it is lowered
//! and rendered live again (preview, then the specialised frame). An edit that comes while
//! a frame is still building supersedes it. A mistake in the scene is reported and the last
//! picture kept.

use crate::live::{draw, Request};
use crate::out::say;
use crate::render::open_renderer;
use crate::{lower_source, Outcome};
use std::cell::{Cell, RefCell};
use std::time::{Duration, Instant};

/// How often the scene file is read for changes: well under the time a person takes to
/// look from the editor to the picture.
const POLL: Duration = Duration::from_millis(100);

pub fn run(r: &Request) -> Outcome {
    let renderer = match open_renderer() {
        Ok(r) => r,
        Err(o) => return o,
    };
    say!(
        "sdfc: watching {}; each change is rendered into {} (Ctrl-C stops)",
        r.scene.display(),
        r.output
            .map_or_else(String::new, |o| o.display().to_string())
    );
    let mut last: Option<Vec<u8>> = None;
    let mut warming = false;
    let mut unreadable = false;
    loop {
        match std::fs::read(r.scene) {
            Ok(bytes) if last.as_ref() != Some(&bytes) => {
                let start = Instant::now();
                unreadable = false;
                let text = String::from_utf8(bytes.clone());
                last = Some(bytes);
                match text {
                    Err(e) => say!(
                        "sdfc: {} is not valid UTF-8 (from byte {}); waiting for the next change",
                        r.scene.display(),
                        e.utf8_error().valid_up_to()
                    ),
                    Ok(text) => {
                        if let Ok(lowered) = lower_source(r.scene, &text, &r.emit()) {
                            let current = last.as_deref().unwrap_or_default();
                            let changed = Changed::new(r.scene, current, r.emit());
                            let superseded = || changed.since();
                            match draw(r, &renderer, &lowered, start, &superseded) {
                                // Input errors (a param the scene no longer has) wait for the
                                // next change; the device or the output failing ends the loop.
                                Some(Outcome::EnvError) => {
                                    renderer.wait_for_background_work();
                                    return Outcome::EnvError;
                                }
                                Some(_) => {}
                                None => {
                                    // Edited again before its frame: on to the new version at
                                    // once (its pipeline goes on building, into the cache).
                                    say!(
                                        "sdfc: {} changed before its frame; rendering the new version",
                                        r.scene.display()
                                    );
                                    continue;
                                }
                            }
                        }
                        if !warming {
                            // After the first frame, not before: on a CPU device the warm-up
                            // compiles the interpreter on the device's one queue, and the
                            // first frame would wait behind it. Later edits get previews.
                            warming = true;
                            warm(&renderer);
                        }
                        say!("sdfc: waiting for a change to {}", r.scene.display());
                    }
                }
            }
            Ok(_) => unreadable = false,
            Err(e) => {
                if !unreadable {
                    say!(
                        "sdfc: cannot read {}: {e}; waiting for it",
                        r.scene.display()
                    );
                }
                unreadable = true;
            }
        }
        std::thread::sleep(POLL);
    }
}

/// Warms the interpreter on a thread of its own: after it, an edit costs the interpreter an
/// upload and a frame, not a pipeline.
fn warm(renderer: &sdfc_render::Renderer) {
    // wgpu's GL backend serves one thread at a time (the renderer makes the others wait):
    // a preview could not be drawn while the pipeline builds, and the warm-up, minutes of
    // llvmpipe's time without Mesa's shader cache, would hold up every edit's frame.
    if renderer.adapter_description().backend == "Gl" {
        say!("sdfc: no previews on the GL backend: its one context serves one thread at a time");
        return;
    }
    let started = Instant::now();
    renderer.warm_interpreter_in_background(move |warm| match warm {
        Ok(()) => say!(
            "sdfc: the interpreter is warm after {:.2?}: previews from now on",
            started.elapsed()
        ),
        Err(e) => say!("sdfc: no previews: the interpreter could not be warmed: {e}"),
    });
}

/// Whether the scene file has changed from the text being rendered into a text that
/// compiles: a save half made, or a mistake, does not stop the frame of the last good
/// version. The file is read at most once per [`POLL`] however often this is asked, and
/// each new text lowered once.
struct Changed<'a> {
    path: &'a std::path::Path,
    text: &'a [u8],
    emit: sdfc_wgsl::Options,
    checked: Cell<Instant>,
    /// The last text read that differs from `text`, and whether it lowers.
    seen: RefCell<Option<(Vec<u8>, bool)>>,
}

impl<'a> Changed<'a> {
    fn new(path: &'a std::path::Path, text: &'a [u8], emit: sdfc_wgsl::Options) -> Changed<'a> {
        Changed {
            path,
            text,
            emit,
            checked: Cell::new(Instant::now()),
            seen: RefCell::new(None),
        }
    }

    fn since(&self) -> bool {
        let good = |seen: &Option<(Vec<u8>, bool)>| seen.as_ref().is_some_and(|s| s.1);
        if good(&self.seen.borrow()) || self.checked.get().elapsed() < POLL {
            return good(&self.seen.borrow());
        }
        self.checked.set(Instant::now());
        // An unreadable file (mid-save) is no change yet.
        let Ok(bytes) = std::fs::read(self.path) else {
            return false;
        };
        if bytes.as_slice() == self.text
            || self.seen.borrow().as_ref().is_some_and(|s| s.0 == bytes)
        {
            return false;
        }
        let lowers = std::str::from_utf8(&bytes)
            .is_ok_and(|text| sdfc_wgsl::lower(text, &self.emit).is_ok());
        *self.seen.borrow_mut() = Some((bytes, lowers));
        lowers
    }
}
