//! The data-flow analysis behind `uniform_flow.rs`: which `if`, `break if` and `switch`
//! decisions reachable from a module's fragment entry points lavapipe could inline, i.e.
//! decide on values computable from uniform-buffer values and constants alone.
use std::collections::HashSet;

use naga::{Block, Expression, Function, Handle, Module, ShaderStage, Statement};

/// Operands of `e` for the variants the shaders combine values with; the others (texture
/// reads, queries) are per-pixel values, never inlinable.
fn operands(e: &Expression) -> Vec<Handle<Expression>> {
    use Expression as E;
    match e {
        E::Access { base, index } => vec![*base, *index],
        E::AccessIndex { base, .. } => vec![*base],
        E::Splat { value, .. } => vec![*value],
        E::Swizzle { vector, .. } => vec![*vector],
        E::Compose { components, .. } => components.clone(),
        E::Load { pointer } => vec![*pointer],
        E::Unary { expr, .. } | E::As { expr, .. } | E::Derivative { expr, .. } => vec![*expr],
        E::Binary { left, right, .. } => vec![*left, *right],
        E::Select {
            condition,
            accept,
            reject,
        } => vec![*condition, *accept, *reject],
        E::Relational { argument, .. } => vec![*argument],
        E::Math {
            arg,
            arg1,
            arg2,
            arg3,
            ..
        } => [Some(*arg), *arg1, *arg2, *arg3]
            .into_iter()
            .flatten()
            .collect(),
        E::ArrayLength(x) => vec![*x],
        _ => Vec::new(),
    }
}

/// A value's two facts: computable from uniform-buffer values and constants alone (`u`: what
/// lavapipe can inline), and reading at least one uniform-buffer value (`g`).
#[derive(Clone, Copy, PartialEq)]
struct Fact {
    u: bool,
    g: bool,
}

impl Fact {
    const CONSTANT: Fact = Fact { u: true, g: false };
    const UNIFORM: Fact = Fact { u: true, g: true };
    const VARYING: Fact = Fact { u: false, g: false };
    fn inlinable(self) -> bool {
        self.u && self.g
    }
}

/// Facts kept across passes: per function its arguments and return value, per function (then
/// per fragment entry point) its local variables. `u` holds only if it holds for every store,
/// call site or return (it starts true and only falls), `g` if it holds for one (it starts
/// false and only rises), so the passes end.
struct Analysis<'a> {
    module: &'a Module,
    args: Vec<Vec<Fact>>,
    returns: Vec<Fact>,
    locals: Vec<Vec<Fact>>,
    changed: bool,
    /// Inlinable control-flow decisions: "function: what".
    found: Vec<String>,
}

fn join(into: &mut Fact, f: Fact, changed: &mut bool) {
    let new = Fact {
        u: into.u && f.u,
        g: into.g || f.g,
    };
    *changed |= new != *into;
    *into = new;
}

impl Analysis<'_> {
    /// The facts of every expression of `f` (function index `me`, `None` for an entry
    /// point; `slot`: its row of `locals`).
    fn facts(&self, f: &Function, me: Option<usize>, slot: usize) -> Vec<Fact> {
        let mut t = vec![Fact::VARYING; f.expressions.len()];
        for (h, e) in f.expressions.iter() {
            let leaf = match e {
                Expression::Literal(_)
                | Expression::Constant(_)
                | Expression::Override(_)
                | Expression::ZeroValue(_) => Some(Fact::CONSTANT),
                Expression::GlobalVariable(g) => Some(
                    if self.module.global_variables[*g].space == naga::AddressSpace::Uniform {
                        Fact::UNIFORM
                    } else {
                        Fact::VARYING
                    },
                ),
                Expression::LocalVariable(l) => Some(self.locals[slot][l.index()]),
                Expression::FunctionArgument(i) => Some(match me {
                    Some(m) => self.args[m][*i as usize],
                    None => Fact::VARYING,
                }),
                Expression::CallResult(callee) => Some(self.returns[callee.index()]),
                _ => None,
            };
            t[h.index()] = leaf.unwrap_or_else(|| {
                let ops = operands(e);
                if ops.is_empty() {
                    return Fact::VARYING;
                }
                Fact {
                    u: ops.iter().all(|o| t[o.index()].u),
                    g: ops.iter().any(|o| t[o.index()].g),
                }
            });
        }
        t
    }

    /// Walks `block`: updates the facts of stores, calls and returns, records decisions.
    fn walk(&mut self, block: &Block, t: &[Fact], f: &Function, me: Option<usize>, slot: usize) {
        for s in block.iter() {
            match s {
                Statement::Block(b) => self.walk(b, t, f, me, slot),
                Statement::If {
                    condition,
                    accept,
                    reject,
                } => {
                    if t[condition.index()].inlinable() {
                        self.found.push(format!("{}: if", name(f)));
                    }
                    self.walk(accept, t, f, me, slot);
                    self.walk(reject, t, f, me, slot);
                }
                Statement::Switch { selector, cases } => {
                    if t[selector.index()].inlinable() {
                        self.found.push(format!("{}: switch", name(f)));
                    }
                    for c in cases {
                        self.walk(&c.body, t, f, me, slot);
                    }
                }
                Statement::Loop {
                    body,
                    continuing,
                    break_if,
                } => {
                    if break_if.is_some_and(|b| t[b.index()].inlinable()) {
                        self.found.push(format!("{}: break if", name(f)));
                    }
                    self.walk(body, t, f, me, slot);
                    self.walk(continuing, t, f, me, slot);
                }
                Statement::Store { pointer, value } => {
                    let mut p = *pointer;
                    while let Expression::Access { base, .. }
                    | Expression::AccessIndex { base, .. } = &f.expressions[p]
                    {
                        p = *base;
                    }
                    if let Expression::LocalVariable(l) = &f.expressions[p] {
                        let fact = t[value.index()];
                        join(&mut self.locals[slot][l.index()], fact, &mut self.changed);
                    }
                }
                Statement::Call {
                    function,
                    arguments,
                    ..
                } => {
                    for (i, a) in arguments.iter().enumerate() {
                        let fact = t[a.index()];
                        join(&mut self.args[function.index()][i], fact, &mut self.changed);
                    }
                }
                Statement::Return { value: Some(v) } => {
                    if let Some(m) = me {
                        join(&mut self.returns[m], t[v.index()], &mut self.changed);
                    }
                }
                _ => {}
            }
        }
    }

    /// A pass over `f`: local variables' initialisers count as stores.
    fn pass(&mut self, f: &Function, me: Option<usize>, slot: usize) {
        let t = self.facts(f, me, slot);
        for (l, v) in f.local_variables.iter() {
            if let Some(init) = v.init {
                join(
                    &mut self.locals[slot][l.index()],
                    t[init.index()],
                    &mut self.changed,
                );
            }
        }
        let t = self.facts(f, me, slot);
        self.walk(&f.body, &t, f, me, slot);
    }
}

