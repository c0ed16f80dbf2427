//! Hostile calls through the C ABI: null pointers, wrong lengths, NaN, out-of-range parameters,
//! unknown names and bad files each return their status with a message that names the argument,
//! index or value; none crashes, and a refused update leaves the state as it was.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::ffi::{c_char, CStr, CString};
use std::path::Path;
use std::ptr::{null, null_mut};

use hya::*;

fn text(ptr: *const c_char) -> String {
    assert!(!ptr.is_null(), "hya returned a null message");
    // SAFETY: hya returns NUL-terminated strings it owns.
    unsafe { CStr::from_ptr(ptr) }.to_string_lossy().into_owned()
}

/// Asserts `status` and that the message holds every one of `words`.
fn refused(status: HyaStatus, expected: HyaStatus, message: &str, words: &[&str]) {
    assert_eq!(status, expected, "message: {message}");
    for word in words {
        assert!(message.contains(word), "`{message}` does not mention `{word}`");
    }
}

fn planar2() -> *mut HyaModel {
    let mut model = null_mut();
    // SAFETY: a NUL-terminated name and a writable output.
    assert_eq!(unsafe { hya_model_from_arm(c"planar2".as_ptr(), &mut model) }, HyaStatus::HyaOk);
    model
}

#[test]
fn bad_models_are_refused_with_a_reason() {
    let mut model = planar2();
    // SAFETY: every pointer below is null, a NUL-terminated string or a writable output.
    unsafe {
        refused(
            hya_model_from_arm(c"pr2".as_ptr(), &mut model),
            HyaStatus::HyaErrInvalid,
            &text(hya_last_error()),
            &["pr2", "hya", "ur5", "panda", "iiwa14", "planar2"],
        );
        assert!(model.is_null(), "a failed creation leaves *out null");
        refused(hya_model_from_arm(null(), &mut model), HyaStatus::HyaErrNull, &text(hya_last_error()), &["name"]);
        refused(
            hya_model_from_arm(c"hya".as_ptr(), null_mut()),
            HyaStatus::HyaErrNull,
            &text(hya_last_error()),
            &["out"],
        );
        let not_utf8 = CString::new(vec![0xff, 0xfe]).unwrap();
        refused(
            hya_model_from_arm(not_utf8.as_ptr(), &mut model),
            HyaStatus::HyaErrInvalid,
            &text(hya_last_error()),
            &["UTF-8"],
        );
        refused(
            hya_model_from_urdf(c"/nonexistent/arm.urdf".as_ptr(), &mut model),
            HyaStatus::HyaErrModel,
            &text(hya_last_error()),
            &["/nonexistent/arm.urdf"],
        );
        let malformed = Path::new(env!("CARGO_MANIFEST_DIR")).join("../hya-urdf/tests/urdf/malformed");
        let mut files = 0;
        for entry in std::fs::read_dir(malformed).unwrap() {
            let path = entry.unwrap().path();
            let c_path = CString::new(path.to_str().unwrap()).unwrap();
            let status = hya_model_from_urdf(c_path.as_ptr(), &mut model);
            let message = text(hya_last_error());
            assert_ne!(status, HyaStatus::HyaOk, "{} was accepted", path.display());
            assert_ne!(status, HyaStatus::HyaErrPanic, "{}: {message}", path.display());
            assert!(model.is_null());
            let file = path.file_name().unwrap().to_str().unwrap();
            assert!(message.contains(file), "`{message}` does not name {file}");
            files += 1;
        }
        assert!(files > 3, "the malformed URDFs were not found");
        // Freeing null is a no-op.
        hya_model_free(null_mut());
        hya_estimator_free(null_mut());
        hya_observer_free(null_mut());
        hya_controller_free(null_mut());
        assert_eq!(hya_model_dof(null()), 0);
    }
}

