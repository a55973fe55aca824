//! Builds the AST of one item from the tree parser's pairs (`grammar/tree.pest`): binary
//! operators and postfix forms through pest's PrattParser, unary minus as a loop, number
//! literals converted (and checked) here.
//! Also enforces the depth limits that keep every later recursive pass off the stack limit.

use crate::ast::*;
use crate::diag::Diagnostic;
use crate::grammar::tree::Rule;
use crate::span::Span;
use crate::MAX_EXPR_DEPTH;
use pest::iterators::{Pair, Pairs};
use pest::pratt_parser::{Assoc, Op, PrattParser};
use std::cell::RefCell;

/// The binary operators, lowest precedence first; each line is one level, all left-associative.
/// Postfix forms (`.f(args)`, `.x`) bind tighter than any of them: the tree parser leaves a
/// term's postfix pairs after its primary in the expression's list, where a term has no
/// minus sign (one that has is a `neg_term` pair, built by [`Lower::term`]).
pub(crate) fn pratt() -> PrattParser<Rule> {
    let l = |r| Op::infix(r, Assoc::Left);
    PrattParser::new()
        .op(l(Rule::op_or))
        .op(l(Rule::op_and))
        .op(l(Rule::op_lt)
            | l(Rule::op_le)
            | l(Rule::op_gt)
            | l(Rule::op_ge)
            | l(Rule::op_eq)
            | l(Rule::op_ne))
        .op(l(Rule::op_add) | l(Rule::op_sub))
        .op(l(Rule::op_mul) | l(Rule::op_div) | l(Rule::op_rem))
        .op(Op::postfix(Rule::postfix))
}

/// The error has been recorded in [`Lower::diags`]; unwind the current item.
#[derive(Debug)]
pub(crate) struct Stop;

type R<T> = Result<T, Stop>;

/// An expression with the depth of its tree (a leaf has depth 1).
struct Node {
    expr: Expr,
    depth: usize,
}

pub(crate) struct Lower<'p> {
    /// Where the text pest saw starts in the whole source.
    offset: usize,
    pratt: &'p PrattParser<Rule>,
    pub(crate) diags: RefCell<Vec<Diagnostic>>,
}

