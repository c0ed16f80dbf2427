//! The C ABI against the Rust API it wraps: on every shipped arm (and a URDF loaded at run time)
//! the dynamics, the estimator, the observers and the controller give the Rust results to 1e-12
//! through the ABI, step after step.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::ffi::{CStr, CString};
use std::path::Path;
use std::ptr::{null, null_mut};

use hya::*;
use hya_core::observers::{
    DisturbanceObserver, ExtendedStateObserver, Measurement, MomentumObserver, NonlinearDisturbanceObserver,
};
use hya_core::{
    ComputedTorque, DisturbanceEstimator, Dynamics, FilterParams, Gains, JointVector, PdPlacement, Reference,
    TimedEstimator,
};
use hya_robots::{with_arm, Arm, ForArm, ROBOTS};

const DT: f64 = 1e-3;
const STEPS: usize = 300;

/// A deterministic sequence of values in `[-1, 1)` (a 64-bit linear congruential generator).
struct Sequence(u64);

impl Sequence {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn vector<const N: usize>(&mut self, scale: f64) -> JointVector<N> {
        JointVector::from_fn(|_, _| scale * self.next())
    }
}

fn assert_close(what: &str, abi: &[f64], rust: &[f64]) {
    assert_eq!(abi.len(), rust.len(), "{what}: lengths");
    for (i, (a, r)) in abi.iter().zip(rust).enumerate() {
        assert!((a - r).abs() <= 1e-12 * (1.0 + r.abs()), "{what}[{i}]: ABI {a} vs Rust {r}");
    }
}

fn ok(status: HyaStatus, message: impl FnOnce() -> String) {
    assert_eq!(status, HyaStatus::HyaOk, "{}", message());
}

fn text(ptr: *const std::ffi::c_char) -> String {
    // SAFETY: hya returns NUL-terminated strings it owns.
    unsafe { CStr::from_ptr(ptr) }.to_string_lossy().into_owned()
}

fn last_error() -> String {
    text(hya_last_error())
}

/// Every handle the ABI makes for one model, and the same objects made in Rust.
struct Compare<'a, const N: usize, D: Dynamics<N> + Copy> {
    model: *mut HyaModel,
    rust: D,
    name: &'a str,
}

