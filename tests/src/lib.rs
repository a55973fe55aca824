//! Shared helpers for the golden and end-to-end tests: where the corpus lives.

pub mod random_instances;
pub mod random_scene;

use std::path::PathBuf;

/// The `tests/` folder of the repository: where it was built, or, for a bench executable
/// carried to another machine (`scripts/gpu-bench.sh`), `tests/` under the folder it runs in.
pub fn root() -> PathBuf {
    let built = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    if built.is_dir() {
        built
    } else {
        PathBuf::from("tests")
    }
}

/// The `.sdf` files of a corpus folder under `tests/`, sorted by name.
pub fn corpus(folder: &str) -> Vec<PathBuf> {
    sdf_files(&root().join(folder))
}

/// The `.sdf` files of any folder, sorted by name (none if it cannot be read).
pub fn sdf_files(dir: &std::path::Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "sdf"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// A corpus file: its name without `.sdf`, path and text.
pub struct CorpusFile {
    pub stem: String,
    pub path: PathBuf,
    pub source: String,
}

/// Reads every `.sdf` file of a corpus folder under `tests/`, which must hold at least `min`.
pub fn read_corpus(folder: &str, min: usize) -> Vec<CorpusFile> {
    let paths = corpus(folder);
    assert!(
        paths.len() >= min,
        "expected the corpus in tests/{folder}, found {} files",
        paths.len()
    );
    paths
        .into_iter()
        .map(|path| {
            let stem = path
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or_else(|| panic!("{}: file name is not UTF-8", path.display()))
                .to_string();
            let source = std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            CorpusFile { stem, path, source }
        })
        .collect()
}

/// A generated scene of `n` shapes (spheres, boxes and tori on a grid, rotated, in three
/// materials) in one flat `union`: the compile-time benchmark's input and the large-scene
/// tests' too. Its camera is the suite's, 60 away, where most rays miss the grid's bounds.
pub fn grid_scene(n: usize) -> String {
    grid_with_camera(n, "position: [0, 20, 60], target: [0, 0, 0]")
}

/// The same grid seen from close by, where every ray marches through the shapes: what the
/// culling experiments and benches measure besides the suite's camera.
pub fn grid_scene_close(n: usize) -> String {
    grid_with_camera(n, "position: [2, 6, 12], target: [0, 3, -4]")
}

fn grid_with_camera(n: usize, camera: &str) -> String {
    let mut s = format!(
        "// Generated grid scene.\n\
         material red {{ color: [0.9, 0.2, 0.15] }}\n\
         material green {{ color: [0.2, 0.8, 0.3], specular: 0.2 }}\n\
         material blue {{ color: [0.2, 0.3, 0.9], reflectivity: 0.3 }}\n\
         camera {{ {camera}, fov: 50deg }}\n\
         scene = union(\n",
    );
    let side = (n as f64).cbrt().ceil() as usize;
    for i in 0..n {
        let (x, y, z) = (i % side, (i / side) % side, i / (side * side));
        let pos = format!(
            "[{}, {}, {}]",
            x as f64 * 1.5 - side as f64,
            y as f64 * 1.5,
            z as f64 * -1.5
        );
        let shape = match i % 3 {
            0 => format!("sphere({})", 0.3 + (i % 7) as f64 * 0.05),
            1 => format!(
                "box([0.5, {}, 0.5]).rotate_y({}deg).material(green)",
                0.4 + (i % 5) as f64 * 0.1,
                i % 90
            ),
            _ => format!("torus(0.4, 0.1).rotate_x({}deg).material(blue)", i % 180),
        };
        let material = if i % 3 == 0 { ".material(red)" } else { "" };
        s += &format!("    {shape}{material}.translate({pos}),\n");
    }
    s += ");\n";
    s
}

/// One flat `union` of translated spheres, as many as fit in `max_bytes` of source: the
/// largest scene of the simplest kind a file at the size limit can hold.
pub fn max_size_union(max_bytes: usize) -> String {
    let mut src = String::from("scene = union(\n");
    let mut n = 0;
    loop {
        let item = format!(
            "  sphere(0.5).translate([{}, {}, {}]),\n",
            n % 100,
            (n / 100) % 100,
            n / 10_000
        );
        if src.len() + item.len() + 4 > max_bytes {
            break;
        }
        src += &item;
        n += 1;
    }
    src + ");\n"
}

/// `let s_k = union(s_{k-1}, s_{k-1}.translate([k, 0, 0]))` for `levels` lines: a file of a
/// few hundred bytes whose scene unfolds into about 3 * 2^levels shapes.
pub fn doubling_lets(levels: usize) -> String {
    let mut s = String::from("let s0 = sphere(0.25);\n");
    for k in 1..=levels {
        s += &format!(
            "let s{k} = union(s{}, s{}.translate([{k}, 0, 0]));\n",
            k - 1,
            k - 1
        );
    }
    s + &format!("scene = s{levels};\n")
}

/// SplitMix64: a small deterministic generator for test points, the same every run and
/// without a dependency.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// A number uniformly in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A point uniformly in the box `lo..hi`.
    pub fn point_in(&mut self, lo: [f64; 3], hi: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| lo[i] + (hi[i] - lo[i]) * self.unit())
    }
}

