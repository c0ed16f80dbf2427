//! A recorded program as Rust text generic over `A: hya_core::Arithmetic`: the live statements
//! as `let` bindings in blocks, named, with their operation counts.
//!
//! Constants stand on the right of `+ − × ÷` (`t3 * 0.5f64`; `c − x` as `-x + c`, `c · x` as
//! `x · c`, both exact) and as `mul_add`'s last two arguments; `A::from(c)` only where neither
//! fits. Every statement rendered is read: fusion ran before liveness ([`crate::rewrite`]).

use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

use crate::names::{identifiers, Naming};
use crate::rewrite::{fuse, read};
use crate::trace::{live, var_id, Emitter, Op, Value};

/// Operation counts of generated code, after fusion and dead-code elimination.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OpCounts {
    /// Additions and subtractions.
    pub adds: usize,
    /// Multiplications.
    pub muls: usize,
    /// Fused multiply-adds `a·b + c` (a multiplication and an addition on CPUs without FMA).
    pub mul_adds: usize,
    /// Divisions.
    pub divs: usize,
    /// `sin_cos` calls.
    pub trig: usize,
}

/// Most statements in one block of rendered code (see [`render()`]).
pub const GROUP: usize = 256;

/// Straight-line code from [`render()`].
#[derive(Debug, Clone)]
pub struct Rendered {
    /// `let` statements.
    pub statements: TokenStream,
    /// Their operation counts.
    pub counts: OpCounts,
    /// The outputs as Rust expressions of type `A` over the statements' names.
    pub outputs: Vec<TokenStream>,
    /// `(first statement's name, comment)` for each body's pass that emitted code.
    pub pass_marks: Vec<(String, String)>,
    /// Which statements are read (an input that is not, is not bound).
    read: Vec<bool>,
}

impl Rendered {
    /// Whether the rendered code reads `value` (an input, say).
    pub fn reads(&self, value: Value) -> bool {
        matches!(value, Value::Var { id, .. } if self.read.get(id) == Some(&true))
    }
}

/// Where each live statement goes.
struct Layout {
    groups: Vec<Vec<usize>>,
    escapes: Vec<bool>,
    batch: Vec<usize>,
    idents: Vec<Option<Ident>>,
}

/// The statements `outputs` depend on as Rust `let` bindings, products fused into the sums they
/// feed, with their operation counts and the outputs as Rust expressions; `names` names
/// labelled statements and the comment that opens each body's pass.
///
/// Statements are grouped in blocks, one per body's pass (and at most [`GROUP`] statements
/// each), that hand on only the values later code reads:
/// `let (elbow_fe_v_wx, …) = { …; (elbow_fe_v_wx, …) };`. Each `let` opens a scope
/// nested in the previous one, and rustc's debug information overflows its stack beyond
/// about 2000 nested scopes; blocks keep the nesting to the blocks' count plus one block.
pub fn render(emitter: &Emitter, outputs: &[Value], names: &dyn Naming) -> Rendered {
    let ops = fuse(&emitter.ops, &emitter.segments());
    let live = live(&ops, outputs);
    let read = read(&ops, &live, outputs);
    let idents = identifiers(emitter, &ops, &live, &read, names);
    let batch = sin_cos_batch(&ops, &live);
    let (groups, group_of, pass_marks) = group(emitter, &ops, &live, &batch, &idents, names);
    // A value leaves its block if an output or a statement of a later block reads it.
    let mut escapes = vec![false; ops.len()];
    outputs.iter().filter(|v| matches!(v, Value::Var { .. })).for_each(|v| escapes[var_id(*v)] = true);
    for id in (0..ops.len()).filter(|&id| live[id]) {
        for operand in ops[id].operands().into_iter().filter(|v| matches!(v, Value::Var { .. })) {
            if group_of[var_id(operand)] != group_of[id] {
                escapes[var_id(operand)] = true;
            }
        }
    }
    let layout = Layout { groups, escapes, batch, idents };
    let mut counts = OpCounts::default();
    let statements = blocks(&ops, &layout, &mut counts);
    let outputs = outputs.iter().map(|v| operand(*v, &layout.idents)).collect();
    Rendered { statements, counts, outputs, pass_marks, read }
}

