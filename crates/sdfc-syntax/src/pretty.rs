//! A deterministic, indented S-expression dump of the AST with spans, for golden tests.
//!
//! Every node is `(head ... @start..end` on its own line with its children indented two more
//! spaces below, and the closing parenthesis at the end of its last line. Names carry their
//! own span as `name@start..end` where it differs from the node's.
//!
//! ```text
//! (let blob@4..8 @0..31
//!   (call sphere @11..20
//!     (num 1 @18..19)))
//! ```

use crate::ast::*;
use crate::span::Span;
use std::fmt::Write;

/// Dumps a whole file.
pub fn dump(file: &File) -> String {
    let mut d = Dumper::default();
    d.open("file".to_string());
    for item in &file.items {
        d.item(item);
    }
    d.close();
    d.out.push('\n');
    d.out
}

/// Dumps one expression (the same format as inside [`dump`]).
pub fn dump_expr(expr: &Expr) -> String {
    let mut d = Dumper::default();
    d.expr(expr);
    d.out.push('\n');
    d.out
}

#[derive(Default)]
struct Dumper {
    out: String,
    indent: usize,
}

fn at(span: Span) -> String {
    format!("@{}..{}", span.start, span.end)
}

fn id(ident: &Ident) -> String {
    format!("{}{}", ident.name, at(ident.span))
}

/// Numbers print as Rust's shortest round-trip form: `1`, `0.3`, `0.5235988`, and exponent
/// notation outside [1e-5, 1e16).
fn num(v: f32) -> String {
    let a = v.abs();
    if v == 0.0 || (1e-5..1e16).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:?}")
    }
}

impl Dumper {
    fn open(&mut self, head: String) {
        if !self.out.is_empty() {
            self.out.push('\n');
        }
        for _ in 0..self.indent {
            self.out.push_str("  ");
        }
        self.out.push('(');
        self.out.push_str(&head);
        self.indent += 1;
    }

    fn close(&mut self) {
        self.out.push(')');
        self.indent -= 1;
    }

    fn leaf(&mut self, head: String) {
        self.open(head);
        self.close();
    }

    fn item(&mut self, item: &Item) {
        let s = at(item.span);
        match &item.kind {
            ItemKind::Let { name, value } => {
                self.open(format!("let {} {s}", id(name)));
                self.expr(value);
            }
            ItemKind::Param { name, default } => {
                self.open(format!("param {} {s}", id(name)));
                self.expr(default);
            }
            ItemKind::Fn { name, params, body } => {
                self.open(format!("fn {} {s}", id(name)));
                for p in params {
                    match &p.default {
                        None => self.leaf(format!("param {}", id(&p.name))),
                        Some(e) => {
                            self.open(format!("param {}", id(&p.name)));
                            self.expr(e);
                            self.close();
                        }
                    }
                }
                self.open("body".to_string());
                self.expr(body);
                self.close();
            }
            ItemKind::Material { name, fields } => {
                self.open(format!("material {} {s}", id(name)));
                self.fields(fields);
            }
            ItemKind::Light { kind, fields } => {
                self.open(format!("light {} {s}", id(kind)));
                self.fields(fields);
            }
            ItemKind::Camera { fields } => {
                self.open(format!("camera {s}"));
                self.fields(fields);
            }
            ItemKind::Render { fields } => {
                self.open(format!("render {s}"));
                self.fields(fields);
            }
            ItemKind::Scene { value } => {
                self.open(format!("scene {s}"));
                self.expr(value);
            }
        }
        self.close();
    }

    fn fields(&mut self, fields: &[Field]) {
        for f in fields {
            self.open(format!("field {}", id(&f.name)));
            self.expr(&f.value);
            self.close();
        }
    }

    fn expr(&mut self, e: &Expr) {
        let s = at(e.span);
        match &e.kind {
            ExprKind::Number(v) => self.leaf(format!("num {} {s}", num(*v))),
            ExprKind::Bool(b) => self.leaf(format!("bool {b} {s}")),
            ExprKind::Name(n) if n.span == e.span => self.leaf(format!("name {} {s}", n.name)),
            // A parenthesised name: the name's own span differs.
            ExprKind::Name(n) => self.leaf(format!("name {} {s}", id(n))),
            ExprKind::Vector(elems) => {
                self.open(format!("vec {s}"));
                for x in elems {
                    self.expr(x);
                }
                self.close();
            }
            ExprKind::Unary(UnaryOp::Neg, x) => {
                self.open(format!("neg {s}"));
                self.expr(x);
                self.close();
            }
            ExprKind::Binary(op, l, r) => {
                self.open(format!("{} {s}", op.symbol()));
                self.expr(l);
                self.expr(r);
                self.close();
            }
            ExprKind::Chain(op, operands) => {
                self.open(format!("{} {s}", op.symbol()));
                for x in operands {
                    self.expr(x);
                }
                self.close();
            }
            ExprKind::Call {
                callee,
                args,
                method,
            } => {
                let head = if *method {
                    format!("method {} {s}", id(callee))
                } else if callee.span.start == e.span.start {
                    format!("call {} {s}", callee.name)
                } else {
                    format!("call {} {s}", id(callee))
                };
                self.open(head);
                for a in args {
                    match &a.name {
                        None => self.expr(&a.value),
                        Some(n) => {
                            self.open(format!("named {}", id(n)));
                            self.expr(&a.value);
                            self.close();
                        }
                    }
                }
                self.close();
            }
            ExprKind::Swizzle(x, letters) => {
                self.open(format!("swizzle {} {s}", id(letters)));
                self.expr(x);
                self.close();
            }
            ExprKind::Lambda { params, body } => {
                let mut head = String::from("lambda");
                for p in params {
                    let _ = write!(head, " {}", id(p));
                }
                let _ = write!(head, " {s}");
                self.open(head);
                self.expr(body);
                self.close();
            }
        }
    }
}