impl<'p> Lower<'p> {
    pub(crate) fn new(offset: usize, pratt: &'p PrattParser<Rule>) -> Lower<'p> {
        Lower {
            offset,
            pratt,
            diags: RefCell::new(Vec::new()),
        }
    }

    fn span(&self, pair: &Pair<'_, Rule>) -> Span {
        let s = pair.as_span();
        Span::new(self.offset + s.start(), self.offset + s.end())
    }

    fn ident(&self, pair: &Pair<'_, Rule>) -> Ident {
        Ident {
            name: pair.as_str().to_string(),
            span: self.span(pair),
        }
    }

    fn error(&self, d: Diagnostic) -> Stop {
        self.diags.borrow_mut().push(d);
        Stop
    }

    /// A pair that the grammar should have made impossible.
    fn internal(&self, span: Span, what: &str) -> Stop {
        self.error(
            Diagnostic::error(span, format!("internal parser error: {what}"))
                .with_hint("this is a bug in sdfc; please report it with the input"),
        )
    }

    /// The next pair of the given rule, skipping punctuation.
    fn expect<'i>(&self, pairs: &mut Pairs<'i, Rule>, rule: Rule, at: Span) -> R<Pair<'i, Rule>> {
        for p in pairs.by_ref() {
            if p.as_rule() == rule {
                return Ok(p);
            }
            if !is_punct(p.as_rule()) {
                break;
            }
        }
        Err(self.internal(at, &format!("missing {rule:?}")))
    }

    // -----------------------------------------------------------------------------------------
    // Items

    pub(crate) fn item(&self, pair: Pair<'_, Rule>) -> R<Item> {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        let kind = match rule {
            Rule::let_item => {
                let name = self.ident(&self.expect(&mut inner, Rule::ident, span)?);
                let value = self.expr(self.expect(&mut inner, Rule::expr, span)?)?;
                ItemKind::Let { name, value }
            }
            Rule::param_item => {
                let name = self.ident(&self.expect(&mut inner, Rule::ident, span)?);
                let default = self.expr(self.expect(&mut inner, Rule::expr, span)?)?;
                ItemKind::Param { name, default }
            }
            Rule::scene_item => {
                let value = self.expr(self.expect(&mut inner, Rule::expr, span)?)?;
                ItemKind::Scene { value }
            }
            Rule::fn_item => {
                let name = self.ident(&self.expect(&mut inner, Rule::ident, span)?);
                let mut params = Vec::new();
                let mut body = None;
                let mut failed = false;
                for p in inner {
                    match p.as_rule() {
                        Rule::fn_param => match self.fn_param(p) {
                            Ok(param) => params.push(param),
                            Err(Stop) => failed = true,
                        },
                        Rule::expr => body = Some(self.expr(p)),
                        _ => {}
                    }
                }
                let body = body.ok_or_else(|| self.internal(span, "fn without a body"))??;
                if failed {
                    return Err(Stop);
                }
                ItemKind::Fn { name, params, body }
            }
            Rule::material_item => {
                let name = self.ident(&self.expect(&mut inner, Rule::ident, span)?);
                ItemKind::Material {
                    name,
                    fields: self.fields(inner)?,
                }
            }
            Rule::light_item => {
                let kind = self.ident(&self.expect(&mut inner, Rule::ident, span)?);
                ItemKind::Light {
                    kind,
                    fields: self.fields(inner)?,
                }
            }
            Rule::camera_item => ItemKind::Camera {
                fields: self.fields(inner)?,
            },
            Rule::render_item => ItemKind::Render {
                fields: self.fields(inner)?,
            },
            other => return Err(self.internal(span, &format!("unexpected item {other:?}"))),
        };
        Ok(Item { kind, span })
    }

    fn fn_param(&self, pair: Pair<'_, Rule>) -> R<FnParam> {
        let span = self.span(&pair);
        let mut inner = pair.into_inner();
        let name = self.ident(&self.expect(&mut inner, Rule::param_name, span)?);
        let default = match inner.find(|p| p.as_rule() == Rule::expr) {
            Some(e) => Some(self.expr(e)?),
            None => None,
        };
        Ok(FnParam { name, default })
    }

    /// The fields of a block; every field is checked even after one fails.
    fn fields(&self, pairs: Pairs<'_, Rule>) -> R<Vec<Field>> {
        let mut fields = Vec::new();
        let mut failed = false;
        for p in pairs.filter(|p| p.as_rule() == Rule::field) {
            let span = self.span(&p);
            let mut inner = p.into_inner();
            let field = self
                .expect(&mut inner, Rule::field_name, span)
                .and_then(|n| {
                    let name = self.ident(&n);
                    let value = self.expr(self.expect(&mut inner, Rule::expr, span)?)?;
                    Ok(Field { name, value })
                });
            match field {
                Ok(f) => fields.push(f),
                Err(Stop) => failed = true,
            }
        }
        if failed {
            Err(Stop)
        } else {
            Ok(fields)
        }
    }

    // -----------------------------------------------------------------------------------------
    // Expressions

    fn expr(&self, pair: Pair<'_, Rule>) -> R<Expr> {
        self.expr_node(pair).map(|n| n.expr)
    }

    fn expr_node(&self, pair: Pair<'_, Rule>) -> R<Node> {
        if pair.as_rule() != Rule::expr {
            return Err(self.internal(self.span(&pair), "expected an expression pair"));
        }
        self.pratt
            .map_primary(|operand| match operand.as_rule() {
                Rule::lambda => self.lambda(operand),
                Rule::neg_term => self.term(operand),
                _ => self.primary(operand),
            })
            .map_postfix(|recv, op| self.postfix(recv?, op))
            .map_infix(|lhs, op, rhs| {
                let (lhs, rhs) = (lhs?, rhs?);
                let bin = binary_op(op.as_rule())
                    .ok_or_else(|| self.internal(self.span(&op), "unknown operator"))?;
                let span = lhs.expr.span.to(rhs.expr.span);
                if matches!(bin, BinaryOp::Or | BinaryOp::And) {
                    // A chain of `|` (or `&`) grows one node, so it does not deepen the tree.
                    let (mut operands, depth) = match lhs.expr {
                        Expr {
                            kind: ExprKind::Chain(o, operands),
                            ..
                        } if o == bin => (operands, lhs.depth),
                        expr => (vec![expr], 1 + lhs.depth),
                    };
                    operands.push(rhs.expr);
                    let depth = depth.max(1 + rhs.depth);
                    let kind = ExprKind::Chain(bin, operands);
                    return self.node(kind, span, depth, self.span(&op));
                }
                let depth = 1 + lhs.depth.max(rhs.depth);
                self.node(
                    ExprKind::Binary(bin, Box::new(lhs.expr), Box::new(rhs.expr)),
                    span,
                    depth,
                    self.span(&op),
                )
            })
            .parse(pair.into_inner())
    }

    /// Wraps up a new node, refusing trees deeper than [`MAX_EXPR_DEPTH`]; `at` is where to
    /// point if it is too deep (the operator or name that made it so).
    fn node(&self, kind: ExprKind, span: Span, depth: usize, at: Span) -> R<Node> {
        if depth > MAX_EXPR_DEPTH {
            return Err(self.error(
                Diagnostic::error(
                    at,
                    format!("expression is nested too deeply (more than {MAX_EXPR_DEPTH} levels)"),
                )
                .with_label("too deep from here")
                .with_hint(depth_hint(&kind)),
            ));
        }
        Ok(Node {
            expr: Expr { kind, span },
            depth,
        })
    }

    /// A `neg_term`, `neg+ primary postfix*`: postfix forms apply first (left to right), then
    /// the minus signs (innermost first). Loops, not recursion, so long chains cannot exhaust
    /// the stack.
    fn term(&self, pair: Pair<'_, Rule>) -> R<Node> {
        let term_span = self.span(&pair);
        let mut negs = Vec::new();
        let mut acc: Option<Node> = None;
        for p in pair.into_inner() {
            match p.as_rule() {
                Rule::neg => negs.push(self.span(&p)),
                Rule::postfix => {
                    let recv = acc.take().ok_or_else(|| {
                        self.internal(self.span(&p), "postfix without a receiver")
                    })?;
                    acc = Some(self.postfix(recv, p)?);
                }
                _ => acc = Some(self.primary(p)?),
            }
        }
        let mut node = acc.ok_or_else(|| self.internal(term_span, "empty term"))?;
        for neg in negs.into_iter().rev() {
            let span = neg.to(node.expr.span);
            let depth = node.depth + 1;
            node = self.node(
                ExprKind::Unary(UnaryOp::Neg, Box::new(node.expr)),
                span,
                depth,
                neg,
            )?;
        }
        Ok(node)
    }

    fn postfix(&self, recv: Node, pair: Pair<'_, Rule>) -> R<Node> {
        let pspan = self.span(&pair);
        let mut inner = pair.into_inner();
        let member = self.ident(&self.expect(&mut inner, Rule::member, pspan)?);
        let is_call = inner.clone().any(|p| p.as_rule() == Rule::lparen);
        // Without an argument list the pair's span may include whitespace that pest skipped
        // before trying one, so the node ends at the member name; with one, the pair ends at
        // its `)`.
        let end = if is_call { pspan } else { member.span };
        let span = recv.expr.span.to(member.span).to(end);
        if is_call {
            let (mut args, depth) = self.args(inner)?;
            let depth = depth.max(recv.depth) + 1;
            args.insert(
                0,
                Arg {
                    name: None,
                    value: recv.expr,
                },
            );
            let at = member.span;
            self.node(
                ExprKind::Call {
                    callee: member,
                    args,
                    method: true,
                },
                span,
                depth,
                at,
            )
        } else {
            let at = member.span;
            self.node(
                ExprKind::Swizzle(Box::new(recv.expr), member),
                span,
                recv.depth + 1,
                at,
            )
        }
    }

    /// The arguments among `pairs` (each an `expr`, after its `arg_name` if it has one), and
    /// the depth of the deepest argument value.
    fn args(&self, pairs: Pairs<'_, Rule>) -> R<(Vec<Arg>, usize)> {
        let mut args = Vec::new();
        let mut depth = 0;
        let mut failed = false;
        let mut name = None;
        for p in pairs {
            match p.as_rule() {
                Rule::arg_name => name = Some(self.ident(&p)),
                Rule::expr => match self.expr_node(p) {
                    Ok(v) => {
                        depth = depth.max(v.depth);
                        args.push(Arg {
                            name: name.take(),
                            value: v.expr,
                        });
                    }
                    Err(Stop) => {
                        name = None;
                        failed = true;
                    }
                },
                _ => {}
            }
        }
        if let Some(name) = name {
            return Err(self.internal(name.span, "argument without a value"));
        }
        if failed {
            Err(Stop)
        } else {
            Ok((args, depth))
        }
    }

    fn primary(&self, pair: Pair<'_, Rule>) -> R<Node> {
        let span = self.span(&pair);
        match pair.as_rule() {
            Rule::number => self.number(pair),
            Rule::boolean => self.node(ExprKind::Bool(pair.as_str() == "true"), span, 1, span),
            Rule::name => self.node(ExprKind::Name(self.ident(&pair)), span, 1, span),
            Rule::call => {
                let mut inner = pair.into_inner();
                let callee = self.ident(&self.expect(&mut inner, Rule::callee, span)?);
                let (args, depth) = self.args(inner)?;
                let at = callee.span;
                self.node(
                    ExprKind::Call {
                        callee,
                        args,
                        method: false,
                    },
                    span,
                    depth + 1,
                    at,
                )
            }
            Rule::vector => {
                let mut elems = Vec::new();
                let mut depth = 0;
                let mut failed = false;
                for p in pair.into_inner().filter(|p| p.as_rule() == Rule::expr) {
                    match self.expr_node(p) {
                        Ok(n) => {
                            depth = depth.max(n.depth);
                            elems.push(n.expr);
                        }
                        Err(Stop) => failed = true,
                    }
                }
                if failed {
                    return Err(Stop);
                }
                self.node(
                    ExprKind::Vector(elems),
                    span,
                    depth + 1,
                    Span::new(span.start as usize, span.start as usize + 1),
                )
            }
            Rule::paren => {
                // No node of its own: the inner expression, with the parentheses in its span.
                let mut inner = pair.into_inner();
                let mut node = self.expr_node(self.expect(&mut inner, Rule::expr, span)?)?;
                node.expr.span = span;
                Ok(node)
            }
            other => Err(self.internal(span, &format!("unexpected primary {other:?}"))),
        }
    }

    fn lambda(&self, pair: Pair<'_, Rule>) -> R<Node> {
        let span = self.span(&pair);
        let head = Span::new(span.start as usize, span.start as usize + 1);
        let mut params = Vec::new();
        let mut body = None;
        for p in pair.into_inner() {
            match p.as_rule() {
                Rule::param_name => params.push(self.ident(&p)),
                Rule::expr => body = Some(p),
                _ => {}
            }
        }
        let body = body.ok_or_else(|| self.internal(span, "lambda without a body"))?;
        let body = self.expr_node(body)?;
        // From the first `|` to the end of the body (the pair may end in skipped whitespace).
        let span = head.to(body.expr.span);
        self.node(
            ExprKind::Lambda {
                params,
                body: Box::new(body.expr),
            },
            span,
            body.depth + 1,
            head,
        )
    }

    fn number(&self, pair: Pair<'_, Rule>) -> R<Node> {
        let span = self.span(&pair);
        let text = pair.as_str();
        let split = body_len(text);
        let body = &text[..split];
        let suffix = (split < text.len()).then(|| {
            (
                &text[split..],
                Span::new(span.start as usize + split, span.end as usize),
            )
        });
        let value = match suffix {
            None => body.parse::<f32>().ok(),
            // Degrees: read in f64, convert in f64, round once to f32.
            Some(("deg", _)) => body
                .parse::<f64>()
                .ok()
                .map(|d| (d * (std::f64::consts::PI / 180.0)) as f32),
            Some((other, sspan)) => {
                let hint = if other.starts_with(['e', 'E']) {
                    "an exponent needs digits, as in `1e-4` or `3.2E+2`"
                } else {
                    "the only number suffix is `deg` (degrees, as in `30deg`)"
                };
                return Err(self.error(
                    Diagnostic::error(sspan, format!("unknown number suffix `{other}`"))
                        .with_label("not a number suffix")
                        .with_hint(hint),
                ));
            }
        };
        let Some(value) = value else {
            return Err(self.error(Diagnostic::error(span, "malformed number").with_label("here")));
        };
        if !value.is_finite() {
            return Err(self.error(
                Diagnostic::error(span, "number too large for a 32-bit float")
                    .with_label("too large")
                    .with_hint("the largest 32-bit float is about 3.4e38"),
            ));
        }
        self.node(ExprKind::Number(value), span, 1, span)
    }
}

