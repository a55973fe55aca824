// The register machine. Instruction i is code[i] = (opcode, dst | imm << 16, a0 | a1 << 16,
// a2 | a3 << 16); registers are vec4<f32>, a scalar splatted in all four lanes, a boolean
// as 1.0 / 0.0; register 0 holds the point. Code runs straight on, except where a culled
// union's part is skipped (`OP_SKIP_UNLESS_LESS`, forward only). The last instruction of a
// range is `ret`, whose first two arguments are the results: it is read after the loop
// rather than returned from inside the switch, which keeps the loop free of early exits
// (lavapipe miscompiled that form for some lanes of a divergent workgroup).
struct Outputs {
    a: vec4<f32>,
    b: vec4<f32>,
}

fn interpret(range: vec2<u32>, p: vec3<f32>) -> Outputs {
    var regs: array<vec4<f32>, MAX_REGISTERS>;
    regs[0] = vec4<f32>(p, 0.0);
    let last = range.y - 1u;
    for (var pc = range.x; pc < last; pc = pc + 1u) {
        let ins = code[pc];
        let dst = ins.y & 0xffffu;
        let imm = ins.y >> 16u;
        let a = regs[ins.z & 0xffffu];
        let b = regs[ins.z >> 16u];
        let c = regs[ins.w & 0xffffu];
        let d = regs[ins.w >> 16u];
        var r = vec4<f32>(0.0);
        switch ins.x {
            // Only ever last: read after the loop.
            case OP_RET: {}
            case OP_CONST: { r = data[frame.consts_at + imm]; }
            case OP_PARAM: { r = data[frame.params_at + imm]; }
            case OP_TIME: { r = vec4<f32>(frame.time); }
            // Writes nothing new: its destination is register 0, rewritten with itself.
            case OP_SKIP_UNLESS_LESS: { if !(a.x < b.x) { pc = pc + imm; } r = regs[dst]; }
            case OP_MOV: { r = a; }
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
            case OP_SD_MANDELBULB: { r = vec4<f32>(sd_mandelbulb(a.xyz, b.x, c.x, d.x)); }
            case OP_SD_MANDELBULB_INT: { r = vec4<f32>(sd_mandelbulb_int(a.xyz, b.x, c.x, d.x)); }
            case OP_SD_MENGER: { r = vec4<f32>(sd_menger(a.xyz, b.x)); }
            case OP_SD_SIERPINSKI: { r = vec4<f32>(sd_sierpinski(a.xyz, b.x)); }
            default: {}
        }
        regs[dst] = r;
    }
    let ret = code[last];
    return Outputs(regs[ret.z & 0xffffu], regs[ret.z >> 16u]);
}
