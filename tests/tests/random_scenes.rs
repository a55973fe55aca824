//! Property: randomly generated *valid* scenes (every shape and operation this version
//! implements, nested, with random sizes) always compile; their WGSL passes naga in full and
//! library form; and the f64 reference distance is finite wherever it is sampled. The GPU
//! agreement half of this check is `crates/sdfc-render/tests/random_gpu.rs`.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use sdfc_ir::eval::{eval_func, Inputs};
use sdfc_tests::random_scene::shape;
use sdfc_wgsl::{compile, Options};

proptest! {
    #![proptest_config(Config { cases: 256, rng_seed: RngSeed::Fixed(0x5dfc), failure_persistence: None, ..Config::default() })]

    #[test]
    fn random_valid_scenes_compile_and_validate(scene in shape(), pts in prop::collection::vec(prop::array::uniform3(-4.0f64..4.0), 16)) {
        let src = format!("scene = {scene};\n");
        let c = match compile(&src, &Options::default()) {
            Ok(c) => c,
            Err(e) => return Err(TestCaseError::fail(format!("{src}\n{e:?}"))),
        };
        let lib = compile(&src, &Options { lib: true, ..Options::default() });
        prop_assert!(lib.is_ok(), "{src}: library form failed");
        let p = c.program();
        for pt in pts {
            let d = eval_func(&p.distance, &p.groups, &Inputs::at(pt))[0].scalar().unwrap_or(f64::NAN);
            prop_assert!(d.is_finite(), "{src}: distance {d} at {pt:?}");
        }
    }
}
