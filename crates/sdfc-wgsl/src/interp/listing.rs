//! The bytecode as readable text (goldens, debugging), and how many registers each opcode
//! reads.

use super::encode::{Bytecode, MAX_REGISTERS};
use super::opcodes::{decode, Opcode};
use std::fmt::Write;

impl Bytecode {
    /// A readable listing, for goldens and debugging.
    pub fn listing(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "registers: {}, constants: {}, instructions: {}",
            self.registers,
            self.consts.len(),
            self.code.len()
        );
        for (i, c) in self.consts.iter().enumerate() {
            let _ = writeln!(s, "c{i} = {c:?}");
        }
        let kinds = ("kinds", [0, self.kinds]);
        let functions = [("distance", self.distance), ("material", self.material)];
        let ray = ("distance_ray", self.distance_ray);
        for (name, [start, end]) in (self.kinds > 0)
            .then_some(kinds)
            .into_iter()
            .chain(functions)
            .chain((self.distance_ray != self.distance).then_some(ray))
        {
            let _ = writeln!(s, "{name}:");
            for pc in start..end {
                let [op, d, a01, a23] = self.code[pc as usize];
                let (op, folded) = decode(op);
                let (dst, imm) = (d & 0xffff, d >> 16);
                let args = [a01 & 0xffff, a01 >> 16, a23 & 0xffff, a23 >> 16];
                let Some(op) = op else {
                    let _ = writeln!(s, "  {pc:4}: ?{}", self.code[pc as usize][0]);
                    continue;
                };
                let n = arity(op);
                let name = |r: u32| match r.checked_sub(MAX_REGISTERS) {
                    Some(k) => format!("c{k}"),
                    None => format!("r{r}"),
                };
                let mut regs: Vec<String> = args[..n].iter().map(|&r| name(r)).collect();
                if folded {
                    regs[0] = format!("({} - {})", regs[0], name(args[3]));
                }
                let imm = match op {
                    Opcode::Param => format!(" #{imm}"),
                    Opcode::Swizzle => format!(
                        " .{}",
                        (0..4)
                            .map(|i| ['x', 'y', 'z', 'w'][((imm >> (2 * i)) & 3) as usize])
                            .collect::<String>()
                    ),
                    Opcode::MatRow => format!(" row {imm}"),
                    Opcode::SkipUnlessLess => format!(" to {}", pc + 1 + imm),
                    Opcode::Instances => format!(" kinds c{imm}"),
                    Opcode::Arg => format!(" word {} x{}", imm & 0xff, imm >> 8),
                    Opcode::MaterialRow => format!(" table c{imm}"),
                    _ => String::new(),
                };
                let lhs = if matches!(
                    op,
                    Opcode::Ret | Opcode::SkipUnlessLess | Opcode::InstanceDone
                ) {
                    String::new()
                } else {
                    format!("r{dst} = ")
                };
                let line = format!("  {pc:4}: {lhs}{}{imm} {}", op.mnemonic(), regs.join(" "));
                let _ = writeln!(s, "{}", line.trim_end());
            }
        }
        s
    }
}

/// Register arguments an opcode reads, as its `case` in `shaders/interpreter/interpret.wgsl`
/// uses them (for listings, the read-before-write test and the CPU twin `exec`; unused slots
/// are 0).
pub(super) fn arity(op: Opcode) -> usize {
    use Opcode::*;
    match op {
        Param | Time | Ray | Arg => 0,
        Ret => 2,
        Neg | Swizzle | Abs | Sign | Floor | Ceil | Fract | Round | Sqrt | Exp | Log | Sin
        | Cos | Tan | Asin | Acos | Atan | Radians | Degrees | Length2 | Length3 | Length4
        | Normalize2 | Normalize3 | Normalize4 | Noise | NoiseGradient | Mov | Instances
        | InstanceDone | MaterialRow => 1,
        Select | Clamp | Mix | Smoothstep | MatRow | SdRoundBox | SdTorus | SdCylinder
        | RotateX | RotateY | RotateZ | SdBoxFrame | SdHexPrism | SdTriPrism => 3,
        MakeVec | Mat3Vec | SdCapsule | SdCappedTorus | SdCappedCone | SdMandelbulb
        | SdMandelbulbInt => 4,
        _ => 2,
    }
}
