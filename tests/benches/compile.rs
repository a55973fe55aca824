//! Compile time from scene text to validated WGSL for scenes of 10, 1 000 and 5 000 shapes
//! (by default, as code and as data), and the share of each stage at 5 000 (as code); and
//! inputs at the documented limits (a 1 MiB flat union, a scene of doubling `let`s). Run: `cargo bench -p sdfc-tests --bench compile`.

use sdfc_tests::{doubling_lets, grid_scene, max_size_union};
use sdfc_wgsl::Options;

fn main() {
    divan::main();
}

/// The whole pipeline at the default options, as `sdfc render` runs it: parse, lower,
/// optimise, emit, validate. From 100 instances up the union is emitted as data
/// (`Instances::Auto`): the WGSL no longer grows with the shapes, and the data is built.
#[divan::bench(args = [10, 1000, 5000], sample_count = 20)]
fn scene_to_validated_wgsl(bencher: divan::Bencher, n: usize) {
    let src = grid_scene(n);
    bencher.bench(|| sdfc_wgsl::compile(divan::black_box(&src), &Options::default()).is_ok());
}

/// The same with every shape's code in the WGSL (`Instances::Never`), as `sdfc compile`
/// writes a file without `--data`.
#[divan::bench(args = [1000, 5000], sample_count = 20)]
fn scene_to_validated_wgsl_as_code(bencher: divan::Bencher, n: usize) {
    let src = grid_scene(n);
    let opts = Options {
        instances: sdfc_wgsl::Instances::Never,
        ..Options::default()
    };
    bencher.bench(|| sdfc_wgsl::compile(divan::black_box(&src), &opts).is_ok());
}

/// The union emitted as data from 16 instances up (`Instances::Always`,
/// `sdfc render --instances`).
#[divan::bench(args = [1000, 5000], sample_count = 20)]
fn scene_to_validated_wgsl_as_data(bencher: divan::Bencher, n: usize) {
    let src = grid_scene(n);
    let opts = Options {
        instances: sdfc_wgsl::Instances::Always,
        ..Options::default()
    };
    bencher.bench(|| sdfc_wgsl::compile(divan::black_box(&src), &opts).map_or(0, |c| c.data.len()));
}

#[divan::bench(sample_count = 20)]
fn stage_parse_5000(bencher: divan::Bencher) {
    let src = grid_scene(5000);
    bencher.bench(|| sdfc_syntax::parse(divan::black_box(&src)).is_ok());
}

#[divan::bench(sample_count = 20)]
fn stage_lower_and_optimise_5000(bencher: divan::Bencher) {
    let src = grid_scene(5000);
    let file = sdfc_syntax::parse(&src).unwrap();
    bencher.bench(|| {
        sdfc_ir::compile(divan::black_box(&file), src.len())
            .0
            .is_some()
    });
}

/// What the live path does before its preview: one parse, then the plain and the culled
/// program lowered at once on two threads (`sdfc render --live`).
#[divan::bench(sample_count = 20)]
fn live_lower_5000(bencher: divan::Bencher) {
    let src = grid_scene(5000);
    bencher.bench(|| sdfc_wgsl::lower_live(divan::black_box(&src), &Options::default()).is_ok());
}

#[divan::bench(sample_count = 20)]
fn stage_emit_5000(bencher: divan::Bencher) {
    let src = grid_scene(5000);
    let file = sdfc_syntax::parse(&src).unwrap();
    let program = sdfc_ir::compile(&file, src.len()).0.unwrap().program;
    bencher.bench(|| sdfc_wgsl::module::emit(divan::black_box(&program), false, None).len());
}

#[divan::bench(sample_count = 20)]
fn stage_validate_5000(bencher: divan::Bencher) {
    let src = grid_scene(5000);
    let code = Options {
        instances: sdfc_wgsl::Instances::Never,
        ..Options::default()
    };
    let wgsl = sdfc_wgsl::compile(&src, &code).unwrap().wgsl;
    bencher.bench(|| sdfc_wgsl::validate::validate("bench.wgsl", divan::black_box(&wgsl)).is_ok());
}

/// A file at the size limit (about 28 000 spheres in one union).
#[divan::bench(sample_count = 5)]
fn limit_max_size_union(bencher: divan::Bencher) {
    let src = max_size_union(sdfc_syntax::MAX_SOURCE_BYTES);
    bencher.bench(|| sdfc_wgsl::compile(divan::black_box(&src), &Options::default()).is_ok());
}

/// 15 doubling `let`s: 98 000 shapes unfolded, one outlined function per `let`.
#[divan::bench(sample_count = 5)]
fn limit_doubling_lets(bencher: divan::Bencher) {
    let src = doubling_lets(15);
    bencher.bench(|| sdfc_wgsl::compile(divan::black_box(&src), &Options::default()).is_ok());
}
