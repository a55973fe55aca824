//! `sdfc render --live --watch`: the live-editing loop. One device and one interpreter
//! pipeline for the whole session; each time the scene file's text changes it is lowered
//! and rendered live again (preview, then the specialised frame). A mistake in the scene is
//! reported and the last picture kept.

use crate::live::{draw, Request};
use crate::render::open_renderer;
use crate::{lower_source, Outcome};
use std::time::{Duration, Instant};

/// How often the scene file is read for changes: well under the time a person takes to
/// look from the editor to the picture.
const POLL: Duration = Duration::from_millis(100);

pub fn run(r: &Request) -> Outcome {
    let renderer = match open_renderer() {
        Ok(r) => r,
        Err(o) => return o,
    };
    eprintln!(
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
                    Err(e) => eprintln!(
                        "sdfc: {} is not valid UTF-8 (from byte {}); waiting for the next change",
                        r.scene.display(),
                        e.utf8_error().valid_up_to()
                    ),
                    Ok(text) => {
                        if let Ok(lowered) = lower_source(r.scene, &text, &r.emit()) {
                            // Input errors (a param the scene no longer has) wait for the
                            // next change; the device or the output failing ends the loop.
                            if let Outcome::EnvError =
                                draw(r, &renderer, &lowered.stages.program, start)
                            {
                                return Outcome::EnvError;
                            }
                        }
                        if !warming {
                            // After the first frame, not before: on a CPU device the warm-up
                            // compiles the interpreter on the device's one queue, and the
                            // first frame would wait behind it. Later edits get previews.
                            warming = true;
                            warm(&renderer);
                        }
                        eprintln!("sdfc: waiting for a change to {}", r.scene.display());
                    }
                }
            }
            Ok(_) => unreadable = false,
            Err(e) => {
                if !unreadable {
                    eprintln!(
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
    let started = Instant::now();
    renderer.warm_interpreter_in_background(move |warm| match warm {
        Ok(()) => eprintln!(
            "sdfc: the interpreter is warm after {:.2?}: previews from now on",
            started.elapsed()
        ),
        Err(e) => eprintln!("sdfc: no previews: the interpreter could not be warmed: {e}"),
    });
}
