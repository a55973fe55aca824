//! Register allocation: virtual registers to the interpreter's physical ones, reused after
//! their value's last read, and the instructions packed as bytecode.

use super::encode::{
    is_register, unsupported, virtual_registers, EncodeError, VIns, CONST_OPERAND, MAX_REGISTERS,
    POINT,
};
use super::opcodes::FOLDED_SUB;

/// Maps virtual registers to physical ones (reused after their value's last read), appends
/// the instructions to `code`; returns how many registers they use.
pub(super) fn allocate(ins: &[VIns], code: &mut Vec<[u32; 4]>) -> Result<u32, EncodeError> {
    // Virtual registers are small dense numbers: tables indexed by them, not maps.
    const NONE: u32 = u32::MAX;
    let virtuals = virtual_registers(ins);
    let mut last_use = vec![usize::MAX; virtuals];
    for (i, x) in ins.iter().enumerate() {
        for &a in x.args.iter().filter(|&&a| is_register(a)) {
            last_use[a as usize] = i;
        }
    }
    let mut phys = vec![NONE; virtuals];
    phys[POINT as usize] = POINT;
    // The free physical registers as bits; the lowest is taken first. 128 bits: a register
    // numbered MAX_REGISTERS may be taken (and freed) just before the check fails.
    let mut free: u128 = 0;
    let mut used = POINT + 1;
    for (i, x) in ins.iter().enumerate() {
        let mut args = [0u32; 4];
        for (slot, &a) in args.iter_mut().zip(&x.args) {
            if !is_register(a) {
                *slot = MAX_REGISTERS + (a & !CONST_OPERAND);
                continue;
            }
            *slot = match phys[a as usize] {
                NONE => return Err(unsupported("a register read before it is written")),
                p => p,
            };
        }
        // Arguments read for the last time free their registers before the result takes
        // one: the interpreter reads every argument before it writes.
        for a in x.args.iter().filter(|&&a| is_register(a)) {
            if *a != POINT && last_use[*a as usize] == i {
                let p = std::mem::replace(&mut phys[*a as usize], NONE);
                if p != NONE {
                    free |= 1 << p;
                }
            }
        }
        let dst = match x.dst {
            // Written again (a culled part's result, after the part's code): the register
            // it already has.
            Some(v) if phys[v as usize] != NONE => phys[v as usize],
            Some(v) => {
                let p = if free != 0 {
                    let p = free.trailing_zeros();
                    free &= free - 1;
                    p
                } else {
                    used += 1;
                    used - 1
                };
                if last_use[v as usize] != usize::MAX {
                    phys[v as usize] = p;
                } else {
                    free |= 1 << p;
                }
                p
            }
            None => 0,
        };
        if used > MAX_REGISTERS {
            return Err(EncodeError::TooLarge(format!(
                "more than {MAX_REGISTERS} values live at once"
            )));
        }
        code.push([
            x.op.code() | if x.folded { FOLDED_SUB } else { 0 },
            dst | (x.imm << 16),
            args[0] | (args[1] << 16),
            args[2] | (args[3] << 16),
        ]);
    }
    Ok(used)
}
