//! The regressor against Pinocchio's `computeJointTorqueRegressor` (rows written by
//! `tools/regressor_reference.py` into `tests/reference/regressor/`), and `Y π` against the
//! model's own inverse dynamics.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::path::{Path, PathBuf};

use hya_core::model::TreeModel;
use hya_ident::{nominal_parameters, BaseParameters, Regressor};
use nalgebra::DVector;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The URDF the reference file `stem` was made from.
fn model(stem: &str) -> TreeModel {
    let candidates = [
        root().join("robots/urdf").join(format!("{stem}.urdf")),
        root().join("hya-urdf/tests/urdf").join(format!("{stem}.urdf")),
        root().join("examples").join(stem).join("urdf").join(format!("{stem}.urdf")),
    ];
    let path = candidates.iter().find(|p| p.exists()).unwrap_or_else(|| panic!("no URDF for {stem}"));
    hya_urdf::load_file(path.to_str().unwrap()).unwrap().model
}

/// The regressor of shipped arm `name` on its generated code, if it is one.
fn generated(name: &str) -> Option<Regressor<'static>> {
    struct Build;
    impl hya_robots::ForArm for Build {
        type Output = Regressor<'static>;
        fn call<const N: usize>(self, arm: hya_robots::Arm<N>) -> Self::Output {
            Regressor::generated::<N>(arm.parametric)
        }
    }
    hya_robots::find(name)?;
    hya_robots::with_arm(name, Build)
}

#[test]
fn the_regressor_equals_pinocchios_on_every_reference_file() {
    let mut files: Vec<_> = std::fs::read_dir(root().join("tests/reference/regressor"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    assert!(files.len() >= 7, "the shipped arms and two other URDFs: found {files:?}");
    let (mut worst, mut generated_arms): (f64, usize) = (0.0, 0);
    for file in files {
        let stem = file.file_stem().unwrap().to_str().unwrap().to_owned();
        let model = model(&stem);
        let n = model.dof();
        let text = std::fs::read_to_string(&file).unwrap();
        let mut sources = vec![("run-time", Regressor::new(&model))];
        sources.extend(generated(&stem).map(|r| ("generated", r)));
        for (source, regressor) in &sources {
            let mut rows = 0;
            for line in text.lines().filter(|l| !l.starts_with('#') && !l.starts_with("\"#")) {
                let values: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
                assert_eq!(values.len(), 3 * n + n * regressor.columns(), "{stem}: row length");
                let (q, qd, qdd) = (&values[..n], &values[n..2 * n], &values[2 * n..3 * n]);
                let y = regressor.rows((q, qd, qdd)).unwrap();
                for i in 0..n {
                    for j in 0..regressor.columns() {
                        let reference = values[3 * n + i * regressor.columns() + j];
                        let error = (y[(i, j)] - reference).abs();
                        worst = worst.max(error / (1.0 + reference.abs()));
                        assert!(
                            error <= 1e-9 * (1.0 + reference.abs()),
                            "{stem} ({source}): Y[{i}, {j}] = {} vs Pinocchio {reference}",
                            y[(i, j)]
                        );
                    }
                }
                rows += 1;
            }
            assert!(rows > 0, "{stem}: no rows");
        }
        generated_arms += usize::from(sources.len() == 2);
    }
    assert_eq!(generated_arms, hya_robots::ROBOTS.len(), "every shipped arm's generated regressor checked");
    println!("largest |Y − Y_pinocchio| / (1 + |Y_pinocchio|): {worst:.1e}");
}

#[test]
fn y_times_the_nominal_parameters_is_the_inverse_dynamics() {
    for robot in hya_robots::ROBOTS {
        let model = hya_urdf::load_str(robot.urdf, robot.name).unwrap().model;
        let pi = nominal_parameters(&model);
        let regressor = Regressor::new(&model);
        let n = model.dof();
        for k in 0..20 {
            let x = |j: usize, scale: f64| scale * ((k * 7 + j * 3) as f64 * 0.37).sin();
            let q: Vec<f64> = (0..n).map(|j| x(j, 2.0)).collect();
            let qd: Vec<f64> = (0..n).map(|j| x(j + n, 3.0)).collect();
            let qdd: Vec<f64> = (0..n).map(|j| x(j + 2 * n, 5.0)).collect();
            let tau = model.inverse_dynamics(&q, &qd, &qdd).unwrap();
            let y_pi = regressor.rows((&q, &qd, &qdd)).unwrap() * &pi;
            for i in 0..n {
                assert!(
                    (y_pi[i] - tau[i]).abs() <= 1e-12 * (1.0 + tau[i].abs()),
                    "{}: (Y π)[{i}] = {} vs ID {}",
                    robot.name,
                    y_pi[i],
                    tau[i]
                );
            }
        }
    }
}

/// `Y_b (K π) = Y π` for arbitrary `π` at states the stack did not contain, on every shipped
/// arm; a planar two-link arm with gravity in its plane has six base parameters (Khalil and
/// Dombre: link 2's inertia about its axis and two in-plane first moments, link 1's the same
/// with link 2's mass lumped at the elbow).
#[test]
fn base_parameters_predict_the_same_torques() {
    for robot in hya_robots::ROBOTS {
        let model = hya_urdf::load_str(robot.urdf, robot.name).unwrap().model;
        let base = BaseParameters::of(&model, 5).unwrap();
        if robot.name == "planar2" {
            assert_eq!(base.rank(), 6);
        }
        let regressor = Regressor::new(&model);
        let n = model.dof();
        for k in 0..5 {
            let x = |j: usize, scale: f64| scale * ((k * 11 + j * 5) as f64 * 0.53 + 0.2).sin();
            let q: Vec<f64> = (0..n).map(|j| x(j, 3.0)).collect();
            let qd: Vec<f64> = (0..n).map(|j| x(j + n, 3.0)).collect();
            let qdd: Vec<f64> = (0..n).map(|j| x(j + 2 * n, 10.0)).collect();
            let pi = DVector::from_fn(regressor.columns(), |i, _| x(i + 3 * n, 2.0));
            let y = regressor.rows((&q, &qd, &qdd)).unwrap();
            let (full, reduced) = (&y * &pi, base.base_regressor(&y) * base.of_parameters(&pi));
            for i in 0..n {
                assert!(
                    (full[i] - reduced[i]).abs() <= 1e-9 * (1.0 + full[i].abs()),
                    "{}: τ[{i}] = {} from π, {} from π_b",
                    robot.name,
                    full[i],
                    reduced[i]
                );
            }
        }
        println!("{}: {} base parameters of {}", robot.name, base.rank(), regressor.columns());
    }
}
