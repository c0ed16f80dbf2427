//! The tracing number type: runs `hya-core`'s algorithms and records straight-line code.
//!
//! A [`Value`] is a known constant or a variable of the generated code. It implements
//! [`hya_core::Real`], so the run-time algorithms of `hya_core::model::algorithms` run on it
//! unchanged; every operation folds what it can (constants, zeros, ones and signs), so `0 · x`
//! and `x + 0` emit nothing, and records one SSA statement on the thread's [`Emitter`]
//! otherwise. Signs are carried on the value, so negation never costs a statement; identical
//! statements are emitted once. [`Emitter::render`] keeps only the statements the outputs
//! depend on and names them after the labels the algorithms gave.

use std::cell::RefCell;
use std::collections::HashMap;

use hya_core::scalar::{Label, Pass};
use hya_core::Real;
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

/// A scalar in traced code: a constant, or an SSA variable, possibly negated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A number known at generation time.
    Const(f64),
    /// Statement `id`'s result, times −1 if `negated`.
    Var {
        /// The statement defining it.
        id: usize,
        /// Whether the value is the negation of the statement's result.
        negated: bool,
    },
}

/// Zero.
pub const ZERO: Value = Value::Const(0.0);

impl Value {
    fn is_const(self, value: f64) -> bool {
        self == Value::Const(value)
    }

    /// The same value with a non-negative constant or a non-negated variable, and the sign.
    fn magnitude(self) -> (Value, bool) {
        match self {
            Value::Const(c) if c < 0.0 => (Value::Const(-c), true),
            Value::Var { id, negated: true } => (Value::Var { id, negated: false }, true),
            other => (other, false),
        }
    }

    fn signed(self, negative: bool) -> Value {
        if negative {
            -self
        } else {
            self
        }
    }
}

#[derive(Debug, Clone)]
enum Op {
    /// An input read: its name in the generated code and the expression it reads.
    Input(String, TokenStream),
    Add(Value, Value),
    Sub(Value, Value),
    Mul(Value, Value),
    Div(Value, Value),
    /// `(sin x, cos x)` of a value; defines this statement (sin) and the next one (cos).
    SinCos(Value),
    /// The cosine half of the preceding `SinCos`.
    CosOf,
}

/// Operation counts of generated code, after dead-code elimination.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OpCounts {
    /// Additions and subtractions.
    pub adds: usize,
    /// Multiplications.
    pub muls: usize,
    /// Divisions.
    pub divs: usize,
    /// `sin_cos` calls.
    pub trig: usize,
}

/// An operand as a hashable key: constants by their bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Key {
    Const(u64),
    Var(usize, bool),
}

impl From<Value> for Key {
    fn from(value: Value) -> Self {
        match value {
            Value::Const(c) => Key::Const(c.to_bits()),
            Value::Var { id, negated } => Key::Var(id, negated),
        }
    }
}

/// Records statements as algorithms run on [`Value`]s: identical statements are emitted once
/// (common-subexpression elimination), and labels and pass marks are kept for naming.
#[derive(Debug, Default)]
pub struct Emitter {
    ops: Vec<Op>,
    seen: HashMap<(u8, Key, Key), Value>,
    labels: HashMap<usize, Label>,
    /// `(first statement, body, pass)`: where each body's pass of an algorithm begins.
    passes: Vec<(usize, usize, Pass)>,
}

thread_local! {
    static CURRENT: RefCell<Option<Emitter>> = const { RefCell::new(None) };
}

/// Runs `f` with a fresh emitter recording every operation on [`Value`]s, and returns its
/// result with the emitter. Traces nest by suspending the outer one.
pub fn trace<R>(f: impl FnOnce() -> R) -> (R, Emitter) {
    let outer = CURRENT.with(|c| c.replace(Some(Emitter::default())));
    let result = f();
    let emitter = CURRENT.with(|c| c.replace(outer)).unwrap_or_default();
    (result, emitter)
}