/// The length of a number token's digits (`num_body` in the grammar): the token is one atomic
/// pair, so that each number costs pest one pair instead of three, and its suffix (any word
/// glued on, as in `30deg`) is split off here. An `e` is part of the body only when digits
/// follow it (after an optional sign), as in the grammar; otherwise it starts the suffix.
fn body_len(text: &str) -> usize {
    let b = text.as_bytes();
    let digits = |mut i: usize| {
        while b.get(i).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
        i
    };
    let mut i = digits(0);
    if b.get(i) == Some(&b'.') {
        i = digits(i + 1);
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        let mut j = i + 1;
        if matches!(b.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let end = digits(j);
        if end > j {
            i = end;
        }
    }
    i
}

/// How to write an expression too deep to parse, by the kind of node that made it so.
fn depth_hint(kind: &ExprKind) -> &'static str {
    match kind {
        // Only `|` and `&` chains stay flat; `-` between shapes nests as arithmetic does.
        ExprKind::Binary(BinaryOp::Sub, ..) => {
            "to cut many shapes out of one, write `subtract(a, union(b, c, ...))` (or \
             `a - (b | c | ...)`); a long sum or difference of numbers can be split with `let` \
             (each `let` starts a new expression)"
        }
        ExprKind::Call { method: true, .. } => {
            "split the chain of calls with `let` (each `let` starts a new expression); \
             consecutive `translate`s add up to one"
        }
        _ => {
            "split it into smaller pieces with `let` (each `let` starts a new expression); \
             for many shapes, `union(a, b, c, ...)` or `a | b | c` rather than nested calls"
        }
    }
}

