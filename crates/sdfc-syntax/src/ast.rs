//! The abstract syntax tree of a `.sdf` file; every node carries the byte span it came from.

use crate::span::Span;

/// A whole `.sdf` file: its items in source order.
#[derive(Clone, Debug, PartialEq)]
pub struct File {
    pub items: Vec<Item>,
}

/// A name as written, with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

/// One top-level item.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    pub kind: ItemKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ItemKind {
    /// `let NAME = EXPR;`
    Let { name: Ident, value: Expr },
    /// `fn NAME(a, b, c = 1.0) = EXPR;`
    Fn {
        name: Ident,
        params: Vec<FnParam>,
        body: Expr,
    },
    /// `param NAME = EXPR;`
    Param { name: Ident, default: Expr },
    /// `material NAME { FIELD: EXPR, ... }`
    Material { name: Ident, fields: Vec<Field> },
    /// `light KIND { FIELD: EXPR, ... }` (KIND is `point` or `directional`, checked when lowering)
    Light { kind: Ident, fields: Vec<Field> },
    /// `camera { FIELD: EXPR, ... }`
    Camera { fields: Vec<Field> },
    /// `render { FIELD: EXPR, ... }`
    Render { fields: Vec<Field> },
    /// `scene = EXPR;`
    Scene { value: Expr },
}

/// A parameter of a `fn`, with its optional default.
#[derive(Clone, Debug, PartialEq)]
pub struct FnParam {
    pub name: Ident,
    pub default: Option<Expr>,
}

/// `NAME: EXPR` inside a block item.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub name: Ident,
    pub value: Expr,
}

/// An expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    /// A number literal, already rounded once to f32; `deg` literals are converted in f64 first.
    Number(f32),
    Bool(bool),
    /// `[a, b]` or `[a, b, c]` (other lengths are rejected when lowering, with a span).
    Vector(Vec<Expr>),
    /// A bare name.
    Name(Ident),
    Unary(UnaryOp, Box<Expr>),
    Binary(BinaryOp, Box<Expr>, Box<Expr>),
    /// `a | b | c` or `a & b & c` (the op is `Or` or `And`): a chain of one shape operator
    /// as one node, two operands or more. A left-deep tree of `Binary` nodes would be as deep
    /// as the chain is long, and the depth limit would refuse a union of a few hundred shapes
    /// written with `|`. A parenthesised chain on the left joins it, as `union` is
    /// associative; one on the right stays an operand.
    Chain(BinaryOp, Vec<Expr>),
    /// `f(args)`, or `recv.f(args)` with `method: true` and the receiver as the first argument.
    Call {
        callee: Ident,
        args: Vec<Arg>,
        method: bool,
    },
    /// `e.xz` and the like; the swizzle letters are checked when lowering.
    Swizzle(Box<Expr>, Ident),
    /// `|p| EXPR` or `|x, z| EXPR`.
    Lambda {
        params: Vec<Ident>,
        body: Box<Expr>,
    },
}

/// A call argument, positional or `name: value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Arg {
    pub name: Option<Ident>,
    pub value: Expr,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    Neg,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    Add,
    Sub,
    Mul,
    Div,
    /// `%`: floored modulo, as GLSL `mod`.
    Rem,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    /// `&`: intersection of shapes.
    And,
    /// `|`: union of shapes.
    Or,
}

impl BinaryOp {
    /// The operator as written in source.
    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Add => "+",
            BinaryOp::Sub => "-",
            BinaryOp::Mul => "*",
            BinaryOp::Div => "/",
            BinaryOp::Rem => "%",
            BinaryOp::Lt => "<",
            BinaryOp::Le => "<=",
            BinaryOp::Gt => ">",
            BinaryOp::Ge => ">=",
            BinaryOp::Eq => "==",
            BinaryOp::Ne => "!=",
            BinaryOp::And => "&",
            BinaryOp::Or => "|",
        }
    }
}
