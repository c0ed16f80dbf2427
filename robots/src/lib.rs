//! # hya-robots
//!
//! The arms hya ships, each as a zero-sized type implementing [`hya_core::Dynamics`] with code
//! generated at build time from the URDF in `urdf/` (see `build.rs`), plus the URDF text itself.
//! Each also has a parameter-holding twin (`HyaParametric`, ...) that reads its inertial
//! parameters from data: the same folded kinematics for perturbed, identified or loaded bodies.
//!
//! The list of robots is `robots.list` (name, type, home pose, description), and nothing else:
//! [`for_each_robot!`] hands it to any macro that needs it, and [`ROBOTS`] holds it at run
//! time. Where each arm's figures come from is in its URDF's header comment.

#![no_std]

#[cfg(feature = "std")]
extern crate std;

use hya_core::{OnSlicesN, SliceDynamics};

include!(concat!(env!("OUT_DIR"), "/registry.rs"));

macro_rules! shipped_robots {
    ($($module:ident $type:ident $parametric:ident $dof:literal [$($home:expr),*] $doc:literal;)*) => {
        $(
            #[doc = $doc]
            pub mod $module {
                include!(concat!(env!("OUT_DIR"), "/", stringify!($module), ".rs"));
                /// The URDF the dynamics were generated from.
                pub const URDF: &str = include_str!(concat!("../urdf/", stringify!($module), ".urdf"));
                /// The home pose, one value per joint (`robots.list`), as published: HyA's
                /// 0.7854 is not π/4.
                #[allow(clippy::approx_constant)]
                pub const HOME: [f64; $dof] = [$($home),*];
            }
            pub use $module::{$type, $parametric};
        )*

        /// Every shipped robot.
        pub const ROBOTS: &[RobotInfo] = &[$(RobotInfo {
            name: stringify!($module),
            dof: $dof,
            joint_names: &$module::$type::JOINT_NAMES,
            home: &$module::HOME,
            urdf: $module::URDF,
            generated: &OnSlicesN::<$dof, $module::$type>($module::$type),
        },)*];
    };
}

for_each_robot!(shipped_robots);

/// A shipped robot, for listing and for run-time dispatch.
#[derive(Clone, Copy)]
pub struct RobotInfo {
    /// Its name (`hya`, `ur5`, ...).
    pub name: &'static str,
    /// Degrees of freedom.
    pub dof: usize,
    /// Joint names in the model's order.
    pub joint_names: &'static [&'static str],
    /// The home pose, one value per joint.
    pub home: &'static [f64],
    /// The URDF text.
    pub urdf: &'static str,
    /// The generated dynamics, on slices.
    pub generated: &'static (dyn SliceDynamics + Sync),
}

impl core::fmt::Debug for RobotInfo {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("RobotInfo").field("name", &self.name).field("dof", &self.dof).finish_non_exhaustive()
    }
}

/// The shipped robot called `name`.
pub fn find(name: &str) -> Option<&'static RobotInfo> {
    ROBOTS.iter().find(|r| r.name == name)
}

/// Why `name` names no robot, for a message: neither a shipped arm (listed, the nearest one
/// suggested) nor a file that exists.
#[cfg(feature = "std")]
pub fn unknown(name: &str) -> std::string::String {
    use std::{format, vec::Vec};
    let names: Vec<&str> = ROBOTS.iter().map(|r| r.name).collect();
    let suggestion = hya_core::closest(name, names.iter().copied())
        .map(|near| format!("; did you mean `{near}`?"))
        .unwrap_or_default();
    format!(
        "`{}` is neither a shipped robot ({}) nor a URDF file{suggestion}",
        hya_core::Clipped(name, 60),
        names.join(", ")
    )
}

/// One shipped arm with its number of joints as the constant `N` ([`with_arm`]): its generated
/// dynamics, and a factory of its parameter-holding twin for other inertial parameters.
#[cfg(feature = "std")]
pub struct Arm<const N: usize> {
    /// Its entry in [`ROBOTS`].
    pub info: &'static RobotInfo,
    /// The generated dynamics with the URDF's parameters.
    pub nominal: &'static (dyn hya_core::Dynamics<N> + Send + Sync),
    /// The generated pose, Jacobian and `J̇ q̇` of its last link (the tool's flange).
    pub tip: &'static (dyn hya_core::FrameKinematics<N> + Send + Sync),
    /// The parameter-holding twin for these body inertias (joint order): the same folded
    /// kinematics for perturbed, identified or loaded bodies.
    pub parametric: ParametricFactory<N>,
    /// Forward dynamics of many states, each with its own bodies, on the parametric twin's kernel
    /// (the simulator's seeds in lockstep).
    pub bodies: &'static (dyn hya_core::BodiesBatch<N> + Send + Sync),
}

/// Builds an arm's parameter-holding twin from its body inertias, in joint order.
#[cfg(feature = "std")]
pub type ParametricFactory<const N: usize> =
    fn(&[hya_core::spatial::RigidBodyInertia; N]) -> std::boxed::Box<dyn hya_core::Dynamics<N> + Send + Sync>;

/// The generated dynamics of the shipped arm called `name`, as `N` joints: `None` if no shipped
/// arm has that name, or it has another number of joints. For a caller that fixed `N` from the
/// arm's joint count ([`hya_core::dispatch::with_joints`]) and so cannot name it in [`with_arm`].
#[cfg(feature = "std")]
pub fn nominal<const N: usize>(name: &str) -> Option<&'static (dyn hya_core::Dynamics<N> + Send + Sync)> {
    struct AsN<const N: usize>;
    impl<const N: usize> ForArm for AsN<N> {
        type Output = Option<&'static (dyn hya_core::Dynamics<N> + Send + Sync)>;
        fn call<const M: usize>(self, arm: Arm<M>) -> Self::Output {
            // The same type exactly when M = N.
            let nominal: &dyn core::any::Any = &arm.nominal;
            nominal.downcast_ref::<&'static (dyn hya_core::Dynamics<N> + Send + Sync)>().copied()
        }
    }
    with_arm(name, AsN::<N>).flatten()
}

/// Something to do with a shipped arm, whose number of joints becomes the constant `N`.
#[cfg(feature = "std")]
pub trait ForArm {
    /// What it gives.
    type Output;
    /// Does it for `arm`.
    fn call<const N: usize>(self, arm: Arm<N>) -> Self::Output;
}

#[cfg(feature = "std")]
macro_rules! arm_dispatch {
    ($($module:ident $type:ident $parametric:ident $dof:literal [$($home:expr),*] $doc:literal;)*) => {
        /// Calls `f` with the shipped arm called `name` (its joint count as `N`); `None` if no
        /// shipped arm has that name. Instantiates `f` once per distinct joint count, not per arm.
        pub fn with_arm<F: ForArm>(name: &str, f: F) -> Option<F::Output> {
            $(
                if name == stringify!($module) {
                    return Some(f.call::<$dof>(Arm {
                        info: find(name)?,
                        nominal: &$type,
                        tip: &$type,
                        parametric: |inertias| std::boxed::Box::new($parametric::new(inertias)),
                        bodies: &$parametric([[0.0; 10]; $dof]),
                    }));
                }
            )*
            None
        }
    };
}
#[cfg(feature = "std")]
for_each_robot!(arm_dispatch);
