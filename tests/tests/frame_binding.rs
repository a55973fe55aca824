//! Every shader sdfc emits takes its per-frame inputs at binding 0 as a read-only storage
//! buffer and declares no uniform: Mesa's lavapipe (22.x) inlines the values of the uniforms
//! a shader's branches read and compiles the shader again at each dispatch with new uniform
//! data, which made every frame of a large scene cost about a pipeline build on a CPU device
//! (docs/performance.md, "Uniforms recompiled at every frame"). The renderer's bind group
//! layouts declare binding 0 the same way; the render tests fail if the two disagree.

use sdfc_wgsl::{compile, Options};

const FRAME: &str = "@group(0) @binding(0) var<storage, read> frame: Frame;";

fn assert_no_uniform(what: &str, wgsl: &str) {
    assert!(
        !wgsl.contains("var<uniform>"),
        "{what} declares a uniform:\n{}",
        wgsl.lines()
            .filter(|l| l.contains("var<uniform>"))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn render_and_eval_shaders_read_the_frame_from_storage() {
    let corpus = sdfc_tests::read_corpus("scenes", 20);
    let mut with_params = 0;
    for file in &corpus {
        let Ok(compiled) = compile(&file.source, &Options::default()) else {
            continue;
        };
        let what = file.path.display();
        assert!(
            compiled.wgsl.contains(FRAME),
            "{what}: no `{FRAME}` in its shader"
        );
        assert_no_uniform(&format!("{what}'s render shader"), &compiled.wgsl);
        let eval = sdfc_wgsl::eval_shader::eval_shader(compiled.program())
            .unwrap_or_else(|e| panic!("{what}: {e:?}"));
        assert!(
            eval.contains("@group(0) @binding(0) var<storage, read> eval_frame: EvalFrame;"),
            "{what}: the evaluation shader's frame is not read-only storage"
        );
        assert_no_uniform(&format!("{what}'s evaluation shader"), &eval);
        with_params += usize::from(!compiled.program().scene.params.is_empty());
    }
    // Params are what the frame carries beyond the header: some scene must have them.
    assert!(with_params > 0, "no corpus scene with a param was checked");
}

#[test]
fn the_interpreter_reads_the_frame_from_storage() {
    let wgsl = sdfc_wgsl::interp::shader().expect("the interpreter validates");
    assert!(
        wgsl.contains(FRAME),
        "the interpreter's frame is not storage"
    );
    assert_no_uniform("the interpreter", wgsl);
}
