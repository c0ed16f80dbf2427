//! The hot paths (filter step, estimator update, controller step, generated dynamics) never
//! touch the heap: a counting global allocator sees no allocation while they run.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::f64::consts::FRAC_PI_4;
use std::ptr::{null, null_mut};

use hya_capi::{
    hya_cartesian_command, hya_cartesian_free, hya_cartesian_new, hya_controller_command, hya_controller_free,
    hya_controller_new, hya_estimator_free, hya_estimator_new, hya_estimator_new_timed, hya_estimator_update,
    hya_estimator_update_at, hya_last_error, hya_model_forward_dynamics, hya_model_forward_dynamics_batch,
    hya_model_forward_dynamics_derivatives, hya_model_forward_dynamics_derivatives_batch, hya_model_free,
    hya_model_from_arm, hya_model_gravity, hya_model_gravity_batch, hya_model_inverse_dynamics,
    hya_model_inverse_dynamics_batch, hya_model_mass_matrix, hya_observer_free, hya_observer_new_extended_state,
    hya_observer_update, HyaStatus,
};
use hya_core::test_arms::PlanarTwoLink;
use hya_core::{
    CartesianImpedance, CartesianReference, ComputedTorque, DisturbanceAttenuation, DisturbanceEstimator, Dynamics,
    FilterParams, FrameKinematics, FrameState, Gains, Impedance, JointVector, OnSlicesN, Reference, SliceDynamics,
    ThirdOrderFilter, TimedEstimator,
};
use hya_robots::{Hya, Panda};

/// Counts allocations made by the current thread (the test harness's own threads do not count).
struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator, with the caller's guarantees.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System.alloc` with this `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn allocations_during(work: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    work();
    ALLOCATIONS.with(Cell::get) - before
}

#[test]
fn hot_paths_do_not_allocate() {
    let arm = PlanarTwoLink::default();
    let params = FilterParams::paper(1e-3).unwrap();
    let q0 = JointVector::from([0.3, -0.2]);
    let mut filter = ThirdOrderFilter::<2>::new(params, q0).unwrap();
    let mut estimator = DisturbanceEstimator::new(&arm, params, q0, arm.gravity(&q0)).unwrap();
    let controller = ComputedTorque::new(&arm, Gains::diagonal([50.0, 50.0], [5.0, 5.0]).unwrap())
        .with_torque_limit(JointVector::from([40.0, 40.0]))
        .unwrap();
    // The counter must see allocations at all, or a zero below would prove nothing.
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);

    let count = allocations_during(|| {
        let mut q = q0;
        for k in 0..2000 {
            q[0] = 0.3 + 0.1 * (k as f64 * 1e-3).sin();
            filter.step(std::hint::black_box(&q)).unwrap();
            let tau = controller
                .command(&q, &filter.state().x2, &Reference::hold(q0), Some(estimator.disturbance()))
                .unwrap()
                .torque;
            estimator.update(&q, &tau).unwrap();
            // The error path must not allocate either.
            assert!(estimator.update(&JointVector::from([f64::NAN, 0.0]), &tau).is_err());
        }
    });
    assert_eq!(count, 0, "the hot paths allocated {count} times");
}

/// The Cartesian impedance controller's tick on the generated Panda: the tool's kinematics from
/// the generated tip, then the command.
#[test]
fn the_cartesian_impedance_step_does_not_allocate() {
    let ready = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785];
    let q = JointVector::<7>::from(ready);
    let frame = FrameState::of(&Panda, &q);
    let mut target = frame.position;
    target[0] += 0.01;
    let reference = CartesianReference::hold(target, frame.orientation);
    let gains = Impedance::new([500.0; 6], [50.0; 6]).unwrap().with_posture(ready, [5.0; 7], [2.0; 7]).unwrap();
    let controller = CartesianImpedance::new(Panda, gains).with_torque_limit(JointVector::from([80.0; 7])).unwrap();
    let d_hat = JointVector::<7>::from([0.5; 7]);
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);
    let count = allocations_during(|| {
        for _ in 0..200 {
            let frame = FrameState::of(&Panda, std::hint::black_box(&q));
            let command = controller.command(&q, &JointVector::zeros(), &frame, &reference, Some(&d_hat)).unwrap();
            std::hint::black_box(command);
            // The error path must not allocate either.
            let bad = JointVector::from([f64::NAN; 7]);
            assert!(controller.command(&bad, &JointVector::zeros(), &frame, &reference, None).is_err());
        }
    });
    assert_eq!(count, 0, "the Cartesian step allocated {count} times");
}