fn with_emitter<R>(f: impl FnOnce(&mut Emitter) -> R) -> R {
    CURRENT.with(|c| {
        let mut current = c.borrow_mut();
        // Operations on variables only exist inside `trace`, which installs the emitter.
        let emitter = current.as_mut().expect("a traced variable is used outside hya_codegen::expr::trace");
        f(emitter)
    })
}

/// A variable named `name` in the generated code, read from `expr` (e.g. `q_sfe` from `q[1]`).
pub fn input(name: impl Into<String>, expr: TokenStream) -> Value {
    with_emitter(|e| e.push(Op::Input(name.into(), expr)))
}

impl Emitter {
    fn push(&mut self, op: Op) -> Value {
        let key = match &op {
            Op::Add(a, b) => Some((0, Key::from(*a), Key::from(*b))),
            Op::Sub(a, b) => Some((1, Key::from(*a), Key::from(*b))),
            Op::Mul(a, b) => Some((2, Key::from(*a), Key::from(*b))),
            Op::SinCos(x) => Some((3, Key::from(*x), Key::Const(0))),
            Op::Div(a, b) => Some((4, Key::from(*a), Key::from(*b))),
            Op::Input(..) | Op::CosOf => None,
        };
        // Addition and multiplication commute: one key for both operand orders.
        let key = key.map(|(kind, a, b)| if matches!(kind, 0 | 2) && b < a { (kind, b, a) } else { (kind, a, b) });
        if let Some(found) = key.and_then(|k| self.seen.get(&k)) {
            return *found;
        }
        self.ops.push(op);
        let value = Value::Var { id: self.ops.len() - 1, negated: false };
        if let Some(k) = key {
            self.seen.insert(k, value);
        }
        value
    }

    fn sin_cos(&mut self, x: Value) -> (Value, Value) {
        let sin = self.push(Op::SinCos(x));
        if let Some(Op::CosOf) = self.ops.get(var_id(sin) + 1) {
            return (sin, Value::Var { id: var_id(sin) + 1, negated: false });
        }
        let cos = self.push(Op::CosOf);
        (sin, cos)
    }

    fn add(&mut self, a: Value, b: Value) -> Value {
        match (a, b) {
            (Value::Const(x), Value::Const(y)) => Value::Const(x + y),
            _ if a.is_const(0.0) => b,
            _ if b.is_const(0.0) => a,
            _ if a == -b => ZERO,
            _ => {
                let ((ma, na), (mb, nb)) = (a.magnitude(), b.magnitude());
                match (na, nb) {
                    (false, false) => self.push(Op::Add(ma, mb)),
                    (false, true) => self.push(Op::Sub(ma, mb)),
                    (true, false) => self.push(Op::Sub(mb, ma)),
                    (true, true) => -self.push(Op::Add(ma, mb)),
                }
            }
        }
    }

    fn mul(&mut self, a: Value, b: Value) -> Value {
        match (a, b) {
            (Value::Const(x), Value::Const(y)) => Value::Const(x * y),
            _ if a.is_const(0.0) || b.is_const(0.0) => ZERO,
            _ if a.is_const(1.0) => b,
            _ if b.is_const(1.0) => a,
            _ if a.is_const(-1.0) => -b,
            _ if b.is_const(-1.0) => -a,
            _ => {
                let ((ma, na), (mb, nb)) = (a.magnitude(), b.magnitude());
                self.push(Op::Mul(ma, mb)).signed(na != nb)
            }
        }
    }

    fn div(&mut self, a: Value, b: Value) -> Value {
        match (a, b) {
            (Value::Const(x), Value::Const(y)) => Value::Const(x / y),
            _ if a.is_const(0.0) => ZERO,
            _ if b.is_const(1.0) => a,
            _ if b.is_const(-1.0) => -a,
            _ => {
                let ((ma, na), (mb, nb)) = (a.magnitude(), b.magnitude());
                self.push(Op::Div(ma, mb)).signed(na != nb)
            }
        }
    }

