//! Front-end values and lexical scopes used while lowering.

use crate::graph::NodeId;
use crate::shape::ShapeId;
use sdfc_syntax::ast::{Expr, FnParam, Ident};
use sdfc_syntax::span::Span;
use std::rc::Rc;

/// What a name or an expression stands for while lowering.
#[derive(Clone, Debug)]
pub enum Val<'a> {
    /// A value-graph node: number, vec2, vec3 or boolean.
    Num(NodeId),
    Shape(ShapeId),
    Lambda(Rc<LambdaVal<'a>>),
    Func(Rc<FnDef<'a>>),
    /// The result of an expression that already reported an error; using it reports nothing
    /// more, so one mistake gives one diagnostic.
    Poison,
}

#[derive(Debug)]
pub struct LambdaVal<'a> {
    pub params: &'a [Ident],
    pub body: &'a Expr,
    pub scope: Rc<Scope<'a>>,
    pub span: Span,
}

#[derive(Debug)]
pub struct FnDef<'a> {
    pub name: &'a Ident,
    pub params: &'a [FnParam],
    pub body: &'a Expr,
    /// Its index among the globals: its body sees the globals before it, and itself (so that
    /// recursion is reported as such rather than as an unknown name).
    pub index: usize,
    pub span: Span,
}

/// A lexical scope: locals (fn parameters, lambda parameters) over the globals defined
/// before `visible`.
#[derive(Debug, Default)]
pub struct Scope<'a> {
    pub locals: Vec<(&'a str, Val<'a>)>,
    pub parent: Option<Rc<Scope<'a>>>,
    pub visible: usize,
}

impl<'a> Scope<'a> {
    pub fn lookup_local(&self, name: &str) -> Option<&Val<'a>> {
        if let Some((_, v)) = self.locals.iter().rev().find(|(n, _)| *n == name) {
            return Some(v);
        }
        self.parent.as_ref().and_then(|p| p.lookup_local(name))
    }

    pub fn local_names(&self, out: &mut Vec<&'a str>) {
        out.extend(self.locals.iter().map(|(n, _)| *n));
        if let Some(p) = &self.parent {
            p.local_names(out);
        }
    }
}