/// The friction files every front end refuses (hya-ident's corpus, for a 2-joint arm), and a
/// missing file, each named in the message; the model given stays usable.
#[test]
fn bad_friction_files_are_refused_with_a_reason() {
    let base = planar2();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../hya-ident/tests/friction/refused");
    let mut files = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let expect = std::fs::read_to_string(&path).unwrap();
        let expect = expect.lines().next().and_then(|l| l.strip_prefix("# expect: ")).unwrap().to_owned();
        let file = path.file_name().unwrap().to_str().unwrap();
        let c_path = CString::new(path.to_str().unwrap()).unwrap();
        let mut model = null_mut();
        // SAFETY: a live model, a NUL-terminated path and a writable output.
        let status = unsafe { hya_model_with_friction(base, c_path.as_ptr(), &mut model) };
        let words: Vec<&str> = std::iter::once(file).chain(expect.split(" | ")).collect();
        refused(status, HyaStatus::HyaErrModel, &text(hya_last_error()), &words);
        assert!(model.is_null(), "a failed creation leaves *out null");
        files += 1;
    }
    assert!(files >= 9, "the corpus was not found");
    let mut model = null_mut();
    // SAFETY: a live model or null, NUL-terminated paths or null, writable outputs.
    unsafe {
        refused(
            hya_model_with_friction(base, c"/nonexistent/friction.toml".as_ptr(), &mut model),
            HyaStatus::HyaErrModel,
            &text(hya_last_error()),
            &["/nonexistent/friction.toml"],
        );
        refused(
            hya_model_with_friction(base, null(), &mut model),
            HyaStatus::HyaErrNull,
            &text(hya_last_error()),
            &["path"],
        );
        refused(
            hya_model_with_friction(null(), c"friction.toml".as_ptr(), &mut model),
            HyaStatus::HyaErrNull,
            &text(hya_last_error()),
            &["model"],
        );
        assert_eq!(hya_model_dof(base), 2, "the model given is unchanged");
        hya_model_free(base);
    }
}

/// Frame kinematics refuse an unknown or null frame and outputs of the wrong length, naming them.
#[test]
fn bad_frame_calls_are_refused() {
    let model = planar2();
    let (q, qd) = ([0.1, 0.2], [0.3, 0.4]);
    let mut out = [0.0; 12];
    // SAFETY: a live model (freed once at the end), NUL-terminated names or null, arrays of at
    // least the lengths passed.
    unsafe {
        let error = || text(hya_model_error(model));
        let status = hya_model_frame_jacobian(model, c"nowhere".as_ptr(), q.as_ptr(), 2, out.as_mut_ptr(), 12);
        refused(status, HyaStatus::HyaErrInvalid, &error(), &["nowhere", "base, upper_arm, forearm, tip"]);
        let status = hya_model_frame_jacobian(model, null(), q.as_ptr(), 2, out.as_mut_ptr(), 12);
        refused(status, HyaStatus::HyaErrNull, &error(), &["frame"]);
        let status = hya_model_frame_jacobian(model, c"tip".as_ptr(), q.as_ptr(), 2, out.as_mut_ptr(), 6);
        refused(status, HyaStatus::HyaErrLength, &error(), &["jacobian", "6", "12"]);
        let status =
            hya_model_frame_acceleration_bias(model, c"tip".as_ptr(), q.as_ptr(), qd.as_ptr(), 1, out.as_mut_ptr(), 6);
        refused(status, HyaStatus::HyaErrLength, &error(), &["q"]);
        let (mut a, mut b, mut c) = ([0.0; 4], [0.0; 4], [0.0; 4]);
        let (a, b, c) = (a.as_mut_ptr(), b.as_mut_ptr(), c.as_mut_ptr());
        let derivatives = |tau: *const f64, [x, y, z]: [*mut f64; 3], len: usize| {
            hya_model_forward_dynamics_derivatives(model, q.as_ptr(), qd.as_ptr(), tau, 2, x, y, z, len)
        };
        refused(derivatives([f64::NAN, 0.0].as_ptr(), [a, b, c], 4), HyaStatus::HyaErrNonFinite, &error(), &["tau[0]"]);
        refused(derivatives(qd.as_ptr(), [a, b, c], 3), HyaStatus::HyaErrLength, &error(), &["dqdd_dq", "3", "4"]);
        refused(derivatives(qd.as_ptr(), [a, a, c], 4), HyaStatus::HyaErrInvalid, &error(), &["distinct"]);
        // One buffer of three matrices, split where they touch: accepted; split a value short,
        // refused.
        let mut three = [0.0; 12];
        let p = three.as_mut_ptr();
        assert_eq!(derivatives(qd.as_ptr(), [p, p.add(4), p.add(8)], 4), HyaStatus::HyaOk, "{}", error());
        refused(
            derivatives(qd.as_ptr(), [p, p.add(3), p.add(8)], 4),
            HyaStatus::HyaErrInvalid,
            &error(),
            &["dqdd_dqd"],
        );
        // A length no array has is a length error, not an overflow.
        refused(
            derivatives(qd.as_ptr(), [p, p.add(4), p.add(8)], usize::MAX),
            HyaStatus::HyaErrLength,
            &error(),
            &["dqdd_dq"],
        );
        hya_model_free(model);
    }
}