impl<const N: usize, D: Dynamics<N> + Copy> Compare<'_, N, D> {
    fn dynamics(&self, seq: &mut Sequence) {
        for _ in 0..20 {
            let (q, qd, qdd) = (seq.vector::<N>(2.0), seq.vector::<N>(3.0), seq.vector::<N>(5.0));
            let mut out = [0.0; N];
            let mut mass = vec![0.0; N * N];
            // SAFETY: a live model and arrays of N (N² for the mass matrix) doubles.
            unsafe {
                ok(
                    hya_model_inverse_dynamics(self.model, q.as_ptr(), qd.as_ptr(), qdd.as_ptr(), N, out.as_mut_ptr()),
                    || self.error(),
                );
                assert_close(self.name, &out, self.rust.inverse_dynamics(&q, &qd, &qdd).as_slice());
                ok(hya_model_gravity(self.model, q.as_ptr(), N, out.as_mut_ptr()), || self.error());
                assert_close(self.name, &out, self.rust.gravity(&q).as_slice());
                ok(hya_model_mass_matrix(self.model, q.as_ptr(), N, mass.as_mut_ptr(), N * N), || self.error());
                assert_close(self.name, &mass, self.rust.mass_matrix(&q).as_slice());
                let tau = seq.vector::<N>(20.0);
                ok(
                    hya_model_forward_dynamics(self.model, q.as_ptr(), qd.as_ptr(), tau.as_ptr(), N, out.as_mut_ptr()),
                    || self.error(),
                );
                assert_close(self.name, &out, self.rust.forward_dynamics(&q, &qd, &tau).unwrap().as_slice());
                let mut derivatives = [vec![0.0; N * N], vec![0.0; N * N], vec![0.0; N * N]];
                let [a, b, c] = &mut derivatives;
                ok(
                    hya_model_forward_dynamics_derivatives(
                        self.model,
                        q.as_ptr(),
                        qd.as_ptr(),
                        tau.as_ptr(),
                        N,
                        a.as_mut_ptr(),
                        b.as_mut_ptr(),
                        c.as_mut_ptr(),
                        N * N,
                    ),
                    || self.error(),
                );
                let (by_q, by_qd, inverse) = self.rust.forward_dynamics_derivatives(&q, &qd, &tau).unwrap();
                for (abi, rust) in derivatives.iter().zip([by_q, by_qd, inverse]) {
                    // Row-major through the ABI: the transpose's column-major storage.
                    assert_close(self.name, abi, rust.transpose().as_slice());
                }
            }
        }
    }

    /// The batch entry points on nineteen states (more than a chunk of the derivatives' batch,
    /// sixteen, and not a multiple of four or eight lanes) equal the Rust model's single calls,
    /// state by state.
    fn batches(&self, seq: &mut Sequence) {
        const COUNT: usize = 19;
        let states: Vec<[JointVector<N>; 4]> =
            (0..COUNT).map(|_| [2.0, 3.0, 5.0, 20.0].map(|scale| seq.vector::<N>(scale))).collect();
        let column = |i: usize| -> Vec<f64> { states.iter().flat_map(|s| s[i].iter().copied()).collect() };
        let [q, qd, qdd, tau] = [0, 1, 2, 3].map(column);
        let mut out = vec![f64::NAN; COUNT * N];
        let mut mass = vec![f64::NAN; COUNT * N * N];
        let mut derivatives = vec![f64::NAN; COUNT * 3 * N * N];
        // SAFETY: a live model; inputs and outputs of COUNT rows of the widths passed.
        unsafe {
            let (q, qd, qdd, tau) = (q.as_ptr(), qd.as_ptr(), qdd.as_ptr(), tau.as_ptr());
            ok(hya_model_inverse_dynamics_batch(self.model, q, qd, qdd, COUNT, N, out.as_mut_ptr()), || self.error());
            for (k, [q, qd, qdd, _]) in states.iter().enumerate() {
                assert_close(self.name, &out[k * N..][..N], self.rust.inverse_dynamics(q, qd, qdd).as_slice());
            }
            out.fill(f64::NAN);
            ok(hya_model_gravity_batch(self.model, q, COUNT, N, out.as_mut_ptr()), || self.error());
            for (k, [q, ..]) in states.iter().enumerate() {
                assert_close(self.name, &out[k * N..][..N], self.rust.gravity(q).as_slice());
            }
            ok(hya_model_mass_matrix_batch(self.model, q, COUNT, N, mass.as_mut_ptr(), mass.len()), || self.error());
            for (k, [q, ..]) in states.iter().enumerate() {
                assert_close(self.name, &mass[k * N * N..][..N * N], self.rust.mass_matrix(q).as_slice());
            }
            out.fill(f64::NAN);
            ok(hya_model_forward_dynamics_batch(self.model, q, qd, tau, COUNT, N, out.as_mut_ptr()), || self.error());
            for (k, [q, qd, _, tau]) in states.iter().enumerate() {
                assert_close(self.name, &out[k * N..][..N], self.rust.forward_dynamics(q, qd, tau).unwrap().as_slice());
            }
            ok(
                hya_model_forward_dynamics_derivatives_batch(
                    self.model,
                    q,
                    qd,
                    tau,
                    COUNT,
                    N,
                    derivatives.as_mut_ptr(),
                    derivatives.len(),
                ),
                || self.error(),
            );
            for (k, [q, qd, _, tau]) in states.iter().enumerate() {
                let (by_q, by_qd, inverse) = self.rust.forward_dynamics_derivatives(q, qd, tau).unwrap();
                let row = &derivatives[k * 3 * N * N..][..3 * N * N];
                for (part, rust) in row.chunks(N * N).zip([by_q, by_qd, inverse]) {
                    // Row-major through the ABI: the transpose's column-major storage.
                    assert_close(self.name, part, rust.transpose().as_slice());
                }
            }
        }
    }

    /// The estimator, the three observers and the controller, fed the same measurements in
    /// closed loop through the ABI and in Rust.
    fn closed_loop(&self, seq: &mut Sequence) {
        let q0 = seq.vector::<N>(0.5);
        let tau0 = self.rust.gravity(&q0);
        let (kp, kd) = ([400.0; N], [40.0; N]);
        let params = FilterParams::new(0.8, 50.0, 40.0, DT).unwrap();
        let zero = [0.0; N];
        let gains: [f64; N] = core::array::from_fn(|i| 20.0 + i as f64);

        let mut estimator = DisturbanceEstimator::new(self.rust, params, q0, tau0).unwrap();
        let mut observers: [Box<dyn DisturbanceObserver<N>>; 3] = [
            Box::new(NonlinearDisturbanceObserver::new(self.rust, 30.0, DT, JointVector::zeros()).unwrap()),
            Box::new(MomentumObserver::new(self.rust, gains.into(), DT, q0, JointVector::zeros(), tau0).unwrap()),
            Box::new(ExtendedStateObserver::new(self.rust, 60.0, DT, q0).unwrap()),
        ];
        let controllers = [PdPlacement::OutsideMassMatrix, PdPlacement::InsideMassMatrix]
            .map(|p| ComputedTorque::new(self.rust, Gains::diagonal(kp, kd).unwrap()).with_placement(p));

        let (mut e, mut o, mut c) = ([null_mut(); 1], [null_mut(); 3], [null_mut(); 2]);
        // SAFETY: a live model, arrays of N doubles, writable outputs.
        unsafe {
            ok(
                hya_estimator_new(self.model, 0.8, 50.0, 40.0, DT, q0.as_ptr(), tau0.as_ptr(), N, &mut e[0]),
                last_error,
            );
            ok(hya_observer_new_nonlinear(self.model, 30.0, DT, zero.as_ptr(), N, &mut o[0]), last_error);
            ok(
                hya_observer_new_momentum(
                    self.model,
                    gains.as_ptr(),
                    DT,
                    q0.as_ptr(),
                    zero.as_ptr(),
                    tau0.as_ptr(),
                    N,
                    &mut o[1],
                ),
                last_error,
            );
            ok(hya_observer_new_extended_state(self.model, 60.0, DT, q0.as_ptr(), N, &mut o[2]), last_error);
            for (placement, out) in [0, 1].into_iter().zip(&mut c) {
                ok(hya_controller_new(self.model, kp.as_ptr(), kd.as_ptr(), N, placement, out), last_error);
            }
        }

        let (mut q, mut qd) = (q0, JointVector::<N>::zeros());
        let mut d_hat = JointVector::<N>::zeros();
        for k in 0..STEPS {
            let t = k as f64 * DT;
            let reference = Reference {
                position: q0.map(|x| x + 0.2 * (3.0 * t).sin()),
                velocity: JointVector::repeat(0.6 * (3.0 * t).cos()),
                acceleration: JointVector::repeat(-1.8 * (3.0 * t).sin()),
            };
            let mut tau = [0.0; N];
            for (controller, handle) in controllers.iter().zip(c) {
                for d_hat in [Some(&d_hat), None] {
                    let rust = controller.command(&q, &qd, &reference, d_hat).unwrap().torque;
                    // SAFETY: a live controller, arrays of N doubles (or a null d̂).
                    let status = unsafe {
                        hya_controller_command(
                            handle,
                            q.as_ptr(),
                            qd.as_ptr(),
                            reference.position.as_ptr(),
                            reference.velocity.as_ptr(),
                            reference.acceleration.as_ptr(),
                            d_hat.map_or(null(), |d| d.as_ptr()),
                            N,
                            tau.as_mut_ptr(),
                        )
                    };
                    ok(status, || text(unsafe { hya_controller_error(handle) }));
                    assert_close("controller", &tau, rust.as_slice());
                }
            }
            // The applied torque: the classic form (gains 1/s², stable on every arm at this
            // step) with the compensation, plus a disturbance the estimator should see.
            let applied = controllers[1].command(&q, &qd, &reference, Some(&d_hat)).unwrap().torque;
            let disturbance = JointVector::<N>::from_fn(|i, _| 2.0 * (5.0 * t + i as f64).sin());
            let qdd = self.rust.forward_dynamics(&q, &qd, &(applied + disturbance)).unwrap();
            qd += qdd * DT;
            q += qd * DT;

            let mut out = [0.0; N];
            d_hat = estimator.update(&q, &applied).unwrap();
            // SAFETY: a live estimator, arrays of N doubles.
            unsafe {
                ok(hya_estimator_update(e[0], q.as_ptr(), applied.as_ptr(), N, out.as_mut_ptr()), || {
                    text(hya_estimator_error(e[0]))
                });
            }
            assert_close("estimator", &out, d_hat.as_slice());
            let measurement = Measurement { position: q, velocity: Some(qd), torque: applied };
            for (observer, handle) in observers.iter_mut().zip(o) {
                let rust = observer.update(&measurement).unwrap();
                // SAFETY: a live observer, arrays of N doubles.
                unsafe {
                    ok(
                        hya_observer_update(handle, q.as_ptr(), qd.as_ptr(), applied.as_ptr(), N, out.as_mut_ptr()),
                        || text(hya_observer_error(handle)),
                    );
                }
                assert_close("observer", &out, rust.as_slice());
            }
        }
        let mut latest = [0.0; N];
        // SAFETY: live handles, freed once.
        unsafe {
            ok(hya_estimator_disturbance(e[0], latest.as_mut_ptr(), N), || text(hya_estimator_error(e[0])));
            assert_close("latest estimate", &latest, d_hat.as_slice());
            hya_estimator_free(e[0]);
            o.into_iter().for_each(|h| hya_observer_free(h));
            c.into_iter().for_each(|h| hya_controller_free(h));
        }
        assert!(d_hat.norm() > 0.1, "{}: the disturbance was not seen at all (|d̂| = {})", self.name, d_hat.norm());
    }

    /// The timestamped estimator on jittered steps, a bridged gap and one too long to bridge.
    fn timed(&self, seq: &mut Sequence) {
        let (q0, tau0) = (seq.vector::<N>(0.5), seq.vector::<N>(5.0));
        let params = FilterParams::paper(DT).unwrap();
        let mut rust = TimedEstimator::new(self.rust, params, 10.0, q0, tau0).unwrap();
        let mut handle = null_mut();
        // SAFETY: a live model, arrays of N doubles, a writable output.
        unsafe {
            let status = hya_estimator_new_timed(
                self.model,
                0.8,
                50.0,
                50.0,
                DT,
                10.0,
                q0.as_ptr(),
                tau0.as_ptr(),
                N,
                &mut handle,
            );
            ok(status, last_error);
        }
        let (mut t, mut gaps) = (10.0, 0);
        for k in 0..STEPS {
            t += match k {
                100 => 0.030,
                200 => 2.5,
                _ => DT * (1.0 + 0.3 * seq.next()),
            };
            let (q, tau) = (q0 + seq.vector::<N>(0.01), tau0 + seq.vector::<N>(1.0));
            let step = rust.update(t, &q, &tau).unwrap();
            let (mut out, mut restarted) = ([0.0; N], false);
            // SAFETY: a live estimator, arrays of N doubles, a writable flag.
            unsafe {
                let status =
                    hya_estimator_update_at(handle, t, q.as_ptr(), tau.as_ptr(), N, out.as_mut_ptr(), &mut restarted);
                ok(status, || text(hya_estimator_error(handle)));
            }
            assert_close("timed estimator", &out, step.disturbance.as_slice());
            assert_eq!(restarted, step.restarted);
            gaps += usize::from(restarted);
        }
        assert_eq!(gaps, 1, "the 2.5 s gap restarts the estimator, nothing else does");
        // SAFETY: a live handle, freed once.
        unsafe { hya_estimator_free(handle) };
    }

    fn error(&self) -> String {
        // SAFETY: a live model.
        text(unsafe { hya_model_error(self.model) })
    }
}

