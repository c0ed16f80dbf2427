//! The controller's model from a scenario: an identified URDF and joint friction
//! (`controller.model_urdf`, `controller.friction_toml`).

use hya_sim::analysis::simulate::simulate_recording;
use hya_sim::run::trace::Recording;
use hya_sim::{Method, Robot, Scenario};

fn planar_urdf() -> String {
    format!("{}/../robots/urdf/planar2.urdf", env!("CARGO_MANIFEST_DIR"))
}

/// planar2's goto scenario, shortened, on the URDF's run-time model.
fn scenario() -> Scenario {
    let mut scenario = Scenario::builtin("planar2_goto").unwrap().quick();
    scenario.robot = planar_urdf();
    scenario.check().unwrap();
    scenario
}

#[test]
fn the_robots_own_urdf_as_controller_model_changes_nothing() {
    let robot = Robot::<2>::load(&planar_urdf()).unwrap();
    let plain = simulate_recording(&scenario(), Method::Lu, &robot, Recording::Bounded).unwrap().trace;
    let mut named = scenario();
    named.controller.model_urdf = Some(planar_urdf());
    let same = simulate_recording(&named, Method::Lu, &robot, Recording::Bounded).unwrap().trace;
    assert_eq!(plain.tau_cmd, same.tau_cmd);
    assert_eq!(plain.d_hat, same.d_hat);
}

#[test]
fn controller_friction_enters_the_command_as_a_feed_forward() {
    let path = std::env::temp_dir().join(format!("hya-controller-friction-{}.toml", std::process::id()));
    std::fs::write(
        &path,
        "smoothing_rad_s = 0.05\ncoulomb_nm = [0, 0]\nviscous_nm_s = [0, 0]\noffset_nm = [0.5, -1.25]\n",
    )
    .unwrap();
    let robot = Robot::<2>::load(&planar_urdf()).unwrap();
    let plain = simulate_recording(&scenario(), Method::None, &robot, Recording::Bounded).unwrap().trace;
    let mut with_friction = scenario();
    with_friction.controller.friction_toml = Some(path.to_str().unwrap().to_owned());
    let fed = simulate_recording(&with_friction, Method::None, &robot, Recording::Bounded).unwrap().trace;
    // The first tick sees the same state: the commands differ by the friction, an offset here.
    let difference = fed.tau_cmd[0] - plain.tau_cmd[0];
    assert!((difference[0] - 0.5).abs() < 1e-12 && (difference[1] + 1.25).abs() < 1e-12, "{difference}");
    let _ = std::fs::remove_file(&path);
}

#[test]
fn a_controller_model_of_other_joints_or_a_bad_friction_file_is_refused_by_name() {
    let robot = Robot::<2>::load(&planar_urdf()).unwrap();
    let mut other = scenario();
    other.controller.model_urdf = Some(format!("{}/../robots/urdf/ur5.urdf", env!("CARGO_MANIFEST_DIR")));
    let error = simulate_recording(&other, Method::Lu, &robot, Recording::Bounded).unwrap_err().to_string();
    assert!(error.contains("controller.model_urdf") && error.contains("not the robot's"), "{error}");
    let mut missing = scenario();
    missing.controller.friction_toml = Some("/nonexistent/friction.toml".into());
    let error = simulate_recording(&missing, Method::Lu, &robot, Recording::Bounded).unwrap_err().to_string();
    assert!(error.contains("controller.friction_toml") && error.contains("/nonexistent/friction.toml"), "{error}");
}

#[test]
fn relative_paths_in_a_scenario_file_are_taken_from_its_folder() {
    let dir = std::env::temp_dir().join(format!("hya-relative-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("models")).unwrap();
    let file = dir.join("scenario.toml");
    let text = "name = \"tiny\"\nrobot = \"models/arm.urdf\"\nduration_s = 0.6\nmethods = [\"none\"]\n[task]\n\
                kind = \"hold\"\n[controller]\nmodel_urdf = \"models/identified.urdf\"\n\
                friction_toml = \"/absolute/friction.toml\"\n";
    std::fs::write(&file, text).unwrap();
    let scenario = Scenario::from_file(&file).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(scenario.robot, dir.join("models/arm.urdf").display().to_string());
    assert_eq!(scenario.controller.model_urdf, Some(dir.join("models/identified.urdf").display().to_string()));
    assert_eq!(scenario.controller.friction_toml.as_deref(), Some("/absolute/friction.toml"));
    // A shipped arm's name is a name, not a path.
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(&file, text.replace("models/arm.urdf", "hya")).unwrap();
    let shipped = Scenario::from_file(&file).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(shipped.robot, "hya");
    // A bare name that is a file beside the scenario is that file.
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("myarm"), "").unwrap();
    std::fs::write(&file, text.replace("models/arm.urdf", "myarm")).unwrap();
    let beside = Scenario::from_file(&file).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(beside.robot, dir.join("myarm").display().to_string());
}