/// The variable-step update of a log with timestamps: jittered steps, new lengths (each one's
/// matrix exponential), cache evictions, gaps, a restart and a refused time.
#[test]
fn the_timestamped_update_does_not_allocate() {
    let arm = PlanarTwoLink::default();
    let params = FilterParams::paper(1e-3).unwrap();
    let q0 = JointVector::from([0.3, -0.2]);
    let mut estimator = TimedEstimator::new(&arm, params, 0.0, q0, arm.gravity(&q0)).unwrap();
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);
    let count = allocations_during(|| {
        let mut t = 0.0;
        for k in 0..2000 {
            // Steps of 0.8 to 1.2 ms in 13 lengths (more than the cache holds), a 30 ms gap every
            // 100 rows, a 3 s one (a restart) at row 1000.
            t += match k {
                1000 => 3.0,
                _ if k % 100 == 99 => 0.03,
                _ => 8e-4 + (k % 13) as f64 * 3e-5,
            };
            let q = JointVector::from([0.3 + 0.1 * t.sin(), -0.2]);
            let tau = arm.gravity(&q);
            let step = estimator.update(std::hint::black_box(t), &q, &tau).unwrap();
            assert_eq!(step.restarted, k == 1000);
            assert!(estimator.update(t, &q, &tau).is_err(), "a repeated time is refused");
        }
    });
    assert!(estimator.discretisations_computed() > 13, "the cache was exercised past its size");
    assert_eq!(count, 0, "the timestamped update allocated {count} times");
}

/// Every entry point of generated dynamics, and the paper's loop on the generated HyA model.
#[test]
fn generated_dynamics_and_the_hya_control_tick_do_not_allocate() {
    let params = FilterParams::paper(1e-3).unwrap();
    let q0 = JointVector::<6>::from([0.0, 0.0, -FRAC_PI_4, FRAC_PI_4, FRAC_PI_4, 0.0]);
    let mut estimator = DisturbanceEstimator::new(Hya, params, q0, Hya.gravity(&q0)).unwrap();
    let controller = ComputedTorque::new(Hya, Gains::diagonal([100.0; 6], [10.0; 6]).unwrap());
    let mut paired =
        DisturbanceAttenuation::new(Hya, params, Gains::diagonal([100.0; 6], [10.0; 6]).unwrap(), q0, Hya.gravity(&q0))
            .unwrap();
    let panda_q = JointVector::<7>::from([0.1, -0.3, 0.2, -1.5, 0.1, 1.2, 0.4]);
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);

    let count = allocations_during(|| {
        for k in 0..500 {
            let q = q0.map(|v| v + 1e-3 * k as f64);
            let qd = JointVector::from_element(0.1);
            let tau = controller.command(&q, &qd, &Reference::hold(q0), Some(estimator.disturbance())).unwrap().torque;
            estimator.update(&q, &tau).unwrap();
            // The paired tick (both inverse dynamics in one batch call) and its error path.
            std::hint::black_box(paired.tick(&q, &qd, &tau, &Reference::hold(q0)).unwrap());
            assert!(paired.tick(&q, &JointVector::from_element(f64::NAN), &tau, &Reference::hold(q0)).is_err());
            std::hint::black_box(Hya.mass_matrix(&q));
            std::hint::black_box(Hya.coriolis_transpose_times_velocity(&q, &qd));
            std::hint::black_box(Hya.velocity_terms(&q, &qd));
            std::hint::black_box(Hya.forward_dynamics(&q, &qd, &tau).unwrap());
            std::hint::black_box(Panda.inverse_dynamics(&panda_q, &panda_q, &panda_q));
            std::hint::black_box(Hya.inverse_dynamics_derivatives(&q, &qd, &tau));
            std::hint::black_box(Hya.forward_dynamics_derivatives(&q, &qd, &tau).unwrap());
            std::hint::black_box(Panda.forward_dynamics(&panda_q, &panda_q, &panda_q).unwrap());
        }
    });
    assert_eq!(count, 0, "generated dynamics allocated {count} times");
}

