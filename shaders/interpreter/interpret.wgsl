// The register machine. Instruction i is code[i] = (opcode, dst | imm << 16, a0 | a1 << 16,
// a2 | a3 << 16); registers are vec4<f32>, a scalar splatted in all four lanes, a boolean
// as 1.0 / 0.0; register 0 holds the point. An operand from MAX_REGISTERS on is a constant
// of the pool (`operand`); with OP_FOLDED_SUB set in the opcode word, the first argument is
// a - d. Code runs straight on, except where a culled
// union's part is skipped (`OP_SKIP_UNLESS_LESS`, forward only). The last instruction of a
// range is `ret`, whose first two arguments are the results: it is read after the loop
// rather than returned from inside the switch, which keeps the loop free of early exits
// (lavapipe miscompiled that form for some lanes of a divergent workgroup).
struct Outputs {
    a: vec4<f32>,
    b: vec4<f32>,
}

// A fractal's orbit in progress. A fractal's instruction runs one iteration per trip of the
// loop and stays at its pc until the orbit is done, instead of looping inside its case:
// lavapipe (gallivm) ends every loop of an invocation once 65 535 loop trips have been taken
// in all, counting a trip for each loop reached even by lanes that all skip it, and masked
// execution reaches every case of the switch. With a loop in four cases each instruction
// cost six trips of that budget, and pixels of large or richly shaded scenes stopped marching
// part way (docs/performance.md). `fractal_at` is the pc of the orbit in progress
// (NO_FRACTAL when none), `fractal_i` its iterations done.
const NO_FRACTAL: u32 = 0xffffffffu;
var<private> fractal_at: u32 = NO_FRACTAL;
var<private> fractal_i: u32;
var<private> bulb: MandelbulbOrbit;
var<private> bulb_int: MandelbulbIntOrbit;
var<private> sponge: MengerLevel;
var<private> gasket: SierpinskiLevel;
// The ray's direction in `scene_distance_ray` (`OP_RAY`).
var<private> ray_dir: vec3<f32>;
// Whether a run of the code was cut short (see `interpret`): the pixel's alpha is then 0, so
// that the renderer can tell (it sets every alpha back to 1).
var<private> cut: bool = false;
// No jump (`execute`; and no walk in progress, shaders/interpreter/instances.wgsl).
const NO_JUMP: u32 = 0xffffffffu;

// Operand i: register i, or from MAX_REGISTERS on constant i - MAX_REGISTERS of the pool.
// Both are read, each at an index in range, and one selected: lavapipe runs both sides of
// a branch anyway.
fn operand(regs: ptr<function, array<vec4<f32>, MAX_REGISTERS>>, i: u32) -> vec4<f32> {
    let from_register = (*regs)[min(i, MAX_REGISTERS - 1u)];
    let from_pool = data[frame.consts_at + max(i, MAX_REGISTERS) - MAX_REGISTERS];
    return select(from_register, from_pool, i >= MAX_REGISTERS);
}

