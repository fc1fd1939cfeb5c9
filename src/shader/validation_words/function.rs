//! Words for what fails in a function or entry point: its statements,
//! calls and the globals it uses.

use std::cell::Cell;

use naga::common::wgsl::TryToWgsl as _;
use naga::valid::{CallError, EntryPointError, ExpressionError, FunctionError, GlobalUse, LocalVariableError, VaryingError};
use naga::{Block, Expression, Function, Handle, Module, Span, Statement, TypeInner};

use super::{var_decl, Said, Words};

impl Words<'_> {
    pub(super) fn entry_point(&self, e: &EntryPointError) -> Said {
        match e {
            EntryPointError::Function(f) => self.function(f),
            EntryPointError::InvalidGlobalUsage(g, usage) => self.global_usage(*g, *usage),
            EntryPointError::BindingCollision(g) => {
                let var = &self.module.global_variables[*g];
                let name = var.name.as_deref().unwrap_or("?");
                let slot = var.binding.as_ref().map(|b| format!("@group({}) @binding({})", b.group, b.binding));
                let span = self.module.global_variables.get_span(*g);
                (Some(span), format!("`{name}` uses {}, as another resource does", slot.unwrap_or_default()))
            }
            EntryPointError::Argument(i, v) => {
                let func = self.func;
                let name = func.and_then(|f| f.arguments.get(*i as usize)).and_then(|a| a.name.clone());
                let span = func.and_then(|f| {
                    f.expressions.iter().find(|(_, e)| matches!(e, Expression::FunctionArgument(a) if a == i))
                });
                let span = span.and_then(|(h, _)| func.map(|f| f.expressions.get_span(h)));
                (span, format!("parameter `{}`: {}", name.unwrap_or_default(), self.varying(v)))
            }
            EntryPointError::Result(v) => (None, format!("the result: {}", self.varying(v))),
            other => self.naga(other),
        }
    }

    pub(super) fn varying(&self, e: &VaryingError) -> String {
        match e {
            VaryingError::InvalidBuiltInType(b, inner) => {
                let b = b.try_to_wgsl().unwrap_or("this builtin");
                format!("@builtin({b}) cannot have type {}", self.inner(inner))
            }
            VaryingError::InvalidType(t) | VaryingError::NotIOShareableType(t) => {
                format!("type {} cannot be passed in or out of an entry point", self.ty(*t))
            }
            other => self.naga(other).1,
        }
    }

    /// A global used against its access mode, placed at the use.
    pub(super) fn global_usage(&self, g: Handle<naga::GlobalVariable>, usage: GlobalUse) -> Said {
        let var = &self.module.global_variables[g];
        let name = var.name.as_deref().unwrap_or("?");
        let ty = self.ty(var.ty);
        let bad = usage.difference(allowed_use(self.module, var));
        let write = bad.contains(GlobalUse::WRITE);
        let verb = if write { "written" } else if bad.contains(GlobalUse::READ) { "read" } else { "used this way" };
        let mut said = format!("`{name}` is {ty}, which cannot be {verb}");
        let mut span = Some(self.module.global_variables.get_span(g));
        let functions = self.func.map(|f| reachable(self.module, f)).unwrap_or_default();
        for f in functions {
            let at = |h: Handle<Expression>| root(f, h) == Some(g);
            let site = if write {
                find_statement(&f.body, &|s| match *s {
                    Statement::ImageStore { image, .. } => at(image),
                    Statement::Store { pointer, .. } | Statement::Atomic { pointer, .. } => at(pointer),
                    _ => false,
                })
            } else {
                f.expressions
                    .iter()
                    .find(|(_, e)| match **e {
                        Expression::ImageLoad { image, .. } | Expression::ImageSample { image, .. } => at(image),
                        Expression::Load { pointer } => at(pointer),
                        _ => false,
                    })
                    .map(|(h, _)| f.expressions.get_span(h))
            };
            if let Some(site) = site.filter(Span::is_defined) {
                span = Some(site);
                if !std::ptr::eq(f, self.func.unwrap_or(f)) {
                    said.push_str(&format!(", but fn `{}` does so", f.name.as_deref().unwrap_or("?")));
                }
                break;
            }
        }
        (span, said)
    }

    pub(super) fn function(&self, e: &FunctionError) -> Said {
        use FunctionError as F;
        match e {
            F::Expression { handle, source } => {
                let (span, said) = self.expression(Some(*handle), source);
                (span.or(Some(self.expr_span(*handle))), said)
            }
            F::LocalVariable { handle, name, source } => {
                let Some(func) = self.func else { return self.naga(e) };
                let var = &func.local_variables[*handle];
                let said = match source {
                    LocalVariableError::InvalidType(t) => format!("a variable cannot hold a {}", self.ty(*t)),
                    LocalVariableError::InitializerType => match var.init.and_then(|i| self.type_of(i)) {
                        Some(init) => format!("it is {} but is initialized with a {init}", self.ty(var.ty)),
                        None => format!("its initializer is not a {}", self.ty(var.ty)),
                    },
                    other => self.naga(other).1,
                };
                (Some(func.local_variables.get_span(*handle)), format!("`var {name}`: {said}"))
            }
            F::InvalidReturnType { expression, expected_ty } => {
                let at = self.statement(|s| matches!(s, Statement::Return { value } if value == expression));
                match (expression, expected_ty) {
                    (Some(v), Some(t)) => {
                        let said = format!("this `return` gives {}, but the function returns {}", self.value(*v), self.ty(*t));
                        (at.or_else(|| self.use_span(*v, None)), said)
                    }
                    (None, Some(t)) => match at.filter(Span::is_defined) {
                        Some(at) => (Some(at), format!("`return;` gives no value, but the function returns {}", self.ty(*t))),
                        None => {
                            // The `return` naga adds at the end: the closing brace.
                            let end = self.fn_span.to_range().map(|r| Span::new(r.end as u32 - 1, r.end as u32));
                            (end, format!("the function can end without a `return`, but it returns {}", self.ty(*t)))
                        }
                    },
                    (Some(v), None) => {
                        let said = format!("this `return` gives {}, but the function declares no return type", self.value(*v));
                        (at.or_else(|| self.use_span(*v, None)), said)
                    }
                    (None, None) => self.naga(e),
                }
            }
            F::InvalidIfType(c) => {
                let at = self.statement(|s| matches!(s, Statement::If { condition, .. } if condition == c));
                (self.use_span(*c, at), format!("the `if` condition {} is not a bool", self.value(*c)))
            }
            F::InvalidSwitchType(c) => {
                let at = self.statement(|s| matches!(s, Statement::Switch { selector, .. } if selector == c));
                (self.use_span(*c, at), format!("the `switch` selector {} is not an i32 or u32", self.value(*c)))
            }
            F::InvalidStorePointer(p) => {
                // naga names the whole target (read-only memory) or the part
                // of it that is no variable (`f()[0] = ..`: the call).
                let Some(func) = self.func else { return self.naga(e) };
                let at = self.statement(|s| matches!(s, Statement::Store { pointer, .. } if base(func, *pointer) == base(func, *p)));
                let why = match func.expressions[base(func, *p)] {
                    Expression::GlobalVariable(g) => {
                        let var = &self.module.global_variables[g];
                        let space = var_decl(var.space).unwrap_or_else(|| self.ty(var.ty));
                        format!("`{}` is {space}, which is read-only", var.name.as_deref().unwrap_or("?"))
                    }
                    Expression::FunctionArgument(_) | Expression::LocalVariable(_) => "it is read-only".into(),
                    _ => "it is not a variable or part of one".into(),
                };
                (at, format!("cannot assign to {}: {why}", self.text(*p)))
            }
            F::InvalidStoreTexture { actual, actual_ty } => {
                let at = self.statement(|s| matches!(s, Statement::ImageStore { image, .. } if image == actual));
                let said = format!("textureStore needs a storage texture, but {} is {}", self.text(*actual), self.inner(actual_ty));
                (at, said)
            }
            F::InvalidStoreValue { actual, actual_ty, expected_ty } => {
                let texture = Cell::new(None);
                let at = self.statement(|s| match s {
                    Statement::ImageStore { image, value, .. } if value == actual => {
                        texture.set(Some(*image));
                        true
                    }
                    _ => false,
                });
                let texture = match texture.get() {
                    Some(t) => format!("{} ({})", self.text(t), self.type_of(t).unwrap_or_default()),
                    None => "the texture".into(),
                };
                let said = format!(
                    "textureStore into {texture} takes a {} value, but {} is {}",
                    self.inner(expected_ty),
                    self.text(*actual),
                    self.inner(actual_ty)
                );
                (at, said.replace(" ()", ""))
            }
            F::InvalidStoreTypes { pointer, value } => {
                let at = self.statement(|s| matches!(s, Statement::Store { pointer: p, value: v } if p == pointer && v == value));
                let target = self.type_of(*pointer).map(|t| format!(" ({t})")).unwrap_or_default();
                (at, format!("cannot assign {} to {}{target}", self.value(*value), self.text(*pointer)))
            }
            F::InvalidImageStore(source) => {
                let culprit = match *source {
                    ExpressionError::InvalidImageCoordinateType(_, h) | ExpressionError::InvalidImageArrayIndexType(h) => Some(h),
                    _ => None,
                };
                let at = self.statement(|s| match *s {
                    Statement::ImageStore { coordinate, array_index, .. } => {
                        culprit.is_some_and(|h| h == coordinate || Some(h) == array_index)
                    }
                    _ => false,
                });
                let (span, said) = self.expression(None, source);
                (span.or_else(|| culprit.and_then(|h| self.use_span(h, at))), format!("textureStore: {said}"))
            }
            F::InvalidCall { function, error } => self.call(*function, error),
            other => self.naga(other),
        }
    }

    pub(super) fn call(&self, f: Handle<Function>, e: &CallError) -> Said {
        let callee = &self.module.functions[f];
        let name = callee.name.as_deref().unwrap_or("?");
        match e {
            CallError::ArgumentCount { required, seen } => {
                let at = self.statement(
                    |s| matches!(s, Statement::Call { function, arguments, .. } if *function == f && arguments.len() == *seen),
                );
                let s = if *required == 1 { "" } else { "s" };
                (at, format!("`{name}` takes {required} argument{s}, but this call passes {seen}"))
            }
            CallError::ArgumentType { index, required, seen_expression } => {
                let at = self.statement(|s| match s {
                    Statement::Call { function, arguments, .. } => {
                        *function == f && arguments.get(*index) == Some(seen_expression)
                    }
                    _ => false,
                });
                let param = callee.arguments.get(*index).and_then(|a| a.name.as_deref()).unwrap_or("?");
                let said = format!(
                    "argument {} of `{name}` (`{param}`) must be {}, but {} is given",
                    index + 1,
                    self.ty(*required),
                    self.value(*seen_expression)
                );
                (self.use_span(*seen_expression, at), said)
            }
            CallError::Argument { index, source } => {
                let argument = Cell::new(None);
                let at = self.statement(|s| match s {
                    Statement::Call { function, arguments, .. } if *function == f && *index < arguments.len() => {
                        argument.set(Some(arguments[*index]));
                        true
                    }
                    _ => false,
                });
                let (span, said) = self.expression(None, source);
                let span = span.or_else(|| argument.get().and_then(|a| self.use_span(a, at)));
                (span, format!("argument {} of `{name}`: {said}", index + 1))
            }
            other => self.naga(other),
        }
    }
}