/// Asserts that two depth images (inf, or any non-finite value, on a miss) have the same hit
/// or miss at every pixel and, where both hit, depths within `relative` of `expected`'s;
/// returns the number of hits. `what` names the image under test in the messages.
pub fn assert_same_depths(expected: &[f32], actual: &[f32], relative: f32, what: &str) -> usize {
    assert_eq!(expected.len(), actual.len(), "{what}: image sizes differ");
    for (i, (e, a)) in expected.iter().zip(actual).enumerate() {
        assert_eq!(
            e.is_finite(),
            a.is_finite(),
            "pixel {i}: expected {e}, {what} {a}"
        );
        if e.is_finite() {
            assert!(
                (e - a).abs() <= relative * e,
                "pixel {i}: expected {e}, {what} {a}"
            );
        }
    }
    expected.iter().filter(|d| d.is_finite()).count()
}

/// A scene of the performance suite by name: `sphere`, `grid_300`, `grid_5000` (generated
/// by [`grid_scene`]), or an example of `examples/` (`spec_section10`, `terrain`,
/// `fractals`, ...).
pub fn suite_scene(name: &str) -> String {
    match name {
        "sphere" => "scene = sphere(1);\n".to_string(),
        "grid_300" => grid_scene(300),
        "grid_5000" => grid_scene(5000),
        _ => {
            let path = root().join(format!("../examples/{name}.sdf"));
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        }
    }
}

/// How long [`warm_up`] draws.
pub const WARM_UP: std::time::Duration = std::time::Duration::from_millis(500);

/// Calls `draw` (at least once) until [`WARM_UP`] has passed or it fails, before a bench
/// times frames: a
/// GPU idles at a fraction of its clock while pipelines build, and a few frames of a
/// millisecond do not wake it (on an NVIDIA H200 the ribbed sphere took 0.08 ms a frame early
/// in a sweep and 0.36 ms later in it, after builds, under settings with the same steps).
pub fn warm_up<E>(mut draw: impl FnMut() -> Result<(), E>) -> Result<(), E> {
    let start = std::time::Instant::now();
    loop {
        draw()?;
        if start.elapsed() >= WARM_UP {
            return Ok(());
        }
    }
}

/// The image size of the render benchmarks: `SDFC_BENCH_SIZE=WxH`, else 160x120.
pub fn bench_size() -> (u32, u32) {
    std::env::var("SDFC_BENCH_SIZE")
        .ok()
        .and_then(|s| {
            let (w, h) = s.split_once('x')?;
            Some((w.parse().ok()?, h.parse().ok()?))
        })
        .unwrap_or((160, 120))
}
