//! Generated against generic dynamics for every shipped robot: inverse dynamics, mass matrix,
//! gravity and forward dynamics. `cargo bench -p hya-robots` (divan); inputs cycle through 64
//! varied states behind `black_box`.

use divan::black_box;
use hya_core::model::TreeDynamics;
use hya_core::{Dynamics, JointVector};

fn main() {
    divan::main();
}

/// 64 varied states `(q, q̇, q̈ or τ)`.
fn states<const N: usize>() -> [[JointVector<N>; 3]; 64] {
    hya_core::sampling::varied_states()
}

fn generic<const N: usize>(name: &str) -> TreeDynamics<N> {
    let robot = hya_robots::find(name).expect("a shipped robot");
    hya_urdf::load_str(robot.urdf, name).expect("the shipped URDF loads").model.into_dynamics().expect("its DOF")
}

/// One benchmark group per robot: each entry point, generated and generic side by side.
macro_rules! robot_benches {
    ($($module:ident $type:ident $parametric:ident $dof:literal [$($home:expr),*] $doc:literal;)*) => {$(
        #[divan::bench_group]
        mod $module {
            use super::*;
            use hya_robots::$type;

            fn run<D: Dynamics<$dof>>(bencher: divan::Bencher, dynamics: D, f: fn(&D, &[JointVector<$dof>; 3])) {
                let states = states::<$dof>();
                let mut k = 0;
                bencher.bench_local(|| {
                    k = (k + 1) % states.len();
                    f(black_box(&dynamics), black_box(&states[k]));
                });
            }

            /// Runs `op` on the generated or the generic model.
            macro_rules! both {
                ($bencher:ident, $path:ident, $op:ident) => {
                    if $path == "generated" {
                        run($bencher, $type, $op::<$type>)
                    } else {
                        run($bencher, generic::<$dof>(stringify!($module)), $op::<TreeDynamics<$dof>>)
                    }
                };
            }

            #[divan::bench(args = ["generated", "generic"], sample_count = 100, sample_size = 1000)]
            fn inverse_dynamics(bencher: divan::Bencher, path: &str) {
                fn op<D: Dynamics<$dof>>(d: &D, [q, qd, qdd]: &[JointVector<$dof>; 3]) {
                    black_box(d.inverse_dynamics(q, qd, qdd));
                }
                both!(bencher, path, op)
            }

            #[divan::bench(args = ["generated", "generic"], sample_count = 100, sample_size = 1000)]
            fn mass_matrix(bencher: divan::Bencher, path: &str) {
                fn op<D: Dynamics<$dof>>(d: &D, [q, _, _]: &[JointVector<$dof>; 3]) {
                    black_box(d.mass_matrix(q));
                }
                both!(bencher, path, op)
            }

            #[divan::bench(args = ["generated", "generic"], sample_count = 100, sample_size = 1000)]
            fn gravity(bencher: divan::Bencher, path: &str) {
                fn op<D: Dynamics<$dof>>(d: &D, [q, _, _]: &[JointVector<$dof>; 3]) {
                    black_box(d.gravity(q));
                }
                both!(bencher, path, op)
            }

            #[divan::bench(args = ["generated", "generic"], sample_count = 100, sample_size = 1000)]
            fn forward_dynamics(bencher: divan::Bencher, path: &str) {
                fn op<D: Dynamics<$dof>>(d: &D, [q, qd, tau]: &[JointVector<$dof>; 3]) {
                    let _ = black_box(d.forward_dynamics(q, qd, tau));
                }
                both!(bencher, path, op)
            }
        }
    )*};
}

hya_robots::for_each_robot!(robot_benches);
