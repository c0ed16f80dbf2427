//! Rewrites of a recorded program before it is rendered: products fused into the sums they
//! feed (`fuse`), and the statements the outputs need (`live`).
//!
//! Fusion comes first, so that a product read only by the sums it was fused into is dead and
//! never emitted: every statement of rendered code is read.

use crate::trace::{var_id, Op, Value};

/// The statement defining `value` if it is a product `x·y` of the same pass segment as `id`,
/// with `x` a variable.
fn product(ops: &[Op], segment: &[usize], id: usize, value: Value) -> Option<(Value, Value)> {
    if segment.get(var_id(value)) != Some(&segment[id]) {
        return None;
    }
    match (value, ops.get(var_id(value))) {
        // Sums and differences read magnitudes: a product read by one is never negated.
        (Value::Var { negated: false, .. }, Some(Op::Mul(x, y))) => match x {
            Value::Var { .. } => Some((*x, *y)),
            Value::Const(_) => Some((*y, *x)),
        },
        _ => None,
    }
}

/// Every sum or difference with a product of its own pass segment among its terms becomes one
/// `a·b + c` ([`Op::MulAdd`]): `x·y + c`, `x·y − c = x·y + (−c)`, `c − x·y = (−x)·y + c`. The
/// first term wins where both are products. Statement numbers are kept, so labels and pass
/// marks stay. `segment[id]` numbers the algorithm's pass each statement was recorded in: a
/// product fused into a sum of a later pass would keep both its factors alive until then,
/// which costs registers (measured: HyA's inverse dynamics ran about 15 % slower).
pub(crate) fn fuse(ops: &[Op], segment: &[usize]) -> Vec<Op> {
    ops.iter()
        .enumerate()
        .map(|(id, op)| {
            let (a, b, minus) = match op {
                Op::Add(a, b) => (*a, *b, false),
                Op::Sub(a, b) => (*a, *b, true),
                _ => return op.clone(),
            };
            match (product(ops, segment, id, a), product(ops, segment, id, b)) {
                (Some((x, y)), _) => Op::MulAdd(x, y, if minus { -b } else { b }),
                (None, Some((x, y))) => Op::MulAdd(if minus { -x } else { x }, y, a),
                (None, None) => op.clone(),
            }
        })
        .collect()
}

/// Which statements are read: by an output or by a live statement (a `sin_cos` kept alive only
/// for its cosine is live but not read).
pub(crate) fn read(ops: &[Op], live: &[bool], outputs: &[Value]) -> Vec<bool> {
    let mut read = vec![false; ops.len()];
    let operands = ops.iter().enumerate().filter(|(id, _)| live[*id]).flat_map(|(_, op)| op.operands());
    for value in operands.chain(outputs.iter().copied()) {
        if let Value::Var { id, .. } = value {
            read[id] = true;
        }
    }
    read
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::live;

    fn var(id: usize) -> Value {
        Value::Var { id, negated: false }
    }

    #[test]
    fn products_fuse_into_sums_and_differences_with_their_signs() {
        let input = || Op::Input(String::new(), proc_macro2::TokenStream::new());
        let ops = [input(), input(), input(), Op::Mul(var(0), Value::Const(2.0)), Op::Sub(var(2), var(3))];
        let fused = fuse(&ops, &[0; 5]);
        // c − x·2 = (−x)·2 + c
        assert!(matches!(fused[4], Op::MulAdd(x, Value::Const(k), c) if x == -var(0) && k == 2.0 && c == var(2)));
        let alive = live(&fused, &[var(4)]);
        assert_eq!(alive, [true, false, true, false, true], "the product is dead once fused");
        assert_eq!(read(&fused, &alive, &[var(4)]), alive);
    }
}