fn name(f: &Function) -> String {
    f.name.clone().unwrap_or_else(|| "?".into())
}

/// The inlinable control-flow decisions reachable from the fragment entry points of
/// `source`.
pub(crate) fn inlinable_decisions(source: &str) -> Vec<String> {
    let module = naga::front::wgsl::parse_str(source).expect("the module parses");
    let fragment: Vec<&Function> = module
        .entry_points
        .iter()
        .filter(|e| e.stage == ShaderStage::Fragment)
        .map(|e| &e.function)
        .collect();
    assert!(!fragment.is_empty(), "no fragment entry point");
    let n = module.functions.len();
    let mut locals: Vec<Vec<Fact>> = module
        .functions
        .iter()
        .map(|(_, f)| vec![Fact::CONSTANT; f.local_variables.len()])
        .collect();
    locals.extend(
        fragment
            .iter()
            .map(|f| vec![Fact::CONSTANT; f.local_variables.len()]),
    );
    let mut a = Analysis {
        module: &module,
        args: module
            .functions
            .iter()
            .map(|(_, f)| vec![Fact::CONSTANT; f.arguments.len()])
            .collect(),
        returns: vec![Fact::CONSTANT; n],
        locals,
        changed: true,
        found: Vec::new(),
    };
    // The facts only grow, so this ends; the last pass (no change) records the decisions.
    let mut passes = 0;
    while a.changed {
        a.changed = false;
        a.found.clear();
        passes += 1;
        assert!(passes < 1000, "the analysis does not converge");
        for (k, f) in fragment.iter().enumerate() {
            a.pass(f, None, n + k);
        }
        for (h, f) in module.functions.iter() {
            a.pass(f, Some(h.index()), h.index());
        }
    }
    // Functions only the vertex or compute entry points call do not count.
    let reachable = reachable_from(&module, &fragment);
    a.found.retain(|d| {
        let f = d.split(':').next().unwrap_or_default();
        reachable.contains(f) || fragment.iter().any(|e| name(e) == f)
    });
    a.found
}

/// Names of the functions called, directly or not, from `roots`.
fn reachable_from(module: &Module, roots: &[&Function]) -> HashSet<String> {
    fn calls(block: &Block, out: &mut Vec<Handle<Function>>) {
        for s in block.iter() {
            match s {
                Statement::Call { function, .. } => out.push(*function),
                Statement::Block(b) => calls(b, out),
                Statement::If { accept, reject, .. } => {
                    calls(accept, out);
                    calls(reject, out);
                }
                Statement::Switch { cases, .. } => cases.iter().for_each(|c| calls(&c.body, out)),
                Statement::Loop {
                    body, continuing, ..
                } => {
                    calls(body, out);
                    calls(continuing, out);
                }
                _ => {}
            }
        }
    }
    let mut todo = Vec::new();
    roots.iter().for_each(|f| calls(&f.body, &mut todo));
    let mut seen = HashSet::new();
    while let Some(h) = todo.pop() {
        if seen.insert(h) {
            calls(&module.functions[h].body, &mut todo);
        }
    }
    seen.into_iter()
        .map(|h| name(&module.functions[h]))
        .collect()
}