#[test]
fn bad_dynamics_calls_are_refused() {
    let model = planar2();
    let (q, qd, qdd) = ([0.1, 0.2], [0.0; 2], [0.0; 2]);
    let nan = [0.1, f64::NAN];
    let mut out = [7.0; 2];
    let mut mass = [0.0; 3];
    // SAFETY: a live model (or null), arrays at least as long as the lengths passed.
    unsafe {
        let error = || text(hya_model_error(model));
        let status = hya_model_inverse_dynamics(null_mut(), q.as_ptr(), qd.as_ptr(), qdd.as_ptr(), 2, out.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNull, &text(hya_last_error()), &["handle"]);
        let status = hya_model_inverse_dynamics(model, q.as_ptr(), null(), qdd.as_ptr(), 2, out.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNull, &error(), &["qd"]);
        let status = hya_model_inverse_dynamics(model, q.as_ptr(), qd.as_ptr(), qdd.as_ptr(), 1, out.as_mut_ptr());
        refused(status, HyaStatus::HyaErrLength, &error(), &["q", "1", "2"]);
        let status = hya_model_inverse_dynamics(model, nan.as_ptr(), qd.as_ptr(), qdd.as_ptr(), 2, out.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNonFinite, &error(), &["q[1]", "NaN"]);
        assert_eq!(out, [7.0; 2], "a refused call wrote its output");
        refused(hya_model_gravity(model, q.as_ptr(), 2, null_mut()), HyaStatus::HyaErrNull, &error(), &["tau"]);
        refused(
            hya_model_mass_matrix(model, q.as_ptr(), 2, mass.as_mut_ptr(), 3),
            HyaStatus::HyaErrLength,
            &error(),
            &["mass", "3", "4"],
        );
        let inf = [f64::INFINITY, 0.0];
        let status = hya_model_forward_dynamics(model, q.as_ptr(), qd.as_ptr(), inf.as_ptr(), 2, out.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNonFinite, &error(), &["tau[0]", "inf"]);
        // In place, the output over an input: refused, the input untouched.
        let mut state = [0.1, 0.2];
        let p = state.as_mut_ptr();
        refused(hya_model_gravity(model, p, 2, p), HyaStatus::HyaErrInvalid, &error(), &["tau", "distinct"]);
        // Partly over the input: refused; right after it (touching): accepted.
        let mut wide = [0.1, 0.2, 7.0, 7.0];
        let w = wide.as_mut_ptr();
        refused(hya_model_gravity(model, w, 2, w.add(1)), HyaStatus::HyaErrInvalid, &error(), &["tau"]);
        assert_eq!(wide, [0.1, 0.2, 7.0, 7.0]);
        assert_eq!(hya_model_gravity(model, w, 2, w.add(2)), HyaStatus::HyaOk, "{}", error());
        assert_ne!(wide[2..], [7.0, 7.0]);
        let status = hya_model_forward_dynamics(model, q.as_ptr(), p, qdd.as_ptr(), 2, p);
        refused(status, HyaStatus::HyaErrInvalid, &error(), &["qdd", "distinct"]);
        assert_eq!(state, [0.1, 0.2]);
        // A success clears nothing but works.
        assert_eq!(hya_model_gravity(model, q.as_ptr(), 2, out.as_mut_ptr()), HyaStatus::HyaOk);
        hya_model_free(model);
    }
}

