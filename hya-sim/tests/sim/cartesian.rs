//! The task-space scenario: its settings checked where the library reads them, its reference
//! (pose and twist) self-consistent, its closed loop reaching the moved pose on an ideal arm,
//! and its experiment writing the report's files.

use hya_core::JointVector;
use hya_sim::config::scenario::{ActuatorKind, FrictionKind, Method, Noise, Scenario, Task};
use hya_sim::config::settings::Setup;
use hya_sim::run::cartesian::CartesianLaw;
use hya_sim::{Experiment, Robot};

fn scenario() -> Scenario {
    Scenario::builtin("panda_cartesian").unwrap()
}

fn refusal(change: impl FnOnce(&mut Scenario)) -> String {
    let mut s = scenario();
    change(&mut s);
    s.check().unwrap_err().to_string()
}

#[test]
fn the_builtin_scenario_is_checked_against_its_arm() {
    let s = scenario();
    assert!(s.task.is_cartesian() && !s.allow_unphysical);
    s.check_for_robot().unwrap();
    assert!(Scenario::task_space_names().any(|n| n == "panda_cartesian"));
    assert!(s.quick().check().is_ok());
}

#[test]
fn settings_that_do_not_fit_a_task_space_task_are_refused_by_key() {
    type Change = Box<dyn FnOnce(&mut Scenario)>;
    let cases: [(&str, &str, Change); 6] = [
        ("controller.cartesian", "needs the impedance's gains", Box::new(|s| s.controller.cartesian = None)),
        ("methods", "pid", Box::new(|s| s.methods.push(Method::Pid))),
        ("task.rotation_rad", "below π", Box::new(|s| set_rotation(s, vec![2.0, 2.0, 2.0]))),
        ("task.offset_m", "three values", Box::new(|s| set_offset(s, vec![0.1, 0.1]))),
        (
            "controller.cartesian.damping[5]",
            "",
            Box::new(|s| s.controller.cartesian.as_mut().unwrap().damping[5] = -1.0),
        ),
        ("controller.cartesian", "acts only with a task of kind cartesian", Box::new(|s| s.task = Task::Hold {})),
    ];
    for (key, why, change) in cases {
        let message = refusal(change);
        assert!(message.contains(key) && message.contains(why), "{key}: {message}");
    }
    // A frame the arm does not have is named with the ones it has, before any run.
    let mut s = scenario();
    s.controller.cartesian.as_mut().unwrap().frame = Some("panda_hand".into());
    let message = s.check_for_robot().unwrap_err().to_string();
    assert!(message.contains("panda_hand") && message.contains("panda_link8"), "{message}");
    // The frame is judged holding the moved pose: the run must last beyond 1 s after the move.
    let message = refusal(|s| s.duration_s = 7.4);
    assert!(message.contains("task.start_s + task.transition_s") && message.contains("1 s"), "{message}");
    // The joint-space runs (hya.simulate, the paper's experiments) refuse it: it is measured at
    // its frame.
    let message = hya_sim::run_method::<7>(&scenario(), Method::Lu).unwrap_err().to_string();
    assert!(message.contains("task space"), "{message}");
    // A posture list of the wrong length is named too.
    let mut s = scenario();
    s.controller.cartesian.as_mut().unwrap().posture_damping_nm_s_rad.pop();
    let message = s.check_for_robot().unwrap_err().to_string();
    assert!(message.contains("posture_damping_nm_s_rad"), "{message}");
}

fn set_rotation(s: &mut Scenario, value: Vec<f64>) {
    if let Task::Cartesian { rotation_rad, .. } = &mut s.task {
        *rotation_rad = value;
    }
}

fn set_offset(s: &mut Scenario, value: Vec<f64>) {
    if let Task::Cartesian { offset_m, .. } = &mut s.task {
        *offset_m = value;
    }
}

