//! One pipeline's module, specialised before the driver sees it.
//!
//! glint's shaders keep every scene feature's code behind override
//! constants (`if SCENE_TEXTURES { ... }`), and the engine sets them per
//! scene. naga turns the overrides into constants but leaves the `if`s, so
//! the driver receives, inlines and only then deletes all of the dead code.
//! On a CPU driver that front end is most of a pipeline's build time (and so
//! of a shader save's reload latency). Here the overrides are applied, every
//! `if` on a constant is replaced by the branch it takes, and whatever that
//! leaves unreachable (functions, expressions) is compacted away, once, in
//! naga's IR. The result is validated again before it is handed on.

use naga::valid::{ValidationFlags, Validator};
use naga::{Block, Expression, Handle, Literal, Module, ShaderStage, Statement};

use super::Shader;

/// `shader`'s module for one compute entry point with `constants` applied
/// and its constant branches resolved. The error is naga's, in words.
pub fn specialised_module(shader: &Shader, entry: &str, constants: &[(&str, f64)]) -> Result<Module, String> {
    let constants = constants.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    let (module, _) = naga::back::pipeline_constants::process_overrides(&shader.module, &shader.module_info, Some((ShaderStage::Compute, entry)), &constants)
        .map_err(|e| format!("applying the override constants: {e}"))?;
    let mut module = module.into_owned();
    let before = module.functions.len();
    let pruned = prune(&mut module);
    if pruned > 0 {
        naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    }
    debug_assert!(module.functions.len() <= before);
    Validator::new(ValidationFlags::all(), super::capabilities())
        .validate(&module)
        .map_err(|e| format!("the specialised module does not validate: {}", e.emit_to_string("")))?;
    Ok(module)
}

/// Resolves every `if` whose condition is a constant in every function and
/// entry point of `module`; returns how many were resolved.
pub fn prune(module: &mut Module) -> usize {
    let mut count = 0;
    let constant_bools: Vec<Option<bool>> = module
        .constants
        .iter()
        .map(|(_, c)| match module.global_expressions[c.init] {
            Expression::Literal(Literal::Bool(b)) => Some(b),
            _ => None,
        })
        .collect();
    let functions = module.functions.iter_mut().map(|(_, f)| f).chain(module.entry_points.iter_mut().map(|e| &mut e.function));
    for f in functions {
        let mut pruned = 0;
        // Resolving one `if` can decide another (a short-circuit's
        // temporary, then the `if` that reads it): repeat until none is.
        loop {
            let facts = Facts { constants: &constant_bools, locals: stored_once(f, &constant_bools) };
            let mut n = 0;
            prune_block(&mut f.body, &|h| known_bool(&f.expressions, &facts, h, 0), &mut n);
            pruned += n;
            if n == 0 {
                break;
            }
        }
        if pruned > 0 {
            // A `let` inside a removed branch would keep its expression (and
            // any function it calls) alive; names only label the output.
            f.named_expressions.clear();
        }
        count += pruned;
    }
    count
}

/// What is known of a function's booleans: the module's constants, and
/// the compiler's own temporaries that hold one known value.
struct Facts<'a> {
    constants: &'a [Option<bool>],
    locals: Vec<Option<bool>>,
}

/// For each local variable of `f`: its value, where it is one of naga's
/// unnamed temporaries (a short-circuit `a || b` becomes `var t; if !a {
/// t = b; } else { t = true; } if t ...`) stored exactly once, with a
/// known value, and never passed to a function. naga stores such a
/// temporary before it reads it, so every read sees that value.
fn stored_once(f: &naga::Function, constants: &[Option<bool>]) -> Vec<Option<bool>> {
    let mut stores: Vec<(u32, Option<bool>)> = vec![(0, None); f.local_variables.len()];
    let no_locals = Facts { constants, locals: Vec::new() };
    let local_of = |h: Handle<Expression>| match f.expressions[h] {
        Expression::LocalVariable(v) => Some(v.index()),
        _ => None,
    };
    fn walk(block: &Block, visit: &mut dyn FnMut(&Statement)) {
        for s in block.iter() {
            visit(s);
            match s {
                Statement::Block(b) => walk(b, visit),
                Statement::If { accept, reject, .. } => {
                    walk(accept, visit);
                    walk(reject, visit);
                }
                Statement::Loop { body, continuing, .. } => {
                    walk(body, visit);
                    walk(continuing, visit);
                }
                Statement::Switch { cases, .. } => cases.iter().for_each(|c| walk(&c.body, visit)),
                _ => {}
            }
        }
    }
    walk(&f.body, &mut |s| match s {
        Statement::Store { pointer, value } => {
            if let Some(v) = local_of(*pointer) {
                stores[v].0 += 1;
                stores[v].1 = known_bool(&f.expressions, &no_locals, *value, 0);
            }
        }
        Statement::Call { arguments, .. } => {
            for v in arguments.iter().filter_map(|a| local_of(*a)) {
                stores[v].0 += 2;
            }
        }
        _ => {}
    });
    f.local_variables
        .iter()
        .zip(stores)
        .map(|((_, var), (count, value))| if var.name.is_none() && var.init.is_none() && count == 1 { value } else { None })
        .collect()
}

