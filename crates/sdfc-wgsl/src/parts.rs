//! The hand-written WGSL parts in `shaders/`, included at build time.

use sdfc_ir::ops::Helper;

pub fn helper(h: Helper) -> &'static str {
    match h {
        Helper::SdSphere => include_str!("../../../shaders/prims/sd_sphere.wgsl"),
        Helper::SdBox => include_str!("../../../shaders/prims/sd_box.wgsl"),
        Helper::SdRoundBox => include_str!("../../../shaders/prims/sd_round_box.wgsl"),
        Helper::SdTorus => include_str!("../../../shaders/prims/sd_torus.wgsl"),
        Helper::SdCylinder => include_str!("../../../shaders/prims/sd_cylinder.wgsl"),
        Helper::SdCapsule => include_str!("../../../shaders/prims/sd_capsule.wgsl"),
        Helper::SdBoxFrame => include_str!("../../../shaders/prims/sd_box_frame.wgsl"),
        Helper::SdCappedTorus => include_str!("../../../shaders/prims/sd_capped_torus.wgsl"),
        Helper::SdCappedCone => include_str!("../../../shaders/prims/sd_capped_cone.wgsl"),
        Helper::SdEllipsoid => include_str!("../../../shaders/prims/sd_ellipsoid.wgsl"),
        Helper::SdOctahedron => include_str!("../../../shaders/prims/sd_octahedron.wgsl"),
        Helper::SdHexPrism => include_str!("../../../shaders/prims/sd_hex_prism.wgsl"),
        Helper::SdTriPrism => include_str!("../../../shaders/prims/sd_tri_prism.wgsl"),
        Helper::SdPyramid => include_str!("../../../shaders/prims/sd_pyramid.wgsl"),
        Helper::SdMandelbulb => include_str!("../../../shaders/prims/sd_mandelbulb.wgsl"),
        Helper::SdMandelbulbInt => {
            include_str!("../../../shaders/prims/sd_mandelbulb_int.wgsl")
        }
        Helper::SdMenger => include_str!("../../../shaders/prims/sd_menger.wgsl"),
        Helper::SdSierpinski => include_str!("../../../shaders/prims/sd_sierpinski.wgsl"),
        Helper::RotateX => include_str!("../../../shaders/transforms/rotate_x.wgsl"),
        Helper::RotateY => include_str!("../../../shaders/transforms/rotate_y.wgsl"),
        Helper::RotateZ => include_str!("../../../shaders/transforms/rotate_z.wgsl"),
        Helper::Noise => include_str!("../../../shaders/noise.wgsl"),
        Helper::NoiseGradient => include_str!("../../../shaders/noise_gradient.wgsl"),
    }
}

pub const HIT: &str = include_str!("../../../shaders/hit.wgsl");
pub const REFINE: &str = include_str!("../../../shaders/refine.wgsl");
pub const MARCH_STEP: &str = include_str!("../../../shaders/march_step.wgsl");
pub const MARCH_STEP_RELAXED: &str = include_str!("../../../shaders/march_step_relaxed.wgsl");
pub const MARCH_TWO_LOOPS: &str = include_str!("../../../shaders/march_two_loops.wgsl");
pub const MARCH_MERGED: &str = include_str!("../../../shaders/march_merged.wgsl");
pub const MARCH_INSTANCES: &str = include_str!("../../../shaders/march_instances.wgsl");
pub const CAMERA: &str = include_str!("../../../shaders/camera.wgsl");
pub const MAIN: &str = include_str!("../../../shaders/main.wgsl");
pub const SAFE_NORMALIZE: &str = include_str!("../../../shaders/normals/safe_normalize.wgsl");
pub const NORMALS_TETRAHEDRON: &str = include_str!("../../../shaders/normals/tetrahedron.wgsl");
pub const NORMALS_CENTRAL: &str = include_str!("../../../shaders/normals/central.wgsl");
pub const NORMALS_ANALYTIC: &str = include_str!("../../../shaders/normals/analytic.wgsl");
pub const NORMALS_FORWARD: &str = include_str!("../../../shaders/normals/forward.wgsl");
pub const SHADOW_HARD: &str = include_str!("../../../shaders/shading/shadow_hard.wgsl");
pub const SHADOW_SOFT: &str = include_str!("../../../shaders/shading/shadow_soft.wgsl");
pub const SHADOW_HARD_SAMPLE: &str =
    include_str!("../../../shaders/shading/shadow_hard_sample.wgsl");
pub const SHADOW_SOFT_SAMPLE: &str =
    include_str!("../../../shaders/shading/shadow_soft_sample.wgsl");
pub const SHADOW_INSTANCES: &str = include_str!("../../../shaders/shading/shadow_instances.wgsl");
pub const AMBIENT_OCCLUSION: &str = include_str!("../../../shaders/shading/ambient_occlusion.wgsl");
pub const AMBIENT_OCCLUSION_LIST: &str =
    include_str!("../../../shaders/shading/ambient_occlusion_list.wgsl");
pub const RADIANCE_PLAIN: &str = include_str!("../../../shaders/shading/radiance_plain.wgsl");
pub const RADIANCE_REFLECTIONS: &str =
    include_str!("../../../shaders/shading/radiance_reflections.wgsl");