struct Check;

impl ForArm for Check {
    type Output = ();
    fn call<const N: usize>(self, arm: Arm<N>) {
        let name = CString::new(arm.info.name).unwrap();
        let mut model = null_mut();
        // SAFETY: a NUL-terminated name and a writable output.
        unsafe { ok(hya_model_from_arm(name.as_ptr(), &mut model), last_error) };
        // SAFETY: a live model.
        assert_eq!(unsafe { hya_model_dof(model) }, N);
        let compare = Compare { model, rust: arm.nominal, name: arm.info.name };
        let mut seq = Sequence(N as u64);
        compare.dynamics(&mut seq);
        compare.batches(&mut seq);
        compare.closed_loop(&mut seq);
        compare.timed(&mut seq);
        // SAFETY: a live model, freed once.
        unsafe { hya_model_free(model) };
    }
}

#[test]
fn every_shipped_arm_equals_the_rust_api() {
    // SAFETY: plain queries.
    let names: Vec<String> = (0..hya_arm_count()).map(|i| text(hya_arm_name(i))).collect();
    assert_eq!(names, ROBOTS.iter().map(|r| r.name).collect::<Vec<_>>());
    assert!(hya_arm_name(hya_arm_count()).is_null());
    for robot in ROBOTS {
        with_arm(robot.name, Check).unwrap();
    }
}

