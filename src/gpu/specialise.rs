//! WGSL programs specialised per pipeline before the driver sees them: the pipeline's
//! override constants folded (naga's `process_overrides`, as wgpu itself does) and then
//! every branch that a folded constant decides replaced by the side it takes, the code no
//! longer called dropped (`naga::compact`).
//!
//! wgpu folds the constants but keeps the branches on them, so a driver receives the whole
//! program each time: the ball shader with the lobe mode, the clear coat, anisotropy, both
//! bases, every tone mapper. lavapipe (Mesa 22.3) translates and inlines all of it into
//! NIR before its own passes remove the dead branches, and creating one ball pipeline
//! took about 0.3 to 0.45 s of the first PNG's 0.9 s; specialised, about 0.1 s
//! (docs/design/shaders.md, "Specialised pipelines"). The picture is the same: the
//! branches dropped are those no invocation could take.
//!
//! A program that cannot be specialised (naga refuses the constants, or the result does
//! not validate) falls back to the WGSL module with the constants handed to wgpu, as
//! before, with a warning.

use std::collections::{HashMap, HashSet};
use std::sync::OnceLock;

use naga::{
    Arena, BinaryOperator, Block, Constant, Expression, Function, Handle, Literal, LocalVariable,
    Scalar, Statement, Type, TypeInner, UnaryOperator, UniqueArena,
};

/// One WGSL program (a composed module of `shaders`), parsed and validated once.
pub(crate) struct ParsedProgram {
    label: &'static str,
    source: &'static str,
    /// The parsed module and its validation, or why there is none (`None`: never
    /// specialised, the tests' control).
    parsed: Option<Result<(naga::Module, naga::valid::ModuleInfo), String>>,
    /// The module wgpu makes of `source`, for the fallback.
    whole: OnceLock<wgpu::ShaderModule>,
}

/// The module a pipeline stage runs and the override constants it still needs from the
/// pipeline (none where it was specialised).
pub(crate) struct Stage<'a> {
    pub module: wgpu::ShaderModule,
    pub constants: &'a [(&'a str, f64)],
}

impl<'a> Stage<'a> {
    /// The stage's compilation options: the constants it still needs.
    pub(crate) fn options(&self) -> wgpu::PipelineCompilationOptions<'a> {
        wgpu::PipelineCompilationOptions {
            constants: self.constants,
            ..Default::default()
        }
    }
}

impl ParsedProgram {
    /// Parses and validates `source` (named `label` in wgpu's messages).
    pub(crate) fn new(label: &'static str, source: &'static str) -> Self {
        ParsedProgram {
            label,
            source,
            parsed: Some(parse(source)),
            whole: OnceLock::new(),
        }
    }

    /// `source` handed to wgpu whole, its constants to the pipeline (as before
    /// specialisation; the tests compare the two).
    pub(crate) fn unspecialised(label: &'static str, source: &'static str) -> Self {
        ParsedProgram {
            label,
            source,
            parsed: None,
            whole: OnceLock::new(),
        }
    }

    /// The module that runs entry point `entry` of `stage` under `constants`: specialised
    /// to them, or else the whole program with the constants left to the pipeline.
    pub(crate) fn stage<'a>(
        &self,
        device: &wgpu::Device,
        stage: naga::ShaderStage,
        entry: &str,
        constants: &'a [(&'a str, f64)],
    ) -> Stage<'a> {
        let specialised = self.parsed.as_ref().map(|parsed| {
            parsed
                .as_ref()
                .map_err(Clone::clone)
                .and_then(|(module, info)| specialise(module, info, stage, entry, constants))
        });
        match specialised {
            Some(Ok(module)) => Stage {
                module: device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(self.label),
                    source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
                }),
                constants: &[],
            },
            failed => {
                if let Some(Err(why)) = failed {
                    log::warn!(
                        "shader '{}', entry point {entry}: not specialised ({why}); the \
                         driver gets the whole program",
                        self.label
                    );
                }
                let whole = self.whole.get_or_init(|| {
                    device.create_shader_module(wgpu::ShaderModuleDescriptor {
                        label: Some(self.label),
                        source: wgpu::ShaderSource::Wgsl(self.source.into()),
                    })
                });
                Stage {
                    module: whole.clone(),
                    constants,
                }
            }
        }
    }
}

/// `source` parsed, and the module's validation; or why it does not parse or validate.
pub(crate) fn parse(source: &str) -> Result<(naga::Module, naga::valid::ModuleInfo), String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let info = validate(&module)?;
    Ok((module, info))
}

/// `module`'s validation by naga, every check and capability on.
pub(crate) fn validate(module: &naga::Module) -> Result<naga::valid::ModuleInfo, String> {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(module)
    .map_err(|e| e.to_string())
}

