//! A lost device (driver reset, removed GPU) is a clear error, never a hang or a panic:
//! every call after the loss fails with `RenderError::DeviceLost`, which the CLI maps to
//! exit status 2 (`is_input_error` is false). The loss is caused by `Renderer::lose_device`,
//! which destroys the device as a reset would.

mod common;

use common::{compile, on_ci};
use sdfc_render::{RenderError, RenderOptions, Renderer};

#[test]
fn every_call_after_a_device_loss_fails_with_device_lost() {
    // A renderer of its own: the shared one of `common` must stay usable.
    let r = match Renderer::new() {
        Ok(r) => r,
        Err(e) if on_ci() => panic!("no wgpu adapter on CI: {e}"),
        Err(e) => {
            eprintln!("SKIPPED: no wgpu adapter on this machine: {e}");
            return;
        }
    };
    let scene = compile("sphere", "scene = sphere(1);");
    let opts = RenderOptions::sized(16, 12);
    r.render(&scene, &opts).expect("render before the loss");

    r.lose_device();

    let render = r.render(&scene, &opts);
    assert!(
        matches!(render, Err(RenderError::DeviceLost(_))),
        "render after the loss: {render:?}"
    );
    let eval = r.eval_gpu(scene.program(), &[[0.0, 0.0, 2.0]], 0.0, &[]);
    assert!(
        matches!(eval, Err(RenderError::DeviceLost(_))),
        "eval after the loss: {eval:?}"
    );
    let interpreted = r.render_interpreted(scene.program(), &opts);
    assert!(
        matches!(interpreted, Err(RenderError::DeviceLost(_))),
        "interpreted render after the loss: {interpreted:?}"
    );
    let other = compile("box", "scene = box(1);");
    let fresh = r.render(&other, &opts);
    assert!(
        matches!(fresh, Err(RenderError::DeviceLost(_))),
        "a new pipeline after the loss: {fresh:?}"
    );
    let e = fresh.unwrap_err();
    assert!(!e.is_input_error());
    assert!(e.to_string().contains("device was lost"), "{e}");
}
