//! One robot handle: the nominal dynamics the controller and observers use, the run-time model
//! the plant perturbs, and how the plant's rigid body is built from a perturbed model.
//!
//! A shipped arm runs on generated code, the plant on its parameter-holding generated twin; a
//! URDF runs on the run-time tree model for both. [`with_robot`] hands a robot to code generic
//! over its number of joints `N` (found from the registry for a shipped arm, from the model for
//! a URDF), instantiated once per joint count.

use hya_core::dispatch::{with_joints, ForJoints};
use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use hya_core::{BodiesBatch, Dynamics, JointMatrix, JointVector};
use hya_robots::{Arm, ForArm};

use crate::error::SimError;

/// Builds the plant's true rigid-body dynamics from a model (perturbed, or carrying a payload).
pub type DynamicsFactory<const N: usize> = dyn Fn(&TreeModel) -> Result<Box<dyn Dynamics<N>>, SimError> + Send + Sync;

/// A robot with `N` joints.
pub struct Robot<const N: usize> {
    /// A shipped arm's name, or the URDF's path.
    pub name: String,
    /// The run-time model with the description's parameters: the plant's starting point.
    pub model: TreeModel,
    /// The nominal dynamics: the controller's and observers' model.
    pub nominal: Box<dyn Dynamics<N> + Send + Sync>,
    /// The plant's rigid body for a (perturbed, loaded) model.
    pub plant: Box<DynamicsFactory<N>>,
    /// Forward dynamics of many plants at once, each with its own bodies, where the plant's rigid
    /// body is generated code (a shipped arm's parametric twin): the seeds of a run in lockstep
    /// ([`crate::plant::lockstep`]). `None` on the run-time model, whose seeds run one by one.
    pub bodies: Option<&'static (dyn BodiesBatch<N> + Send + Sync)>,
}

impl<const N: usize> std::fmt::Debug for Robot<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Robot").field("name", &self.name).field("joints", &N).finish_non_exhaustive()
    }
}

/// Body inertias of a model in joint order, as parametric generated dynamics take them.
fn inertias<const N: usize>(model: &TreeModel) -> Result<[RigidBodyInertia; N], SimError> {
    let bodies = model.bodies();
    if bodies.len() != N {
        return Err(SimError::JointCount { robot: model.name().to_owned(), expected: N, found: bodies.len() });
    }
    Ok(core::array::from_fn(|i| bodies[i].inertia))
}

/// The run-time model of a shipped arm by name, else of a URDF file by path.
pub fn robot_model(robot: &str) -> Result<TreeModel, SimError> {
    Ok(match hya_robots::find(robot) {
        Some(shipped) => hya_urdf::load_str(shipped.urdf, shipped.name)?.model,
        None if std::fs::symlink_metadata(robot).is_err() => {
            return Err(SimError::UnknownRobot(hya_robots::unknown(robot)))
        }
        None => hya_urdf::load_file(robot)?.model,
    })
}

impl<const N: usize> Robot<N> {
    /// A shipped arm: generated code for the nominal dynamics and the plant.
    pub fn shipped(arm: Arm<N>) -> Result<Self, SimError> {
        let parametric = arm.parametric;
        Ok(Self {
            name: arm.info.name.to_owned(),
            model: robot_model(arm.info.name)?,
            nominal: Box::new(arm.nominal),
            plant: Box::new(move |m: &TreeModel| Ok(parametric(&inertias::<N>(m)?) as Box<dyn Dynamics<N>>)),
            bodies: Some(arm.bodies),
        })
    }

    /// A robot described by `model` (a URDF at `name`): the run-time tree model for the nominal
    /// dynamics and the plant.
    pub fn from_model(name: &str, model: TreeModel) -> Result<Self, SimError> {
        let nominal = model.clone().into_dynamics::<N>()?;
        let plant = |m: &TreeModel| Ok(Box::new(m.clone().into_dynamics::<N>()?) as Box<dyn Dynamics<N>>);
        Ok(Self { name: name.to_owned(), model, nominal: Box::new(nominal), plant: Box::new(plant), bodies: None })
    }

    /// The robot called `robot` (a shipped arm's name or a URDF's path), which must have `N`
    /// joints. Where `N` is not known at compile time, [`with_robot`] finds it; a shipped arm
    /// loaded here runs behind [`Resized`], which copies each joint vector once more.
    pub fn load(robot: &str) -> Result<Self, SimError> {
        struct Exactly<const N: usize>;
        impl<const N: usize> ForArm for Exactly<N> {
            type Output = Result<Robot<N>, SimError>;
            fn call<const M: usize>(self, arm: Arm<M>) -> Self::Output {
                if M != N {
                    return Err(SimError::JointCount { robot: arm.info.name.into(), expected: N, found: M });
                }
                let shipped = Robot::<M>::shipped(arm)?;
                let plant = shipped.plant;
                Ok(Robot {
                    name: shipped.name,
                    model: shipped.model,
                    nominal: Box::new(Resized::<M, _>(shipped.nominal)),
                    plant: Box::new(move |m: &TreeModel| {
                        Ok(Box::new(Resized::<M, _>(plant(m)?)) as Box<dyn Dynamics<N>>)
                    }),
                    bodies: None,
                })
            }
        }
        match hya_robots::with_arm(robot, Exactly::<N>) {
            Some(found) => found,
            None => Self::from_model(robot, robot_model(robot)?),
        }
    }
}

