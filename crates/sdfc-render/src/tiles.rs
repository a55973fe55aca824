//! Dispatching only the 8x8 tiles whose rays can meet the scene's bounds
//! (`sdfc_wgsl::screen::screen_rect`), and giving every other pixel the colour and AOVs of
//! one that was run and cannot meet them (the background of a ray that takes no step): the
//! same picture as the whole dispatch, bit for bit, without running the shader there.

use crate::render::header;
use crate::{Frame, RenderOptions};
use sdfc_ir::Program;
use std::time::Instant;

/// The shader's workgroup size in x and y.
const TILE: u32 = 8;
/// `frame.flags` holds the first tile's column and row in 12 bits each.
const MAX_TILE: u32 = 0xfff;

/// The tiles to dispatch, and a pixel among them that no ray there can meet the scene from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Region {
    /// The first tile's column and row.
    pub first: (u32, u32),
    /// How many tiles across and down.
    pub count: (u32, u32),
    /// A pixel in the region whose rays miss the scene's bounds: every pixel outside the
    /// region gets its colour and AOVs.
    pub background: (u32, u32),
}

impl Region {
    /// `frame.flags` with the first tile's column in bits 8 to 19 and its row in 20 to 31.
    pub(crate) fn flags(&self, flags: u32) -> u32 {
        flags | self.first.0 << 8 | self.first.1 << 20
    }

    fn holds(&self, x: u32, y: u32) -> bool {
        let (tx, ty) = (x / TILE, y / TILE);
        tx >= self.first.0
            && tx < self.first.0 + self.count.0
            && ty >= self.first.1
            && ty < self.first.1 + self.count.1
    }
}

/// The region to dispatch for a frame of `program`, or `None` for the whole image: where
/// the scene's rectangle on the image is unknown or, with the tiles beside it that hold the
/// background pixel, would cover every tile. `opts.all_pixels` asks for the whole image.
pub(crate) fn region(program: &Program, opts: &RenderOptions) -> Option<Region> {
    if opts.all_pixels {
        return None;
    }
    let (w, h) = (opts.width, opts.height);
    let [x0, y0, x1, y1] = sdfc_wgsl::screen::screen_rect(program, w, h)?;
    let tiles = (w.div_ceil(TILE), h.div_ceil(TILE));
    if tiles.0 > MAX_TILE || tiles.1 > MAX_TILE {
        return None;
    }
    // The rectangle's tiles, and one more tile holding a pixel off the rectangle, the
    // background: the first beside it with room, left, right, above or below (so a column
    // or row is added). An empty rectangle (nothing on the image) keeps that tile alone.
    let (first, last, beside) = if x0 >= x1 || y0 >= y1 {
        ((0, 0), (0, 0), (0, 0))
    } else {
        let (first, last) = ((x0 / TILE, y0 / TILE), ((x1 - 1) / TILE, (y1 - 1) / TILE));
        let candidates = [
            (first.0 > 0).then(|| (first.0 - 1, first.1)),
            (last.0 + 1 < tiles.0).then(|| (last.0 + 1, first.1)),
            (first.1 > 0).then(|| (first.0, first.1 - 1)),
            (last.1 + 1 < tiles.1).then(|| (first.0, last.1 + 1)),
        ];
        let beside = candidates.into_iter().flatten().next()?;
        (first, last, beside)
    };
    let first = (first.0.min(beside.0), first.1.min(beside.1));
    let last = (last.0.max(beside.0), last.1.max(beside.1));
    let background = (beside.0 * TILE, beside.1 * TILE);
    let count = (last.0 - first.0 + 1, last.1 - first.1 + 1);
    if count.0 * count.1 >= tiles.0 * tiles.1 {
        return None;
    }
    Some(Region {
        first,
        count,
        background,
    })
}

/// A frame's dispatch: its header (`frame.flags` with the first tile), its size in
/// workgroups, and the region where it is not the whole image.
pub(crate) struct Dispatch {
    pub header: [u32; 4],
    pub groups: (u32, u32),
    region: Option<Region>,
}

impl Dispatch {
    /// The dispatch of a frame of `program` (`groups`: the whole image's size in tiles); the
    /// whole image where the shader does not read its first tile (`tiled` false: a text
    /// emitted before it did, or written by hand).
    pub(crate) fn plan(
        program: &Program,
        tiled: bool,
        opts: &RenderOptions,
        groups: (u32, u32),
    ) -> Dispatch {
        let mut header = header(opts);
        let region = region(program, opts).filter(|_| tiled);
        if let Some(r) = &region {
            header[3] = r.flags(header[3]);
        }
        Dispatch {
            header,
            groups: region.map_or(groups, |r| r.count),
            region,
        }
    }

    /// Completes the frame it drew: the pixels outside the region (the time it takes
    /// counted in the frame's wall time).
    pub(crate) fn finish(&self, frame: &mut Frame) {
        if let Some(r) = &self.region {
            let start = Instant::now();
            fill(frame, r);
            frame.wall_time += start.elapsed();
        }
    }
}