#[test]
fn bad_batch_calls_are_refused_naming_the_row() {
    let model = planar2();
    // Three states of two joints; the second's joint 1 is not a number.
    let q = [0.1, 0.2, 0.3, f64::NAN, 0.5, 0.6];
    let zeros = [0.0; 6];
    let mut out = [7.0; 6];
    let mut mass = [7.0; 12];
    // SAFETY: a live model (or null), arrays at least as long as the rows passed.
    unsafe {
        let error = || text(hya_model_error(model));
        let (z, o) = (zeros.as_ptr(), out.as_mut_ptr());
        refused(
            hya_model_inverse_dynamics_batch(model, q.as_ptr(), z, z, 3, 2, o),
            HyaStatus::HyaErrNonFinite,
            &error(),
            &["row 1", "q[1]", "NaN"],
        );
        refused(
            hya_model_gravity_batch(model, z, 2, 3, o),
            HyaStatus::HyaErrLength,
            &error(),
            &["q", "rows of 3", "2"],
        );
        refused(hya_model_gravity_batch(model, z, 3, 2, null_mut()), HyaStatus::HyaErrNull, &error(), &["tau"]);
        refused(
            hya_model_mass_matrix_batch(model, z, 3, 2, mass.as_mut_ptr(), 6),
            HyaStatus::HyaErrLength,
            &error(),
            &["mass", "6", "12"],
        );
        refused(
            hya_model_mass_matrix_batch(model, z, usize::MAX / 2, 2, mass.as_mut_ptr(), 12),
            HyaStatus::HyaErrLength,
            &error(),
            &["q", "rows"],
        );
        refused(
            hya_model_gravity_batch(null_mut(), z, 3, 2, o),
            HyaStatus::HyaErrNull,
            &text(hya_last_error()),
            &["handle"],
        );
        assert_eq!((out, mass), ([7.0; 6], [7.0; 12]), "a refused batch wrote its output");
        // In place: the output over an input is refused, not read while written.
        let mut states = [0.1; 6];
        let p = states.as_mut_ptr();
        refused(hya_model_gravity_batch(model, p, 3, 2, p.add(2)), HyaStatus::HyaErrInvalid, &error(), &["distinct"]);
        assert_eq!(states, [0.1; 6]);
        // A result that overflows is named by its row: τ of the third state, speeds of 1e200.
        let fast = [0.0, 0.0, 0.0, 0.0, 1e200, 1e200];
        refused(
            hya_model_inverse_dynamics_batch(model, z, fast.as_ptr(), z, 3, 2, o),
            HyaStatus::HyaErrNumeric,
            &error(),
            &["row 2", "tau"],
        );
        // No state at all is no work, and no error.
        assert_eq!(hya_model_gravity_batch(model, z, 0, 2, o), HyaStatus::HyaOk);
        assert_eq!(hya_model_forward_dynamics_derivatives_batch(model, z, z, z, 0, 2, o, 0), HyaStatus::HyaOk);
        hya_model_free(model);
    }
}

