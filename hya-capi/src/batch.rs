//! Many states in one call: `count` rows of `n` = dof values one after another (row-major
//! `count × n`), each output row-major `count × width`. A shipped arm runs them in its generated
//! batches, several states per SIMD register (`hya_core::SliceDynamics`' rows); a URDF model
//! one state at a time. The checks are the single calls', with the row named: `n` must be the
//! model's dof, every input finite ("row 3: non-finite q[1] = NaN"), every result finite.
//!
//! A call that fails on a state (a singular mass matrix) reports the first such row; rows
//! before it may be written, as by hya-core's batches.

use crate::arm_model::ArmModel;
use crate::model::HyaModel;
use crate::slices::{input_rows, output_rows};
use crate::status::{on_handle, Failure, HyaStatus};
use hya_core::dispatch::MAX_JOINTS;

/// Runs `work` on the model behind `model` with its dof.
///
/// # Safety
/// `model` is null or a live handle.
unsafe fn on_rows(model: *mut HyaModel, work: impl FnOnce(&dyn ArmModel, usize) -> Result<(), Failure>) -> HyaStatus {
    // SAFETY: the caller's contract.
    unsafe { on_handle(model, |m| work(&*m.arm, m.arm.dof())) }
}

/// `Err` naming the row of the first non-finite result in `values`, rows `width` long.
fn finite_rows(quantity: &'static str, values: &[f64], width: usize) -> Result<(), Failure> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(at) => {
            let error = hya_core::Error::NonFiniteResult { quantity, index: at % width, value: values[at] };
            Err(Failure::InRow { row: at / width, failure: Box::new(Failure::Core(error)) })
        }
    }
}

/// The batch's error with the row it came from: the first row whose single call fails (the
/// batches stop at the first failing state).
fn in_row(
    error: hya_core::Error,
    count: usize,
    mut failing: impl FnMut(usize) -> Result<(), hya_core::Error>,
) -> Failure {
    match (0..count).find_map(|k| failing(k).err().map(|e| (k, e))) {
        Some((row, e)) => Failure::InRow { row, failure: Box::new(Failure::Core(e)) },
        None => Failure::Core(error),
    }
}

/// Three arguments of `count × n` doubles each ([`input_rows`]).
///
/// # Safety
/// Each pointer is null or valid for reading `count × n` doubles.
unsafe fn inputs<'a>(
    arguments: [(&'static str, *const f64); 3],
    rows: (usize, usize),
    dof: usize,
) -> Result<[&'a [f64]; 3], Failure> {
    let [a, b, c] = arguments;
    // SAFETY: the caller's contract.
    unsafe {
        Ok([input_rows(a.0, a.1, rows, dof)?, input_rows(b.0, b.1, rows, dof)?, input_rows(c.0, c.1, rows, dof)?])
    }
}

/// Row `k` of `values`, rows `width` long.
fn row(values: &[f64], k: usize, width: usize) -> &[f64] {
    &values[k * width..(k + 1) * width]
}

/// Inverse dynamics of `count` states: `q`, `qd`, `qdd` and `tau` hold `count × n` doubles,
/// row-major, `n` = dof. See `hya_model_inverse_dynamics`.
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `count × n` doubles; `tau`
/// aliases no input.
#[no_mangle]
pub unsafe extern "C" fn hya_model_inverse_dynamics_batch(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    qdd: *const f64,
    count: usize,
    n: usize,
    tau: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_rows(model, |arm, dof| {
            let [q, qd, qdd] = inputs([("q", q), ("qd", qd), ("qdd", qdd)], (count, n), dof)?;
            let tau = output_rows("tau", tau, count, dof)?;
            arm.rows().inverse_dynamics_rows(q, qd, qdd, tau).map_err(Failure::Core)?;
            finite_rows("tau", tau, dof)
        })
    }
}

/// Gravity torques of `count` states: `q` and `tau` hold `count × n` doubles, `n` = dof. See
/// `hya_model_gravity`.
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `count × n` doubles.
#[no_mangle]
pub unsafe extern "C" fn hya_model_gravity_batch(
    model: *mut HyaModel,
    q: *const f64,
    count: usize,
    n: usize,
    tau: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_rows(model, |arm, dof| {
            let q = input_rows("q", q, (count, n), dof)?;
            let tau = output_rows("tau", tau, count, dof)?;
            arm.rows().gravity_rows(q, tau).map_err(Failure::Core)?;
            finite_rows("tau", tau, dof)
        })
    }
}

/// Mass matrices of `count` states: `q` holds `count × n` doubles (`n` = dof), `mass`
/// `count × n²`, one matrix after another. See `hya_model_mass_matrix`.
///
/// # Safety
/// `model` is null or a live handle; `q` holds `count × n` doubles and `mass` `count × n²`.
#[no_mangle]
pub unsafe extern "C" fn hya_model_mass_matrix_batch(
    model: *mut HyaModel,
    q: *const f64,
    count: usize,
    n: usize,
    mass: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_rows(model, |arm, dof| {
            let q = input_rows("q", q, (count, n), dof)?;
            let mass = output_rows("mass", mass, count, dof * dof)?;
            arm.rows().mass_matrix_rows(q, mass).map_err(Failure::Core)?;
            finite_rows("mass", mass, dof * dof)
        })
    }
}