/// What a global's declaration lets a shader do with it (as naga judges it).
fn allowed_use(module: &Module, var: &naga::GlobalVariable) -> GlobalUse {
    let storage = |access: naga::StorageAccess| {
        let mut allowed = GlobalUse::QUERY;
        allowed.set(GlobalUse::READ, access.contains(naga::StorageAccess::LOAD));
        allowed.set(GlobalUse::WRITE, access.contains(naga::StorageAccess::STORE));
        allowed.set(GlobalUse::ATOMIC, access.contains(naga::StorageAccess::ATOMIC));
        allowed
    };
    match var.space {
        naga::AddressSpace::Storage { access } => storage(access),
        naga::AddressSpace::Uniform | naga::AddressSpace::Immediate => GlobalUse::READ | GlobalUse::QUERY,
        naga::AddressSpace::Handle => match module.types[var.ty].inner {
            TypeInner::Image { class: naga::ImageClass::Storage { access, .. }, .. } => storage(access),
            _ => GlobalUse::READ | GlobalUse::QUERY,
        },
        _ => GlobalUse::all(),
    }
}

/// The first statement `pred` picks, in source order, nested blocks included.
pub(super) fn find_statement(block: &Block, pred: &dyn Fn(&Statement) -> bool) -> Option<Span> {
    for (statement, span) in block.span_iter() {
        if pred(statement) {
            return Some(*span);
        }
        let inner = match statement {
            Statement::Block(b) => find_statement(b, pred),
            Statement::If { accept, reject, .. } => find_statement(accept, pred).or_else(|| find_statement(reject, pred)),
            Statement::Switch { cases, .. } => cases.iter().find_map(|c| find_statement(&c.body, pred)),
            Statement::Loop { body, continuing, .. } => {
                find_statement(body, pred).or_else(|| find_statement(continuing, pred))
            }
            _ => None,
        };
        if inner.is_some() {
            return inner;
        }
    }
    None
}

