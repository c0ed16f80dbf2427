//! # hya-ident
//!
//! Identification of an arm from its logs starts here: inverse dynamics is linear in the
//! bodies' inertial parameters,
//!
//! ```text
//! τ = Y(q, q̇, q̈) π,   π = (π_1, …, π_B),   π_b = (m, h_x, h_y, h_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz)
//! ```
//!
//! (ten per body, [`regressor`]), and a log identifies `π` only as well as the motion in it
//! excites `Y`: [`excitation`] designs a periodic trajectory (a finite Fourier series per joint,
//! within the joints' position and velocity limits) whose stacked regressor is well
//! conditioned ([`conditioning`]); only some combinations of the parameters, the base
//! parameters ([`base`]), act on the joints at all; [`log`] filters a log's rows into samples,
//! [`fit`](mod@fit) finds the base parameters and the joints' friction from them, and
//! [`physical`] full parameters of real bodies that match them; [`identify`](mod@identify) does
//! all of it, holding out the log's end to test the prediction.

pub mod base;
pub mod conditioning;
pub mod excitation;
pub mod fit;
pub mod friction;
pub mod identify;
pub mod log;
pub mod physical;
pub mod prior;
pub mod regressor;
pub mod with_friction;

pub use base::BaseParameters;

/// The most joints identification and excitation design take: the arms the estimator runs
/// ([`hya_core::dispatch::MAX_JOINTS`]). The regressor of `n` joints has `10 n` columns and the
/// base-parameter stack `20 n` states of `n` rows each, so memory grows as `n³`.
pub const MAX_JOINTS: usize = hya_core::dispatch::MAX_JOINTS;

/// `Ok(dof)` if `model` has 1 to [`MAX_JOINTS`] joints; checked before anything that grows with
/// the joint count is allocated.
pub fn check_joint_count(model: &hya_core::model::TreeModel) -> Result<usize, hya_core::model::ModelError> {
    hya_core::model::ModelError::joint_count(model, "identification", MAX_JOINTS)
}
pub use conditioning::Conditioning;
pub use excitation::{ExcitationDesign, ExcitationError, FourierTrajectory, Limits};
pub use fit::{fit, fit_with, Fit, FitError, Law, Sample};
pub use friction::JointFriction;
pub use identify::{identify, Identification, IdentifyError, Options};
pub use log::{LogFilter, RowError, Timing};
pub use physical::{consistent_parameters, is_consistent, Consistent};
pub use regressor::{body_inertia, body_parameters, nominal_parameters, Regressor, PARAMETERS_PER_BODY};
pub use with_friction::WithFriction;
