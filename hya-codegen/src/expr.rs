//! A tracing emitter of straight-line scalar code.
//!
//! Algorithms run on [`Value`]s instead of numbers: a value is a known constant or a variable of
//! the generated code. Every operation folds what it can (constants, zeros, ones and signs), so
//! `0 · x` and `x + 0` emit nothing, and records one SSA statement otherwise. Signs are carried
//! on the value, so negation never costs a statement. [`Emitter::render`] keeps only the
//! statements the outputs depend on.

use std::fmt::Write;

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
/// One.
pub const ONE: Value = Value::Const(1.0);

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
}

#[derive(Debug, Clone)]
enum Op {
    /// An input read, e.g. `q[3]`.
    Input(String),
    Add(Value, Value),
    Sub(Value, Value),
    Mul(Value, Value),
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

/// Records statements as algorithms run on [`Value`]s.
///
/// Identical statements are emitted once (common-subexpression elimination): an operation on
/// operands already combined the same way returns the earlier result.
#[derive(Debug, Default)]
pub struct Emitter {
    ops: Vec<Op>,
    seen: std::collections::HashMap<(u8, Key, Key), Value>,
}

impl Emitter {
    /// An empty trace.
    pub fn new() -> Self {
        Self::default()
    }

    fn push(&mut self, op: Op) -> Value {
        let key = match &op {
            Op::Add(a, b) => Some((0, Key::from(*a), Key::from(*b))),
            Op::Sub(a, b) => Some((1, Key::from(*a), Key::from(*b))),
            Op::Mul(a, b) => Some((2, Key::from(*a), Key::from(*b))),
            Op::SinCos(x) => Some((3, Key::from(*x), Key::Const(0))),
            Op::Input(_) | Op::CosOf => None,
        };
        // Addition and multiplication commute: one key for both operand orders.
        let key = key.map(|(kind, a, b)| if kind != 1 && b < a { (kind, b, a) } else { (kind, a, b) });
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

    /// A variable read from the generated function's arguments (`expr` is Rust, e.g. `qd[2]`).
    pub fn input(&mut self, expr: impl Into<String>) -> Value {
        self.push(Op::Input(expr.into()))
    }

    /// `(sin x, cos x)` with one call.
    pub fn sin_cos(&mut self, x: Value) -> (Value, Value) {
        if let Value::Const(c) = x {
            return (Value::Const(c.sin()), Value::Const(c.cos()));
        }
        let sin = self.push(Op::SinCos(x));
        let cos = self.push(Op::CosOf);
        (sin, cos)
    }

    /// `a + b`, folded.
    pub fn add(&mut self, a: Value, b: Value) -> Value {
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

    /// `a − b`, folded.
    pub fn sub(&mut self, a: Value, b: Value) -> Value {
        self.add(a, -b)
    }

    /// `a · b`, folded.
    pub fn mul(&mut self, a: Value, b: Value) -> Value {
        match (a, b) {
            (Value::Const(x), Value::Const(y)) => Value::Const(x * y),
            _ if a.is_const(0.0) || b.is_const(0.0) => ZERO,
            _ if a.is_const(1.0) => b,
            _ if b.is_const(1.0) => a,
            _ if a.is_const(-1.0) => -b,
            _ if b.is_const(-1.0) => -a,
            _ => {
                let ((ma, na), (mb, nb)) = (a.magnitude(), b.magnitude());
                let product = self.push(Op::Mul(ma, mb));
                if na != nb {
                    -product
                } else {
                    product
                }
            }
        }
    }

    /// Sum of products `Σ aᵢ bᵢ`.
    pub fn dot(&mut self, a: &[Value], b: &[Value]) -> Value {
        a.iter().zip(b).fold(ZERO, |sum, (&x, &y)| {
            let product = self.mul(x, y);
            self.add(sum, product)
        })
    }

    /// The statements `outputs` depend on, as Rust `let` bindings, with their operation counts
    /// and the outputs as Rust expressions.
    pub fn render(&self, outputs: &[Value]) -> Rendered {
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
                Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) => {
                    mark(a, &mut live);
                    mark(b, &mut live);
                }
                Op::SinCos(x) => mark(x, &mut live),
                Op::CosOf => live[id - 1] = true,
                Op::Input(_) => {}
            }
        }
        // Live statements are numbered in order, so the emitted names have no gaps.
        let mut names = vec![0usize; self.ops.len()];
        let mut next = 0;
        for (id, op) in self.ops.iter().enumerate() {
            if live[id] && !matches!(op, Op::CosOf) {
                names[id] = next;
                next += if matches!(op, Op::SinCos(_)) { 2 } else { 1 };
            }
            if matches!(op, Op::CosOf) {
                names[id] = names[id - 1] + 1;
            }
        }
        let show = |v: Value| expression_named(v, &names);
        let mut code = String::new();
        let mut counts = OpCounts::default();
        for (id, op) in self.ops.iter().enumerate() {
            if !live[id] {
                continue;
            }
            let t = names[id];
            let statement = match op {
                Op::Input(expr) => format!("let t{t} = {expr};"),
                Op::Add(a, b) => {
                    counts.adds += 1;
                    format!("let t{t} = {} + {};", show(*a), show(*b))
                }
                Op::Sub(a, b) => {
                    counts.adds += 1;
                    format!("let t{t} = {} - {};", show(*a), show(*b))
                }
                Op::Mul(a, b) => {
                    counts.muls += 1;
                    format!("let t{t} = {} * {};", show(*a), show(*b))
                }
                Op::SinCos(x) => {
                    counts.trig += 1;
                    format!("let (t{t}, t{}) = ::hya_core::sin_cos({});", t + 1, show(*x))
                }
                Op::CosOf => continue,
            };
            let _ = writeln!(code, "{statement}");
        }
        let outputs = outputs.iter().map(|v| show(*v)).collect();
        Rendered { code, counts, outputs }
    }
}