/// A URDF through the run-time model equals the same file loaded in Rust; handles outlive their
/// model.
#[test]
fn a_urdf_model_equals_the_loaded_tree() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../hya-urdf/tests/urdf/messy_tree.urdf");
    let loaded = hya_urdf::load_file(path.to_str().unwrap()).unwrap();
    let c_path = CString::new(path.to_str().unwrap()).unwrap();
    let mut model = null_mut();
    // SAFETY: a NUL-terminated path and a writable output.
    unsafe { ok(hya_model_from_urdf(c_path.as_ptr(), &mut model), last_error) };
    // SAFETY: a live model.
    let dof = unsafe { hya_model_dof(model) };
    assert_eq!(dof, loaded.model.dof());
    struct Tree(*mut HyaModel, hya_core::model::TreeModel);
    impl hya_core::dispatch::ForJoints for Tree {
        type Output = ();
        fn call<const N: usize>(self) {
            let rust = self.1.into_dynamics::<N>().unwrap();
            let compare = Compare { model: self.0, rust: &rust, name: "messy_tree" };
            let mut seq = Sequence(7);
            compare.dynamics(&mut seq);
            compare.batches(&mut seq);
            // The estimator made from the model keeps working after the model is freed.
            let (q0, tau0) = ([0.1; N], [0.0; N]);
            let mut estimator = null_mut();
            let mut d_hat = [0.0; N];
            // SAFETY: live handles, arrays of N doubles, each handle freed once.
            unsafe {
                ok(
                    hya_estimator_new(self.0, 0.8, 50.0, 50.0, DT, q0.as_ptr(), tau0.as_ptr(), N, &mut estimator),
                    last_error,
                );
                hya_model_free(self.0);
                ok(hya_estimator_update(estimator, q0.as_ptr(), tau0.as_ptr(), N, d_hat.as_mut_ptr()), || {
                    text(hya_estimator_error(estimator))
                });
                hya_estimator_free(estimator);
            }
            assert!(d_hat.iter().all(|d| d.is_finite()));
        }
    }
    hya_core::dispatch::with_joints(dof, Tree(model, loaded.model)).unwrap();
}

