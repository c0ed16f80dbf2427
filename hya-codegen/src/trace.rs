//! The tracing number type: runs `hya-core`'s algorithms and records straight-line code.
//!
//! A [`Value`] is a known constant or a variable of the generated code. It implements
//! [`hya_core::Real`], so the run-time algorithms of `hya_core::model::algorithms` run on it
//! unchanged; every operation folds what it can (constants, zeros, ones and signs), so `0 · x`
//! and `x + 0` emit nothing, and records one SSA statement on the thread's [`Emitter`]
//! otherwise. Signs are carried on the value, so negation never costs a statement; identical
//! statements are emitted once. What happens to the recording next is
//! `rewrite`'s (fusion, liveness) and [`render`](mod@crate::render)'s.

use std::cell::RefCell;
use std::collections::HashMap;

use hya_core::scalar::{Label, Pass};
use hya_core::Real;
use proc_macro2::TokenStream;

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

/// One recorded statement.
#[derive(Debug, Clone)]
pub(crate) enum Op {
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
    /// `a·b + c`, written by `rewrite::fuse` where a product feeds a sum (`a` a variable).
    MulAdd(Value, Value, Value),
}

impl Op {
    /// The values the statement reads.
    pub(crate) fn operands(&self) -> Vec<Value> {
        match self {
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => vec![*a, *b],
            Op::MulAdd(a, b, c) => vec![*a, *b, *c],
            Op::SinCos(x) => vec![*x],
            Op::Input(..) | Op::CosOf => Vec::new(),
        }
    }
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
    pub(crate) ops: Vec<Op>,
    seen: HashMap<(u8, Key, Key), Value>,
    pub(crate) labels: HashMap<usize, Label>,
    /// `(first statement, body, pass)`: where each body's pass of an algorithm begins.
    pub(crate) passes: Vec<(usize, usize, Pass)>,
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
        let emitter = current.as_mut().expect("a traced variable is used outside hya_codegen::trace::trace");
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
            Op::Input(..) | Op::CosOf | Op::MulAdd(..) => None,
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

    /// For each statement, the number of the body's pass it was recorded in (0 before the first).
    pub(crate) fn segments(&self) -> Vec<usize> {
        let mut segment = vec![0; self.ops.len()];
        for (k, &(start, _, _)) in self.passes.iter().enumerate() {
            segment.iter_mut().skip(start).for_each(|s| *s = k + 1);
        }
        segment
    }

    /// A non-finite constant the outputs depend on (a division by a joint inertia that folded
    /// to zero, say), which no literal can hold.
    pub fn non_finite_constant(&self, outputs: &[Value]) -> Option<f64> {
        let live = live(&self.ops, outputs);
        let operands = self.ops.iter().enumerate().filter(|(id, _)| live[*id]).flat_map(|(_, op)| op.operands());
        operands.chain(outputs.iter().copied()).find_map(|v| match v {
            Value::Const(c) if !c.is_finite() => Some(c),
            _ => None,
        })
    }
}

/// Which statements `outputs` depend on (a cosine keeps its sine's `sin_cos` alive).
pub(crate) fn live(ops: &[Op], outputs: &[Value]) -> Vec<bool> {
    let mut live = vec![false; ops.len()];
    let mark = |v: &Value, live: &mut Vec<bool>| {
        if let Value::Var { id, .. } = v {
            live[*id] = true;
        }
    };
    outputs.iter().for_each(|v| mark(v, &mut live));
    for id in (0..ops.len()).rev() {
        if !live[id] {
            continue;
        }
        match &ops[id] {
            Op::CosOf => live[id - 1] = true,
            op => op.operands().iter().for_each(|v| mark(v, &mut live)),
        }
    }
    live
}

/// The statement defining a variable (`usize::MAX` for a constant).
pub(crate) fn var_id(value: Value) -> usize {
    match value {
        Value::Const(_) => usize::MAX,
        Value::Var { id, .. } => id,
    }
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