#[test]
fn bad_estimator_parameters_and_steps_are_refused_and_leave_the_state() {
    let model = planar2();
    let (q0, tau0) = ([0.1, 0.2], [0.0; 2]);
    let mut estimator = null_mut();
    // SAFETY: a live model (or null), arrays of 2 doubles, writable outputs.
    unsafe {
        let status = hya_estimator_new(model, -0.8, 50.0, 50.0, 1e-3, q0.as_ptr(), tau0.as_ptr(), 2, &mut estimator);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["zeta", "-0.8"]);
        let status = hya_estimator_new(model, 0.8, 50.0, 50.0, 0.0, q0.as_ptr(), tau0.as_ptr(), 2, &mut estimator);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["dt"]);
        // The limits `hya filter` and Python refuse too (hya-core's FilterParams).
        let status = hya_estimator_new(model, 1e-4, 50.0, 50.0, 1e-3, q0.as_ptr(), tau0.as_ptr(), 2, &mut estimator);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["zeta", "0.001"]);
        let status = hya_estimator_new(model, 0.8, 0.5, 50.0, 1e-6, q0.as_ptr(), tau0.as_ptr(), 2, &mut estimator);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["omega1", "at least 1e-6"]);
        let status = hya_estimator_new(model, 0.8, f64::NAN, 50.0, 1e-3, q0.as_ptr(), tau0.as_ptr(), 2, &mut estimator);
        assert_ne!(status, HyaStatus::HyaOk);
        let status = hya_estimator_new(null(), 0.8, 50.0, 50.0, 1e-3, q0.as_ptr(), tau0.as_ptr(), 2, &mut estimator);
        refused(status, HyaStatus::HyaErrNull, &text(hya_last_error()), &["model"]);
        assert!(estimator.is_null());

        // Two estimators; one also receives refused steps. They must stay equal.
        let mut twin = null_mut();
        for out in [&mut estimator, &mut twin] {
            let status = hya_estimator_new(model, 0.8, 50.0, 50.0, 1e-3, q0.as_ptr(), tau0.as_ptr(), 2, out);
            assert_eq!(status, HyaStatus::HyaOk, "{}", text(hya_last_error()));
        }
        let (mut d, mut d_twin) = ([0.0; 2], [0.0; 2]);
        for k in 0..200 {
            let q = [0.1 + 0.01 * k as f64, 0.2];
            let tau = [1.0, -0.5];
            let nan = [f64::NAN, 0.0];
            let error = || text(hya_estimator_error(estimator));
            refused(
                hya_estimator_update(estimator, nan.as_ptr(), tau.as_ptr(), 2, d.as_mut_ptr()),
                HyaStatus::HyaErrNonFinite,
                &error(),
                &["q", "NaN"],
            );
            refused(
                hya_estimator_update(estimator, q.as_ptr(), tau.as_ptr(), 3, d.as_mut_ptr()),
                HyaStatus::HyaErrLength,
                &error(),
                &["3"],
            );
            refused(
                hya_estimator_update(estimator, q.as_ptr(), tau.as_ptr(), 2, null_mut()),
                HyaStatus::HyaErrNull,
                &error(),
                &["d_hat"],
            );
            assert_eq!(hya_estimator_update(estimator, q.as_ptr(), tau.as_ptr(), 2, d.as_mut_ptr()), HyaStatus::HyaOk);
            assert_eq!(hya_estimator_update(twin, q.as_ptr(), tau.as_ptr(), 2, d_twin.as_mut_ptr()), HyaStatus::HyaOk);
            assert_eq!(d, d_twin, "a refused step changed the estimator (step {k})");
        }
        // Each kind of estimator refuses the other kind's update, and time must move forward.
        let status = hya_estimator_update_at(estimator, 1.0, q0.as_ptr(), tau0.as_ptr(), 2, d.as_mut_ptr(), null_mut());
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_estimator_error(estimator)), &["hya_estimator_new_timed"]);
        let mut timed = null_mut();
        let status =
            hya_estimator_new_timed(model, 0.8, 50.0, 50.0, 1e-3, 5.0, q0.as_ptr(), tau0.as_ptr(), 2, &mut timed);
        assert_eq!(status, HyaStatus::HyaOk, "{}", text(hya_last_error()));
        let status = hya_estimator_update(timed, q0.as_ptr(), tau0.as_ptr(), 2, d.as_mut_ptr());
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_estimator_error(timed)), &["hya_estimator_update_at"]);
        for t in [5.0, 4.0, f64::NAN] {
            let status = hya_estimator_update_at(timed, t, q0.as_ptr(), tau0.as_ptr(), 2, d.as_mut_ptr(), null_mut());
            refused(status, HyaStatus::HyaErrInvalid, &text(hya_estimator_error(timed)), &["`t`"]);
        }
        // Outputs over inputs: d̂ over τ, the `restarted` flag inside d̂; refused, the state kept
        // (the next step is accepted at the same time).
        let mut joint = [0.0; 2];
        let status =
            hya_estimator_update_at(timed, 5.001, q0.as_ptr(), joint.as_ptr(), 2, joint.as_mut_ptr(), null_mut());
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_estimator_error(timed)), &["d_hat"]);
        let flag = d.as_mut_ptr().cast::<bool>();
        let status = hya_estimator_update_at(timed, 5.001, q0.as_ptr(), tau0.as_ptr(), 2, d.as_mut_ptr(), flag);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_estimator_error(timed)), &["restarted"]);
        let status = hya_estimator_update_at(timed, 5.001, q0.as_ptr(), tau0.as_ptr(), 2, d.as_mut_ptr(), null_mut());
        assert_eq!(status, HyaStatus::HyaOk, "{}", text(hya_estimator_error(timed)));
        hya_estimator_free(timed);
        let status = hya_estimator_update(null_mut(), q0.as_ptr(), tau0.as_ptr(), 2, d.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNull, &text(hya_last_error()), &["handle"]);
        hya_estimator_free(estimator);
        hya_estimator_free(twin);
        hya_model_free(model);
    }
}

