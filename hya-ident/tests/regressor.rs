//! The regressor against Pinocchio's `computeJointTorqueRegressor` (rows written by
//! `tools/regressor_reference.py` into `tests/reference/regressor/`), and `Y π` against the
//! model's own inverse dynamics.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use std::path::{Path, PathBuf};

use hya_core::model::TreeModel;
use hya_ident::{nominal_parameters, Regressor};

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

#[test]
fn the_regressor_equals_pinocchios_on_every_reference_file() {
    let mut files: Vec<_> = std::fs::read_dir(root().join("tests/reference/regressor"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    assert!(files.len() >= 7, "the shipped arms and two other URDFs: found {files:?}");
    let mut worst: f64 = 0.0;
    for file in files {
        let stem = file.file_stem().unwrap().to_str().unwrap().to_owned();
        let model = model(&stem);
        let n = model.dof();
        let regressor = Regressor::new(&model);
        let text = std::fs::read_to_string(&file).unwrap();
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
                        "{stem}: Y[{i}, {j}] = {} vs Pinocchio {reference}",
                        y[(i, j)]
                    );
                }
            }
            rows += 1;
        }
        assert!(rows > 0, "{stem}: no rows");
    }
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