/// Something to do with a robot of `N` joints, `N` found at run time ([`with_robot`]).
pub trait ForRobot {
    /// What it gives.
    type Output;
    /// Does it with `robot`.
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<Self::Output, SimError>;
}

/// Calls `f` with the robot called `robot`: a shipped arm by name (generated code), else the
/// URDF at that path (the run-time model), of 1 to [`hya_core::dispatch::MAX_JOINTS`] joints.
pub fn with_robot<F: ForRobot>(robot: &str, f: F) -> Result<F::Output, SimError> {
    struct Shipped<F>(F);
    impl<F: ForRobot> ForArm for Shipped<F> {
        type Output = Result<F::Output, SimError>;
        fn call<const N: usize>(self, arm: Arm<N>) -> Self::Output {
            self.0.call(Robot::shipped(arm)?)
        }
    }
    struct Described<'a, F>(F, &'a str, TreeModel);
    impl<F: ForRobot> ForJoints for Described<'_, F> {
        type Output = Result<F::Output, SimError>;
        fn call<const N: usize>(self) -> Self::Output {
            self.0.call(Robot::<N>::from_model(self.1, self.2)?)
        }
    }
    if hya_robots::find(robot).is_some() {
        return hya_robots::with_arm(robot, Shipped(f)).unwrap_or_else(|| unreachable_arm(robot));
    }
    let model = robot_model(robot)?;
    let dof = model.dof();
    with_joints(dof, Described(f, robot, model)).unwrap_or(Err(SimError::TooManyJoints { robot: robot.into(), dof }))
}

/// [`hya_robots::with_arm`] found no arm that [`hya_robots::find`] found: the registry's two
/// views disagree (a bug, reported as an error rather than a panic).
fn unreachable_arm<T>(robot: &str) -> Result<T, SimError> {
    Err(SimError::UnknownRobot(format!("`{robot}` is listed but has no dispatch (a registry bug)")))
}

/// Dynamics of `M` joints seen as dynamics of `N = M` joints, for code whose `N` came from the
/// caller rather than from the arm ([`Robot::load`]): each vector is copied once more, bit for
/// bit. Built only where `M == N` was checked.
pub struct Resized<const M: usize, D>(pub D);

/// The same values as a vector of `K` entries (`K` equal to the length, as [`Resized`] checked).
fn resize<const K: usize>(values: &[f64]) -> JointVector<K> {
    JointVector::<K>::from_column_slice(values)
}

fn resize_matrix<const K: usize>(values: &[f64]) -> JointMatrix<K> {
    JointMatrix::<K>::from_column_slice(values)
}

impl<const M: usize, const N: usize, D: Dynamics<M>> Dynamics<N> for Resized<M, D> {
    fn inverse_dynamics(&self, q: &JointVector<N>, qd: &JointVector<N>, qdd: &JointVector<N>) -> JointVector<N> {
        let [q, qd, qdd] = [q, qd, qdd].map(|v| resize::<M>(v.as_slice()));
        resize(self.0.inverse_dynamics(&q, &qd, &qdd).as_slice())
    }
    fn coriolis_transpose_times_velocity(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        let [q, qd] = [q, qd].map(|v| resize::<M>(v.as_slice()));
        resize(self.0.coriolis_transpose_times_velocity(&q, &qd).as_slice())
    }
    fn gravity(&self, q: &JointVector<N>) -> JointVector<N> {
        resize(self.0.gravity(&resize(q.as_slice())).as_slice())
    }
    fn velocity_terms(&self, q: &JointVector<N>, qd: &JointVector<N>) -> JointVector<N> {
        let [q, qd] = [q, qd].map(|v| resize::<M>(v.as_slice()));
        resize(self.0.velocity_terms(&q, &qd).as_slice())
    }
    fn mass_matrix(&self, q: &JointVector<N>) -> JointMatrix<N> {
        resize_matrix(self.0.mass_matrix(&resize(q.as_slice())).as_slice())
    }
    fn inverse_dynamics_derivatives(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        qdd: &JointVector<N>,
    ) -> (JointMatrix<N>, JointMatrix<N>) {
        let [q, qd, qdd] = [q, qd, qdd].map(|v| resize::<M>(v.as_slice()));
        let (d_dq, d_dqd) = self.0.inverse_dynamics_derivatives(&q, &qd, &qdd);
        (resize_matrix(d_dq.as_slice()), resize_matrix(d_dqd.as_slice()))
    }
    fn forward_dynamics(
        &self,
        q: &JointVector<N>,
        qd: &JointVector<N>,
        tau: &JointVector<N>,
    ) -> Result<JointVector<N>, hya_core::Error> {
        let [q, qd, tau] = [q, qd, tau].map(|v| resize::<M>(v.as_slice()));
        Ok(resize(self.0.forward_dynamics(&q, &qd, &tau)?.as_slice()))
    }
}