#[test]
fn bad_controllers_and_observers_are_refused() {
    let model = planar2();
    let (kp, kd, bad) = ([100.0; 2], [10.0; 2], [100.0, -1.0]);
    let zero = [0.0; 2];
    let mut controller = null_mut();
    let mut observer = null_mut();
    let mut tau = [0.0; 2];
    // SAFETY: a live model, arrays of 2 doubles, writable outputs.
    unsafe {
        let status = hya_controller_new(model, kp.as_ptr(), kd.as_ptr(), 2, 7, &mut controller);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["placement", "7"]);
        let status = hya_controller_new(model, kp.as_ptr(), bad.as_ptr(), 2, 0, &mut controller);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["kd", "-1"]);
        assert!(controller.is_null());
        let status = hya_controller_new(model, kp.as_ptr(), kd.as_ptr(), 2, 1, &mut controller);
        assert_eq!(status, HyaStatus::HyaOk);
        let p = zero.as_ptr();
        let status = hya_controller_command(controller, p, p, null(), p, p, null(), 2, tau.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNull, &text(hya_controller_error(controller)), &["q_des"]);
        let nan = [0.0, f64::NAN];
        let status = hya_controller_command(controller, p, p, p, p, p, nan.as_ptr(), 2, tau.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNonFinite, &text(hya_controller_error(controller)), &["d_hat[1]"]);
        hya_controller_free(controller);

        let status = hya_observer_new_nonlinear(model, -3.0, 1e-3, p, 2, &mut observer);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["gain"]);
        let status = hya_observer_new_extended_state(model, 1e6, 1e-3, p, 2, &mut observer);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["bandwidth"]);
        let status = hya_observer_new_nonlinear(model, 30.0, 1e-3, p, 2, &mut observer);
        assert_eq!(status, HyaStatus::HyaOk);
        // Chen's observer needs the measured velocity.
        let status = hya_observer_update(observer, p, null(), p, 2, tau.as_mut_ptr());
        assert_eq!(status, HyaStatus::HyaErrInvalid, "{}", text(hya_observer_error(observer)));
        assert!(text(hya_observer_error(observer)).contains("qd"), "{}", text(hya_observer_error(observer)));
        hya_observer_free(observer);
        hya_model_free(model);
    }
}

