//! Binding call arguments (positional, then named) to a signature, with clear errors.

use super::{Lowerer, Reported, R};
use sdfc_syntax::ast::{Arg, Expr};
use sdfc_syntax::diag::{nearest, Diagnostic};
use sdfc_syntax::span::Span;

impl<'a> Lowerer<'a> {
    /// Binds `args` to the parameters `names`, the first `required` of which must be given.
    /// Returns one expression (or `None` for an omitted optional) per parameter.
    pub fn bind_args(
        &mut self,
        fname: &str,
        signature: &str,
        names: &[&str],
        required: usize,
        args: &'a [Arg],
        span: Span,
    ) -> R<Vec<Option<&'a Expr>>> {
        self.check_named_last(args)?;
        let mut out: Vec<Option<&'a Expr>> = vec![None; names.len()];
        let mut ok = true;
        for (i, a) in args.iter().enumerate() {
            match &a.name {
                None => {
                    if i >= names.len() {
                        self.error(
                            Diagnostic::error(
                                a.value.span,
                                format!(
                                    "`{fname}` takes {} argument{}, found {}",
                                    names.len(),
                                    if names.len() == 1 { "" } else { "s" },
                                    args.len()
                                ),
                            )
                            .with_label("extra argument")
                            .with_hint(format!("the signature is `{signature}`")),
                        );
                        ok = false;
                        break;
                    }
                    out[i] = Some(&a.value);
                }
                Some(n) => match names.iter().position(|x| *x == n.name) {
                    Some(k) if out[k].is_some() => {
                        self.error(
                            Diagnostic::error(
                                n.span,
                                format!("argument `{}` is given twice", n.name),
                            )
                            .with_label("again here")
                            .with_hint(format!("the signature is `{signature}`")),
                        );
                        ok = false;
                    }
                    Some(k) => out[k] = Some(&a.value),
                    None => {
                        let mut d = Diagnostic::error(
                            n.span,
                            format!("`{fname}` has no parameter `{}`", n.name),
                        )
                        .with_label("unknown argument name");
                        d = match nearest(&n.name, names.iter().copied()) {
                            Some(s) => d.with_hint(format!(
                                "did you mean `{s}`? the signature is `{signature}`"
                            )),
                            None => d.with_hint(format!("the signature is `{signature}`")),
                        };
                        self.error(d);
                        ok = false;
                    }
                },
            }
        }
        if !ok {
            return Err(Reported);
        }
        let missing: Vec<&str> = (0..required)
            .filter(|&k| out[k].is_none())
            .map(|k| names[k])
            .collect();
        if !missing.is_empty() {
            let list = missing
                .iter()
                .map(|m| format!("`{m}`"))
                .collect::<Vec<_>>()
                .join(", ");
            return Err(self.error(
                Diagnostic::error(span, format!("`{fname}` is missing {list}"))
                    .with_label(format!(
                        "{} argument{} missing",
                        missing.len(),
                        if missing.len() == 1 { "" } else { "s" }
                    ))
                    .with_hint(format!("the signature is `{signature}`")),
            ));
        }
        Ok(out)
    }

    /// Binds a variadic call such as `union(a, b, c, smooth: k)`: every positional argument
    /// goes to the list, named ones to `names`.
    pub fn bind_variadic(
        &mut self,
        fname: &str,
        signature: &str,
        min: usize,
        names: &[&str],
        args: &'a [Arg],
        span: Span,
    ) -> R<(Vec<&'a Expr>, Vec<Option<&'a Expr>>)> {
        self.check_named_last(args)?;
        let positional: Vec<&'a Expr> = args
            .iter()
            .filter(|a| a.name.is_none())
            .map(|a| &a.value)
            .collect();
        let named: Vec<&'a Arg> = args.iter().filter(|a| a.name.is_some()).collect();
        if positional.len() < min {
            return Err(self.error(
                Diagnostic::error(
                    span,
                    format!(
                        "`{fname}` needs at least {min} shape{}, found {}",
                        if min == 1 { "" } else { "s" },
                        positional.len()
                    ),
                )
                .with_label("too few arguments")
                .with_hint(format!("the signature is `{signature}`")),
            ));
        }
        let mut out = vec![None; names.len()];
        for a in named {
            let n = a.name.as_ref().ok_or(Reported)?;
            match names.iter().position(|x| *x == n.name) {
                Some(k) => out[k] = Some(&a.value),
                None => {
                    let mut d = Diagnostic::error(
                        n.span,
                        format!("`{fname}` has no parameter `{}`", n.name),
                    )
                    .with_label("unknown argument name");
                    if let Some(s) = nearest(&n.name, names.iter().copied()) {
                        d = d.with_hint(format!("did you mean `{s}`?"));
                    }
                    return Err(self.error(d));
                }
            }
        }
        Ok((positional, out))
    }

    fn check_named_last(&mut self, args: &'a [Arg]) -> R<()> {
        let mut named_seen: Option<Span> = None;
        for a in args {
            match (&a.name, named_seen) {
                (Some(n), None) => named_seen = Some(n.span),
                (None, Some(prev)) => {
                    return Err(self.error(
                        Diagnostic::error(a.value.span, "a positional argument after a named one")
                            .with_label("positional")
                            .with_secondary(prev, "named argument before it")
                            .with_hint("named arguments come last: `f(a, b, name: value)`"),
                    ))
                }
                _ => {}
            }
        }
        Ok(())
    }
}
