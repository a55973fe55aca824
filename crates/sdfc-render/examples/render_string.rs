//! Renders a scene given as a string to a PNG.
//!
//! `cargo run -p sdfc-render --example render_string -- [OUT.png] [SCENE_TEXT]`
//! (defaults: `render_string.png` and a smooth-union blob on a floor).

use sdfc_render::{RenderOptions, Renderer};

const BLOB: &str = "\
material clay { color: [0.85, 0.45, 0.3], specular: 0.3 }
camera { position: [0, 1.5, 4], target: [0, 0.5, 0], fov: 45deg }
light point { position: [3, 5, 4], color: [1, 1, 1], intensity: 1 }
render { background: [0.6, 0.7, 0.85] }
scene = union(sphere(0.6).translate([-0.4, 0.6, 0]), sphere(0.45).translate([0.4, 0.8, 0.1]),
              smooth: 0.4).material(clay)
      | plane([0, 1, 0], 0);
";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "render_string.png".into());
    let source = args.next().unwrap_or_else(|| BLOB.into());
    let compiled = match sdfc_wgsl::compile(&source, &sdfc_wgsl::Options::default()) {
        Ok(c) => c,
        Err(f @ sdfc_wgsl::Failure::Diagnostics(_)) => {
            // The scene's mistakes, each with its line and the source under it.
            eprint!("{}", f.render("<string>", &source));
            std::process::exit(1);
        }
        Err(f) => return Err(f.into()),
    };
    let renderer = Renderer::new()?;
    eprintln!("rendering on {}", renderer.adapter_description());
    let frame = renderer.render(&compiled, &RenderOptions::sized(320, 240))?;
    sdfc_render::output::write_png(&out, &frame)?;
    eprintln!("wrote {out} in {:?}", frame.wall_time);
    Ok(())
}
