//! Every shipped arm runs in the simulator: its built-in goto scenario, shortened, through the
//! same machinery `hya run` uses, with the arm's own number of joints.

use hya_sim::{Experiment, Method, Scenario};

fn shortened(name: &str) -> Scenario {
    let mut scenario = Scenario::builtin(name).unwrap().quick();
    scenario.methods = vec![Method::None, Method::Lu];
    scenario.check().unwrap();
    scenario
}

#[test]
fn every_shipped_arm_has_a_goto_scenario_that_runs() {
    let names: Vec<&str> = Scenario::arm_goto_names().collect();
    for robot in hya_robots::ROBOTS.iter().filter(|r| r.name != "hya") {
        let name = format!("{}_goto", robot.name);
        assert!(names.contains(&name.as_str()), "no built-in scenario {name}");
        let scenario = shortened(&name);
        assert_eq!(scenario.robot, robot.name);
        let out = std::env::temp_dir().join(format!("hya-arms-test-{}-{name}", std::process::id()));
        let (dir, _) = hya_sim::output::OutputDir::open(&out, false, "the arms test", &[]).unwrap();
        let summary = Experiment {
            scenarios: std::slice::from_ref(&scenario),
            seeds: 1,
            progress: &|_| {},
            out: &dir,
            quick: true,
            full_sweep: false,
            provenance: &hya_sim::report::Provenance::unknown("the arms test"),
        }
        .run()
        .unwrap();
        assert_eq!(summary.robot, robot.name);
        for run in &summary.runs {
            assert_eq!(run.rmse_q.len(), robot.dof, "{name} / {}: one RMSE per joint", run.method);
            assert!(run.rmse_q.iter().all(|e| e.is_finite() && *e < 0.5), "{name} / {}: {:?}", run.method, run.rmse_q);
        }
        let report = std::fs::read_to_string(out.join("report.md")).unwrap();
        assert!(report.contains(&format!("| j{} |", robot.dof)), "the tables have a column per joint");
        std::fs::remove_dir_all(&out).unwrap();
    }
}

#[test]
fn a_robot_with_the_wrong_number_of_joints_is_refused_by_name() {
    let mut scenario = shortened("panda_goto");
    scenario.robot = "ur5".into();
    let error = hya_sim::run_method::<7>(&scenario, Method::Lu).unwrap_err().to_string();
    assert!(error.contains("ur5") && error.contains('7'), "{error}");
}

#[test]
fn a_urdf_path_runs_on_the_run_time_model_as_the_shipped_arm_runs_on_generated_code() {
    let shipped = shortened("planar2_goto");
    let mut from_file = shipped.clone();
    from_file.robot = format!("{}/../robots/urdf/planar2.urdf", env!("CARGO_MANIFEST_DIR"));
    let a = hya_sim::run_method::<2>(&shipped, Method::Lu).unwrap().metrics.rmse_q;
    let b = hya_sim::run_method::<2>(&from_file, Method::Lu).unwrap().metrics.rmse_q;
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() <= 1e-6 * x.abs(), "generated {x} vs run-time {y}");
    }
}