/// The batch entry points of generated dynamics work in place: the caller's slices in and out.
#[test]
fn generated_batches_do_not_allocate() {
    let states: [[JointVector<6>; 3]; 37] = hya_core::sampling::varied_states();
    let [q, qd, qdd]: [Vec<JointVector<6>>; 3] = core::array::from_fn(|i| states.iter().map(|s| s[i]).collect());
    let mut out = vec![JointVector::<6>::zeros(); states.len()];
    let mut m = vec![hya_core::JointMatrix::<6>::zeros(); states.len()];
    let (mut m2, mut m3) = (m.clone(), m.clone());
    let mut rows = vec![0.0; 3 * 36 * states.len()];
    let flat = |v: &[JointVector<6>]| -> Vec<f64> { v.iter().flat_map(|x| x.iter().copied()).collect() };
    let (q_rows, qd_rows, tau_rows) = (flat(&q), flat(&qd), flat(&qdd));
    let mut jacobian = vec![hya_core::FrameJacobian::<6>::zeros(); states.len()];
    let mut bias = vec![hya_core::FrameVector::zeros(); states.len()];
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);
    let count = allocations_during(|| {
        Hya.inverse_dynamics_batch(&q, &qd, &qdd, &mut out).unwrap();
        Hya.gravity_batch(&q, &mut out).unwrap();
        Hya.mass_matrix_batch(&q, &mut m).unwrap();
        Hya.forward_dynamics_batch(&q, &qd, &qdd, &mut out).unwrap();
        Hya.inverse_dynamics_derivatives_batch(&q, &qd, &qdd, &mut m, &mut m2).unwrap();
        Hya.forward_dynamics_derivatives_batch(&q, &qd, &qdd, (&mut m, &mut m2, &mut m3)).unwrap();
        OnSlicesN::<6, _>(Hya).forward_dynamics_derivatives_rows(&q_rows, &qd_rows, &tau_rows, &mut rows).unwrap();
        Hya.frame_jacobian_batch(&q, &mut jacobian).unwrap();
        Hya.frame_acceleration_bias_batch(&q, &qd, &mut bias).unwrap();
        // The error path neither.
        assert!(Hya.inverse_dynamics_batch(&q[1..], &qd, &qdd, &mut out).is_err());
    });
    assert_eq!(count, 0, "generated batches allocated {count} times");
}

/// The run-time model's fixed-size form keeps its workspace on the stack: every entry point,
/// the articulated-body algorithm and the analytic derivatives included.
#[test]
fn the_fixed_size_run_time_model_does_not_allocate() {
    let model = hya_urdf::load_str(hya_robots::hya::URDF, "hya").unwrap().model.into_dynamics::<6>().unwrap();
    let q = JointVector::<6>::from([0.1, -0.2, -0.5, 1.0, 0.3, 0.4]);
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);
    let count = allocations_during(|| {
        let tau = model.inverse_dynamics(&q, &q, &q);
        std::hint::black_box(model.mass_matrix(&q));
        std::hint::black_box(model.gravity(&q));
        std::hint::black_box(model.coriolis_transpose_times_velocity(&q, &q));
        std::hint::black_box(model.forward_dynamics(&q, &q, &tau).unwrap());
        std::hint::black_box(model.inverse_dynamics_derivatives(&q, &q, &q));
    });
    assert_eq!(count, 0, "TreeDynamics<6> allocated {count} times");
}