#[test]
fn the_reference_twist_is_the_pose_rate_and_the_move_ends_at_the_offset() {
    let s = scenario();
    let robot = Robot::<7>::load(&s.robot).unwrap();
    let settings = Setup::<7>::for_arm(&s, &robot.model).unwrap();
    let setup = settings.cartesian.as_ref().unwrap();
    let q0 = settings.initial_position;
    let mut law =
        CartesianLaw::new((setup, &settings.task), robot.nominal.as_ref(), &robot.model, (&q0, settings.torque_limit))
            .unwrap()
            .unwrap();
    let (start, end) = (law.reference(0.0), law.reference(s.duration_s));
    let Task::Cartesian { start_s, transition_s, offset_m, rotation_rad } = &s.task else { unreachable!() };
    assert_eq!(law.reference(*start_s - 1e-3), start, "it holds before the move");
    for (i, offset) in offset_m.iter().enumerate() {
        assert!((end.position[i] - start.position[i] - offset).abs() < 1e-12);
    }
    let turn = end.orientation * start.orientation.transpose();
    let expected = hya_core::cartesian::Vector3::new(rotation_rad[0], rotation_rad[1], rotation_rad[2]);
    assert!((hya_core::cartesian::rotation_vector(&turn) - expected).norm() < 1e-12);
    // Central differences of the pose against the twist, within the move.
    let h = 1e-6;
    for k in 1..10 {
        let t = start_s + transition_s * k as f64 / 10.0;
        let (before, now, after) = (law.reference(t - h), law.reference(t), law.reference(t + h));
        let velocity = (after.position - before.position) / (2.0 * h);
        let spin =
            hya_core::cartesian::rotation_vector(&(after.orientation * before.orientation.transpose())) / (2.0 * h);
        assert!((velocity - now.twist.fixed_rows::<3>(0)).norm() < 1e-6, "linear at {t}");
        assert!((spin - now.twist.fixed_rows::<3>(3)).norm() < 1e-6, "angular at {t}");
    }
    // The frame's error is zero at the start pose, at the start.
    assert!(law.pose_error(0.0, &q0).norm() < 1e-12);
    assert!(law.pose_error(0.0, &(q0 + JointVector::from_element(0.01))).norm() > 1e-3);
}

/// The scenario on an ideal arm (the nominal rigid body, no friction, lag, payload or noise),
/// shortened: what is left of the frame's error is the loop's own.
fn ideal() -> Scenario {
    let mut s = scenario();
    s.duration_s = 3.0;
    s.methods = vec![Method::None, Method::Lu];
    if let Task::Cartesian { start_s, transition_s, .. } = &mut s.task {
        (*start_s, *transition_s) = (0.6, 0.8);
    }
    s.plant.parameter_spread = 0.0;
    s.plant.friction = FrictionKind::Off;
    s.plant.actuator = ActuatorKind::Ideal;
    s.noise.torque = Noise::Off {};
    s.loads.weight_drop = None;
    s.check().unwrap();
    s
}

#[test]
fn on_an_ideal_arm_the_loop_holds_the_moved_pose_and_the_report_is_written() {
    let s = ideal();
    let out = std::env::temp_dir().join(format!("hya-cartesian-test-{}", std::process::id()));
    let (dir, _) = hya_sim::output::OutputDir::open(&out, false, "the cartesian test", &[]).unwrap();
    let summary = hya_sim::CartesianExperiment {
        scenario: &s,
        seeds: 1,
        progress: &|_| {},
        out: &dir,
        quick: false,
        provenance: &hya_sim::report::Provenance::unknown("the cartesian test"),
    }
    .run()
    .unwrap();
    assert_eq!(summary.runs.len(), 2);
    for run in &summary.runs {
        // Encoders quantise and differentiate: the hold is not exact, but well under a millimetre
        // and a milliradian against a 12 cm, 0.2 rad move.
        assert!(run.tool.position_final_m < 1e-3, "{:?}", run);
        assert!(run.tool.orientation_final_rad < 1e-3, "{:?}", run);
        assert!(run.tool.position_peak_m > run.tool.position_final_m, "the move lags its reference");
    }
    assert_eq!(summary.changes.len(), 1, "lu against none");
    for file in ["report.md", "summary.json", "cartesian_runs.csv", "tool_errors.svg", "tool_error_lu.csv"] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## In short") && report.contains("`lu`'s compensation"), "{report}");
    assert!(report.contains("- Mode: full."), "{report}");
    // The joint-space experiment does not take it.
    let message = Experiment {
        scenarios: std::slice::from_ref(&s),
        seeds: 1,
        progress: &|_| {},
        out: &dir,
        quick: true,
        full_sweep: false,
        provenance: &hya_sim::report::Provenance::unknown("the cartesian test"),
    }
    .run()
    .unwrap_err()
    .to_string();
    assert!(message.contains("task space"), "{message}");
    std::fs::remove_dir_all(&out).unwrap();
}