fn binary_op(rule: Rule) -> Option<BinaryOp> {
    Some(match rule {
        Rule::op_or => BinaryOp::Or,
        Rule::op_and => BinaryOp::And,
        Rule::op_lt => BinaryOp::Lt,
        Rule::op_le => BinaryOp::Le,
        Rule::op_gt => BinaryOp::Gt,
        Rule::op_ge => BinaryOp::Ge,
        Rule::op_eq => BinaryOp::Eq,
        Rule::op_ne => BinaryOp::Ne,
        Rule::op_add => BinaryOp::Add,
        Rule::op_sub => BinaryOp::Sub,
        Rule::op_mul => BinaryOp::Mul,
        Rule::op_div => BinaryOp::Div,
        Rule::op_rem => BinaryOp::Rem,
        _ => return None,
    })
}

/// Keyword and punctuation pairs, which carry no information once the tree is built (the
/// tree parser's other punctuation is silent).
fn is_punct(rule: Rule) -> bool {
    matches!(
        rule,
        Rule::kw_let
            | Rule::kw_fn
            | Rule::kw_param
            | Rule::kw_material
            | Rule::kw_light
            | Rule::kw_camera
            | Rule::kw_render
            | Rule::kw_scene
            | Rule::assign
            | Rule::lparen
    )
}

#[cfg(test)]
mod tests {
    use super::body_len;

    /// The split of a number token into digits and suffix agrees with the grammar's
    /// `num_body`: an exponent needs digits, and a dot is the body's only where the grammar
    /// took it.
    #[test]
    fn number_tokens_split_where_the_digits_end() {
        for (token, body) in [
            ("1", "1"),
            ("1.5", "1.5"),
            (".5", ".5"),
            ("2.", "2."),
            ("1e-4", "1e-4"),
            ("3.2E+2", "3.2E+2"),
            ("30deg", "30"),
            ("1.5e3deg", "1.5e3"),
            ("1e", "1"),
            ("1e+", "1"),
            ("2ex", "2"),
            ("7rad", "7"),
            ("1E5_x", "1E5"),
        ] {
            assert_eq!(&token[..body_len(token)], body, "{token}");
        }
    }
}
