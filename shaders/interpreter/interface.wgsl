// The interpreter's inputs: one Frame buffer with the image, the camera and the render
// settings (the specialised shader's compile-time constants, here runtime values), the
// bytecode, and a data buffer of lights, params and constants.
struct Frame {
    resolution: vec2<u32>,
    time: f32,
    flags: u32,
    camera_position: vec3<f32>,
    tan_half_fov: f32,
    camera_forward: vec3<f32>,
    max_distance: f32,
    camera_right: vec3<f32>,
    inv_gamma: f32,
    camera_up: vec3<f32>,
    relaxation: f32,
    background: vec3<f32>,
    // The absolute surface threshold; unused with `epsilon: pixel` (switches bit 0).
    epsilon: f32,
    fog_color: vec3<f32>,
    fog_density: f32,
    max_steps: u32,
    antialias: u32,
    // 0 tetrahedron, 1 central, 2 forward.
    normals: u32,
    // 0 none, 1 hard, 2 soft.
    shadows: u32,
    shadow_k: f32,
    // 0: no ambient occlusion.
    ao_samples: u32,
    ao_step: f32,
    ao_strength: f32,
    ao_falloff: f32,
    reflections: u32,
    light_count: u32,
    // Bit 0: `epsilon: pixel`; bit 1: fog; bit 2: the distance is trusted (`distance_trusted()`).
    switches: u32,
    // Instruction ranges [start, end) of the distance and material functions in `code` (the
    // ray function's is `distance_ray_code`, below).
    distance_code: vec2<u32>,
    material_code: vec2<u32>,
    // Where the lights (two entries each: position or reversed direction with w = 1 for a
    // point light, then colour times intensity), the params and the constants start in `data`.
    lights_at: u32,
    params_at: u32,
    consts_at: u32,
    // Where the scene's bounds are in `data`: (low corner, mask of the finite ends), then
    // (high corner, the outside factor of `shadow`), then the low and high corners of the box
    // shadow rays stop at (`bounds_outside`); see `ray_span`.
    bounds_at: u32,
    // Where a union read as data starts in `data` (shaders/interpreter/instances.wgsl).
    instances_at: u32,
    // The size of the scene's smallest shape (the specialised shader's FEATURE_SIZE).
    feature_size: f32,
    // The instruction range of the distance the march steps with along a ray
    // (`scene_distance_ray`; `distance_code` where the scene has none).
    distance_ray_code: vec2<u32>,
}

@group(0) @binding(0) var<storage, read> frame: Frame;
@group(0) @binding(1) var<storage, read_write> color_out: array<u32>;
@group(0) @binding(2) var<storage, read_write> aov_out: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> code: array<vec4<u32>>;
@group(0) @binding(4) var<storage, read> data: array<vec4<f32>>;

// The specialised shader's entry point calls this to load its inputs; here the settings
// stay in the Frame buffer, which the shared parts read directly (see `interp::runtime`).
fn load_frame() {
}

// A surface's material: albedo = (rgb colour, reflectivity); phong = (ambient, diffuse, specular, shininess).
struct SceneMaterial {
    albedo: vec4<f32>,
    phong: vec4<f32>,
}
