//! Peephole folds over the virtual instructions before registers are allocated: constant
//! translations into their readers, culled parts' bounds into one `far_corner`.

use super::encode::{is_register, virtual_registers, VIns, POINT};
use super::listing::arity;
use super::opcodes::Opcode;

/// The peephole folds, in order: translations first, so that a bound's `abs` carries its
/// own into the `far_corner`.
pub(super) fn fold(ins: Vec<VIns>) -> Vec<VIns> {
    fold_far_corners(fold_translations(ins))
}

/// Whether an instruction can take a folded `sub` as its first argument: it reads at most
/// three arguments (the offset goes in the fourth slot) and computes with the first.
fn takes_folded(x: &VIns) -> bool {
    !x.folded
        && x.args.len() <= 3
        && (1..=3).contains(&arity(x.op))
        && !matches!(x.op, Opcode::Ret | Opcode::SkipUnlessLess | Opcode::Mov)
}

/// Folds each `v = sub point k` (a shape translated by a constant offset) into the
/// instructions that read `v`, where every one of them reads it as its first argument only
/// and has a free fourth slot for `k`: they compute `point - k` as they fetch (the same f32
/// subtraction), and the `sub` goes. The point is always live and `k` is a constant, so no
/// register lives longer. Skips are re-aimed past the same instructions.
fn fold_translations(mut ins: Vec<VIns>) -> Vec<VIns> {
    let virtuals = virtual_registers(&ins);
    let mut writes = vec![0u32; virtuals];
    let mut foldable = vec![true; virtuals];
    for x in &ins {
        if let Some(d) = x.dst {
            writes[d as usize] += 1;
        }
        for (slot, &a) in x.args.iter().enumerate() {
            if is_register(a) && (slot != 0 || !takes_folded(x)) {
                foldable[a as usize] = false;
            }
        }
    }
    let mut offset = vec![None; virtuals];
    let mut keep = vec![true; ins.len()];
    for (i, x) in ins.iter().enumerate() {
        if let (Opcode::Sub, Some(d), false, [POINT, k]) = (x.op, x.dst, x.folded, &x.args[..]) {
            let d = d as usize;
            if !is_register(*k) && writes[d] == 1 && foldable[d] && d != POINT as usize {
                offset[d] = Some(*k);
                keep[i] = false;
            }
        }
    }
    for x in &mut ins {
        let Some(&first) = x.args.first() else {
            continue;
        };
        if let Some(k) = is_register(first).then(|| offset[first as usize]).flatten() {
            x.args[0] = POINT;
            x.args.resize(3, POINT);
            x.args.push(k);
            x.folded = true;
        }
    }
    kept(ins, &keep)
}

/// Folds each culled part's bound `length3(add(abs(x), k))` (`k` a constant, each
/// intermediate read once) into one `far_corner x k` (the same f32 operations), the `abs`
/// keeping its folded translation. `x` must be written once (or be the point), so that it
/// holds the same value where the `length3` stood.
fn fold_far_corners(mut ins: Vec<VIns>) -> Vec<VIns> {
    let virtuals = virtual_registers(&ins);
    let (mut writes, mut reads) = (vec![0u32; virtuals], vec![0u32; virtuals]);
    let mut def = vec![usize::MAX; virtuals];
    for (i, x) in ins.iter().enumerate() {
        if let Some(d) = x.dst {
            writes[d as usize] += 1;
            def[d as usize] = i;
        }
        for &a in x.args.iter().filter(|&&a| is_register(a)) {
            reads[a as usize] += 1;
        }
    }
    // The instruction defining a register read only once, by its reader.
    let once = |v: u32| {
        let v = v as usize;
        (is_register(v as u32) && v != POINT as usize && writes[v] == 1 && reads[v] == 1)
            .then_some(def[v])
    };
    let mut keep = vec![true; ins.len()];
    for l in 0..ins.len() {
        let x = &ins[l];
        if x.op != Opcode::Length3 || x.folded {
            continue;
        }
        let Some(j) = x.args.first().and_then(|&v| once(v)) else {
            continue;
        };
        let add = &ins[j];
        if add.op != Opcode::Add || add.folded {
            continue;
        }
        let (t, k) = match add.args[..] {
            [t, k] if !is_register(k) => (t, k),
            [k, t] if !is_register(k) => (t, k),
            _ => continue,
        };
        let Some(i) = once(t) else { continue };
        let abs = &ins[i];
        let source = abs.args[0];
        let stable = !is_register(source) || source == POINT || writes[source as usize] == 1;
        if abs.op != Opcode::Abs || !stable {
            continue;
        }
        let mut args = vec![source, k];
        if abs.folded {
            args.extend([POINT, abs.args[3]]);
        }
        let folded = abs.folded;
        let x = &mut ins[l];
        x.op = Opcode::FarCorner;
        x.args = args;
        x.folded = folded;
        keep[i] = false;
        keep[j] = false;
    }
    kept(ins, &keep)
}

/// The instructions marked kept, with each skip re-aimed to jump over as many kept
/// instructions as before.
fn kept(mut ins: Vec<VIns>, keep: &[bool]) -> Vec<VIns> {
    // Where each instruction lands (and where the end does).
    let mut at = Vec::with_capacity(ins.len() + 1);
    let mut n = 0u32;
    for &k in keep {
        at.push(n);
        n += k as u32;
    }
    at.push(n);
    for (i, x) in ins.iter_mut().enumerate() {
        if x.op == Opcode::SkipUnlessLess && x.imm > 0 {
            let target = i + 1 + x.imm as usize;
            x.imm = at[target] - at[i] - 1;
        }
    }
    ins.into_iter()
        .zip(keep)
        .filter_map(|(x, &k)| k.then_some(x))
        .collect()
}