/// What an access path starts from: `data` of `data[i].x`.
fn base(f: &Function, mut h: Handle<Expression>) -> Handle<Expression> {
    while let Expression::Access { base, .. } | Expression::AccessIndex { base, .. } = f.expressions[h] {
        h = base;
    }
    h
}

/// The global a pointer or texture expression starts from.
fn root(f: &Function, h: Handle<Expression>) -> Option<Handle<naga::GlobalVariable>> {
    match f.expressions[base(f, h)] {
        Expression::GlobalVariable(g) => Some(g),
        _ => None,
    }
}

/// `start` and the functions it calls, directly or not, in the order found.
fn reachable<'m>(module: &'m Module, start: &'m Function) -> Vec<&'m Function> {
    fn calls(block: &Block, out: &mut Vec<Handle<Function>>) {
        for statement in block.iter() {
            match statement {
                Statement::Call { function, .. } => out.push(*function),
                Statement::Block(b) => calls(b, out),
                Statement::If { accept, reject, .. } => {
                    calls(accept, out);
                    calls(reject, out);
                }
                Statement::Switch { cases, .. } => cases.iter().for_each(|c| calls(&c.body, out)),
                Statement::Loop { body, continuing, .. } => {
                    calls(body, out);
                    calls(continuing, out);
                }
                _ => {}
            }
        }
    }
    let mut found = vec![start];
    let mut seen = Vec::new();
    let mut i = 0;
    while i < found.len() {
        let mut callees = Vec::new();
        calls(&found[i].body, &mut callees);
        for h in callees {
            if !seen.contains(&h) {
                seen.push(h);
                found.push(&module.functions[h]);
            }
        }
        i += 1;
    }
    found
}
