//! Ad-hoc profiling entry (not a benchmark): times each compile stage once.
fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5000);
    let src = sdfc_tests::grid_scene(n);
    let t = std::time::Instant::now();
    let file = sdfc_syntax::parse(&src).unwrap();
    let t_parse = t.elapsed();
    let t = std::time::Instant::now();
    let (stages, _) = sdfc_ir::compile(&file, src.len());
    let t_ir = t.elapsed();
    let program = stages.unwrap().program;
    let t = std::time::Instant::now();
    let wgsl = sdfc_wgsl::module::emit(&program, false);
    let t_emit = t.elapsed();
    let t = std::time::Instant::now();
    let m = naga::front::wgsl::parse_str(&wgsl).unwrap();
    let t_naga = t.elapsed();
    let t = std::time::Instant::now();
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&m)
    .unwrap();
    let t_valid = t.elapsed();
    if std::env::args().nth(2).is_some() {
        std::fs::write("/tmp/probe.wgsl", &wgsl).unwrap();
    }
    println!("n={n} parse={t_parse:?} ir={t_ir:?} emit={t_emit:?} naga_parse={t_naga:?} naga_validate={t_valid:?} lines={} bytes={}", wgsl.lines().count(), wgsl.len());
}
