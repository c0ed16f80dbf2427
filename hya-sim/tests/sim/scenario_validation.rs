//! Every number of a scenario is checked at the boundary: a bad value is refused with the key's
//! name before anything runs, never silently defaulted, never met later as a misleading error.

use hya_sim::scenario::{Noise, Task, WeightDrop};
use hya_sim::Scenario;

/// `change` applied to the built-in `goto_weight`, written to TOML and read back: the error.
fn refusal(change: impl Fn(&mut Scenario)) -> String {
    let mut scenario = Scenario::builtin("goto_weight").unwrap();
    change(&mut scenario);
    let text = toml::to_string(&scenario).unwrap();
    match Scenario::from_toml(&text, "test.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn drop_of(s: &mut Scenario) -> &mut WeightDrop {
    s.loads.weight_drop.as_mut().unwrap()
}

#[test]
fn bad_numbers_are_refused_with_their_key() {
    type Change = fn(&mut Scenario);
    let cases: &[(&str, Change)] = &[
        ("duration_s", |s| s.duration_s = 0.3),
        ("ticks", |s| s.duration_s = 1e9),
        ("observer_bandwidth_rad_s", |s| s.controller.observer_bandwidth_rad_s = 1e200),
        ("controller.dt_s", |s| s.controller.dt_s = 1e304),
        ("noise.velocity.sigma", |s| s.noise.velocity = Noise::Gaussian { sigma: f64::NAN }),
        ("noise.torque.sigma", |s| s.noise.torque = Noise::Gaussian { sigma: f64::INFINITY }),
        ("noise.position.bound", |s| s.noise.position = Noise::Uniform { bound: f64::NAN }),
        ("drop_s", |s| drop_of(s).drop_s = f64::NAN),
        ("fall_height_m", |s| drop_of(s).fall_height_m = -1.0),
        ("mass_kg", |s| drop_of(s).mass_kg = 1e300),
        ("remove_s", |s| drop_of(s).remove_s = Some(1.0)),
        ("substeps", |s| s.plant.substeps = Some(100_000)),
        ("damping_ratio", |s| s.controller.damping_ratio = -1.0),
        ("parameter_spread", |s| s.plant.parameter_spread = f64::NAN),
        ("task.start_s", |s| {
            if let Task::Goto { start_s, .. } = &mut s.task {
                *start_s = f64::NAN;
            }
        }),
        ("task.ramp_s", |s| s.task = Task::Sine { amplitude_rad: vec![0.1; 6], frequency_hz: 0.2, ramp_s: f64::NAN }),
        ("initial_position_rad[2]", |s| s.initial_position_rad = Some(vec![0.0, 0.0, f64::INFINITY, 0.0, 0.0, 0.0])),
        ("name", |s| s.name = "../escape".into()),
    ];
    for (key, change) in cases {
        let message = refusal(change);
        assert!(message.contains(key), "the refusal does not name {key}: {message}");
    }
}

#[test]
fn extra_keys_after_off_or_hold_are_refused() {
    let base = Scenario::builtin("estimator_noise_low").unwrap();
    let mut text = toml::to_string(&base).unwrap();
    text = text.replace("[task]\nkind = \"hold\"", "[task]\nkind = \"hold\"\nstart_s = 3.0");
    assert!(Scenario::from_toml(&text, "t.toml").is_err(), "hold took a start_s:\n{text}");
    let mut off = base.clone();
    off.noise.torque = Noise::Off {};
    let text = toml::to_string(&off).unwrap().replace("kind = \"off\"", "kind = \"off\"\nsigma = 1.0");
    let message = Scenario::from_toml(&text, "t.toml").unwrap_err().to_string();
    assert!(message.contains("sigma"), "{message}");
}

#[test]
fn a_method_named_twice_is_refused() {
    let message = refusal(|s| s.methods = vec![hya_sim::Method::Lu; 3]);
    assert!(message.contains("`lu` is named twice"), "{message}");
}

#[test]
fn unphysical_values_are_refused_unless_allowed() {
    type Change = fn(&mut Scenario);
    let cases: &[(&str, Change)] = &[
        ("plant.coulomb_nm[0]", |s| s.plant.coulomb_nm[0] = 1e300),
        ("plant.hydraulic.valve_rated_flow_m3_s[3]", |s| s.plant.hydraulic.valve_rated_flow_m3_s[3] = 1e300),
        ("plant.hydraulic.torque_bandwidth_hz[1]", |s| s.plant.hydraulic.torque_bandwidth_hz[1] = 1e9),
        ("plant.actuator_time_constant_s[5]", |s| s.plant.actuator_time_constant_s[5] = 1e300),
        ("plant.hydraulic.supply_pressure_pa", |s| s.plant.hydraulic.supply_pressure_pa = 1e12),
    ];
    for (key, change) in cases {
        let message = refusal(change);
        assert!(message.contains(key) && message.contains("allow_unphysical"), "{key}: {message}");
        assert!(message.len() < 300, "a long message: {message}");
        let mut allowed = Scenario::builtin("goto_weight").unwrap();
        change(&mut allowed);
        allowed.allow_unphysical = true;
        assert!(allowed.check().is_ok(), "{key} refused although allowed");
    }
    for name in Scenario::builtin_names().chain(Scenario::arm_goto_names()).chain(Scenario::task_space_names()) {
        assert!(!Scenario::builtin(name).unwrap().allow_unphysical, "{name} needs allow_unphysical");
    }
}

#[test]
fn messages_print_numbers_short_and_names_clipped() {
    let message = refusal(|s| s.controller.dt_s = 1e-300);
    assert!(message.contains("`controller.dt_s` = 1e-300"), "{message}");
    let message = refusal(|s| s.name = "x".repeat(10_000_000) + "/");
    assert!(message.len() < 300, "the name is echoed whole ({} bytes)", message.len());
}
