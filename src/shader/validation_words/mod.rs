//! naga's validation errors in words.
//!
//! naga reports a validation error as a chain of enums (entry point ->
//! function -> expression) that hold handles into the module's arenas and
//! types as `TypeInner`; their `Display` prints those as Debug output
//! (`[3]`, `Some([0])`, `Vector { size: Tri, .. }`) and labels spans with
//! `naga::ir::Expression [3]`. [`word`] walks the chain with the module at
//! hand instead: it names each value by its source text (a `let`'s name, a
//! variable, or the expression as written), writes types as WGSL
//! (`vec3<f32>`, through naga's own `TypeContext`), and picks the span of
//! what fails. A `let` value's span is where it is defined, so a failing
//! *use* of one (an `if` condition, a stored value, a `return`, a call
//! argument) is placed at the statement that uses it.
//!
//! The variants a WGSL shader can reach past naga's front end are worded
//! here; any other is written with naga's text, handles taken out.

use std::cell::Cell;

use naga::common::wgsl::TypeContext;
use naga::valid::ValidationError;
use naga::{Expression, Function, Handle, Module, Span, Statement, TypeInner, WithSpan};

mod expression;
mod function;

use function::find_statement;

/// A validation error in words: where it is and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct Worded {
    /// The failing statement or expression in the expanded text; the
    /// function's own span only when nothing narrower is known, undefined
    /// when naga gave nothing at all.
    pub span: Span,
    /// What is wrong, with WGSL type names and the values' source text.
    pub message: String,
}

/// Words `error`, which naga raised validating `module` (parsed from `text`).
pub fn word(module: &Module, text: &str, error: &WithSpan<ValidationError>) -> Worded {
    let words = Words { module, text, func: None, fn_span: Span::UNDEFINED, fell_back: Cell::new(false) };
    let (span, mut message, fell_back) = match error.as_inner() {
        ValidationError::EntryPoint { name, stage, source } => {
            match module.entry_points.iter().find(|ep| ep.name == *name && ep.stage == *stage) {
                Some(ep) => {
                    let w = Words { func: Some(&ep.function), ..words };
                    let (span, said) = w.entry_point(source);
                    (span, format!("in fn `{name}`: {said}"), w.fell_back.get())
                }
                None => (None, chain(error.as_inner()), true),
            }
        }
        ValidationError::Function { handle, name, source } => {
            let fn_span = module.functions.get_span(*handle);
            let w = Words { func: Some(&module.functions[*handle]), fn_span, ..words };
            let (span, said) = w.function(source);
            (span, format!("in fn `{name}`: {said}"), w.fell_back.get())
        }
        ValidationError::Type { handle, name, source } => {
            let name = if name.is_empty() { words.ty(*handle) } else { name.clone() };
            let said = words.type_error(source);
            (words.type_span(*handle), format!("type `{name}`: {said}"), words.fell_back.get())
        }
        ValidationError::GlobalVariable { handle, name, source } => {
            let said = words.global_error(*handle, source);
            let span = module.global_variables.get_span(*handle);
            (Some(span), format!("`var {name}`: {said}"), words.fell_back.get())
        }
        ValidationError::Constant { name, source, .. } => (None, format!("const `{name}`: {}", chain(source)), true),
        ValidationError::Override { name, source, .. } => {
            (None, format!("override `{name}`: {}", chain(source)), true)
        }
        ValidationError::ConstExpression { handle, source } => {
            let span = module.global_expressions.get_span(*handle);
            let said = words.quote(span).unwrap_or_else(|| "a constant expression".into());
            (Some(span), format!("{said}: {}", chain(source)), true)
        }
        other => (None, chain(other), true),
    };
    if fell_back {
        // naga's labels say more only where we have not said it ourselves.
        for (_, label) in error.spans().filter(|(_, l)| !l.is_empty() && !internal(l)) {
            message.push_str(&format!("; {label}"));
        }
    }
    let span = span.filter(Span::is_defined).unwrap_or_else(|| narrowest(error));
    Worded { span, message }
}

/// naga's most specific span: the smallest, leaving out a whole function's
/// span when there is anything narrower.
fn narrowest(error: &WithSpan<ValidationError>) -> Span {
    let spans: Vec<(Span, &String)> = error.spans().map(|(s, l)| (*s, l)).filter(|(s, _)| s.is_defined()).collect();
    let narrow: Vec<_> = spans.iter().filter(|(_, l)| !l.starts_with("naga::ir::Function")).collect();
    let pool = if narrow.is_empty() { spans.iter().collect() } else { narrow };
    pool.into_iter()
        .min_by_key(|(s, _)| s.to_range().map_or(usize::MAX, |r| r.len()))
        .map_or(Span::UNDEFINED, |(s, _)| *s)
}