/// Forward dynamics of `count` states: `q`, `qd`, `tau` and `qdd` hold `count × n` doubles,
/// `n` = dof. `HYA_ERR_NUMERIC` at the first state whose mass matrix is not positive definite
/// (the message names its row). See `hya_model_forward_dynamics`.
///
/// # Safety
/// `model` is null or a live handle; each non-null array holds `count × n` doubles; `qdd`
/// aliases no input.
#[no_mangle]
pub unsafe extern "C" fn hya_model_forward_dynamics_batch(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    tau: *const f64,
    count: usize,
    n: usize,
    qdd: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_rows(model, |arm, dof| {
            let [q, qd, tau] = inputs([("q", q), ("qd", qd), ("tau", tau)], (count, n), dof)?;
            let qdd = output_rows("qdd", qdd, count, dof)?;
            let model = arm.rows();
            model.forward_dynamics_rows(q, qd, tau, qdd).map_err(|e| {
                let mut scratch = [0.0; MAX_JOINTS];
                in_row(e, count, |k| {
                    let [q, qd, tau] = [q, qd, tau].map(|x| row(x, k, dof));
                    model.forward_dynamics_into(q, qd, tau, &mut scratch[..dof])
                })
            })?;
            finite_rows("qdd", qdd, dof)
        })
    }
}

/// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` of forward dynamics at `count` states: `q`, `qd`, `tau` hold
/// `count × n` doubles (`n` = dof); `out` holds `count × 3n²`: per state `∂q̈/∂q`, `∂q̈/∂q̇`,
/// `M⁻¹`, each `n × n` row-major (row `i` is `∂q̈_i`), one after another.
/// `HYA_ERR_NUMERIC` at the first state whose mass matrix is not positive definite (the message
/// names its row). See `hya_model_forward_dynamics_derivatives`.
///
/// # Safety
/// `model` is null or a live handle; `q`, `qd`, `tau` hold `count × n` doubles and `out`
/// `count × 3n²`; `out` overlaps no input.
#[no_mangle]
pub unsafe extern "C" fn hya_model_forward_dynamics_derivatives_batch(
    model: *mut HyaModel,
    q: *const f64,
    qd: *const f64,
    tau: *const f64,
    count: usize,
    n: usize,
    out: *mut f64,
) -> HyaStatus {
    // SAFETY: the caller's contract; lengths checked against the model.
    unsafe {
        on_rows(model, |arm, dof| {
            let [q, qd, tau] = inputs([("q", q), ("qd", qd), ("tau", tau)], (count, n), dof)?;
            let width = 3 * dof * dof;
            let out = output_rows("out", out, count, width)?;
            let model = arm.rows();
            model.forward_dynamics_derivatives_rows(q, qd, tau, out).map_err(|e| {
                let mut scratch = [[0.0; MAX_JOINTS * MAX_JOINTS]; 3];
                in_row(e, count, |k| {
                    let [by_q, by_qd, inverse] = &mut scratch;
                    let outputs = [&mut by_q[..dof * dof], &mut by_qd[..dof * dof], &mut inverse[..dof * dof]];
                    let [q, qd, tau] = [q, qd, tau].map(|x| row(x, k, dof));
                    model.forward_dynamics_derivatives_into(q, qd, tau, outputs)
                })
            })?;
            finite_rows("out", out, width)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loader refuses every description whose mass matrix is singular where it checks, so a
    /// singular state is reached here through the search itself.
    #[test]
    fn a_batch_error_is_named_by_the_first_row_that_fails_alone() {
        let singular = || hya_core::Error::SingularMassMatrix;
        let failure = in_row(singular(), 5, |k| if k >= 3 { Err(singular()) } else { Ok(()) });
        assert!(matches!(&failure, Failure::InRow { row: 3, .. }), "{failure}");
        assert!(failure.to_string().starts_with("row 3: "), "{failure}");
        assert_eq!(failure.status(), HyaStatus::HyaErrNumeric);
        // No row fails alone: the batch's own error, without a row.
        let failure = in_row(singular(), 5, |_| Ok(()));
        assert!(matches!(failure, Failure::Core(hya_core::Error::SingularMassMatrix)), "{failure}");
    }

    #[test]
    fn a_non_finite_result_is_named_by_its_row_and_entry() {
        let failure = finite_rows("qdd", &[0.0, 1.0, 2.0, f64::INFINITY, 4.0, 5.0], 2).unwrap_err();
        assert!(matches!(&failure, Failure::InRow { row: 1, .. }), "{failure}");
        assert_eq!(failure.status(), HyaStatus::HyaErrNumeric);
        assert!(finite_rows("qdd", &[0.0; 4], 2).is_ok());
    }
}