    /// Names statement `id` after `label`, unless it already has a name or the labelled value is
    /// its negation (a name never holds the negative of what it says).
    fn label(&mut self, value: Value, label: Label) {
        if let Value::Var { id, negated: false } = value {
            self.labels.entry(id).or_insert(label);
        }
    }

    /// Which statements `outputs` depend on.
    fn live(&self, outputs: &[Value]) -> Vec<bool> {
        let mut live = vec![false; self.ops.len()];
        let mark = |v: &Value, live: &mut Vec<bool>| {
            if let Value::Var { id, .. } = v {
                live[*id] = true;
            }
        };
        outputs.iter().for_each(|v| mark(v, &mut live));
        for id in (0..self.ops.len()).rev() {
            if !live[id] {
                continue;
            }
            match &self.ops[id] {
                Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => {
                    mark(a, &mut live);
                    mark(b, &mut live);
                }
                Op::SinCos(x) => mark(x, &mut live),
                Op::CosOf => live[id - 1] = true,
                Op::Input(..) => {}
            }
        }
        live
    }

    /// A non-finite constant the outputs depend on (a division by a joint inertia that folded
    /// to zero, say), which no literal can hold.
    pub fn non_finite_constant(&self, outputs: &[Value]) -> Option<f64> {
        let live = self.live(outputs);
        let constants = self.ops.iter().enumerate().filter(|(id, _)| live[*id]).flat_map(|(_, op)| match op {
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => vec![*a, *b],
            Op::SinCos(x) => vec![*x],
            Op::Input(..) | Op::CosOf => Vec::new(),
        });
        constants.chain(outputs.iter().copied()).find_map(|v| match v {
            Value::Const(c) if !c.is_finite() => Some(c),
            _ => None,
        })
    }

    /// The operands a statement reads.
    fn operands(&self, id: usize) -> Vec<usize> {
        match &self.ops[id] {
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => {
                [*a, *b].into_iter().filter(|v| matches!(v, Value::Var { .. })).map(var_id).collect()
            }
            Op::SinCos(x) => [*x].into_iter().filter(|v| matches!(v, Value::Var { .. })).map(var_id).collect(),
            Op::CosOf | Op::Input(..) => Vec::new(),
        }
    }

    /// Identifiers for the live statements: inputs by their names, labelled statements by
    /// `names` (made unique), the rest `t0, t1, …`.
    fn identifiers(&self, live: &[bool], names: &dyn Naming) -> Vec<Option<Ident>> {
        let mut used = std::collections::HashSet::new();
        let mut temporaries = 0;
        let mut idents = vec![None; self.ops.len()];
        for (id, op) in self.ops.iter().enumerate().filter(|(id, _)| live[*id]) {
            let wanted = match (op, self.labels.get(&id)) {
                (Op::Input(name, _), _) => name.clone(),
                (_, Some(label)) => names.label(*label),
                _ => {
                    temporaries += 1;
                    format!("t{}", temporaries - 1)
                }
            };
            let unique = crate::names::unique_name(&mut used, wanted);
            idents[id] = Some(Ident::new(&unique, Span::call_site()));
        }
        idents
    }