/// Whether a naga label is its internals (`naga::ir::Expression [3]`, a Debug dump).
fn internal(label: &str) -> bool {
    label.contains("naga::") || label.contains(" {") || plain(label) != label
}

/// naga's own text for an error and its sources, with handles taken out.
fn chain(e: &dyn std::error::Error) -> String {
    let mut s = plain(&e.to_string());
    let mut cur = e.source();
    while let Some(inner) = cur {
        s.push_str(": ");
        s.push_str(&plain(&inner.to_string()));
        cur = inner.source();
    }
    s
}

/// `text` without naga's handles: ` [3]`, `Some([3])`, and the
/// `naga::valid::Capabilities::` path in capability names.
fn plain(text: &str) -> String {
    /// The length of a handle (`[3]`) at the start of `s`.
    fn handle_at(s: &str) -> Option<usize> {
        let digits = s.strip_prefix('[')?;
        let n = digits.find(|c: char| !c.is_ascii_digit())?;
        (n > 0 && digits[n..].starts_with(']')).then_some(n + 2)
    }
    let text = text.replace("naga::valid::Capabilities::", "");
    let mut out = String::with_capacity(text.len());
    let mut rest = text.as_str();
    while !rest.is_empty() {
        if let Some(n) = rest.strip_prefix("Some(").and_then(handle_at).filter(|&n| rest[5 + n..].starts_with(')')) {
            rest = &rest[5 + n + 1..];
            continue;
        }
        // A handle follows a space or `(`; `member[2]` is an index, kept.
        if out.is_empty() || out.ends_with(' ') || out.ends_with('(') {
            if let Some(n) = handle_at(rest) {
                rest = &rest[n..];
                continue;
            }
        }
        let c = rest.chars().next().unwrap_or(' ');
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    let out = out.replace(" )", ")").replace("()", "");
    out.split(' ').filter(|w| !w.is_empty()).collect::<Vec<_>>().join(" ")
}

/// A type as WGSL is usually written: `texture_storage_2d<rgba32float, write>`
/// (naga writes no space after the comma).
fn spaced(ty: &str) -> String {
    ty.replace(", ", ",").replace(',', ", ")
}

/// How WGSL declares a variable in `space` (`var<storage, read>`); None
/// for textures and samplers, which are declared by their type.
fn var_decl(space: naga::AddressSpace) -> Option<String> {
    match naga::common::wgsl::address_space_str(space) {
        (Some(space), Some(access)) => Some(format!("var<{space}, {access}>")),
        // naga leaves out the default access, `read`.
        (Some("storage"), None) => Some("var<storage, read>".into()),
        (Some(space), None) => Some(format!("var<{space}>")),
        (None, _) => None,
    }
}

/// Types written as WGSL, structs by their names.
struct Names<'a>(&'a Module);

impl TypeContext for Names<'_> {
    fn lookup_type(&self, handle: Handle<naga::Type>) -> &naga::Type {
        &self.0.types[handle]
    }

    fn type_name(&self, handle: Handle<naga::Type>) -> &str {
        self.0.types[handle].name.as_deref().unwrap_or("struct")
    }

    fn write_override<W: std::fmt::Write>(&self, handle: Handle<naga::Override>, out: &mut W) -> std::fmt::Result {
        out.write_str(self.0.overrides[handle].name.as_deref().unwrap_or("an override"))
    }

    fn write_unnamed_struct<W: std::fmt::Write>(&self, inner: &TypeInner, out: &mut W) -> std::fmt::Result {
        let named = self.0.types.iter().find(|(_, t)| t.inner == *inner).and_then(|(_, t)| t.name.as_deref());
        out.write_str(named.unwrap_or("struct"))
    }

    fn write_non_wgsl_inner<W: std::fmt::Write>(&self, _: &TypeInner, out: &mut W) -> std::fmt::Result {
        out.write_str("a reference")
    }
}

/// The walk over one error: the module, and the function it happened in.
struct Words<'a> {
    module: &'a Module,
    text: &'a str,
    func: Option<&'a Function>,
    /// The function's span, where naga has one (not for entry points).
    fn_span: Span,
    /// Whether some part of the error was left in naga's words.
    fell_back: Cell<bool>,
}

type Said = (Option<Span>, String);

impl<'a> Words<'a> {
    /// naga's own text, marked as such.
    fn naga(&self, e: &dyn std::error::Error) -> Said {
        self.fell_back.set(true);
        (None, chain(e))
    }

    fn ty(&self, ty: Handle<naga::Type>) -> String {
        spaced(&Names(self.module).type_to_string(ty))
    }

    fn inner(&self, inner: &TypeInner) -> String {
        let mut s = String::new();
        let _ = Names(self.module).write_type_inner(inner, &mut s);
        spaced(&s)
    }