#[test]
fn bad_cartesian_controllers_and_commands_are_refused() {
    let model = planar2();
    let (stiffness, damping, negative) = ([100.0; 6], [10.0; 6], [10.0, 10.0, 10.0, -1.0, 10.0, 10.0]);
    let (zero, nan) = ([0.0; 2], [0.0, f64::NAN]);
    let identity = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let mirrored = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0];
    let mut controller = null_mut();
    let mut tau = [0.0; 2];
    let (s, d, p) = (stiffness.as_ptr(), damping.as_ptr(), zero.as_ptr());
    // SAFETY: a live model, arrays of the lengths passed or null, writable outputs.
    unsafe {
        let status = hya_cartesian_new(
            model,
            null(),
            s,
            negative.as_ptr(),
            null(),
            null(),
            null(),
            null(),
            2,
            1e-3,
            &mut controller,
        );
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["damping", "-1"]);
        let status =
            hya_cartesian_new(model, null(), null(), d, null(), null(), null(), null(), 2, 1e-3, &mut controller);
        refused(status, HyaStatus::HyaErrNull, &text(hya_last_error()), &["stiffness"]);
        let status = hya_cartesian_new(model, null(), s, d, p, null(), p, null(), 2, 1e-3, &mut controller);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["posture", "all given or none"]);
        let status = hya_cartesian_new(model, null(), null(), d, null(), p, null(), null(), 2, 1e-3, &mut controller);
        refused(status, HyaStatus::HyaErrNull, &text(hya_last_error()), &["stiffness"]);
        let status =
            hya_cartesian_new(model, null(), s, d, null(), null(), null(), nan.as_ptr(), 2, 1e-3, &mut controller);
        refused(status, HyaStatus::HyaErrNonFinite, &text(hya_last_error()), &["torque_limit[1]"]);
        let status = hya_cartesian_new(model, null(), s, d, null(), null(), null(), p, 2, 1e-3, &mut controller);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["torque_limit"]);
        let status = hya_cartesian_new(model, null(), s, d, p, p, p, null(), 1, 1e-3, &mut controller);
        refused(status, HyaStatus::HyaErrLength, &text(hya_last_error()), &["posture_rest"]);
        let status =
            hya_cartesian_new(model, null(), s, d, null(), null(), null(), null(), 2, f64::NAN, &mut controller);
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["mu"]);
        let status = hya_cartesian_new(
            model,
            c"nowhere".as_ptr(),
            s,
            d,
            null(),
            null(),
            null(),
            null(),
            2,
            0.0,
            &mut controller,
        );
        refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["nowhere"]);
        assert!(controller.is_null());
        // The last link by default.
        let status = hya_cartesian_new(model, null(), s, d, null(), null(), null(), null(), 2, 1e-3, &mut controller);
        assert_eq!(status, HyaStatus::HyaOk, "{}", text(hya_last_error()));
        let position = [0.5, 0.0, 0.0];
        let command = |q: &[f64; 2], orientation: &[f64; 9], d_hat: *const f64, tau: &mut [f64; 2]| {
            hya_cartesian_command(
                controller,
                q.as_ptr(),
                p,
                position.as_ptr(),
                orientation.as_ptr(),
                null(),
                d_hat,
                2,
                tau.as_mut_ptr(),
            )
        };
        refused(
            command(&nan, &identity, null(), &mut tau),
            HyaStatus::HyaErrNonFinite,
            &text(hya_cartesian_error(controller)),
            &["q[1]"],
        );
        refused(
            command(&zero, &mirrored, null(), &mut tau),
            HyaStatus::HyaErrInvalid,
            &text(hya_cartesian_error(controller)),
            &["orientation_des", "determinant"],
        );
        refused(
            command(&zero, &identity, nan.as_ptr(), &mut tau),
            HyaStatus::HyaErrNonFinite,
            &text(hya_cartesian_error(controller)),
            &["d_hat[1]"],
        );
        let status =
            hya_cartesian_command(controller, p, p, null(), identity.as_ptr(), null(), null(), 2, tau.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNull, &text(hya_cartesian_error(controller)), &["position_des"]);
        assert_eq!(command(&zero, &identity, null(), &mut tau), HyaStatus::HyaOk);
        hya_cartesian_free(controller);
        hya_model_free(model);
    }
}