/// `module` with only entry point `entry` of `stage`, its overrides set to `constants`,
/// the branches they decide cut to the side taken, and what is left unused removed.
pub(crate) fn specialise(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    stage: naga::ShaderStage,
    entry: &str,
    constants: &[(&str, f64)],
) -> Result<naga::Module, String> {
    let values: naga::back::PipelineConstants = constants
        .iter()
        .map(|&(name, value)| (name.to_owned(), value))
        .collect();
    let (folded, _) = naga::back::pipeline_constants::process_overrides(
        module,
        info,
        Some((stage, entry)),
        &values,
    )
    .map_err(|e| e.to_string())?;
    let mut module = folded.into_owned();
    cut_decided_branches(&mut module);
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    validate(&module).map_err(|e| format!("the specialised module does not validate: {e}"))?;
    Ok(module)
}

/// Replaces every `if` whose condition is a constant `bool` by the block it takes, in
/// every function and entry point of `module`. Names of expressions no longer evaluated
/// are dropped (`naga::compact` keeps every named expression alive).
pub(crate) fn cut_decided_branches(module: &mut naga::Module) {
    let naga::Module {
        types,
        functions,
        entry_points,
        constants,
        global_expressions,
        ..
    } = module;
    let mut known = Known {
        types,
        constants,
        global_expressions,
        returns: HashMap::new(),
    };
    // A callee comes before its callers in the arena: each function's constant result
    // is known before a caller branches on it.
    for (handle, function) in functions.iter_mut() {
        let locals = cut_function(function, &known);
        if let Some(value) = constant_return(function, &known, &locals) {
            known.returns.insert(handle, value);
        }
    }
    for entry_point in entry_points.iter_mut() {
        cut_function(&mut entry_point.function, &known);
    }
}

/// What decides a condition beyond the function's own expressions: the module's constants
/// and the functions known to return a constant `bool`.
struct Known<'a> {
    types: &'a UniqueArena<Type>,
    constants: &'a Arena<Constant>,
    global_expressions: &'a Arena<Expression>,
    returns: HashMap<Handle<Function>, bool>,
}

impl Known<'_> {
    fn is_bool(&self, ty: Handle<Type>) -> bool {
        self.types[ty].inner == TypeInner::Scalar(Scalar::BOOL)
    }
}

/// Cuts `function`'s decided branches; returns its constant locals after the cuts.
fn cut_function(
    function: &mut Function,
    known: &Known<'_>,
) -> HashMap<Handle<LocalVariable>, bool> {
    // naga writes `a && b` as a local set to `a` and, under `if a`, to `b`: once that `if`
    // is cut, the local is a constant that a later branch reads (`has_clearcoat`), so cut
    // again until nothing changes.
    let locals = loop {
        let locals = constant_locals(function, known);
        let expressions = &function.expressions;
        if !cut(&mut function.body, &|h| {
            constant_bool(expressions, known, &locals, h)
        }) {
            break locals;
        }
    };
    let mut emitted = HashSet::new();
    visit(&function.body, &mut |statement| {
        if let Statement::Emit(ref range) = *statement {
            emitted.extend(range.clone());
        }
    });
    function
        .named_expressions
        .retain(|h, _| emitted.contains(h));
    locals
}

/// The constant `bool` a function returns whatever its arguments: one whose body only
/// evaluates expressions, stores constants into its locals and returns a constant, as
/// `has_clearcoat` with the coat compiled out. (A body that does anything else, a call
/// for one, is not taken.)
fn constant_return(
    function: &Function,
    known: &Known<'_>,
    locals: &HashMap<Handle<LocalVariable>, bool>,
) -> Option<bool> {
    if !function
        .result
        .as_ref()
        .is_some_and(|r| known.is_bool(r.ty))
    {
        return None;
    }
    let mut value = None;
    for statement in function.body.iter() {
        match *statement {
            Statement::Emit(_) | Statement::Store { .. } if value.is_none() => {}
            Statement::Block(ref b) if value.is_none() && b.iter().all(stores_or_emits) => {}
            Statement::Return { value: Some(e) } if value.is_none() => {
                value = Some(constant_bool(&function.expressions, known, locals, e)?);
            }
            _ => return None,
        }
    }
    value
}

fn stores_or_emits(statement: &Statement) -> bool {
    matches!(statement, Statement::Store { .. } | Statement::Emit(_))
}

/// The `bool` locals of `function` that hold one constant wherever they are read: every
/// store into one stores that value, its initialiser is that value (or, for `false`, it has
/// none: a local starts at zero), and nothing but loads and stores touches it.
fn constant_locals(function: &Function, known: &Known<'_>) -> HashMap<Handle<LocalVariable>, bool> {
    let none = HashMap::new();
    let value = |h| constant_bool(&function.expressions, known, &none, h);
    let local = |h: Handle<Expression>| match function.expressions[h] {
        Expression::LocalVariable(l) => Some(l),
        _ => None,
    };
    // None: a local seen to hold something else.
    let mut held: HashMap<Handle<LocalVariable>, Option<bool>> = HashMap::new();
    let mut see = |l, v: Option<bool>| {
        let slot = held.entry(l).or_insert(v);
        if *slot != v {
            *slot = None;
        }
    };
    for (l, var) in function.local_variables.iter() {
        let start = if known.is_bool(var.ty) {
            var.init.map_or(Some(false), value)
        } else {
            None
        };
        see(l, start);
    }
    // Any expression that takes a local's pointer other than a load (a member's access).
    for (_, e) in function.expressions.iter() {
        let pointer = match *e {
            Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => Some(base),
            _ => None,
        };
        if let Some(l) = pointer.and_then(local) {
            see(l, None);
        }
    }
    visit(&function.body, &mut |statement| match *statement {
        Statement::Store { pointer, value: v } => {
            if let Some(l) = local(pointer) {
                see(l, value(v));
            }
        }
        Statement::Call { ref arguments, .. } => {
            for l in arguments.iter().filter_map(|&a| local(a)) {
                see(l, None);
            }
        }
        _ => {}
    });
    held.into_iter()
        .filter_map(|(l, v)| Some((l, v?)))
        .collect()
}