/// The live statements in groups (a cosine with its sine, batched sines with the first of
/// them), a group opening at each body's pass; and the pass marks.
#[allow(clippy::type_complexity)]
fn group(
    emitter: &Emitter,
    ops: &[Op],
    live: &[bool],
    batch: &[usize],
    idents: &[Option<Ident>],
    names: &dyn Naming,
) -> (Vec<Vec<usize>>, Vec<usize>, Vec<(String, String)>) {
    let mut group_of = vec![usize::MAX; ops.len()];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut pass_marks = Vec::new();
    let mut passes = emitter.passes.iter().peekable();
    let mut pending = None;
    for id in 0..ops.len() {
        while let Some(&&(_, body, pass)) = passes.peek().filter(|p| p.0 <= id) {
            pending = Some((body, pass));
            passes.next();
        }
        if !live[id] {
            continue;
        }
        if matches!(ops[id], Op::CosOf) {
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
    (groups, group_of, pass_marks)
}

/// The blocks of statements.
fn blocks(ops: &[Op], layout: &Layout, counts: &mut OpCounts) -> TokenStream {
    let mut blocks = Vec::new();
    for group in &layout.groups {
        let mut statements = Vec::new();
        let mut handed_on = Vec::new();
        for &id in group {
            statements.push(match layout.batch.iter().position(|&b| b == id) {
                Some(0) => batched_sin_cos(ops, &layout.batch, &layout.idents, counts),
                Some(_) => quote! {},
                None => statement(ops, id, &layout.idents, counts),
            });
            let cos = matches!(ops.get(id + 1), Some(Op::CosOf)).then_some(id + 1);
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

/// The live `sin_cos` statements, if all their arguments are defined before the first of
/// them (joint angles, in every algorithm here): they then run as one lane-parallel call,
/// placed where the first one was. Empty otherwise.
fn sin_cos_batch(ops: &[Op], live: &[bool]) -> Vec<usize> {
    let batch: Vec<usize> = (0..ops.len()).filter(|&id| live[id] && matches!(ops[id], Op::SinCos(_))).collect();
    let first = batch.first().copied().unwrap_or(0);
    let ready =
        batch.iter().all(|&id| ops[id].operands().iter().all(|&v| matches!(v, Value::Const(_)) || var_id(v) < first));
    if ready {
        batch
    } else {
        Vec::new()
    }
}

/// `name`, or `_` for a statement not bound (a sine whose cosine alone is read).
fn binding(idents: &[Option<Ident>], id: usize) -> Ident {
    idents.get(id).cloned().flatten().unwrap_or_else(|| Ident::new("_", Span::call_site()))
}

/// `let [(s_a, c_a), (s_b, c_b), …] = A::sin_cos_lanes([q_a, q_b, …]);`, counted as one
/// `sin_cos` per value.
fn batched_sin_cos(ops: &[Op], batch: &[usize], idents: &[Option<Ident>], counts: &mut OpCounts) -> TokenStream {
    let mut pairs = Vec::new();
    let mut arguments = Vec::new();
    for &id in batch {
        let Op::SinCos(x) = &ops[id] else { continue };
        counts.trig += 1;
        let (sin, cos) = (binding(idents, id), binding(idents, id + 1));
        pairs.push(quote! { (#sin, #cos) });
        arguments.push(operand(*x, idents));
    }
    quote! { let [#(#pairs),*] = A::sin_cos_lanes([#(#arguments),*]); }
}

/// Statement `id` as a `let`, counted.
fn statement(ops: &[Op], id: usize, idents: &[Option<Ident>], counts: &mut OpCounts) -> TokenStream {
    let name = binding(idents, id);
    let show = |v: &Value| operand(*v, idents);
    // The right operand of `+ − × ÷`: a variable, or an `f64` literal.
    let right = |v: &Value| constant_or_variable(v, idents);
    let value = match &ops[id] {
        Op::Input(_, expr) => expr.clone(),
        Op::Add(a, b) | Op::Sub(a, b) => {
            counts.adds += 1;
            let minus = matches!(ops[id], Op::Sub(..));
            match (a, minus) {
                (Value::Const(_), false) => binary(quote!(+), show(b), right(a)),
                (Value::Const(_), true) => binary(quote!(+), show(&-*b), right(a)),
                (_, false) => binary(quote!(+), show(a), right(b)),
                (_, true) => binary(quote!(-), show(a), right(b)),
            }
        }
        Op::Mul(a, b) => {
            counts.muls += 1;
            match a {
                Value::Const(_) => binary(quote!(*), show(b), right(a)),
                _ => binary(quote!(*), show(a), right(b)),
            }
        }
        Op::Div(a, b) => {
            counts.divs += 1;
            match a {
                Value::Const(c) => {
                    let (c, b) = (literal(*c), show(b));
                    quote! { A::from(#c) / #b }
                }
                _ => binary(quote!(/), show(a), right(b)),
            }
        }
        Op::MulAdd(a, b, c) => {
            counts.mul_adds += 1;
            let (a, b, c) = (show(a), right(b), right(c));
            quote! { A::mul_add(#a, #b, #c) }
        }
        Op::SinCos(x) => {
            counts.trig += 1;
            let cos = binding(idents, id + 1);
            let x = show(x);
            return quote! { let (#name, #cos) = A::sin_cos(#x); };
        }
        Op::CosOf => return quote! {},
    };
    quote! { let #name = #value; }
}

/// `a op b`.
fn binary(op: TokenStream, a: TokenStream, b: TokenStream) -> TokenStream {
    quote! { #a #op #b }
}

/// A variable's name, or an `f64` literal (an argument `impl Into<A>` takes either).
fn constant_or_variable(value: &Value, idents: &[Option<Ident>]) -> TokenStream {
    match value {
        Value::Const(c) => literal(*c),
        Value::Var { .. } => operand(*value, idents),
    }
}

/// Rust for a value of type `A`: `name`, `-name`, `A::from(0.5f64)`.
pub(crate) fn operand(value: Value, idents: &[Option<Ident>]) -> TokenStream {
    match value {
        Value::Const(c) => {
            let c = literal(c);
            quote! { A::from(#c) }
        }
        Value::Var { id, negated } => {
            let name = binding(idents, id);
            if negated {
                quote! { -#name }
            } else {
                quote! { #name }
            }
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trace::{input, trace, ZERO};
    use hya_core::scalar::{Label, Pass};
    use hya_core::Real;
    use quote::quote;

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
        let rendered = render(&e, &[product], &Plain);
        assert_eq!(rendered.counts, OpCounts { muls: 1, ..OpCounts::default() });
        assert_eq!(text(&rendered.statements), "let t0 = { let x = q [0] ; let y = q [1] ; let t0 = x * y ; t0 } ;");
        assert_eq!(text(&rendered.outputs[0]), "t0");
    }

    #[test]
    fn negated_terms_become_subtractions_constants_stand_right_and_dead_code_is_dropped() {
        let (outputs, e) = trace(|| {
            let x = input("a", quote!(a));
            let y = input("b", quote!(b));
            let _unused = x * Value::Const(3.0);
            let (sin, _cos) = y.sin_cos();
            [-x + y, sin, y / x, Value::Const(2.0) - x * Value::Const(0.5), Value::Const(1.0) / y]
        });
        let rendered = render(&e, &outputs, &Plain);
        assert_eq!(rendered.counts, OpCounts { adds: 1, mul_adds: 1, divs: 2, trig: 1, ..OpCounts::default() });
        assert_eq!(
            text(&rendered.statements),
            "let (t0 , t1 , t2 , t3 , t4) = { let a = a ; let b = b ; let [(t0 , _)] = A :: sin_cos_lanes ([b]) ; \
             let t1 = b - a ; let t2 = b / a ; let t3 = A :: mul_add (- a , 0.5f64 , 2f64) ; \
             let t4 = A :: from (1f64) / b ; (t0 , t1 , t2 , t3 , t4) } ;"
        );
    }

    #[test]
    fn products_fuse_into_the_sums_they_feed_and_are_then_dead() {
        let (outputs, e) = trace(|| {
            let (x, y, z) = (input("x", quote!(x)), input("y", quote!(y)), input("z", quote!(z)));
            [x * y + z, z - x * y * y]
        });
        let rendered = render(&e, &outputs, &Plain);
        assert_eq!(rendered.counts, OpCounts { muls: 1, mul_adds: 2, ..OpCounts::default() });
        let text = text(&rendered.statements);
        // `x·y` is read by the second product, so it stays; the first `mul_add` does not read it.
        assert_eq!(
            text,
            "let (t1 , t2) = { let x = x ; let y = y ; let z = z ; let t0 = x * y ; \
             let t1 = A :: mul_add (x , y , z) ; let t2 = A :: mul_add (- t0 , y , z) ; (t1 , t2) } ;"
        );
    }

    #[test]
    fn sines_of_inputs_run_as_one_call_and_others_stay_apart() {
        let (outputs, e) = trace(|| {
            let (a, b) = (input("a", quote!(a)), input("b", quote!(b)));
            let (sa, ca) = a.sin_cos();
            let (sb, _) = b.sin_cos();
            [sa * ca, sb]
        });
        let rendered = render(&e, &outputs, &Plain);
        assert_eq!(rendered.counts.trig, 2);
        let statements = text(&rendered.statements);
        assert!(statements.contains("let [(t0 , t1) , (t2 , _)] = A :: sin_cos_lanes ([a , b]) ;"), "{statements}");
        // The second argument is computed after the first sine: no batch.
        let (outputs, e) = trace(|| {
            let a = input("a", quote!(a));
            let (sa, _) = a.sin_cos();
            let (sb, _) = (sa * a).sin_cos();
            [sb]
        });
        let text = text(&render(&e, &outputs, &Plain).statements);
        assert_eq!(text.matches("A :: sin_cos (").count(), 2, "{text}");
    }

    #[test]
    fn a_sine_kept_only_for_its_cosine_is_not_bound() {
        let (outputs, e) = trace(|| {
            let a = input("a", quote!(a));
            [a.sin_cos().1]
        });
        let text = text(&render(&e, &outputs, &Plain).statements);
        assert!(text.contains("let [(_ , t0)] = A :: sin_cos_lanes ([a]) ;"), "{text}");
    }

    #[test]
    fn labelled_values_take_their_names_and_collisions_are_numbered() {
        let (outputs, e) = trace(|| {
            let x = input("x", quote!(x));
            let label = Label { body: 2, quantity: hya_core::scalar::Quantity::Velocity, component: 1 };
            [(x * x).labelled(label), (x + x).labelled(label)]
        });
        let rendered = render(&e, &outputs, &Plain);
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
        let rendered = render(&e, &outputs, &Plain);
        assert_eq!(
            text(&rendered.statements),
            "let t0 = { let x = x ; let t0 = A :: mul_add (x , x , x) ; t0 } ; let t1 = { let t1 = t0 * t0 ; t1 } ;"
        );
        assert_eq!(rendered.pass_marks, [("t1".to_owned(), "body 0".to_owned())]);
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