/// The value of a boolean condition where the constants decide it:
/// `!SCENE_TEXTURES || prim == NONE` is true with SCENE_TEXTURES false,
/// whatever `prim` is (naga folds only expressions of constants alone).
fn known_bool(expressions: &naga::Arena<Expression>, facts: &Facts, h: Handle<Expression>, depth: u32) -> Option<bool> {
    use naga::{BinaryOperator, UnaryOperator};
    if depth > 32 {
        return None;
    }
    let known = |e| known_bool(expressions, facts, e, depth + 1);
    match expressions[h] {
        Expression::Literal(Literal::Bool(b)) => Some(b),
        Expression::Constant(c) => facts.constants.get(c.index()).copied().flatten(),
        Expression::Load { pointer } => match expressions[pointer] {
            Expression::LocalVariable(v) => facts.locals.get(v.index()).copied().flatten(),
            _ => None,
        },
        Expression::Unary { op: UnaryOperator::LogicalNot, expr } => known(expr).map(|b| !b),
        Expression::Binary { op: BinaryOperator::LogicalOr, left, right } => match (known(left), known(right)) {
            (Some(true), _) | (_, Some(true)) => Some(true),
            (Some(false), Some(false)) => Some(false),
            _ => None,
        },
        Expression::Binary { op: BinaryOperator::LogicalAnd, left, right } => match (known(left), known(right)) {
            (Some(false), _) | (_, Some(false)) => Some(false),
            (Some(true), Some(true)) => Some(true),
            _ => None,
        },
        _ => None,
    }
}

fn prune_block(block: &mut Block, known: &dyn Fn(Handle<Expression>) -> Option<bool>, count: &mut usize) {
    let old = std::mem::take(block);
    for (statement, span) in old.span_into_iter() {
        let statement = match statement {
            Statement::If { condition, accept, reject } => match known(condition) {
                Some(taken) => {
                    *count += 1;
                    let mut chosen = if taken { accept } else { reject };
                    prune_block(&mut chosen, known, count);
                    Statement::Block(chosen)
                }
                None => {
                    let (mut accept, mut reject) = (accept, reject);
                    prune_block(&mut accept, known, count);
                    prune_block(&mut reject, known, count);
                    Statement::If { condition, accept, reject }
                }
            },
            Statement::Block(mut b) => {
                prune_block(&mut b, known, count);
                Statement::Block(b)
            }
            Statement::Loop { mut body, mut continuing, break_if } => {
                prune_block(&mut body, known, count);
                prune_block(&mut continuing, known, count);
                Statement::Loop { body, continuing, break_if }
            }
            Statement::Switch { selector, mut cases } => {
                for c in &mut cases {
                    prune_block(&mut c.body, known, count);
                }
                Statement::Switch { selector, cases }
            }
            other => other,
        };
        let ends = terminates(&statement);
        block.push(statement, span);
        if ends {
            // What follows can never run (a resolved `if` that returns
            // leaves the rest of its function dead, calls and all).
            return;
        }
    }
}

/// Whether control never goes past `statement`.
fn terminates(statement: &Statement) -> bool {
    match statement {
        Statement::Return { .. } | Statement::Kill | Statement::Break | Statement::Continue => true,
        Statement::Block(b) => b.last().is_some_and(terminates),
        Statement::If { accept, reject, .. } => accept.last().is_some_and(terminates) && reject.last().is_some_and(terminates),
        _ => false,
    }
}

#[cfg(test)]
mod tests;
