//! Lowering of expressions: literals, names, operators, swizzles, calls of `fn`s.

use super::scope::{LambdaVal, Scope, Val};
use super::{Lowerer, Reported, R};
use crate::eval;
use crate::graph::NodeId;
use crate::ops::{Op, Swizzle};
use crate::shape::{CombineOp, ShapeId, ShapeKind};
use crate::types::Ty;
use crate::value::Value;
use sdfc_syntax::ast::{Arg, BinaryOp, Expr, ExprKind, Ident, UnaryOp};
use sdfc_syntax::diag::{nearest, Diagnostic};
use sdfc_syntax::span::Span;
use std::rc::Rc;

/// Names every scene may use without defining them.
pub const PREDEFINED: &[&str] = &["time", "pi", "tau"];

impl<'a> Lowerer<'a> {
    pub fn expr(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>) -> R<Val<'a>> {
        match &e.kind {
            ExprKind::Number(x) => {
                if !x.is_finite() {
                    return Err(self.error(
                        Diagnostic::error(e.span, "number too large for a 32-bit float")
                            .with_label("overflows f32"),
                    ));
                }
                Ok(Val::Num(self.g.add(
                    Op::Const(crate::value::Const::from_value(&Value::F(*x))),
                    &[],
                    e.span,
                )))
            }
            ExprKind::Bool(b) => Ok(Val::Num(self.g.konst(Value::B(*b)))),
            ExprKind::Vector(items) => self.vector(items, e.span, scope),
            ExprKind::Name(id) => self.name(id, scope),
            ExprKind::Unary(UnaryOp::Neg, inner) => {
                let v = self.expr(inner, scope)?;
                match v {
                    Val::Num(n) if self.g.ty(n).is_float_like() => {
                        Ok(Val::Num(self.g.add(Op::Neg, &[n], e.span)))
                    }
                    Val::Poison => Err(Reported),
                    other => Err(self.error(
                        Diagnostic::error(
                            e.span,
                            format!("cannot negate {}", self.describe(&other)),
                        )
                        .with_label("unary `-` needs a number or a vector")
                        .with_hint(
                            "to cut a shape out of another, write `a - b` or `subtract(a, b)`",
                        ),
                    )),
                }
            }
            ExprKind::Binary(op, l, r) => self.binary(*op, l, r, e.span, scope),
            ExprKind::Chain(op, operands) => {
                let operands: Vec<&Expr> = operands.iter().collect();
                self.shape_chain(*op, &operands, e.span, scope)
            }
            ExprKind::Call { callee, args, .. } => self.call(callee, args, e.span, scope),
            ExprKind::Swizzle(inner, letters) => self.swizzle(inner, letters, e.span, scope),
            ExprKind::Lambda { params, body } => Ok(Val::Lambda(Rc::new(LambdaVal {
                params,
                body,
                scope: scope.clone(),
                span: e.span,
            }))),
        }
    }

    fn vector(&mut self, items: &'a [Expr], span: Span, scope: &Rc<Scope<'a>>) -> R<Val<'a>> {
        if !(2..=3).contains(&items.len()) {
            return Err(self.error(
                Diagnostic::error(
                    span,
                    format!(
                        "a vector has 2 or 3 components, this one has {}",
                        items.len()
                    ),
                )
                .with_label("vector literal")
                .with_hint("write `[x, y]` or `[x, y, z]`"),
            ));
        }
        let mut comps = Vec::new();
        let mut failed = false;
        for it in items {
            match self.expr(it, scope) {
                Ok(v) => match self.expect_num(v, it.span, "a vector component") {
                    Ok(n) => comps.push(n),
                    Err(_) => failed = true,
                },
                Err(_) => failed = true,
            }
        }
        if failed {
            return Err(Reported);
        }
        Ok(Val::Num(self.g.add(Op::MakeVec, &comps, span)))
    }

    fn name(&mut self, id: &Ident, scope: &Rc<Scope<'a>>) -> R<Val<'a>> {
        if let Some(v) = self.lookup(&id.name, scope) {
            return match v {
                Val::Poison => Err(Reported),
                v => Ok(v),
            };
        }
        match id.name.as_str() {
            "time" => return Ok(Val::Num(self.g.add(Op::Time, &[], id.span))),
            "pi" => return Ok(Val::Num(self.g.f32(std::f32::consts::PI))),
            "tau" => return Ok(Val::Num(self.g.f32(std::f32::consts::TAU))),
            _ => {}
        }
        if let Some(d) = self.defined_later(&id.name, id.span, "the name") {
            return Err(self.error(d));
        }
        let mut known = self.visible_names(scope);
        known.extend(PREDEFINED);
        let mut d = Diagnostic::error(id.span, format!("unknown name `{}`", id.name))
            .with_label("not defined above this point");
        if let Some(s) = nearest(&id.name, known.iter().copied()) {
            d = d.with_hint(format!("did you mean `{s}`?"));
        } else if super::builtins::is_builtin_function(&id.name) {
            d = d.with_hint(format!(
                "`{}` is a function: call it, `{}(...)`",
                id.name, id.name
            ));
        } else if self.materials.iter().any(|m| m.name == id.name) {
            d = d.with_hint(format!(
                "`{}` is a material; use it as `shape.material({})`",
                id.name, id.name
            ));
        } else {
            d = d.with_hint(
                "names must be defined (with `let`, `param` or `fn`) above their first use",
            );
        }
        Err(self.error(d))
    }

    fn binary(
        &mut self,
        op: BinaryOp,
        l: &'a Expr,
        r: &'a Expr,
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        if matches!(op, BinaryOp::Or | BinaryOp::And) {
            // The parser gives chains (`ExprKind::Chain`); in a tree built by hand each
            // `Binary` of `|` or `&` is a union or intersection of its two sides.
            return self.shape_chain(op, &[l, r], span, scope);
        }
        let lv = self.expr(l, scope);
        let rv = self.expr(r, scope);
        let (lv, rv) = (lv?, rv?);
        if op == BinaryOp::Sub {
            if let (Val::Shape(a), Val::Shape(b)) = (&lv, &rv) {
                let kind = ShapeKind::Combine {
                    op: CombineOp::Subtract,
                    smooth: None,
                    children: vec![*a, *b],
                };
                return Ok(Val::Shape(self.shape(kind, span)));
            }
        }
        let a = self.expect_operand(lv, l.span, op)?;
        let b = self.expect_operand(rv, r.span, op)?;
        let (ta, tb) = (self.g.ty(a), self.g.ty(b));
        let iop = match op {
            BinaryOp::Add => Op::Add,
            BinaryOp::Sub => Op::Sub,
            BinaryOp::Mul => Op::Mul,
            BinaryOp::Div => Op::Div,
            BinaryOp::Rem => Op::Mod,
            BinaryOp::Lt => Op::Lt,
            BinaryOp::Le => Op::Le,
            BinaryOp::Gt => Op::Gt,
            BinaryOp::Ge => Op::Ge,
            BinaryOp::Eq => Op::Eq,
            BinaryOp::Ne => Op::Ne,
            BinaryOp::And | BinaryOp::Or => unreachable!("handled above"),
        };
        if crate::graph::infer(iop, &[ta, tb]).is_none() {
            let what = if matches!(iop, Op::Lt | Op::Le | Op::Gt | Op::Ge | Op::Eq | Op::Ne) {
                "comparisons take two numbers"
            } else {
                "arithmetic takes numbers or vectors of the same size (a number broadcasts)"
            };
            return Err(self.error(
                Diagnostic::error(
                    span,
                    format!(
                        "`{}` cannot combine {} and {}",
                        op.symbol(),
                        ta.user_name(),
                        tb.user_name()
                    ),
                )
                .with_label(what)
                .with_secondary(l.span, ta.user_name())
                .with_secondary(r.span, tb.user_name()),
            ));
        }
        Ok(Val::Num(self.g.add(iop, &[a, b], span)))
    }

    /// `a | b | c` and `a & b & c`: one n-ary union or intersection of the operands (the
    /// parser gives the chain as one node, so long chains stay off the stack).
    fn shape_chain(
        &mut self,
        op: BinaryOp,
        operands: &[&'a Expr],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        let mut children = Vec::new();
        let mut failed = false;
        let what = if op == BinaryOp::Or {
            "`|` (union)"
        } else {
            "`&` (intersection)"
        };
        for &o in operands {
            match self.expr(o, scope) {
                Ok(Val::Shape(s)) => children.push(s),
                Ok(Val::Poison) | Err(_) => failed = true,
                Ok(other) => {
                    let d = self.describe(&other);
                    let hint = if op == BinaryOp::Or {
                        "`|` joins shapes; comparisons and logic on numbers go through `select(a, b, cond)`"
                    } else {
                        "`&` intersects shapes"
                    };
                    self.error(
                        Diagnostic::error(o.span, format!("{what} needs shapes, found {d}"))
                            .with_label("not a shape")
                            .with_hint(hint),
                    );
                    failed = true;
                }
            }
        }
        if failed {
            return Err(Reported);
        }
        let cop = if op == BinaryOp::Or {
            CombineOp::Union
        } else {
            CombineOp::Intersect
        };
        let kind = ShapeKind::Combine {
            op: cop,
            smooth: None,
            children,
        };
        Ok(Val::Shape(self.shape(kind, span)))
    }

    fn swizzle(
        &mut self,
        inner: &'a Expr,
        letters: &Ident,
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        let v = self.expr(inner, scope)?;
        let n = match v {
            Val::Num(n) if matches!(self.g.ty(n), Ty::Vec2 | Ty::Vec3) => n,
            Val::Poison => return Err(Reported),
            other => {
                let d = self.describe(&other);
                return Err(self.error(
                    Diagnostic::error(letters.span, format!("`.{}` needs a vector, found {d}", letters.name))
                        .with_label("swizzle")
                        .with_hint("swizzles select components of vec2 and vec3 values; methods need parentheses, `.f()`"),
                ));
            }
        };
        let width = self.g.ty(n).width();
        let mut idx = Vec::new();
        for c in letters.name.chars() {
            match "xyz".find(c) {
                Some(i) if i < width => idx.push(i as u8),
                _ => idx.clear(),
            }
            if idx.is_empty() {
                break;
            }
        }
        if idx.is_empty() || idx.len() > 3 {
            let (comps, example) = if width == 2 {
                ("x and y", ".yx")
            } else {
                ("x, y and z", ".xz")
            };
            return Err(self.error(
                Diagnostic::error(
                    letters.span,
                    format!(
                        "`.{}` is not a swizzle of {}",
                        letters.name,
                        self.g.ty(n).user_name()
                    ),
                )
                .with_label("unknown component")
                .with_hint(format!(
                    "use 1 to 3 of the letters {comps}, such as `{example}`"
                )),
            ));
        }
        Ok(Val::Num(self.g.add(
            Op::Swizzle(Swizzle::new(&idx)),
            &[n],
            span,
        )))
    }

    /// A call: a user `fn` (inlined) or a built-in.
    pub fn call(
        &mut self,
        callee: &'a Ident,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        self.check_size(span)?;
        match self.lookup(&callee.name, scope) {
            Some(Val::Func(def)) => return self.inline(&def, args, span, scope),
            Some(Val::Poison) => return Err(Reported),
            Some(other) => {
                let d = self.describe(&other);
                return Err(self.error(
                    Diagnostic::error(
                        callee.span,
                        format!("`{}` is {d}, not a function", callee.name),
                    )
                    .with_label("called here"),
                ));
            }
            None => {}
        }
        self.builtin_call(callee, args, span, scope)
    }

    fn inline(
        &mut self,
        def: &Rc<super::scope::FnDef<'a>>,
        args: &'a [Arg],
        span: Span,
        scope: &Rc<Scope<'a>>,
    ) -> R<Val<'a>> {
        if self.call_stack.contains(&def.index) {
            return Err(self.error(
                Diagnostic::error(span, format!("recursion through fn `{}`", def.name.name))
                    .with_label("this call re-enters the function")
                    .with_secondary(def.span, "defined here")
                    .with_hint("sdfc inlines every fn, so a fn may not call itself, directly or through another fn"),
            ));
        }
        self.count_inlined_call(span)?;
        self.called.insert(def.index);
        let names: Vec<&str> = def.params.iter().map(|p| p.name.name.as_str()).collect();
        let required = def
            .params
            .iter()
            .take_while(|p| p.default.is_none())
            .count();
        let signature = format!("{}({})", def.name.name, names.join(", "));
        let bound = self.bind_args(&def.name.name, &signature, &names, required, args, span)?;
        // Arguments are evaluated in the caller's scope, defaults in the fn's own scope
        // (where the parameters before them are already bound).
        let mut vals = Vec::new();
        for b in &bound {
            vals.push(match b {
                Some(e) => Some(self.expr(e, scope)?),
                None => None,
            });
        }
        let mut fn_scope = Scope {
            locals: Vec::new(),
            parent: None,
            visible: def.index + 1,
        };
        for (p, v) in def.params.iter().zip(vals) {
            let v = match (v, &p.default) {
                (Some(v), _) => v,
                (None, Some(d)) => {
                    let s = Rc::new(Scope {
                        locals: fn_scope.locals.clone(),
                        parent: None,
                        visible: def.index,
                    });
                    self.expr(d, &s)?
                }
                (None, None) => return Err(Reported),
            };
            fn_scope.locals.push((p.name.name.as_str(), v));
        }
        self.call_stack.push(def.index);
        let out = self.expr(def.body, &Rc::new(fn_scope));
        self.call_stack.pop();
        out
    }

    /// A description of a value for messages: "a number", "a shape", "a function".
    pub fn describe(&self, v: &Val<'a>) -> String {
        match v {
            Val::Num(n) => self.g.ty(*n).user_name().to_string(),
            Val::Shape(_) => "a shape".into(),
            Val::Lambda(_) => "a lambda".into(),
            Val::Func(_) => "a function".into(),
            Val::Poison => "an invalid value".into(),
        }
    }

    fn expect_operand(&mut self, v: Val<'a>, span: Span, op: BinaryOp) -> R<NodeId> {
        match v {
            Val::Num(n) if self.g.ty(n) != Ty::Bool => Ok(n),
            Val::Poison => Err(Reported),
            other => {
                let d = self.describe(&other);
                let is_bool = matches!(other, Val::Num(n) if self.g.ty(n) == Ty::Bool);
                let hint = match (&other, op) {
                    _ if is_bool => "a comparison gives a boolean, which only `select(a, b, cond)` takes",
                    (Val::Shape(_), BinaryOp::Add) => "to join shapes write `a | b` or `union(a, b)`",
                    (Val::Shape(_), _) => "shapes combine with `|`, `&` and `-`; transform them with `.scale(f)`, `.translate(v)`",
                    _ => "arithmetic takes numbers and vectors",
                };
                Err(self.error(
                    Diagnostic::error(
                        span,
                        format!("`{}` needs a number or vector here, found {d}", op.symbol()),
                    )
                    .with_label("operand")
                    .with_hint(hint),
                ))
            }
        }
    }

    pub fn expect_num(&mut self, v: Val<'a>, span: Span, what: &str) -> R<NodeId> {
        match v {
            Val::Num(n) if self.g.ty(n) == Ty::F32 => Ok(n),
            Val::Poison => Err(Reported),
            other => {
                let d = self.describe(&other);
                let mut diag =
                    Diagnostic::error(span, format!("{what} must be a number, found {d}"))
                        .with_label("expected a number");
                if what == super::WHAT_SMOOTH && matches!(other, Val::Shape(_)) {
                    diag = diag.with_hint("`smooth` is a blend radius; to combine more shapes, make them one first: `subtract(a, union(b, c))`");
                } else if matches!(other, Val::Num(n) if self.g.ty(n) == Ty::Bool) {
                    diag = diag.with_hint(
                        "a boolean (a comparison, `true` or `false`) is not a number; to pick a number by one, write `select(a, b, cond)` (b where cond holds, else a)",
                    );
                }
                Err(self.error(diag))
            }
        }
    }

    pub fn expect_shape(&mut self, v: Val<'a>, span: Span, what: &str) -> R<ShapeId> {
        match v {
            Val::Shape(s) => Ok(s),
            Val::Poison => Err(Reported),
            other => {
                let d = self.describe(&other);
                Err(self.error(
                    Diagnostic::error(span, format!("{what} must be a shape, found {d}"))
                        .with_label("expected a shape")
                        .with_hint(
                            "shapes come from calls such as `sphere(1)` or `box([1, 2, 1])`",
                        ),
                ))
            }
        }
    }

    /// The value of a node if it depends on constants only (folded with f32 semantics).
    pub fn const_of(&mut self, n: NodeId) -> Option<Value<f32>> {
        if let Some(v) = self.const_memo.get(&n) {
            return *v;
        }
        let node = *self.g.node(n);
        let out = match node.op {
            Op::Const(c) => Some(c.to_value()),
            op if op.is_input() => None,
            op => {
                let mut args = Vec::new();
                for a in node.args() {
                    args.push(self.const_of(*a)?);
                }
                Some(eval::apply(op, node.ty, &args))
            }
        };
        self.const_memo.insert(n, out);
        out
    }

    /// Evaluates an expression that must be a compile-time constant.
    pub fn const_value(&mut self, e: &'a Expr, scope: &Rc<Scope<'a>>, what: &str) -> R<Value<f32>> {
        let v = self.expr(e, scope)?;
        let n = match v {
            Val::Num(n) => n,
            Val::Poison => return Err(Reported),
            other => {
                let d = self.describe(&other);
                let mut diag = Diagnostic::error(
                    e.span,
                    format!("{what} must be a constant value, found {d}"),
                )
                .with_label("expected a number or vector");
                if what == super::WHAT_PARAM_DEFAULT && matches!(other, Val::Shape(_)) {
                    diag = diag.with_hint("a param is a number or vector that a render can change; name a shape with `let`, and give it a param as its size: `param r = 1; let blob = sphere(r);`");
                }
                return Err(self.error(diag));
            }
        };
        match self.const_of(n) {
            Some(c) if c.all_finite() => Ok(c),
            Some(_) => Err(self.error(
                Diagnostic::error(e.span, format!("{what} is not finite"))
                    .with_label("evaluates to infinity or NaN")
                    .with_hint(super::NOT_FINITE_HINT),
            )),
            None => Err(self.error(
                Diagnostic::error(e.span, format!("{what} must be a constant"))
                    .with_label("depends on a `param` or `time`")
                    .with_hint("only shape arguments may use params and time"),
            )),
        }
    }
}