// One instruction, or one iteration of a fractal's, at pc; returns the next pc.
fn execute(regs: ptr<function, array<vec4<f32>, MAX_REGISTERS>>, at: u32) -> u32 {
    var pc = at;
    // Whether a fractal's orbit goes on: its instruction runs again.
    var stay = false;
    // Where a union's walk goes next (NO_JUMP: on, or the walk's result written).
    var jump = NO_JUMP;
    let ins = code[pc];
    let dst = ins.y & 0xffffu;
    let imm = ins.y >> 16u;
    let b = operand(regs, ins.z >> 16u);
    let c = operand(regs, ins.w & 0xffffu);
    let d = operand(regs, ins.w >> 16u);
    // A translated shape's point, `p - offset`, is computed here rather than by an
    // instruction of its own (OP_FOLDED_SUB; such an instruction reads at most three
    // arguments, so `d` is free to hold the offset).
    let first = operand(regs, ins.z & 0xffffu);
    let a = select(first, first - d, (ins.x & OP_FOLDED_SUB) != 0u);
    var r = vec4<f32>(0.0);
    switch ins.x & ~OP_FOLDED_SUB {
        // Only ever last: read after the loop.
        case OP_RET: {}
        case OP_PARAM: { r = data[frame.params_at + imm]; }
        case OP_TIME: { r = vec4<f32>(frame.time); }
        case OP_RAY: { r = vec4<f32>(ray_dir, 0.0); }
        // Writes nothing new: its destination is register 0, rewritten with itself.
        case OP_SKIP_UNLESS_LESS: { if !(a.x < b.x) { pc = pc + imm; } r = (*regs)[dst]; }
        case OP_MOV: { r = a; }
//WALK:BEGIN A union read as data: shaders/interpreter/instances.wgsl (only in the variant
// that walks one, `interp::Variant::Walk`: lavapipe runs every case of the switch at every
// instruction, and these four made every other scene's frames 12 to 17% slower there).
        case OP_INSTANCES: { jump = walk_trip(regs, pc, a.xyz, imm); r = walk_out; }
        case OP_INSTANCE_DONE: { jump = walk_back(regs, a.x); }
        case OP_ARG: { r = instance_arg(imm); }
        case OP_MATERIAL_ROW: { r = data[frame.consts_at + imm + 2u * u32(a.y)]; }
//WALK:END
        case OP_NEG: { r = -a; }
        case OP_ADD: { r = a + b; }
        case OP_SUB: { r = a - b; }
        case OP_MUL: { r = a * b; }
        case OP_DIV: { r = a / b; }
        case OP_MOD: { r = a - b * floor(a / b); }
        case OP_LT: { r = select(vec4<f32>(0.0), vec4<f32>(1.0), a < b); }
        case OP_LE: { r = select(vec4<f32>(0.0), vec4<f32>(1.0), a <= b); }
        case OP_GT: { r = select(vec4<f32>(0.0), vec4<f32>(1.0), a > b); }
        case OP_GE: { r = select(vec4<f32>(0.0), vec4<f32>(1.0), a >= b); }
        case OP_EQ: { r = select(vec4<f32>(0.0), vec4<f32>(1.0), a == b); }
        case OP_NE: { r = select(vec4<f32>(0.0), vec4<f32>(1.0), a != b); }
        case OP_SELECT: { r = select(a, b, c.x != 0.0); }
        case OP_MAKE_VEC: { r = vec4<f32>(a.x, b.x, c.x, d.x); }
        case OP_SWIZZLE: { r = vec4<f32>(a[imm & 3u], a[(imm >> 2u) & 3u], a[(imm >> 4u) & 3u], a[(imm >> 6u) & 3u]); }
        case OP_MAT3_VEC: { r = vec4<f32>(mat3x3<f32>(a.xyz, b.xyz, c.xyz) * d.xyz, 0.0); }
        case OP_MAT_ROW: { r = vec4<f32>(a[imm], b[imm], c[imm], 0.0); }
        case OP_ABS: { r = abs(a); }
        case OP_SIGN: { r = sign(a); }
        case OP_FLOOR: { r = floor(a); }
        case OP_CEIL: { r = ceil(a); }
        case OP_FRACT: { r = fract(a); }
        case OP_ROUND: { r = round(a); }
        case OP_SQRT: { r = sqrt(a); }
        case OP_POW: { r = pow(a, b); }
        case OP_EXP: { r = exp(a); }
        case OP_LOG: { r = log(a); }
        case OP_SIN: { r = sin(a); }
        case OP_COS: { r = cos(a); }
        case OP_TAN: { r = tan(a); }
        case OP_ASIN: { r = asin(a); }
        case OP_ACOS: { r = acos(a); }
        case OP_ATAN: { r = atan(a); }
        case OP_ATAN2: { r = atan2(a, b); }
        case OP_MIN: { r = min(a, b); }
        case OP_MAX: { r = max(a, b); }
        case OP_CLAMP: { r = clamp(a, b, c); }
        case OP_MIX: { r = mix(a, b, c); }
        case OP_STEP: { r = step(a, b); }
        case OP_SMOOTHSTEP: { r = smoothstep(a, b, c); }
        case OP_RADIANS: { r = radians(a); }
        case OP_DEGREES: { r = degrees(a); }
        case OP_LENGTH2: { r = vec4<f32>(length(a.xy)); }
        case OP_LENGTH3: { r = vec4<f32>(length(a.xyz)); }
        case OP_FAR_CORNER: { r = vec4<f32>(length(abs(a.xyz) + b.xyz)); }
        case OP_LENGTH4: { r = vec4<f32>(length(a)); }
        case OP_DOT2: { r = vec4<f32>(dot(a.xy, b.xy)); }
        case OP_DOT3: { r = vec4<f32>(dot(a.xyz, b.xyz)); }
        case OP_DOT4: { r = vec4<f32>(dot(a, b)); }
        case OP_NORMALIZE2: { r = vec4<f32>(normalize(a.xy), 0.0, 0.0); }
        case OP_NORMALIZE3: { r = vec4<f32>(normalize(a.xyz), 0.0); }
        case OP_NORMALIZE4: { r = normalize(a); }
        case OP_CROSS: { r = vec4<f32>(cross(a.xyz, b.xyz), 0.0); }
        // Distance helpers: one line each.
        case OP_SD_SPHERE: { r = vec4<f32>(sd_sphere(a.xyz, b.x)); }
        case OP_SD_BOX: { r = vec4<f32>(sd_box(a.xyz, b.xyz)); }
        case OP_SD_ROUND_BOX: { r = vec4<f32>(sd_round_box(a.xyz, b.xyz, c.x)); }
        case OP_SD_TORUS: { r = vec4<f32>(sd_torus(a.xyz, b.x, c.x)); }
        case OP_SD_CYLINDER: { r = vec4<f32>(sd_cylinder(a.xyz, b.x, c.x)); }
        case OP_SD_CAPSULE: { r = vec4<f32>(sd_capsule(a.xyz, b.xyz, c.xyz, d.x)); }
        case OP_ROTATE_X: { r = vec4<f32>(rotate_x(a.xyz, b.x, c.x), 0.0); }
        case OP_ROTATE_Y: { r = vec4<f32>(rotate_y(a.xyz, b.x, c.x), 0.0); }
        case OP_ROTATE_Z: { r = vec4<f32>(rotate_z(a.xyz, b.x, c.x), 0.0); }
        case OP_NOISE: { r = vec4<f32>(noise(a.xyz)); }
        case OP_NOISE_GRADIENT: { r = vec4<f32>(noise_gradient(a.xyz), 0.0); }
        case OP_SD_BOX_FRAME: { r = vec4<f32>(sd_box_frame(a.xyz, b.xyz, c.x)); }
        case OP_SD_CAPPED_TORUS: { r = vec4<f32>(sd_capped_torus(a.xyz, b.xy, c.x, d.x)); }
        case OP_SD_CAPPED_CONE: { r = vec4<f32>(sd_capped_cone(a.xyz, b.x, c.x, d.x)); }
        case OP_SD_ELLIPSOID: { r = vec4<f32>(sd_ellipsoid(a.xyz, b.xyz)); }
        case OP_SD_OCTAHEDRON: { r = vec4<f32>(sd_octahedron(a.xyz, b.x)); }
        case OP_SD_HEX_PRISM: { r = vec4<f32>(sd_hex_prism(a.xyz, b.x, c.x)); }
        case OP_SD_TRI_PRISM: { r = vec4<f32>(sd_tri_prism(a.xyz, b.x, c.x)); }
        case OP_SD_PYRAMID: { r = vec4<f32>(sd_pyramid(a.xyz, b.x)); }
        case OP_SD_MANDELBULB: {
            let lp = length(a.xyz);
            if fractal_at != pc {
                bulb = MandelbulbOrbit(a.xyz, 1.0, lp);
                fractal_i = 0u;
            }
            let far = lp > 1.25 * d.x;
            if !far && fractal_i < u32(c.x) && bulb.r <= 2.0 {
                bulb = mandelbulb_step(bulb, a.xyz, b.x);
                stay = true;
            } else {
                r = vec4<f32>(select(mandelbulb_estimate(bulb), lp - d.x, far));
            }
        }
        case OP_SD_MANDELBULB_INT: {
            let lp = length(a.xyz);
            if fractal_at != pc {
                bulb_int = MandelbulbIntOrbit(a.xyz, 1.0, lp);
                fractal_i = 0u;
            }
            let far = lp > 1.25 * d.x;
            if !far && fractal_i < u32(c.x) && bulb_int.r <= 2.0 {
                bulb_int = mandelbulb_int_step(bulb_int, a.xyz, b.x);
                stay = true;
            } else {
                r = vec4<f32>(select(mandelbulb_int_estimate(bulb_int), lp - d.x, far));
            }
        }
        case OP_SD_MENGER: {
            if fractal_at != pc {
                sponge = menger_start(a.xyz);
                fractal_i = 0u;
            }
            if fractal_i < u32(b.x) {
                sponge = menger_step(sponge, a.xyz);
                stay = true;
            } else {
                r = vec4<f32>(0.5 * sponge.dist);
            }
        }
        case OP_SD_SIERPINSKI: {
            if fractal_at != pc {
                gasket = SierpinskiLevel(2.0 * a.xyz, 2.0);
                fractal_i = 0u;
            }
            if fractal_i < u32(b.x) {
                gasket = sierpinski_step(gasket);
                stay = true;
            } else {
                r = vec4<f32>(sierpinski_estimate(gasket));
            }
        }
        default: {}
    }
    if jump != NO_JUMP {
        return jump;
    }
    if stay {
        fractal_at = pc;
        fractal_i = fractal_i + 1u;
        return pc;
    }
    fractal_at = NO_FRACTAL;
    (*regs)[dst] = r;
    return pc + 1u;
}

fn interpret(range: vec2<u32>, p: vec3<f32>) -> Outputs {
    var regs: array<vec4<f32>, MAX_REGISTERS>;
    regs[0] = vec4<f32>(p, 0.0);
    let last = range.y - 1u;
    var pc = range.x;
    fractal_at = NO_FRACTAL;
//WALK:BEGIN
    walk_at = NO_JUMP;
//WALK:END
    loop {
        if pc >= last {
            break;
        }
        pc = execute(&regs, pc);
//UNROLL
    }
    // The loop stops early only where the driver ended it (lavapipe's budget of loop trips,
    // above): the results are not the scene's, and the entry point marks the pixel.
    if pc < last {
        cut = true;
    }
    let ret = code[last];
    return Outputs(operand(&regs, ret.z & 0xffffu), operand(&regs, ret.z >> 16u));
}