    /// The statements `outputs` depend on as Rust `let` bindings, with their operation counts
    /// and the outputs as Rust expressions; `names` names labelled statements and the comment
    /// that opens each body's pass.
    ///
    /// Statements are grouped in blocks, one per body's pass (and at most [`GROUP`] statements
    /// each), that hand on only the values later code reads:
    /// `let (elbow_fe_v_wx, …) = { …; (elbow_fe_v_wx, …) };`. Each `let` opens a scope
    /// nested in the previous one, and rustc's debug information overflows its stack beyond
    /// about 2000 nested scopes; blocks keep the nesting to the blocks' count plus one block.
    pub fn render(&self, outputs: &[Value], names: &dyn Naming) -> Rendered {
        let live = self.live(outputs);
        let idents = self.identifiers(&live, names);
        let show = |v: Value| expression(v, &idents);
        let batch = self.sin_cos_batch(&live);
        // Group the live statements; a cosine stays with its sine, and batched sines with the
        // first of them.
        let mut group_of = vec![usize::MAX; self.ops.len()];
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut pass_marks = Vec::new();
        let mut passes = self.passes.iter().peekable();
        let mut pending = None;
        for id in 0..self.ops.len() {
            while let Some(&&(_, body, pass)) = passes.peek().filter(|p| p.0 <= id) {
                pending = Some((body, pass));
                passes.next();
            }
            if !live[id] {
                continue;
            }
            if matches!(self.ops[id], Op::CosOf) {
                group_of[id] = group_of[id - 1];
                continue;
            }
            if let Some(&first) = batch.first().filter(|&&first| first < id && batch.contains(&id)) {
                group_of[id] = group_of[first];
                groups[group_of[first]].push(id);
                continue;
            }
            let opens = pending.take();
            if groups.is_empty() || opens.is_some() || groups.last().is_some_and(|g| g.len() >= GROUP) {
                groups.push(Vec::new());
            }
            if let (Some((body, pass)), Some(name)) = (opens, &idents[id]) {
                pass_marks.push((name.to_string(), names.pass(body, pass)));
            }
            group_of[id] = groups.len() - 1;
            if let Some(group) = groups.last_mut() {
                group.push(id);
            }
        }
        // A value leaves its block if an output or a statement of a later block reads it.
        let mut escapes = vec![false; self.ops.len()];
        outputs.iter().filter(|v| matches!(v, Value::Var { .. })).for_each(|v| escapes[var_id(*v)] = true);
        for id in (0..self.ops.len()).filter(|&id| live[id]) {
            for operand in self.operands(id) {
                if group_of[operand] != group_of[id] {
                    escapes[operand] = true;
                }
            }
        }
        let mut counts = OpCounts::default();
        let layout = Layout { groups: &groups, group_of: &group_of, escapes: &escapes, batch: &batch, idents: &idents };
        let plain = self.blocks(&layout, &show, &mut counts, false);
        // A sum reading a product of its own block, which the FMA variant fuses.
        let fusable = layout.groups.iter().flatten().any(|&id| match &self.ops[id] {
            Op::Add(a, b) | Op::Sub(a, b) => {
                [a, b].iter().any(|v| self.product_in_block(**v, id, layout.group_of).is_some())
            }
            _ => false,
        });
        // The outputs' variables, bound by whichever variant runs.
        let mut results: Vec<Ident> = Vec::new();
        for v in outputs.iter().filter(|v| matches!(v, Value::Var { .. })) {
            let ident = idents[var_id(*v)].clone().unwrap_or_else(|| Ident::new("dead", Span::call_site()));
            if !results.contains(&ident) {
                results.push(ident);
            }
        }
        let statements = if !fusable {
            plain
        } else {
            let fused = self.blocks(&layout, &show, &mut OpCounts::default(), true);
            let pattern = match results.as_slice() {
                [one] => quote! { #one },
                _ => quote! { (#(#results),*) },
            };
            quote! {
                let #pattern = match ::hya_core::with_fma(#[inline(always)] || { #fused #pattern }) {
                    Some(values) => values,
                    None => { #plain #pattern }
                };
            }
        };
        let outputs = outputs.iter().map(|v| show(*v)).collect();
        Rendered { statements, counts, outputs, pass_marks }
    }

    /// The blocks of statements, products fused into the sums they feed within a block if
    /// `fused` (see [`Emitter::render`]).
    fn blocks(
        &self,
        layout: &Layout<'_>,
        show: &dyn Fn(Value) -> TokenStream,
        counts: &mut OpCounts,
        fused: bool,
    ) -> TokenStream {
        let mut blocks = Vec::new();
        for group in layout.groups {
            let mut statements = Vec::new();
            let mut handed_on = Vec::new();
            for &id in group {
                statements.push(match layout.batch.iter().position(|&b| b == id) {
                    Some(0) => self.batched_sin_cos(layout.batch, layout.idents, show, counts),
                    Some(_) => quote! {},
                    None => self.statement(id, layout.idents, show, counts, fused.then_some(layout.group_of)),
                });
                let cos = matches!(self.ops.get(id + 1), Some(Op::CosOf)).then_some(id + 1);
                for defined in std::iter::once(id).chain(cos) {
                    if layout.escapes[defined] {
                        handed_on.extend(layout.idents[defined].clone());
                    }
                }
            }
            blocks.push(match handed_on.as_slice() {
                [] => quote! {},
                [one] => quote! { let #one = { #(#statements)* #one }; },
                _ => quote! { let (#(#handed_on),*) = { #(#statements)* (#(#handed_on),*) }; },
            });
        }
        quote! { #(#blocks)* }
    }

    /// `x · y` if `value` is the result of a multiplication in the same block as statement `id`.
    fn product_in_block(&self, value: Value, id: usize, group_of: &[usize]) -> Option<(Value, Value)> {
        match (value, &self.ops.get(var_id(value))) {
            (Value::Var { id: m, negated: false }, Some(Op::Mul(x, y))) if group_of[m] == group_of[id] => {
                Some((*x, *y))
            }
            _ => None,
        }
    }

    /// The live `sin_cos` statements, if all their arguments are defined before the first of
    /// them (joint angles, in every algorithm here): they then run as one lane-parallel call,
    /// placed where the first one was. Empty otherwise.
    fn sin_cos_batch(&self, live: &[bool]) -> Vec<usize> {
        let batch: Vec<usize> =
            (0..self.ops.len()).filter(|&id| live[id] && matches!(self.ops[id], Op::SinCos(_))).collect();
        let first = batch.first().copied().unwrap_or(0);
        let ready = batch.iter().all(|&id| self.operands(id).iter().all(|&operand| operand < first));
        if ready {
            batch
        } else {
            Vec::new()
        }
    }

    /// `let [(s_a, c_a), (s_b, c_b), …] = sin_cos_lanes([q_a, q_b, …]);`, counted as one
    /// `sin_cos` per lane.
    fn batched_sin_cos(
        &self,
        batch: &[usize],
        idents: &[Option<Ident>],
        show: &dyn Fn(Value) -> TokenStream,
        counts: &mut OpCounts,
    ) -> TokenStream {
        let placeholder = || Ident::new("_", Span::call_site());
        let name = |id: usize| idents.get(id).cloned().flatten().unwrap_or_else(placeholder);
        let mut pairs = Vec::new();
        let mut arguments = Vec::new();
        for &id in batch {
            let Op::SinCos(x) = &self.ops[id] else { continue };
            counts.trig += 1;
            let (sin, cos) = (name(id), name(id + 1));
            pairs.push(quote! { (#sin, #cos) });
            arguments.push(show(*x));
        }
        quote! { let [#(#pairs),*] = ::hya_core::sin_cos_lanes([#(#arguments),*]); }
    }

    /// Statement `id` as a `let`, counted.
    ///
    /// With `fused` (the statements' blocks), a sum or difference with a product of the same
    /// block becomes one `mul_add`: `a ± x·y`, `x·y − b` (the product's own statement is then
    /// dead unless something else reads it, and the compiler drops it).
    fn statement(
        &self,
        id: usize,
        idents: &[Option<Ident>],
        show: &dyn Fn(Value) -> TokenStream,
        counts: &mut OpCounts,
        fused: Option<&[usize]>,
    ) -> TokenStream {
        let placeholder = || Ident::new("_", Span::call_site());
        let name = idents[id].clone().unwrap_or_else(placeholder);
        let product = |v: &Value| fused.and_then(|group_of| self.product_in_block(*v, id, group_of));
        // `a + b` (or `a − b` if `minus`) as one `mul_add`, if either term is such a product.
        let fma = |a: Value, b: Value, minus: bool| {
            let (x, y, c) = match (product(&a), product(&b)) {
                (Some((x, y)), _) => (x, y, if minus { -b } else { b }),
                (None, Some((x, y))) => (if minus { -x } else { x }, y, a),
                (None, None) => return None,
            };
            let (x, y, c) = (show(x), show(y), show(c));
            Some(quote! { let #name = ::hya_core::mul_add(#x, #y, #c); })
        };
        match &self.ops[id] {
            Op::Input(_, expr) => quote! { let #name = #expr; },
            Op::Add(a, b) | Op::Sub(a, b) => {
                counts.adds += 1;
                let minus = matches!(self.ops[id], Op::Sub(..));
                fma(*a, *b, minus).unwrap_or_else(|| {
                    let (a, b) = (show(*a), show(*b));
                    if minus {
                        quote! { let #name = #a - #b; }
                    } else {
                        quote! { let #name = #a + #b; }
                    }
                })
            }
            Op::Mul(a, b) => {
                counts.muls += 1;
                let (a, b) = (show(*a), show(*b));
                quote! { let #name = #a * #b; }
            }
            Op::Div(a, b) => {
                counts.divs += 1;
                let (a, b) = (show(*a), show(*b));
                quote! { let #name = #a / #b; }
            }
            Op::SinCos(x) => {
                counts.trig += 1;
                let x = show(*x);
                let cos = idents.get(id + 1).cloned().flatten().unwrap_or_else(placeholder);
                quote! { let (#name, #cos) = ::hya_core::sin_cos(#x); }
            }
            Op::CosOf => quote! {},
        }
    }
}

/// Where each live statement goes in rendered code (see [`Emitter::render`]).
struct Layout<'a> {
    groups: &'a [Vec<usize>],
    group_of: &'a [usize],
    escapes: &'a [bool],
    batch: &'a [usize],
    idents: &'a [Option<Ident>],
}

/// Most statements in one block of rendered code (see [`Emitter::render`]).
pub const GROUP: usize = 256;

fn var_id(value: Value) -> usize {
    match value {
        Value::Var { id, .. } => id,
        Value::Const(_) => usize::MAX,
    }
}

/// How the generated code names labelled values and marks passes.
pub trait Naming {
    /// The identifier for a labelled value (made unique by the emitter).
    fn label(&self, label: Label) -> String;
    /// The comment text opening `body`'s `pass`.
    fn pass(&self, body: usize, pass: Pass) -> String;
}

/// A float literal that parses back to the same `f64`; negative values as `-literal`.
pub fn literal(value: f64) -> TokenStream {
    assert!(value.is_finite(), "generated code never holds a non-finite constant");
    let magnitude = proc_macro2::Literal::f64_suffixed(value.abs());
    if value.is_sign_negative() && value != 0.0 {
        quote! { -#magnitude }
    } else {
        quote! { #magnitude }
    }
}

/// Rust for a value: `name`, `-name`, `0.5f64`, `-2f64`.
fn expression(value: Value, idents: &[Option<Ident>]) -> TokenStream {
    match value {
        Value::Const(c) => literal(c),
        Value::Var { id, negated } => {
            let name = idents[id].clone().unwrap_or_else(|| Ident::new("dead", Span::call_site()));
            if negated {
                quote! { -#name }
            } else {
                quote! { #name }
            }
        }
    }
}

/// Straight-line code from [`Emitter::render`].
#[derive(Debug, Clone)]
pub struct Rendered {
    /// `let` statements.
    pub statements: TokenStream,
    /// Their operation counts.
    pub counts: OpCounts,
    /// The outputs as Rust expressions over the statements' names.
    pub outputs: Vec<TokenStream>,
    /// `(first statement's name, comment)` for each body's pass that emitted code.
    pub pass_marks: Vec<(String, String)>,
}

impl std::ops::Neg for Value {
    type Output = Value;
    /// `−self`, free: no statement is emitted.
    fn neg(self) -> Value {
        match self {
            Value::Const(c) => Value::Const(-c),
            Value::Var { id, negated } => Value::Var { id, negated: !negated },
        }
    }
}

/// Binary operations fold on constants without an emitter and record through it otherwise.
macro_rules! traced_operator {
    ($trait:ident, $method:ident, $fold:expr) => {
        impl std::ops::$trait for Value {
            type Output = Value;
            fn $method(self, rhs: Value) -> Value {
                match (self, rhs) {
                    (Value::Const(a), Value::Const(b)) => Value::Const($fold(a, b)),
                    _ => with_emitter(|e| Emitter::$method(e, self, rhs)),
                }
            }
        }
    };
}

traced_operator!(Add, add, |a: f64, b: f64| a + b);
traced_operator!(Mul, mul, |a: f64, b: f64| a * b);
traced_operator!(Div, div, |a: f64, b: f64| a / b);

impl std::ops::Sub for Value {
    type Output = Value;
    fn sub(self, rhs: Value) -> Value {
        self + -rhs
    }
}

impl Real for Value {
    const TRACES: bool = true;

    fn constant(value: f64) -> Self {
        Value::Const(value)
    }

    fn sin_cos(self) -> (Self, Self) {
        match self {
            Value::Const(c) => (Value::Const(c.sin()), Value::Const(c.cos())),
            _ => with_emitter(|e| e.sin_cos(self)),
        }
    }

    fn labelled(self, label: Label) -> Self {
        if let Value::Var { .. } = self {
            with_emitter(|e| e.label(self, label));
        }
        self
    }

    fn begin_pass(body: usize, pass: Pass) {
        CURRENT.with(|c| {
            if let Some(e) = c.borrow_mut().as_mut() {
                let start = e.ops.len();
                e.passes.push((start, body, pass));
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Plain;
    impl Naming for Plain {
        fn label(&self, label: Label) -> String {
            format!("b{}_{}", label.body, label.component)
        }
        fn pass(&self, body: usize, _pass: Pass) -> String {
            format!("body {body}")
        }
    }

    fn text(tokens: &TokenStream) -> String {
        tokens.to_string()
    }

    #[test]
    fn zeros_ones_and_signs_fold_away() {
        let ((product, checks), e) = trace(|| {
            let x = input("x", quote!(q[0]));
            let y = input("y", quote!(q[1]));
            let checks = [x * ZERO == ZERO, Value::Const(1.0) * x == x, x + ZERO == x, x + -x == ZERO];
            (-x * -y, checks)
        });
        assert_eq!(checks, [true; 4]);
        let rendered = e.render(&[product], &Plain);
        assert_eq!(rendered.counts, OpCounts { adds: 0, muls: 1, divs: 0, trig: 0 });
        assert_eq!(text(&rendered.statements), "let t0 = { let x = q [0] ; let y = q [1] ; let t0 = x * y ; t0 } ;");
        assert_eq!(text(&rendered.outputs[0]), "t0");
    }

    #[test]
    fn negated_terms_become_subtractions_and_dead_code_is_dropped() {
        let (outputs, e) = trace(|| {
            let x = input("a", quote!(a));
            let y = input("b", quote!(b));
            let _unused = x * Value::Const(3.0);
            let (sin, _cos) = y.sin_cos();
            [-x + y, sin, y / x]
        });
        let rendered = e.render(&outputs, &Plain);
        assert_eq!(rendered.counts, OpCounts { adds: 1, muls: 0, divs: 1, trig: 1 });
        assert_eq!(
            text(&rendered.statements),
            "let (t0 , t1 , t2) = { let a = a ; let b = b ; let [(t0 , _)] = :: hya_core :: sin_cos_lanes ([b]) ; \
             let t1 = b - a ; let t2 = b / a ; (t0 , t1 , t2) } ;"
        );
    }

    /// The fused and the plain variant of a rendered function body.
    fn variants(text: &str) -> (&str, &str) {
        text.split_once("None =>").map(|(f, p)| (f, p.trim())).unwrap_or_default()
    }

    #[test]
    fn products_feeding_sums_fuse_in_the_variant_run_where_the_cpu_has_fma() {
        let (outputs, e) = trace(|| {
            let (x, y, z) = (input("x", quote!(x)), input("y", quote!(y)), input("z", quote!(z)));
            [x * y + z, z - x * y * y]
        });
        let rendered = e.render(&outputs, &Plain);
        assert_eq!(rendered.counts, OpCounts { adds: 2, muls: 2, divs: 0, trig: 0 });
        let text = text(&rendered.statements);
        let (fused, plain) = variants(&text);
        assert!(text.starts_with("let (t1 , t3) = match :: hya_core :: with_fma (# [inline (always)] ||"), "{text}");
        assert!(fused.contains("let t1 = :: hya_core :: mul_add (x , y , z) ;"), "{fused}");
        assert!(fused.contains("let t3 = :: hya_core :: mul_add (- t0 , y , z) ;"), "{fused}");
        assert!(!plain.contains("mul_add") && plain.contains("let t1 = t0 + z ;"), "{plain}");
    }

    #[test]
    fn sines_of_inputs_run_as_one_call_and_others_stay_apart() {
        let (outputs, e) = trace(|| {
            let (a, b) = (input("a", quote!(a)), input("b", quote!(b)));
            let (sa, ca) = a.sin_cos();
            let (sb, _) = b.sin_cos();
            [sa * ca, sb]
        });
        let rendered = e.render(&outputs, &Plain);
        assert_eq!(rendered.counts.trig, 2);
        assert!(
            text(&rendered.statements)
                .contains("let [(t0 , t1) , (t2 , _)] = :: hya_core :: sin_cos_lanes ([a , b]) ;"),
            "{}",
            text(&rendered.statements)
        );
        // The second argument is computed after the first sine: no batch.
        let (outputs, e) = trace(|| {
            let a = input("a", quote!(a));
            let (sa, _) = a.sin_cos();
            let (sb, _) = (sa * a).sin_cos();
            [sb]
        });
        let text = text(&e.render(&outputs, &Plain).statements);
        assert_eq!(text.matches(":: hya_core :: sin_cos (").count(), 2, "{text}");
    }

    #[test]
    fn labelled_values_take_their_names_and_collisions_are_numbered() {
        let (outputs, e) = trace(|| {
            let x = input("x", quote!(x));
            let label = Label { body: 2, quantity: hya_core::scalar::Quantity::Velocity, component: 1 };
            [(x * x).labelled(label), (x + x).labelled(label)]
        });
        let rendered = e.render(&outputs, &Plain);
        assert_eq!(
            text(&rendered.statements),
            "let (b2_1 , b2_1_1) = { let x = x ; let b2_1 = x * x ; let b2_1_1 = x + x ; (b2_1 , b2_1_1) } ;"
        );
    }

    #[test]
    fn blocks_open_at_passes_and_hand_on_only_what_later_code_reads() {
        let (outputs, e) = trace(|| {
            let x = input("x", quote!(x));
            let inner = x * x;
            let kept = inner + x;
            Value::begin_pass(0, Pass::Forward);
            [kept * kept]
        });
        let rendered = e.render(&outputs, &Plain);
        // The variant without FMA (the one with it fuses `t0 + x` and is checked above).
        let text = text(&rendered.statements);
        assert_eq!(
            variants(&text).1,
            "{ let t1 = { let x = x ; let t0 = x * x ; let t1 = t0 + x ; t1 } ; \
             let t2 = { let t2 = t1 * t1 ; t2 } ; t2 } } ;"
        );
        assert_eq!(rendered.pass_marks, [("t2".to_owned(), "body 0".to_owned())]);
    }

    #[test]
    fn literals_round_trip() {
        for v in [0.1, 1e-300, 123456.789e10, 1.0 / 3.0, 2.0] {
            let text = literal(v).to_string();
            assert_eq!(text.trim_end_matches("f64").parse::<f64>().unwrap(), v);
        }
        assert_eq!(literal(-0.5).to_string(), "- 0.5f64");
    }
}
