//! Words for a failing expression, and for module-level types and globals.

use naga::common::wgsl::{ToWgsl as _, TryToWgsl as _};
use naga::valid::{ComposeError, ExpressionError, GlobalVariableError, TypeError, WidthError};
use naga::{Expression, Handle, Span};

use super::{plain, var_decl, Said, Words};

impl Words<'_> {
    /// An expression error; `h` is the failing expression, when known.
    pub(super) fn expression(&self, h: Option<Handle<Expression>>, e: &ExpressionError) -> Said {
        use ExpressionError as E;
        let func = self.func;
        let this = h.and_then(|h| func.map(|f| &f.expressions[h]));
        let said = match e {
            E::InvalidBinaryOperandTypes { op, lhs_expr, lhs_type, rhs_expr, rhs_type } => format!(
                "`{}` cannot combine {} ({}) and {} ({})",
                binary(*op),
                self.text(*lhs_expr),
                self.inner(lhs_type),
                self.text(*rhs_expr),
                self.inner(rhs_type)
            ),
            E::InvalidUnaryOperandType(op, v) => {
                let op = match op {
                    naga::UnaryOperator::Negate => "-",
                    naga::UnaryOperator::LogicalNot => "!",
                    naga::UnaryOperator::BitwiseNot => "~",
                };
                format!("`{op}` cannot apply to {}", self.value(*v))
            }
            E::SelectValuesTypeMismatch { accept, reject } => match this {
                Some(Expression::Select { accept: a, reject: r, .. }) => format!(
                    "select's two values differ: {} is {} but {} is {}",
                    self.text(*r),
                    self.inner(reject),
                    self.text(*a),
                    self.inner(accept)
                ),
                _ => format!("select's two values differ: {} and {}", self.inner(reject), self.inner(accept)),
            },
            E::SelectConditionNotABool { actual } => {
                let cond = match this {
                    Some(Expression::Select { condition, .. }) => format!("{} ", self.text(*condition)),
                    _ => String::new(),
                };
                format!("select's condition {cond}is {}, not a bool or a vector of bool", self.inner(actual))
            }
            E::ShiftAmountTooLarge { lhs_type, rhs_expr } => format!(
                "the shift amount {} is not less than the bit width of {}",
                self.text(*rhs_expr),
                self.inner(lhs_type)
            ),
            E::IndexOutOfBounds(base, i) => format!("index {i} is out of bounds for {}", self.value(*base)),
            E::NegativeIndex(base) => format!("negative index into {}", self.value(*base)),
            E::InvalidIndexType(i) => format!("the index {} is not an i32 or u32", self.value(*i)),
            E::InvalidBaseType(b) => format!("{} cannot be indexed", self.value(*b)),
            E::InvalidPointerType(p) => format!("{} is not a reference to memory", self.value(*p)),
            E::InvalidArrayType(a) => format!("arrayLength needs a runtime-sized array, not {}", self.value(*a)),
            E::InvalidSplatType(v) => format!("{} is not a scalar to fill a vector with", self.value(*v)),
            E::InvalidVectorType(v) => format!("{} is not a vector, so it has no components to swizzle", self.value(*v)),
            E::InvalidSwizzleComponent(c, size) => format!(
                "swizzle component `{}` is outside a vec{}",
                ["x", "y", "z", "w"][*c as usize],
                naga::common::vector_size_str(*size)
            ),
            E::Compose(c) => {
                let ty = match this {
                    Some(Expression::Compose { ty, .. }) => self.ty(*ty),
                    _ => "value".into(),
                };
                match c {
                    ComposeError::Type(t) => format!("a {} cannot be constructed", self.ty(*t)),
                    ComposeError::ComponentCount { given, expected } => {
                        format!("a {ty} is built of {expected} components, but {given} are given")
                    }
                    ComposeError::ComponentType { index } => match this {
                        Some(Expression::Compose { components, .. }) if (*index as usize) < components.len() => format!(
                            "component {} of the {ty}, {}, has the wrong type",
                            index + 1,
                            self.value(components[*index as usize])
                        ),
                        _ => format!("component {} of the {ty} has the wrong type", index + 1),
                    },
                }
            }
            E::InvalidZeroValue(t) => format!("{} has no zero value: it cannot be constructed", self.ty(*t)),
            E::InvalidFloatArgument(v) => format!("{} is not a float", self.value(*v)),
            E::InvalidBooleanVector(v) => format!("{} is not a vector of bool", self.value(*v)),
            E::ExpectedImageType(t) => format!("a texture is needed here, not a {}", self.ty(*t)),
            E::ExpectedSamplerType(t) => format!("a sampler is needed here, not a {}", self.ty(*t)),
            E::ExpectedBindingArrayType(t) => format!("a binding_array is needed here, not a {}", self.ty(*t)),
            E::InvalidImageCoordinateType(dim, c) => {
                format!("the texture coordinates {} do not fit a {} texture", self.value(*c), dim.to_wgsl())
            }
            E::InvalidImageArrayIndexType(i) => format!("the texture array index {} is not an i32 or u32", self.value(*i)),
            E::InvalidImageOtherIndexType(i) => {
                format!("the sample or level index {} is not an i32 or u32", self.value(*i))
            }
            E::InvalidSampleOffset(dim, o) => format!("the offset {} does not fit a {} texture", self.value(*o), dim.to_wgsl()),
            E::InvalidDepthReference(d) => format!("the depth reference {} is not an f32", self.value(*d)),
            E::InvalidSampleLevelExactType(l) => format!("the level {} is not an f32 (or i32)", self.value(*l)),
            E::InvalidSampleLevelBiasType(b) => format!("the bias {} is not an f32", self.value(*b)),
            E::InvalidSampleLevelGradientType(dim, g) => {
                format!("the gradient {} does not fit a {} texture", self.value(*g), dim.to_wgsl())
            }
            E::InvalidCastArgument => match this {
                Some(Expression::As { expr, kind, convert }) => {
                    let width = convert.unwrap_or(4);
                    let to = naga::Scalar { kind: *kind, width }.to_wgsl_for_diagnostics();
                    let how = if convert.is_some() { "convert" } else { "bitcast" };
                    format!("cannot {how} {} to {to}", self.value(*expr))
                }
                _ => "this conversion is not possible".into(),
            },
            E::WrongArgumentCount(f) => format!("wrong number of arguments to `{}`", f.try_to_wgsl().unwrap_or("this builtin")),
            E::InvalidArgumentType(f, i, v) => format!(
                "argument {} of `{}`, {}, has a type it does not take",
                i + 1,
                f.try_to_wgsl().unwrap_or("this builtin"),
                self.value(*v)
            ),
            E::UnsupportedWidth(f, kind, width) => format!(
                "`{}` does not take {} arguments yet",
                f.try_to_wgsl().unwrap_or("this builtin"),
                naga::Scalar { kind: *kind, width: *width }.to_wgsl_for_diagnostics()
            ),
            E::InvalidWorkGroupUniformLoadResultType(t) => format!("workgroupUniformLoad cannot load a {}", self.ty(*t)),
            E::Type(r) => self.resolve(r),
            other => return self.naga(other),
        };
        (None, said)
    }

    pub(super) fn resolve(&self, e: &naga::proc::ResolveError) -> String {
        use naga::proc::ResolveError as R;
        match e {
            R::OutOfBoundsIndex { expr, index } => format!("index {index} is out of bounds for {}", self.value(*expr)),
            R::InvalidAccess { expr, .. } => format!("{} cannot be indexed", self.value(*expr)),
            R::InvalidSubAccess { ty, .. } => format!("a {} cannot be indexed", self.ty(*ty)),
            R::InvalidScalar(v) => format!("{} is not a scalar", self.value(*v)),
            R::InvalidVector(v) => format!("{} is not a vector", self.value(*v)),
            R::InvalidPointer(v) => format!("{} is not a reference to memory", self.value(*v)),
            R::InvalidImage(v) => format!("{} is not a texture", self.value(*v)),
            other => self.naga(other).1,
        }
    }

    pub(super) fn type_error(&self, e: &TypeError) -> String {
        match e {
            TypeError::WidthError(WidthError::MissingCapability { name, flag }) => {
                format!("`{name}` values need the {flag} capability, which glint does not enable")
            }
            TypeError::WidthError(WidthError::Invalid(kind, width)) => {
                let scalar = naga::Scalar { kind: *kind, width: *width }.to_wgsl_for_diagnostics();
                format!("{scalar} is not supported here")
            }
            TypeError::InvalidArrayBaseType(t) => format!("{} cannot be an array's element", self.ty(*t)),
            TypeError::InvalidData(t) => format!("a data type is needed, not {}", self.ty(*t)),
            TypeError::InvalidPointerBase(t) => format!("a pointer cannot point to {}", self.ty(*t)),
            TypeError::InvalidDynamicArray(field, t) => {
                format!("member `{field}` ({}) cannot be a runtime-sized array", self.ty(*t))
            }
            other => self.naga(other).1,
        }
    }

    /// A type has no span of its own when the source writes it in place
    /// (`f64`): the first variable, global or function using it.
    pub(super) fn type_span(&self, ty: Handle<naga::Type>) -> Option<Span> {
        let m = self.module;
        let own = m.types.get_span(ty);
        if own.is_defined() {
            return Some(own);
        }
        let functions = m.functions.iter().map(|(h, f)| (f, m.functions.get_span(h)));
        let functions = functions.chain(m.entry_points.iter().map(|ep| (&ep.function, Span::UNDEFINED)));
        for (f, span) in functions {
            if let Some((h, _)) = f.local_variables.iter().find(|(_, v)| v.ty == ty) {
                return Some(f.local_variables.get_span(h));
            }
            if f.arguments.iter().any(|a| a.ty == ty) || f.result.as_ref().is_some_and(|r| r.ty == ty) {
                return Some(span);
            }
        }
        m.global_variables.iter().find(|(_, v)| v.ty == ty).map(|(h, _)| m.global_variables.get_span(h))
    }

    pub(super) fn global_error(&self, g: Handle<naga::GlobalVariable>, e: &GlobalVariableError) -> String {
        let var = &self.module.global_variables[g];
        let space = |s| var_decl(s).unwrap_or_else(|| "binding".into());
        match e {
            GlobalVariableError::InvalidType(s) => format!("a {} cannot be a {}", self.ty(var.ty), space(*s)),
            GlobalVariableError::InvalidUsage(s) => format!("a {} cannot be used this way", space(*s)),
            GlobalVariableError::InitializerNotAllowed(s) => format!("a {} cannot have an initializer", space(*s)),
            GlobalVariableError::MissingTypeFlags { .. } => {
                format!("its type {} cannot be used in a {}", self.ty(var.ty), space(var.space))
            }
            GlobalVariableError::Alignment(s, t, why) => {
                format!("{} is not laid out as a {} needs: {}", self.ty(*t), space(*s), plain(&why.to_string()))
            }
            other => self.naga(other).1,
        }
    }
}

/// WGSL's spelling of a binary operator.
fn binary(op: naga::BinaryOperator) -> &'static str {
    use naga::BinaryOperator as B;
    match op {
        B::Add => "+",
        B::Subtract => "-",
        B::Multiply => "*",
        B::Divide => "/",
        B::Modulo => "%",
        B::Equal => "==",
        B::NotEqual => "!=",
        B::Less => "<",
        B::LessEqual => "<=",
        B::Greater => ">",
        B::GreaterEqual => ">=",
        B::And => "&",
        B::ExclusiveOr => "^",
        B::InclusiveOr => "|",
        B::LogicalAnd => "&&",
        B::LogicalOr => "||",
        B::ShiftLeft => "<<",
        B::ShiftRight => ">>",
    }
}
