//! The HyA model loaded from `robots/urdf/hya.urdf` against the golden values published with its
//! reference description (RobCoGen's generated code for HyA; gravity 9.81 m/s² along −z).
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_urdf::{load_file, Warning};

/// The authors' home pose, as published: 0.7854, not π/4.
#[allow(clippy::approx_constant)]
const Q_INIT: [f64; 6] = [0.0, 0.0, -0.7854, 0.7854, 0.7854, 0.0];
const QA: [f64; 6] = [0.1, -0.2, -0.5, 1.0, 0.3, 0.4];
const QDA: [f64; 6] = [0.5, -0.4, 0.3, -0.2, 0.1, 0.6];
const QDDA: [f64; 6] = [1.0, -1.0, 0.5, 0.8, -0.3, 0.2];
const ZERO: [f64; 6] = [0.0; 6];

const TAU_ZERO: [f64; 6] = [0.0, 43.1238488073, 0.2604415432, 9.3237588626, 0.3150001423, 0.0];
const TAU_Q_INIT: [f64; 6] = [0.0, 40.2959021342, 4.9492114049, 4.5932244126, 0.2688694044, -0.0555794064];
const TAU_A: [f64; 6] = [2.1468108624, 37.5536011240, 3.5175392619, 5.9761151753, 0.3558367280, -0.1411035949];
const GRAVITY_A: [f64; 6] = [0.0, 39.2432629281, 4.0872427412, 5.8409699608, 0.3436302829, -0.1827350120];
const VELOCITY_TERMS_A: [f64; 6] =
    [0.0674028409, -0.1496590478, -0.0787483451, 0.0705371248, -0.0028081596, 0.0077300917];
const MASS_A: [[f64; 6]; 6] = [
    [2.0913770492, 0.0372552229, -0.3730856443, 0.2653535600, 0.0189609610, 0.0261722881],
    [0.0372552229, 2.0452267136, 0.2276867131, 0.4542820307, 0.0253050885, -0.0085436013],
    [-0.3730856443, 0.2276867131, 0.2225656385, 0.0090981766, 0.0186020901, -0.0158175517],
    [0.2653535600, 0.4542820307, 0.0090981766, 0.3182508561, 0.0231605462, 0.0066747563],
    [0.0189609610, 0.0253050885, 0.0186020901, 0.0231605462, 0.0217935951, 0.0003366437],
    [0.0261722881, -0.0085436013, -0.0158175517, 0.0066747563, 0.0003366437, 0.0092770000],
];

/// Absolute tolerance, N·m and kg·m². Every entry agrees to 1e-9 (the golden values' 10 digits)
/// except HR's gravity torque, off by 1.3e-8 to 1.5e-8: the table prints Humerus_R's centre of
/// mass as x = -0.0023899989 m, and the golden values were computed with a value near
/// -0.0023899995 (rounding it to -0.00239 flips the error's sign at the same size). A 1e-9 m
/// change of that figure moves HR's torque by m g δ = 2.3e-8 N·m, hence 2e-8.
const TOLERANCE: f64 = 2e-8;

fn hya_urdf() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/urdf/hya.urdf")
}

fn assert_close(what: &str, got: &[f64], expected: &[f64]) {
    for (i, (g, e)) in got.iter().zip(expected).enumerate() {
        assert!((g - e).abs() <= TOLERANCE, "{what}[{i}]: {g} vs golden {e}");
    }
}

#[test]
fn hya_matches_its_golden_values() {
    let loaded = load_file(hya_urdf()).unwrap();
    let model = &loaded.model;
    assert_eq!(model.joint_names().collect::<Vec<_>>(), ["SAA", "SFE", "HR", "EFE", "WR", "WFE"]);
    assert_close("tau(0,0,0)", &model.inverse_dynamics(&ZERO, &ZERO, &ZERO).unwrap(), &TAU_ZERO);
    assert_close("tau(q_init,0,0)", &model.inverse_dynamics(&Q_INIT, &ZERO, &ZERO).unwrap(), &TAU_Q_INIT);
    assert_close("tau(qA,qdA,qddA)", &model.inverse_dynamics(&QA, &QDA, &QDDA).unwrap(), &TAU_A);
    assert_close("G(qA)", &model.gravity(&QA).unwrap(), &GRAVITY_A);
    let velocity_terms: Vec<f64> =
        model.inverse_dynamics(&QA, &QDA, &ZERO).unwrap().iter().zip(&GRAVITY_A).map(|(tau, g)| tau - g).collect();
    assert_close("C(qA,qdA)", &velocity_terms, &VELOCITY_TERMS_A);
    let mass = model.mass_matrix(&QA).unwrap();
    for (i, row) in MASS_A.iter().enumerate() {
        assert_close(&format!("M(qA) row {i}"), mass.row(i).transpose().as_slice(), row);
    }
}

#[test]
fn hya_end_effector_and_wrist_warning() {
    let loaded = load_file(hya_urdf()).unwrap();
    let ee = loaded.model.frame_pose("ee", &ZERO).unwrap().translation;
    assert!((ee - nalgebra::Vector3::new(0.742, 0.02075, 0.178)).norm() < 1e-9, "{ee}");
    assert!(matches!(loaded.warnings.as_slice(), [Warning::TriangleInequality { link, .. }] if link == "Wrist_FE"));
}