#[test]
fn results_that_overflow_are_refused_not_returned() {
    // q̇ = 1e160 squares past the largest double: the CLI refused it, the C ABI returned HYA_OK
    // with NaN torques.
    let model = planar2();
    let (q, qd, qdd) = ([0.1, 0.2], [1e160, 0.0], [0.0; 2]);
    let mut tau = [0.0; 2];
    // SAFETY: a live model, arrays of 2 doubles.
    unsafe {
        let status = hya_model_inverse_dynamics(model, q.as_ptr(), qd.as_ptr(), qdd.as_ptr(), 2, tau.as_mut_ptr());
        refused(status, HyaStatus::HyaErrNumeric, &text(hya_model_error(model)), &["tau[", "not finite"]);
        hya_model_free(model);
    }
}

#[test]
fn chen_s_gain_beyond_the_sample_rate_is_refused() {
    // y = 1e300 at 1 ms gave d̂ ≈ 1e284 on a moving arm.
    let model = planar2();
    let zero = [0.0; 2];
    let mut observer = null_mut();
    // SAFETY: a live model, arrays of 2 doubles, a writable output.
    unsafe {
        for gain in [1e300, 1e9] {
            let status = hya_observer_new_nonlinear(model, gain, 1e-3, zero.as_ptr(), 2, &mut observer);
            refused(status, HyaStatus::HyaErrInvalid, &text(hya_last_error()), &["gain", "slowest rate"]);
            assert!(observer.is_null());
        }
        hya_model_free(model);
    }
}

#[test]
fn handles_of_the_wrong_kind_and_freed_handles_are_refused() {
    let model = planar2();
    let zero = [0.0; 2];
    let mut observer = null_mut();
    let mut tau = [0.0; 2];
    // SAFETY: the pointers passed are live handles, freed handles or of another kind: what the
    // registry must catch before reading through them.
    unsafe {
        assert_eq!(hya_observer_new_nonlinear(model, 30.0, 1e-3, zero.as_ptr(), 2, &mut observer), HyaStatus::HyaOk);
        let as_model = observer.cast::<HyaModel>();
        let status = hya_model_gravity(as_model, zero.as_ptr(), 2, tau.as_mut_ptr());
        refused(status, HyaStatus::HyaErrHandle, &text(hya_last_error()), &["HyaObserver", "not a HyaModel"]);
        assert_eq!(hya_model_dof(as_model), 0);
        hya_model_free(as_model);
        refused(HyaStatus::HyaErrHandle, HyaStatus::HyaErrHandle, &text(hya_last_error()), &["HyaObserver"]);
        // The observer survived the wrong free and works.
        let status = hya_observer_update(observer, zero.as_ptr(), zero.as_ptr(), zero.as_ptr(), 2, tau.as_mut_ptr());
        assert_eq!(status, HyaStatus::HyaOk, "{}", text(hya_observer_error(observer)));
        hya_observer_free(observer);
        // A double free, and a call on the freed handle.
        hya_observer_free(observer);
        refused(HyaStatus::HyaErrHandle, HyaStatus::HyaErrHandle, &text(hya_last_error()), &["freed already"]);
        let status = hya_observer_update(observer, zero.as_ptr(), zero.as_ptr(), zero.as_ptr(), 2, tau.as_mut_ptr());
        refused(status, HyaStatus::HyaErrHandle, &text(hya_last_error()), &["not a live HyaObserver"]);
        assert!(text(hya_observer_error(observer)).contains("not a live handle"));
        hya_model_free(model);
        hya_model_free(model);
        refused(HyaStatus::HyaErrHandle, HyaStatus::HyaErrHandle, &text(hya_last_error()), &["HyaModel"]);
    }
}

#[cfg(unix)]
#[test]
fn a_fifo_as_the_urdf_is_refused_without_blocking() {
    let dir = std::env::temp_dir().join(format!("hya-capi-fifo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("arm.urdf");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let path = CString::new(fifo.to_str().unwrap()).unwrap();
    let mut model = null_mut();
    // SAFETY: a NUL-terminated path and a writable output.
    let status = unsafe { hya_model_from_urdf(path.as_ptr(), &mut model) };
    std::fs::remove_dir_all(&dir).unwrap();
    refused(status, HyaStatus::HyaErrModel, &text(hya_last_error()), &["arm.urdf", "named pipe"]);
}