/// A float literal that parses back to the same `f64` (`{:?}` prints the shortest such text).
pub fn literal(value: f64) -> String {
    assert!(value.is_finite(), "generated code never holds a non-finite constant");
    format!("{value:?}_f64")
}

/// Rust for a value: `t12`, `-t12`, `0.5_f64`, `-2.0_f64`, with statement `id` named `t{names[id]}`.
fn expression_named(value: Value, names: &[usize]) -> String {
    match value {
        Value::Const(c) => literal(c),
        Value::Var { id, negated: false } => format!("t{}", names[id]),
        Value::Var { id, negated: true } => format!("-t{}", names[id]),
    }
}

/// Straight-line code from [`Emitter::render`].
#[derive(Debug, Clone, PartialEq)]
pub struct Rendered {
    /// `let` statements, one per line.
    pub code: String,
    /// Their operation counts.
    pub counts: OpCounts,
    /// The outputs as Rust expressions over the statements' names.
    pub outputs: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zeros_ones_and_signs_fold_away() {
        let mut e = Emitter::new();
        let x = e.input("q[0]");
        let y = e.input("q[1]");
        assert_eq!(e.mul(x, ZERO), ZERO);
        assert_eq!(e.mul(ONE, x), x);
        assert_eq!(e.add(x, ZERO), x);
        assert_eq!(e.add(x, -x), ZERO);
        assert_eq!(e.mul(Value::Const(-1.0), x), -x);
        let product = e.mul(-x, -y);
        let rendered = e.render(&[product]);
        assert_eq!(rendered.counts, OpCounts { adds: 0, muls: 1, trig: 0 });
        assert_eq!(rendered.code, "let t0 = q[0];\nlet t1 = q[1];\nlet t2 = t0 * t1;\n");
        assert_eq!(rendered.outputs, ["t2"]);
    }

    #[test]
    fn negated_terms_become_subtractions_and_dead_code_is_dropped() {
        let mut e = Emitter::new();
        let x = e.input("a");
        let y = e.input("b");
        let _unused = e.mul(x, Value::Const(3.0));
        let difference = e.add(-x, y);
        let (sin, _cos) = e.sin_cos(y);
        let Rendered { code, counts, outputs } = e.render(&[difference, sin]);
        assert_eq!(counts, OpCounts { adds: 1, muls: 0, trig: 1 });
        assert_eq!(code, "let t0 = a;\nlet t1 = b;\nlet t2 = t1 - t0;\nlet (t3, t4) = ::hya_core::sin_cos(t1);\n");
        assert_eq!(outputs, ["t2", "t3"]);
    }

    #[test]
    fn literals_round_trip() {
        for v in [0.1, -1e-300, 123456.789e10, 1.0 / 3.0] {
            let text = literal(v);
            assert_eq!(text.trim_end_matches("_f64").parse::<f64>().unwrap(), v);
        }
    }
}