/// Gives every pixel outside `region` the colour and AOVs of its background pixel. A ray
/// that misses the scene's bounds brings back the background (`radiance`: `BACKGROUND`, the
/// same for every ray, no fog), so every such pixel is the same; a background that varied
/// with the ray (a sky) would need the shader run there.
fn fill(frame: &mut Frame, region: &Region) {
    let w = frame.width;
    let (bx, by) = region.background;
    let b = (by * w + bx) as usize;
    let color: [u8; 4] = frame.rgba[4 * b..4 * b + 4]
        .try_into()
        .expect("four bytes a pixel");
    let aov = frame
        .aovs
        .as_ref()
        .map(|a| (a.depth[b], a.normal[b], a.steps[b]));
    for y in 0..frame.height {
        for x in 0..w {
            if region.holds(x, y) {
                continue;
            }
            let i = (y * w + x) as usize;
            frame.rgba[4 * i..4 * i + 4].copy_from_slice(&color);
            if let (Some(a), Some((depth, normal, steps))) = (frame.aovs.as_mut(), aov) {
                a.depth[i] = depth;
                a.normal[i] = normal;
                a.steps[i] = steps;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Aovs;
    use std::time::Duration;

    fn program(scene: &str) -> Program {
        let source = format!(
            "camera {{ position: [0, 0, 10], target: [0, 0, 0], fov: 50deg }}\nscene = {scene};"
        );
        sdfc_wgsl::compile(&source, &Default::default())
            .unwrap_or_else(|f| panic!("{f:?}"))
            .stages
            .program
    }

    #[test]
    fn the_region_holds_the_rectangle_and_a_background_pixel_off_it() {
        let p = program("sphere(1)");
        let opts = RenderOptions::sized(64, 48);
        let r = region(&p, &opts).expect("a region");
        let [x0, y0, x1, y1] = sdfc_wgsl::screen::screen_rect(&p, 64, 48).unwrap();
        for (x, y) in [(x0, y0), (x1 - 1, y1 - 1)] {
            assert!(r.holds(x, y), "{r:?} lacks ({x}, {y})");
        }
        let (bx, by) = r.background;
        assert!(r.holds(bx, by));
        assert!(!(x0..x1).contains(&bx) || !(y0..y1).contains(&by), "{r:?}");
        assert!(r.count.0 * r.count.1 < 8 * 6);
        assert_eq!(r.flags(1), 1 | r.first.0 << 8 | r.first.1 << 20);
        let all = RenderOptions {
            all_pixels: true,
            ..opts.clone()
        };
        assert_eq!(region(&p, &all), None);
        assert_eq!(
            region(&program("sphere(1) | plane([0, 1, 0], 1)"), &opts),
            None
        );
        // Nothing on the image: one tile, for the background.
        let off = region(&program("sphere(1).translate([40, 0, 0])"), &opts).unwrap();
        assert_eq!(
            (off.first, off.count, off.background),
            ((0, 0), (1, 1), (0, 0))
        );
    }

    #[test]
    fn the_background_comes_from_each_side_in_turn() {
        let opts = RenderOptions::sized(64, 48);
        // (scene, where its background pixel lies against the scene's rectangle)
        for (scene, side) in [
            ("sphere(1.2).translate([5.2, 0, 0])", "left"),
            ("sphere(1.2).translate([-5.2, 0, 0])", "right"),
            ("box([9, 0.4, 0.5]).translate([0, -3.2, 0])", "above"),
            ("box([9, 0.4, 0.5]).translate([0, 3.9, 0])", "below"),
        ] {
            let p = program(scene);
            let [x0, y0, x1, y1] = sdfc_wgsl::screen::screen_rect(&p, 64, 48).unwrap();
            let r = region(&p, &opts).expect("a region");
            let (bx, by) = r.background;
            let found = if bx + TILE <= x0 {
                "left"
            } else if bx >= x1 {
                "right"
            } else if by + TILE <= y0 {
                "above"
            } else if by >= y1 {
                "below"
            } else {
                "on the rectangle"
            };
            assert_eq!(found, side, "{scene}: {r:?}, rectangle {x0} {y0} {x1} {y1}");
        }
    }

    #[test]
    fn fill_copies_the_background_pixel_outside_the_region() {
        let (w, h) = (24u32, 16u32);
        let n = (w * h) as usize;
        let mut frame = Frame {
            width: w,
            height: h,
            rgba: (0..4 * n).map(|i| (i / 4) as u8).collect(),
            aovs: Some(Aovs {
                depth: (0..n).map(|i| i as f32).collect(),
                normal: vec![[0.0; 3]; n],
                steps: (0..n).map(|i| i as f32).collect(),
            }),
            device_time: None,
            wall_time: Duration::ZERO,
        };
        let region = Region {
            first: (1, 0),
            count: (1, 1),
            background: (8, 0),
        };
        fill(&mut frame, &region);
        let aovs = frame.aovs.as_ref().unwrap();
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                let from = if (8..16).contains(&x) && y < 8 { i } else { 8 };
                assert_eq!(frame.rgba[4 * i], from as u8, "({x}, {y})");
                assert_eq!(aovs.depth[i], from as f32, "({x}, {y})");
                assert_eq!(aovs.steps[i], from as f32, "({x}, {y})");
            }
        }
    }
}