/// Calls `f` on every statement of `block` and of the blocks in it.
pub(crate) fn visit(block: &Block, f: &mut dyn FnMut(&Statement)) {
    for statement in block.iter() {
        f(statement);
        match *statement {
            Statement::If {
                ref accept,
                ref reject,
                ..
            } => {
                visit(accept, f);
                visit(reject, f);
            }
            Statement::Block(ref inner) => visit(inner, f),
            Statement::Loop {
                ref body,
                ref continuing,
                ..
            } => {
                visit(body, f);
                visit(continuing, f);
            }
            Statement::Switch { ref cases, .. } => {
                for case in cases {
                    visit(&case.body, f);
                }
            }
            _ => {}
        }
    }
}

/// The value of expression `h` of a function where it is a constant `bool`: a literal or a
/// constant, their negation, a logical and (or) that one constant operand decides, as
/// `HAS_CLEARCOAT == 1u && b.clearcoat > 0.0` with the coat compiled out (naga folds only
/// what is constant throughout), a load of a local that holds a constant (`locals`), or
/// the result of a call to a function known to return a constant.
fn constant_bool(
    expressions: &Arena<Expression>,
    known: &Known<'_>,
    locals: &HashMap<Handle<LocalVariable>, bool>,
    h: Handle<Expression>,
) -> Option<bool> {
    let of = |e| constant_bool(expressions, known, locals, e);
    match expressions[h] {
        Expression::Literal(Literal::Bool(b)) => Some(b),
        Expression::Constant(c) => match known.global_expressions[known.constants[c].init] {
            Expression::Literal(Literal::Bool(b)) => Some(b),
            _ => None,
        },
        Expression::CallResult(f) => known.returns.get(&f).copied(),
        Expression::Load { pointer } => match expressions[pointer] {
            Expression::LocalVariable(l) => locals.get(&l).copied(),
            _ => None,
        },
        Expression::Unary {
            op: UnaryOperator::LogicalNot,
            expr,
        } => of(expr).map(|b| !b),
        Expression::Binary {
            op: op @ (BinaryOperator::LogicalAnd | BinaryOperator::LogicalOr),
            left,
            right,
        } => {
            // The value one side alone gives: false for and, true for or.
            let decisive = op == BinaryOperator::LogicalOr;
            match (of(left), of(right)) {
                (Some(a), _) if a == decisive => Some(decisive),
                (_, Some(b)) if b == decisive => Some(decisive),
                (Some(_), Some(_)) => Some(!decisive),
                _ => None,
            }
        }
        _ => None,
    }
}

/// Replaces each `if` of `block` whose condition `decided` knows by the side it takes;
/// whether any was.
fn cut(block: &mut Block, decided: &dyn Fn(Handle<Expression>) -> Option<bool>) -> bool {
    let mut any = false;
    let statements = std::mem::take(block);
    let mut kept = Block::with_capacity(statements.len());
    for (statement, span) in statements.span_into_iter() {
        let statement = match statement {
            Statement::If {
                condition,
                mut accept,
                mut reject,
            } => match decided(condition) {
                Some(taken) => {
                    any = true;
                    let mut side = if taken { accept } else { reject };
                    cut(&mut side, decided);
                    Statement::Block(side)
                }
                None => {
                    any |= cut(&mut accept, decided);
                    any |= cut(&mut reject, decided);
                    Statement::If {
                        condition,
                        accept,
                        reject,
                    }
                }
            },
            Statement::Block(mut inner) => {
                any |= cut(&mut inner, decided);
                Statement::Block(inner)
            }
            Statement::Loop {
                mut body,
                mut continuing,
                break_if,
            } => {
                any |= cut(&mut body, decided);
                any |= cut(&mut continuing, decided);
                Statement::Loop {
                    body,
                    continuing,
                    break_if,
                }
            }
            Statement::Switch {
                selector,
                mut cases,
            } => {
                for case in cases.iter_mut() {
                    any |= cut(&mut case.body, decided);
                }
                Statement::Switch { selector, cases }
            }
            other => other,
        };
        kept.push(statement, span);
    }
    *block = kept;
    any
}