/// After creation, no call through the C ABI touches the heap: dynamics, estimator, observer and
/// controller calls, and their error paths (messages go to fixed buffers).
#[test]
fn c_abi_calls_after_creation_do_not_allocate() {
    const N: usize = 6; // HyA
    let (mut model, mut estimator, mut observer, mut controller) = (null_mut(), null_mut(), null_mut(), null_mut());
    let mut timed = null_mut();
    let q0 = [0.2; N];
    let tau0 = [0.0; N];
    // SAFETY: NUL-terminated names, arrays of N doubles, writable outputs.
    unsafe {
        assert_eq!(hya_model_from_arm(c"hya".as_ptr(), &mut model), HyaStatus::HyaOk);
        assert_eq!(
            hya_estimator_new(model, 0.8, 50.0, 50.0, 1e-3, q0.as_ptr(), tau0.as_ptr(), N, &mut estimator),
            HyaStatus::HyaOk
        );
        assert_eq!(
            hya_estimator_new_timed(model, 0.8, 50.0, 50.0, 1e-3, 0.0, q0.as_ptr(), tau0.as_ptr(), N, &mut timed),
            HyaStatus::HyaOk
        );
        assert_eq!(hya_observer_new_extended_state(model, 60.0, 1e-3, q0.as_ptr(), N, &mut observer), HyaStatus::HyaOk);
        assert_eq!(
            hya_controller_new(model, [100.0; N].as_ptr(), [20.0; N].as_ptr(), N, 1, &mut controller),
            HyaStatus::HyaOk
        );
        // The thread's last-error buffer is made on first use; make it before counting.
        let _ = hya_last_error();
    }
    // The counter must see allocations at all, or a zero below would prove nothing.
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);

    let count = allocations_during(|| {
        let (mut q, zero, nan) = (q0, [0.0; N], [f64::NAN; N]);
        let (mut tau, mut d_hat, mut mass) = ([0.0; N], [0.0; N], [0.0; N * N]);
        let (mut states, zeros, nans) = ([0.2; 5 * N], [0.0; 5 * N], [f64::NAN; 5 * N]);
        let (mut out, mut derivatives) = ([0.0; 5 * N], [0.0; 5 * 3 * N * N]);
        // SAFETY: live handles, arrays of N (N² for the mass matrix) doubles, or deliberately
        // null or short arguments the ABI must refuse.
        unsafe {
            for k in 0..500 {
                q[0] = 0.2 + 0.1 * (k as f64 * 1e-3).sin();
                let p = q.as_ptr();
                hya_controller_command(
                    controller,
                    p,
                    zero.as_ptr(),
                    q0.as_ptr(),
                    zero.as_ptr(),
                    zero.as_ptr(),
                    d_hat.as_ptr(),
                    N,
                    tau.as_mut_ptr(),
                );
                hya_estimator_update(estimator, p, tau.as_ptr(), N, d_hat.as_mut_ptr());
                // Jittered steps: new lengths, each one's matrix exponential, cache evictions.
                let t = 1e-3 * k as f64 + 2e-4 * (k as f64 * 0.7).sin();
                let status =
                    hya_estimator_update_at(timed, 1e-3 + t, p, tau.as_ptr(), N, d_hat.as_mut_ptr(), null_mut());
                assert_eq!(status, HyaStatus::HyaOk);
                hya_observer_update(observer, p, null(), tau.as_ptr(), N, d_hat.as_mut_ptr());
                hya_model_inverse_dynamics(model, p, zero.as_ptr(), zero.as_ptr(), N, tau.as_mut_ptr());
                hya_model_forward_dynamics(model, p, zero.as_ptr(), tau.as_ptr(), N, d_hat.as_mut_ptr());
                // Batches of the generated code, and their refusals (a non-finite row, a wrong
                // output length, an output over an input).
                let status = hya_model_forward_dynamics_batch(
                    model,
                    states.as_ptr(),
                    zeros.as_ptr(),
                    zeros.as_ptr(),
                    5,
                    N,
                    out.as_mut_ptr(),
                );
                assert_eq!(status, HyaStatus::HyaOk);
                hya_model_inverse_dynamics_batch(
                    model,
                    states.as_ptr(),
                    zeros.as_ptr(),
                    zeros.as_ptr(),
                    5,
                    N,
                    out.as_mut_ptr(),
                );
                let (d, len) = (derivatives.as_mut_ptr(), derivatives.len());
                let status = hya_model_forward_dynamics_derivatives_batch(
                    model,
                    states.as_ptr(),
                    zeros.as_ptr(),
                    zeros.as_ptr(),
                    5,
                    N,
                    d,
                    len,
                );
                assert_eq!(status, HyaStatus::HyaOk);
                let status = hya_model_gravity_batch(model, nans.as_ptr(), 5, N, out.as_mut_ptr());
                assert_eq!(status, HyaStatus::HyaErrNonFinite);
                let status = hya_model_forward_dynamics_derivatives_batch(
                    model,
                    states.as_ptr(),
                    zeros.as_ptr(),
                    zeros.as_ptr(),
                    5,
                    N,
                    d,
                    len - 1,
                );
                assert_eq!(status, HyaStatus::HyaErrLength);
                let status = hya_model_gravity_batch(model, states.as_ptr(), 5, N, states.as_mut_ptr());
                assert_eq!(status, HyaStatus::HyaErrInvalid);
                // A single call in place, refused; the derivatives' outputs, one over another.
                assert_eq!(hya_model_gravity(model, p, N, q.as_mut_ptr()), HyaStatus::HyaErrInvalid);
                let (d, nn) = (derivatives.as_mut_ptr(), N * N);
                let status = hya_model_forward_dynamics_derivatives(
                    model,
                    p,
                    zero.as_ptr(),
                    zero.as_ptr(),
                    N,
                    d,
                    d.add(1),
                    d.add(2 * nn),
                    nn,
                );
                assert_eq!(status, HyaStatus::HyaErrInvalid);
                let status = hya_model_forward_dynamics_derivatives(
                    model,
                    p,
                    zero.as_ptr(),
                    zero.as_ptr(),
                    N,
                    d,
                    d.add(nn),
                    d.add(2 * nn),
                    nn,
                );
                assert_eq!(status, HyaStatus::HyaOk);
                hya_model_mass_matrix(model, p, N, mass.as_mut_ptr(), N * N);
                hya_model_gravity(model, p, N, tau.as_mut_ptr());
                // Error paths: a NaN, a short length, a null handle, a null output.
                assert_eq!(
                    hya_estimator_update(estimator, nan.as_ptr(), tau.as_ptr(), N, d_hat.as_mut_ptr()),
                    HyaStatus::HyaErrNonFinite
                );
                assert_eq!(hya_model_gravity(model, p, N - 1, tau.as_mut_ptr()), HyaStatus::HyaErrLength);
                assert_eq!(hya_model_gravity(null_mut(), p, N, tau.as_mut_ptr()), HyaStatus::HyaErrNull);
                assert_eq!(
                    hya_controller_command(controller, p, p, p, p, p, null(), N, null_mut()),
                    HyaStatus::HyaErrNull
                );
            }
        }
    });
    assert_eq!(count, 0, "calls through the ABI allocated {count} times");
    // The Cartesian controller on a frame of the run-time tree: its kinematics into the buffers
    // made at creation, and its refusals, without the heap.
    let mut cartesian = null_mut();
    let (stiffness, damping) = ([500.0; 6], [50.0; 6]);
    // SAFETY: a live model, a NUL-terminated frame, arrays of 6 doubles, a writable output.
    unsafe {
        let status = hya_cartesian_new(
            model,
            c"ee".as_ptr(),
            stiffness.as_ptr(),
            damping.as_ptr(),
            null(),
            null(),
            null(),
            null(),
            N,
            1e-3,
            &mut cartesian,
        );
        assert_eq!(status, HyaStatus::HyaOk, "{:?}", std::ffi::CStr::from_ptr(hya_last_error()));
    }
    let identity = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let skewed = [1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let count = allocations_during(|| {
        let (mut q, zero, mut tau) = (q0, [0.0; N], [0.0; N]);
        // SAFETY: a live handle, arrays of the lengths passed, or a skewed orientation it refuses.
        unsafe {
            for k in 0..500 {
                q[1] = 0.2 + 0.1 * (k as f64 * 1e-3).sin();
                let position = [0.3, 0.1, 0.4];
                let status = hya_cartesian_command(
                    cartesian,
                    q.as_ptr(),
                    zero.as_ptr(),
                    position.as_ptr(),
                    identity.as_ptr(),
                    null(),
                    zero.as_ptr(),
                    N,
                    tau.as_mut_ptr(),
                );
                assert_eq!(status, HyaStatus::HyaOk);
                let status = hya_cartesian_command(
                    cartesian,
                    q.as_ptr(),
                    zero.as_ptr(),
                    position.as_ptr(),
                    skewed.as_ptr(),
                    null(),
                    null(),
                    N,
                    tau.as_mut_ptr(),
                );
                assert_eq!(status, HyaStatus::HyaErrInvalid);
            }
        }
    });
    assert_eq!(count, 0, "the Cartesian controller through the ABI allocated {count} times");
    // SAFETY: live handles, each freed once.
    unsafe {
        hya_cartesian_free(cartesian);
        hya_controller_free(controller);
        hya_observer_free(observer);
        hya_estimator_free(estimator);
        hya_estimator_free(timed);
        hya_model_free(model);
    }
}