    /// The source text of a span in backticks, if it is short and on one line.
    fn quote(&self, span: Span) -> Option<String> {
        let text = self.text.get(span.to_range()?)?.trim();
        (!text.is_empty() && text.len() <= 60 && !text.contains('\n')).then(|| format!("`{text}`"))
    }

    /// A function expression's span, a call's widened to its arguments
    /// (naga spans only the callee's name: `select`).
    fn expr_span(&self, h: Handle<Expression>) -> Span {
        let Some(func) = self.func else { return Span::UNDEFINED };
        let span = func.expressions.get_span(h);
        let Some(range) = span.to_range() else { return span };
        let after = &self.text[range.end..];
        if !after.trim_start().starts_with('(') {
            return span;
        }
        let open = range.end + (after.len() - after.trim_start().len());
        let mut depth = 0;
        for (i, c) in self.text[open..].char_indices() {
            match c {
                '(' => depth += 1,
                ')' if depth == 1 => return Span::new(range.start as u32, (open + i + 1) as u32),
                ')' => depth -= 1,
                _ => {}
            }
        }
        span
    }

    /// A value's name as the source says it: `shown`, `data[0]`.
    fn text(&self, h: Handle<Expression>) -> String {
        let Some(func) = self.func else { return "a value".into() };
        if let Some(name) = func.named_expressions.get(&h) {
            return format!("`{name}`");
        }
        let name = match func.expressions[h] {
            Expression::FunctionArgument(i) => func.arguments.get(i as usize).and_then(|a| a.name.clone()),
            Expression::GlobalVariable(g) => self.module.global_variables[g].name.clone(),
            Expression::LocalVariable(l) => func.local_variables[l].name.clone(),
            Expression::Constant(c) => self.module.constants[c].name.clone(),
            Expression::Load { pointer } => return self.text(pointer),
            _ => None,
        };
        name.map(|n| format!("`{n}`"))
            .or_else(|| self.quote(self.expr_span(h)))
            .unwrap_or_else(|| "a value".into())
    }

    /// The WGSL type of a function expression, when naga can work it out;
    /// a reference's (`data[0]`, a `var`) is what it holds.
    fn type_of(&self, h: Handle<Expression>) -> Option<String> {
        let func = self.func?;
        let ctx = naga::proc::ResolveContext::with_locals(self.module, &func.local_variables, &func.arguments);
        let mut typifier = naga::front::Typifier::new();
        typifier.grow(h, &func.expressions, &ctx).ok()?;
        Some(match *typifier.get(h, &self.module.types) {
            TypeInner::Pointer { base, .. } => self.ty(base),
            TypeInner::ValuePointer { size: Some(size), scalar, .. } => self.inner(&TypeInner::Vector { size, scalar }),
            TypeInner::ValuePointer { size: None, scalar, .. } => self.inner(&TypeInner::Scalar(scalar)),
            ref other => self.inner(other),
        })
    }

    /// A value and its type: "`shown` (vec3<f32>)".
    fn value(&self, h: Handle<Expression>) -> String {
        match self.type_of(h) {
            Some(ty) => format!("{} ({ty})", self.text(h)),
            None => self.text(h),
        }
    }

    /// Where a use of `h` fails: `h` itself if it is written there, else
    /// (a `let`, a variable, an argument, no span) the statement using it.
    fn use_span(&self, h: Handle<Expression>, statement: Option<Span>) -> Option<Span> {
        let func = self.func?;
        let elsewhere = func.named_expressions.contains_key(&h)
            || matches!(
                func.expressions[h],
                Expression::FunctionArgument(_)
                    | Expression::GlobalVariable(_)
                    | Expression::LocalVariable(_)
                    | Expression::Load { .. }
            );
        let own = func.expressions.get_span(h);
        if elsewhere || !own.is_defined() {
            statement.or(Some(own))
        } else {
            Some(own)
        }
    }

    /// The span of the first statement of the function that `pred` picks.
    fn statement(&self, pred: impl Fn(&Statement) -> bool) -> Option<Span> {
        find_statement(&self.func?.body, &pred)
    }
}

#[cfg(test)]
mod tests {
    use super::plain;

    #[test]
    fn naga_text_loses_its_handles() {
        assert_eq!(plain("Expression [3] is invalid"), "Expression is invalid");
        assert_eq!(plain("Global variable [1] is used incorrectly"), "Global variable is used incorrectly");
        assert_eq!(plain("The expression Some([2]) does not match"), "The expression does not match");
        // An index is not a handle.
        assert_eq!(plain("Structure member[2] at 4 overlaps"), "Structure member[2] at 4 overlaps");
        assert_eq!(plain("requires the `naga::valid::Capabilities::FLOAT64` flag"), "requires the `FLOAT64` flag");
    }
}
