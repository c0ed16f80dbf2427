//! The joint-torque regressor `Y(q, q̇, q̈)` of every shipped arm: by the run-time model's RNEA
//! against by the generated twins, side by side. `cargo bench -p hya-ident` (divan); inputs
//! cycle through 64 varied states behind `black_box`.

use divan::black_box;
use hya_ident::Regressor;

fn main() {
    divan::main();
}

/// 64 varied states `(q, q̇, q̈)` of `n` joints.
fn states(n: usize) -> Vec<[Vec<f64>; 3]> {
    (0..64)
        .map(|k| {
            let x = |j: usize, scale: f64| scale * ((k * 7 + j * 3) as f64 * 0.37).sin();
            [
                (0..n).map(|j| x(j, 2.0)).collect(),
                (0..n).map(|j| x(j + n, 3.0)).collect(),
                (0..n).map(|j| x(j + 2 * n, 5.0)).collect(),
            ]
        })
        .collect()
}

fn run(bencher: divan::Bencher, regressor: &Regressor<'_>, n: usize) {
    let states = states(n);
    let mut y = nalgebra::DMatrix::zeros(n, regressor.columns());
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) % states.len();
        let [q, qd, qdd] = &states[k];
        black_box(regressor)
            .rows_into((black_box(q), black_box(qd), black_box(qdd)), &mut y, 0)
            .expect("a state of the arm's size");
    });
}

/// The arm's regressor on its generated code.
fn generated(name: &str) -> Regressor<'static> {
    struct Build;
    impl hya_robots::ForArm for Build {
        type Output = Regressor<'static>;
        fn call<const N: usize>(self, arm: hya_robots::Arm<N>) -> Self::Output {
            Regressor::generated::<N>(arm.parametric)
        }
    }
    hya_robots::with_arm(name, Build).expect("a shipped arm")
}

const ARMS: [&str; 5] = ["hya", "ur5", "panda", "iiwa14", "planar2"];

#[divan::bench(args = ARMS)]
fn run_time(bencher: divan::Bencher, name: &str) {
    let robot = hya_robots::find(name).expect("a shipped arm");
    let model = hya_urdf::load_str(robot.urdf, name).expect("the shipped URDF loads").model;
    run(bencher, &Regressor::new(&model), model.dof());
}

#[divan::bench(args = ARMS)]
fn generated_twins(bencher: divan::Bencher, name: &str) {
    let regressor = generated(name);
    let n = hya_robots::find(name).expect("a shipped arm").dof;
    run(bencher, &regressor, n);
}
