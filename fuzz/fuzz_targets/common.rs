//! What every fuzz target checks once a description loaded: the model evaluates to finite
//! numbers at rest and in motion, and the generator either emits code or refuses, never panics.

use hya_urdf::LoadedModel;

pub fn check_loaded(loaded: &LoadedModel) {
    let model = &loaded.model;
    let n = model.dof();
    let (q, qd) = (vec![0.3; n], vec![0.5; n]);
    let tau = model.inverse_dynamics(&q, &qd, &vec![1.0; n]).expect("a loaded model evaluates");
    assert!(tau.iter().all(|t| t.is_finite()), "non-finite inverse dynamics {tau:?}");
    let mass = model.mass_matrix(&q).expect("a loaded model evaluates");
    assert!(mass.iter().all(|m| m.is_finite()), "non-finite mass matrix");
    if n <= 7 {
        let _ = hya_codegen::generate(loaded, "Fuzz");
    }
}