/// A model with an identified joint law (`hya_model_with_friction`) equals `hya_ident::WithFriction`
/// over the same file: dynamics, and the estimator, observers and controllers made from it.
#[test]
fn a_model_with_friction_equals_the_rust_model_with_friction() {
    let dir = std::env::temp_dir().join(format!("hya-capi-friction-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("friction.toml");
    std::fs::write(
        &path,
        "smoothing_rad_s = 0.05\ncoulomb_nm = [2.0, 0.7]\nviscous_nm_s = [1.5, 0.4]\noffset_nm = [0.3, -0.1]\n\
         armature_kg_m2 = [0.2, 0.05]\n",
    )
    .unwrap();
    let friction = hya_ident::JointFriction::from_file(&path, 2).unwrap();
    let rigid = hya_robots::nominal::<2>("planar2").unwrap();
    let rust = hya_ident::WithFriction::new(rigid, friction);

    let (base, c_path) = (planar2_model(), CString::new(path.to_str().unwrap()).unwrap());
    let mut model = null_mut();
    // SAFETY: a live model, a NUL-terminated path and a writable output; each handle freed once.
    unsafe {
        ok(hya_model_with_friction(base, c_path.as_ptr(), &mut model), last_error);
        hya_model_free(base);
    }
    let compare = Compare { model, rust: &rust, name: "planar2 with friction" };
    let mut seq = Sequence(11);
    compare.dynamics(&mut seq);
    compare.closed_loop(&mut seq);
    // SAFETY: a live model, freed once.
    unsafe { hya_model_free(model) };
    std::fs::remove_dir_all(&dir).unwrap();
}

fn planar2_model() -> *mut HyaModel {
    let mut model = null_mut();
    // SAFETY: a NUL-terminated name and a writable output.
    unsafe { ok(hya_model_from_arm(c"planar2".as_ptr(), &mut model), last_error) };
    model
}

/// Frame Jacobians and `J̇ q̇` through the ABI equal the run-time tree's on every shipped arm
/// and every link. (`Compare::dynamics` holds the forward-dynamics derivatives on every shipped
/// arm, a URDF model and a model with friction.)
#[test]
fn frame_kinematics_equal_the_rust_api() {
    let mut seq = Sequence(41);
    for robot in ROBOTS {
        let tree = hya_urdf::load_str(robot.urdf, robot.name).unwrap().model;
        let name = CString::new(robot.name).unwrap();
        let mut model = null_mut();
        // SAFETY: a NUL-terminated name and a writable output.
        unsafe { ok(hya_model_from_arm(name.as_ptr(), &mut model), last_error) };
        let n = robot.dof;
        let v = |seq: &mut Sequence, scale: f64| -> Vec<f64> { (0..n).map(|_| scale * seq.next()).collect() };
        let (q, qd) = (v(&mut seq, 2.0), v(&mut seq, 3.0));
        let error = || text(unsafe { hya_model_error(model) });
        for frame in tree.frames() {
            let c_frame = CString::new(frame.name.as_str()).unwrap();
            let (mut jacobian, mut bias) = (vec![0.0; 6 * n], [0.0; 6]);
            // SAFETY: a live model, a NUL-terminated frame, arrays of the lengths passed.
            unsafe {
                ok(
                    hya_model_frame_jacobian(model, c_frame.as_ptr(), q.as_ptr(), n, jacobian.as_mut_ptr(), 6 * n),
                    error,
                );
                ok(
                    hya_model_frame_acceleration_bias(
                        model,
                        c_frame.as_ptr(),
                        q.as_ptr(),
                        qd.as_ptr(),
                        n,
                        bias.as_mut_ptr(),
                        6,
                    ),
                    error,
                );
            }
            let rust = tree.frame_jacobian(&frame.name, &q).unwrap();
            assert_close(&frame.name, &jacobian, rust.transpose().as_slice());
            assert_close(&frame.name, &bias, &tree.frame_acceleration_bias(&frame.name, &q, &qd).unwrap());
        }
        // SAFETY: a live model, freed once.
        unsafe { hya_model_free(model) };
    }
}

/// The Cartesian impedance controller through the ABI equals `hya_core::CartesianImpedance` on
/// the run-time tree's frame kinematics, on the Panda's flange and on one of its middle links,
/// with and without posture, twist and `d̂`; a frame the model lacks and an orientation that is
/// not a rotation are refused by name.
#[test]
fn the_cartesian_controller_equals_the_rust_api() {
    use hya_core::{CartesianImpedance, CartesianReference, FrameState, Impedance};
    const N: usize = 7;
    let tree = hya_urdf::load_str(hya_robots::panda::URDF, "panda").unwrap().model;
    let mut model = null_mut();
    // SAFETY: a NUL-terminated name and a writable output.
    unsafe { ok(hya_model_from_arm(c"panda".as_ptr(), &mut model), last_error) };
    let (stiffness, damping) = ([1500.0, 500.0, 600.0, 8.0, 23.0, 0.7], [200.0, 70.0, 80.0, 1.0, 3.0, 0.1]);
    let rest = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785];
    let (kn, dn) = ([5.0; N], [2.0; N]);
    let limit = [20.0, 20.0, 20.0, 20.0, 5.0, 5.0, 5.0];
    let mut seq = Sequence(7);
    for (frame, posture) in [("panda_link8", true), ("panda_link5", false)] {
        let c_frame = CString::new(frame).unwrap();
        let mut controller = null_mut();
        let (rest_ptr, kn_ptr, dn_ptr) =
            if posture { (rest.as_ptr(), kn.as_ptr(), dn.as_ptr()) } else { (null(), null(), null()) };
        // SAFETY: a live model, a NUL-terminated frame, arrays of 6 and N doubles or null.
        unsafe {
            let status = hya_cartesian_new(
                model,
                c_frame.as_ptr(),
                stiffness.as_ptr(),
                damping.as_ptr(),
                rest_ptr,
                kn_ptr,
                dn_ptr,
                if posture { null() } else { limit.as_ptr() },
                N,
                1e-3,
                &mut controller,
            );
            ok(status, last_error);
        }
        let mut gains = Impedance::<N>::new(stiffness, damping).unwrap();
        if posture {
            gains = gains.with_posture(rest, kn, dn).unwrap();
        }
        let mut rust = CartesianImpedance::new(hya_robots::Panda, gains);
        if !posture {
            rust = rust.with_torque_limit(JointVector::from(limit)).unwrap();
        }
        for step in 0..20 {
            let q = JointVector::<N>::from(rest) + seq.vector::<N>(0.3);
            let qd = seq.vector::<N>(1.0);
            let d_hat = seq.vector::<N>(2.0);
            let at = FrameState::of_tree(&tree, frame, &seq.vector::<N>(0.3)).unwrap();
            let twist = hya_core::cartesian::Vector6::from_fn(|_, _| 0.1 * seq.next());
            let reference = CartesianReference { position: at.position, orientation: at.orientation, twist };
            let (given_twist, given_d_hat) = (step % 2 == 0, step % 3 == 0);
            let mut tau = [0.0; N];
            let orientation: Vec<f64> = reference.orientation.transpose().as_slice().to_vec(); // row-major
                                                                                               // SAFETY: a live controller, arrays of the lengths passed or null.
            unsafe {
                let status = hya_cartesian_command(
                    controller,
                    q.as_ptr(),
                    qd.as_ptr(),
                    reference.position.as_ptr(),
                    orientation.as_ptr(),
                    if given_twist { twist.as_ptr() } else { null() },
                    if given_d_hat { d_hat.as_ptr() } else { null() },
                    N,
                    tau.as_mut_ptr(),
                );
                ok(status, || text(hya_cartesian_error(controller)));
            }
            let reference =
                CartesianReference { twist: if given_twist { twist } else { Default::default() }, ..reference };
            let frame_now = FrameState::of_tree(&tree, frame, &q).unwrap();
            let expected = rust.command(&q, &qd, &frame_now, &reference, given_d_hat.then_some(&d_hat)).unwrap();
            assert_close(frame, &tau, expected.torque.as_slice());
        }
        // Not a rotation: refused, named.
        let skewed = [1.0, 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let mut tau = [0.0; N];
        // SAFETY: a live controller, arrays of the lengths passed.
        unsafe {
            let status = hya_cartesian_command(
                controller,
                rest.as_ptr(),
                kn.as_ptr(),
                [0.3, 0.0, 0.5].as_ptr(),
                skewed.as_ptr(),
                null(),
                null(),
                N,
                tau.as_mut_ptr(),
            );
            assert_eq!(status, HyaStatus::HyaErrInvalid);
            assert!(text(hya_cartesian_error(controller)).contains("orientation_des"));
            hya_cartesian_free(controller);
        }
    }
    // A frame the Panda does not have: refused, its frames listed.
    let mut controller = null_mut();
    // SAFETY: a live model, a NUL-terminated frame, arrays of 6 doubles, a writable output.
    unsafe {
        let status = hya_cartesian_new(
            model,
            c"panda_hand".as_ptr(),
            stiffness.as_ptr(),
            damping.as_ptr(),
            null(),
            null(),
            null(),
            null(),
            N,
            1e-3,
            &mut controller,
        );
        assert_eq!(status, HyaStatus::HyaErrInvalid);
        assert!(controller.is_null());
        let message = last_error();
        assert!(message.contains("panda_hand") && message.contains("panda_link8"), "{message}");
        hya_model_free(model);
    }
}
