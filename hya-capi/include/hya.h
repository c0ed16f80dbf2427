/*
 * hya: disturbance estimation and computed-torque control for robot arms, from C and C++.
 *
 * Units: rad, rad/s, rad/s^2, N*m, s. Arrays are `double` with an explicit length `n`, which
 * must equal the model's joint count (hya_model_dof); a mass matrix has n*n entries
 * (symmetric, so row- and column-major agree). The batch functions (hya_model_*_batch) take
 * `count` states as rows of `n`, row-major (count*n doubles per argument), and name the row
 * of a failure. An output (an array, or hya_estimator_update_at's `restarted`) that overlaps an
 * input array or another output is refused with HYA_ERR_INVALID, the output named, before
 * anything is computed: no call works in place.
 *
 * Status: every function returns HYA_OK or an error status. A function called on a handle
 * writes the failure's message into that handle (hya_model_error, hya_estimator_error,
 * hya_observer_error, hya_controller_error); a creation function, or any call given a null
 * handle or one that is not a live handle of its kind (HYA_ERR_HANDLE: freed, of another kind,
 * never made by hya), writes it into the calling thread's last error (hya_last_error). Messages name the
 * argument, index and value at fault. Rust panics never cross the boundary: they become
 * HYA_ERR_PANIC. Read outputs only after HYA_OK.
 *
 * Ownership: every hya_*_new / hya_model_from_* call that returns HYA_OK gives the caller one
 * handle, freed with the matching hya_*_free (free(NULL-handle) is a no-op). An estimator,
 * observer or controller keeps its own reference to the model's dynamics, so the model may be
 * freed first. Message pointers are owned by hya: valid until the next call on the same handle
 * (or, for hya_last_error, the next hya call on the same thread) and never freed by the caller.
 *
 * Allocation: only the creation functions allocate; per-call functions (dynamics, updates,
 * commands), including their error paths, do not.
 *
 * Threads: a handle is not to be used from two threads at once without a lock (calls take it
 * mutably, at least to write its message). Distinct handles are independent, also when made
 * from the same model, and may be used on different threads concurrently. Every call checks its
 * handle in a process-wide registry of live handles under a read lock (creation and freeing take
 * it to write): calls on different threads do not wait for each other, but one may wait for a
 * creation or a free in progress on another thread; create and free outside a real-time loop.
 */


#ifndef HYA_H
#define HYA_H

/* Generated from hya-capi/src by cbindgen (see hya-capi/tests/header.rs); do not edit. */

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

// The most bytes a message keeps (longer ones are cut at a character boundary).
#define HYA_MESSAGE_CAPACITY 512

// What a call did. `HYA_OK` is zero; every other value is a failure whose message is kept by
// the handle (or, for creation and null handles, by `hya_last_error`).
typedef enum {
  // Success; outputs were written.
  HYA_OK = 0,
  // A required pointer (handle, array, name, output) was null.
  HYA_ERR_NULL = 1,
  // An array's length is not the model's joint count (or its square, for a mass matrix).
  HYA_ERR_LENGTH = 2,
  // An input held NaN or an infinity; state is unchanged.
  HYA_ERR_NON_FINITE = 3,
  // A parameter is out of range (filter bandwidth, gain, sample time, ...), or a name is not
  // a shipped arm or not a frame of the model, or a model has more joints than hya dispatches
  // to, or an output overlaps an input or another output of the call.
  HYA_ERR_INVALID = 4,
  // A URDF or a friction file could not be read or is not valid.
  HYA_ERR_MODEL = 5,
  // A numerical failure: a singular mass matrix, an input beyond the filter's range.
  HYA_ERR_NUMERIC = 6,
  // A bug inside hya: a Rust panic, caught at the boundary.
  HYA_ERR_PANIC = 7,
  // A handle that is not a live handle of the kind the call takes: one of another kind (an
  // observer passed as a model), one already freed, or a pointer hya never made. Nothing was
  // read through it.
  HYA_ERR_HANDLE = 8,
} HyaStatus;

// Where the PD feedback enters the computed-torque law.
typedef enum {
  // The paper's form: torque-level PD, gains in N·m/rad and N·m·s/rad.
  HYA_PD_OUTSIDE_MASS_MATRIX = 0,
  // The classic form: acceleration-level PD, gains in 1/s² and 1/s.
  HYA_PD_INSIDE_MASS_MATRIX = 1,
} HyaPdPlacement;

// A Cartesian impedance controller (opaque). Made by `hya_cartesian_new`, freed by
// `hya_cartesian_free`.
typedef struct HyaCartesian HyaCartesian;

// A computed-torque controller (opaque). Made by `hya_controller_new`, freed by
// `hya_controller_free`.
typedef struct HyaController HyaController;

// The paper's disturbance estimator for one arm (opaque). Made by `hya_estimator_new`, freed by
// `hya_estimator_free`.
typedef struct HyaEstimator HyaEstimator;

// A robot's rigid-body dynamics (opaque). Made by `hya_model_from_arm` or
// `hya_model_from_urdf`, freed by `hya_model_free`.
typedef struct HyaModel HyaModel;

// A baseline disturbance observer (opaque). Made by one of `hya_observer_new_*`, freed by
// `hya_observer_free`.
typedef struct HyaObserver HyaObserver;

#ifdef __cplusplus
extern "C" {
#endif // __cplusplus

// `τ = M(q) q̈ + C(q, q̇) + G(q)` (N·m) at `count` states: `q` (rad), `qd` (rad/s), `qdd`
// (rad/s²) and `tau` hold `count × n` doubles, row-major, `n` = dof. As
// `hya_model_inverse_dynamics`, state by state.
//
// # Safety
// `model` is null or a live handle; each non-null array holds `count × n` doubles.
HyaStatus hya_model_inverse_dynamics_batch(HyaModel *model,
                                           const double *q,
                                           const double *qd,
                                           const double *qdd,
                                           size_t count,
                                           size_t n,
                                           double *tau);

// `G(q)` (N·m) at `count` states: `q` (rad) and `tau` hold `count × n` doubles, `n` = dof. As
// `hya_model_gravity`, state by state.
//
// # Safety
// `model` is null or a live handle; each non-null array holds `count × n` doubles.
HyaStatus hya_model_gravity_batch(HyaModel *model,
                                  const double *q,
                                  size_t count,
                                  size_t n,
                                  double *tau);

// `M(q)` (kg·m²) at `count` states: `q` holds `count × n` doubles (`n` = dof), `mass` `len` =
// `count × n²`, one symmetric matrix after another. As `hya_model_mass_matrix`, state by state.
//
// # Safety
// `model` is null or a live handle; `q` holds `count × n` doubles and `mass` `len`.
HyaStatus hya_model_mass_matrix_batch(HyaModel *model,
                                      const double *q,
                                      size_t count,
                                      size_t n,
                                      double *mass,
                                      size_t len);

// `q̈ = M(q)⁻¹ (τ − C(q, q̇) − G(q))` (rad/s²) at `count` states: `q`, `qd`, `tau` (N·m) and
// `qdd` hold `count × n` doubles, `n` = dof. As `hya_model_forward_dynamics`, state by state;
// `HYA_ERR_NUMERIC` at the first state whose mass matrix is not positive definite, named by
// its row (the rows before it written).
//
// # Safety
// `model` is null or a live handle; each non-null array holds `count × n` doubles.
HyaStatus hya_model_forward_dynamics_batch(HyaModel *model,
                                           const double *q,
                                           const double *qd,
                                           const double *tau,
                                           size_t count,
                                           size_t n,
                                           double *qdd);

// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` of forward dynamics at `count` states: `q`, `qd`, `tau` hold
// `count × n` doubles (`n` = dof); `out` holds `len` = `count × 3n²`: per state `∂q̈/∂q`
// (1/s²), `∂q̈/∂q̇` (1/s), `M⁻¹ = ∂q̈/∂τ` (1/(kg·m²)), each `n × n` row-major (row `i` is
// `∂q̈_i`), one after another. As `hya_model_forward_dynamics_derivatives`, state by state;
// `HYA_ERR_NUMERIC` at the first state whose mass matrix is not positive definite, named by
// its row (the rows before it written).
//
// # Safety
// `model` is null or a live handle; `q`, `qd`, `tau` hold `count × n` doubles and `out` `len`.
HyaStatus hya_model_forward_dynamics_derivatives_batch(HyaModel *model,
                                                       const double *q,
                                                       const double *qd,
                                                       const double *tau,
                                                       size_t count,
                                                       size_t n,
                                                       double *out,
                                                       size_t len);

// Makes a Cartesian impedance controller on `model`'s dynamics holding frame `frame` (any link
// of the description; null: the last link) with the spring `stiffness` (6 doubles: N/m for x,
// y, z, then N·m/rad) and damper `damping` (6: N·s/m, then N·m·s/rad), each finite and
// non-negative. With `posture_rest`, `posture_stiffness` and `posture_damping` (all three, or
// all null), the joints are held near the rest pose (rad) in the task's null space (N·m/rad,
// N·m·s/rad); `mu` (m, finite, ≥ 0; 1e-3 is a fair default) damps the null-space projector near
// singular poses; unless `torque_limit` is null, joint `i`'s command is saturated to
// `±torque_limit[i]` N·m (each finite and > 0). The posture and limit arrays hold `n` = dof
// doubles. A frame the model does not have is `HYA_ERR_INVALID`, the message listing its
// frames. On `HYA_OK`, `*out` is a new handle for `hya_cartesian_free`; otherwise null, and
// `hya_last_error` says why.
//
// # Safety
// `model` is null or a live handle; `frame` is null or a NUL-terminated string; `stiffness`
// and `damping` are null or hold 6 doubles; the posture and limit arrays are null or hold `n`
// doubles; `out` is null or writable.
HyaStatus hya_cartesian_new(const HyaModel *model,
                            const char *frame,
                            const double *stiffness,
                            const double *damping,
                            const double *posture_rest,
                            const double *posture_stiffness,
                            const double *posture_damping,
                            const double *torque_limit,
                            size_t n,
                            double mu,
                            HyaCartesian **out);

// The commanded torque `tau` (`n` = dof) at the measured `(q, qd)` for the frame's desired
// position `position_des` (3 doubles, m), orientation `orientation_des` (9 doubles: the 3 × 3
// rotation row-major, whose columns are the frame's desired axes in the base's) and twist
// `twist_des` (6 doubles: m/s, then rad/s; null: at rest) and, unless `d_hat` is null, the
// compensation `− d̂`. An orientation that is not a rotation is `HYA_ERR_INVALID`.
//
// # Safety
// `controller` is null or a live handle; `q`, `qd`, `d_hat` are null or hold `n` doubles, the
// reference arrays 3, 9 and 6.
HyaStatus hya_cartesian_command(HyaCartesian *controller,
                                const double *q,
                                const double *qd,
                                const double *position_des,
                                const double *orientation_des,
                                const double *twist_des,
                                const double *d_hat,
                                size_t n,
                                double *tau);

// The message of the controller's last failed call (empty if none); owned by the controller.
//
// # Safety
// `controller` is null or a live handle.
const char *hya_cartesian_error(const HyaCartesian *controller);

// Frees a Cartesian controller (null is a no-op).
//
// # Safety
// `controller` is null or a handle from `hya_cartesian_new`, not used afterwards.
void hya_cartesian_free(HyaCartesian *controller);

// Makes a controller on `model`'s dynamics with diagonal gains `kp`, `kd` (`n` = dof each,
// finite and non-negative) and the PD placement `placement` (an `HyaPdPlacement` value; any
// other is `HYA_ERR_INVALID`). On `HYA_OK`, `*out` is a new handle for `hya_controller_free`;
// otherwise null, and `hya_last_error` says why.
//
// # Safety
// `model` is null or a live handle; `kp`, `kd` are null or hold `n` doubles; `out` is null or
// writable.
HyaStatus hya_controller_new(const HyaModel *model,
                             const double *kp,
                             const double *kd,
                             size_t n,
                             uint32_t placement,
                             HyaController **out);

// The commanded torque `tau` for the state `(q, qd)`, the reference `(q_des, qd_des,
// qdd_des)` and, unless `d_hat` is null, the compensation `− d̂`; `n` = dof each.
//
// # Safety
// `controller` is null or a live handle; each non-null array holds `n` doubles.
HyaStatus hya_controller_command(HyaController *controller,
                                 const double *q,
                                 const double *qd,
                                 const double *q_des,
                                 const double *qd_des,
                                 const double *qdd_des,
                                 const double *d_hat,
                                 size_t n,
                                 double *tau);

// The message of the controller's last failed call (empty if none); owned by the controller.
//
// # Safety
// `controller` is null or a live handle.
const char *hya_controller_error(const HyaController *controller);

// Frees a controller (null is a no-op).
//
// # Safety
// `controller` is null or a handle from `hya_controller_new`, not used afterwards.
void hya_controller_free(HyaController *controller);

// Makes an estimator on `model`'s dynamics with filter damping `zeta`, bandwidths `omega1`
// (position filter, rad/s) and `omega2` (rad/s), sample time `dt` (s), started at rest at
// `(q0, tau0)` (`n` = dof each). The paper uses `zeta = 0.8`, `omega1 = omega2 = 50`.
// On `HYA_OK`, `*out` is a new handle for `hya_estimator_free`; otherwise null, and
// `hya_last_error` says why.
//
// # Safety
// `model` is null or a live handle; `q0`, `tau0` are null or hold `n` doubles; `out` is null or
// writable.
HyaStatus hya_estimator_new(const HyaModel *model,
                            double zeta,
                            double omega1,
                            double omega2,
                            double dt,
                            const double *q0,
                            const double *tau0,
                            size_t n,
                            HyaEstimator **out);

// Makes an estimator for samples with their own timestamps (logs, loops whose period jitters):
// each update brings its time `t` (s) and both filters advance exactly over that step's own
// length (first-order hold), the discretisations of recent lengths cached. `dt` is the nominal
// sample time (the first length cached); the estimator starts at rest at `(t0, q0, tau0)` (`n` =
// dof each). A step longer than `100 / max(omega1, omega2)` s (2 s at the paper's 50 rad/s)
// restarts it at rest instead of bridging. Update it with `hya_estimator_update_at` only.
//
// # Safety
// As `hya_estimator_new`.
HyaStatus hya_estimator_new_timed(const HyaModel *model,
                                  double zeta,
                                  double omega1,
                                  double omega2,
                                  double dt,
                                  double t0,
                                  const double *q0,
                                  const double *tau0,
                                  size_t n,
                                  HyaEstimator **out);

// The sample at time `t` (s, after the previous sample's): measured `q` and `tau` (`n` = dof
// each) in, the new `d̂` (N·m) out; `*restarted` (unless null) says whether the step was a gap
// too long to bridge, after which the estimator restarted at rest. For estimators made by
// `hya_estimator_new_timed`. A refused sample (a time not after the previous one, NaN, wrong
// length) leaves the estimator as it was.
//
// # Safety
// `estimator` is null or a live handle; each non-null array holds `n` doubles; `restarted` is null or writable.
HyaStatus hya_estimator_update_at(HyaEstimator *estimator,
                                  double t,
                                  const double *q,
                                  const double *tau,
                                  size_t n,
                                  double *d_hat,
                                  bool *restarted);

// One step of the sample time `dt`: measured `q` and `tau` (`n` = dof each) in, the new `d̂`
// (N·m) out. For estimators made by `hya_estimator_new`. A refused step
// (NaN, wrong length) leaves the estimator as it was.
//
// # Safety
// `estimator` is null or a live handle; each non-null array holds `n` doubles.
HyaStatus hya_estimator_update(HyaEstimator *estimator,
                               const double *q,
                               const double *tau,
                               size_t n,
                               double *d_hat);

// The latest `d̂` (N·m), `n` = dof entries.
//
// # Safety
// `estimator` is null or a live handle; `d_hat` is null or holds `n` doubles.
HyaStatus hya_estimator_disturbance(HyaEstimator *estimator, double *d_hat, size_t n);

// Restarts the estimator at rest at `(q0, tau0)` (`n` = dof each); a timed one at its latest
// sample's time.
//
// # Safety
// `estimator` is null or a live handle; each non-null array holds `n` doubles.
HyaStatus hya_estimator_reset(HyaEstimator *estimator,
                              const double *q0,
                              const double *tau0,
                              size_t n);

// The message of the estimator's last failed call (empty if none); owned by the estimator.
//
// # Safety
// `estimator` is null or a live handle.
const char *hya_estimator_error(const HyaEstimator *estimator);

// Frees an estimator (null is a no-op).
//
// # Safety
// `estimator` is null or a handle from `hya_estimator_new`, not used afterwards.
void hya_estimator_free(HyaEstimator *estimator);

// Makes a model of the shipped arm called `name` (`"hya"`, `"ur5"`, `"panda"`, `"iiwa14"`,
// `"planar2"`; see `hya_arm_name`): its generated, unrolled dynamics. On `HYA_OK`, `*out` is a
// new handle for `hya_model_free`; otherwise `*out` is null and `hya_last_error` says why.
//
// # Safety
// `name` is null or a NUL-terminated string; `out` is null or writable.
HyaStatus hya_model_from_arm(const char *name, HyaModel **out);

// Loads the URDF file at `path` as a run-time kinematic-tree model (1 to 7 joints). On `HYA_OK`,
// `*out` is a new handle for `hya_model_free`; otherwise `*out` is null and `hya_last_error`
// names the file and the problem in it.
//
// # Safety
// `path` is null or a NUL-terminated string; `out` is null or writable.
HyaStatus hya_model_from_urdf(const char *path, HyaModel **out);

// Makes a new model: `model` with the joint law that `hya identify` wrote to the file at `path`
// (`friction.toml`: Coulomb, viscous and offset per joint, and the armature `I_a` where it has
// one). Its inverse dynamics is `ID(q, q̇, q̈) + τ_f(q̇) + I_a q̈` and its mass matrix
// `M(q) + diag(I_a)`, so estimators made from it estimate what the law leaves unexplained, as
// `hya estimate --friction` does, and controllers made from it feed the law forward at the
// measured velocity. `model` is unchanged. On `HYA_OK`, `*out` is a new handle for
// `hya_model_free`; otherwise `*out` is null and `hya_last_error` names the file, the key and
// the value (a list of the wrong length for this model's joints, a value out of its plausible
// range).
//
// # Safety
// `model` is null or a live handle; `path` is null or a NUL-terminated string; `out` is null or
// writable.
HyaStatus hya_model_with_friction(const HyaModel *model, const char *path, HyaModel **out);

// Frees a model (null is a no-op). Estimators, observers and controllers made from it stay
// valid.
//
// # Safety
// `model` is null or a handle from `hya_model_from_*`, not used afterwards.
void hya_model_free(HyaModel *model);

// The model's joint count, or 0 for a null handle.
//
// # Safety
// `model` is null or a live handle.
size_t hya_model_dof(const HyaModel *model);

// The message of the model's last failed call (empty if none); owned by the model.
//
// # Safety
// `model` is null or a live handle.
const char *hya_model_error(const HyaModel *model);

// Inverse dynamics `τ = M(q) q̈ + C(q, q̇) + G(q)`; every array has `n` = dof entries.
// `HYA_ERR_NUMERIC` if a torque is not finite (inputs too large for double precision).
//
// # Safety
// `model` is null or a live handle; each non-null array holds `n` doubles.
HyaStatus hya_model_inverse_dynamics(HyaModel *model,
                                     const double *q,
                                     const double *qd,
                                     const double *qdd,
                                     size_t n,
                                     double *tau);

// The mass matrix `M(q)`: `q` has `n` = dof entries, `mass` has `len` = dof² (symmetric, so
// row- and column-major agree).
//
// # Safety
// `model` is null or a live handle; `q` holds `n` doubles and `mass` `len`.
HyaStatus hya_model_mass_matrix(HyaModel *model,
                                const double *q,
                                size_t n,
                                double *mass,
                                size_t len);

// The gravity torque `G(q)`; both arrays have `n` = dof entries.
//
// # Safety
// `model` is null or a live handle; each non-null array holds `n` doubles.
HyaStatus hya_model_gravity(HyaModel *model, const double *q, size_t n, double *tau);

// Forward dynamics `q̈ = M(q)⁻¹ (τ − C(q, q̇) − G(q))`; every array has `n` = dof entries.
// `HYA_ERR_NUMERIC` if `M(q)` is not positive definite.
//
// # Safety
// `model` is null or a live handle; each non-null array holds `n` doubles.
HyaStatus hya_model_forward_dynamics(HyaModel *model,
                                     const double *q,
                                     const double *qd,
                                     const double *tau,
                                     size_t n,
                                     double *qdd);

// `(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)` of forward dynamics at `(q, q̇, τ)`: `q`, `qd`, `tau` have `n` = dof
// entries, `dqdd_dq`, `dqdd_dqd` and `mass_inverse` `len` = dof² each, row-major (row `i` is
// `∂q̈_i`): `−M⁻¹ ∂ID/∂q` and `−M⁻¹ ∂ID/∂q̇` at `q̈ = FD(q, q̇, τ)`, and `M⁻¹ = ∂q̈/∂τ`.
// `HYA_ERR_NUMERIC` if `M(q)` is not positive definite.
//
// The three outputs must lie apart from each other and from the inputs (`HYA_ERR_INVALID` if
// two share an address). Allocates on a URDF model (run-time code).
//
// # Safety
// `model` is null or a live handle; `q`, `qd`, `tau` hold `n` doubles and each output `len`.
HyaStatus hya_model_forward_dynamics_derivatives(HyaModel *model,
                                                 const double *q,
                                                 const double *qd,
                                                 const double *tau,
                                                 size_t n,
                                                 double *dqdd_dq,
                                                 double *dqdd_dqd,
                                                 double *mass_inverse,
                                                 size_t len);

// The geometric Jacobian of frame `frame` (any link of the description) at `q` (`n` = dof):
// `jacobian` holds `len` = 6 × dof doubles, row-major, rows 0–2 mapping `q̇` to the linear
// velocity of the frame's origin and rows 3–5 to its angular velocity, both in the base's axes
// (Pinocchio's `LOCAL_WORLD_ALIGNED`). `HYA_ERR_INVALID` for a frame the model does not have
// (the message lists its frames). Allocates (run-time code).
//
// # Safety
// `model` is null or a live handle; `frame` is null or a NUL-terminated string; `q` holds `n`
// doubles and `jacobian` `len`.
HyaStatus hya_model_frame_jacobian(HyaModel *model,
                                   const char *frame,
                                   const double *q,
                                   size_t n,
                                   double *jacobian,
                                   size_t len);

// `J̇(q, q̇) q̇` of frame `frame`: `bias` holds 6 doubles, the classical acceleration of the
// frame's origin (m/s²) and its angular acceleration (rad/s²) at `q̈ = 0`, in the base's axes
// (`q` and `qd` have `n` = dof entries). `HYA_ERR_INVALID` for a frame the model does not have
// (the message lists its frames). Allocates (run-time code).
//
// # Safety
// `model` is null or a live handle; `frame` is null or a NUL-terminated string; `q` and `qd`
// hold `n` doubles and `bias` `len`.
HyaStatus hya_model_frame_acceleration_bias(HyaModel *model,
                                            const char *frame,
                                            const double *q,
                                            const double *qd,
                                            size_t n,
                                            double *bias,
                                            size_t len);

// The number of shipped arms (for `hya_arm_name`).
size_t hya_arm_count(void);

// The name of shipped arm `index` (a static string), or null beyond `hya_arm_count()`.
const char *hya_arm_name(size_t index);

// The home pose of the shipped arm called `name` (rad, `n` = its joint count): a pose inside its
// joint limits, where the examples start.
//
// # Safety
// `name` is null or a NUL-terminated string; `q` is null or holds `n` doubles.
HyaStatus hya_arm_home(const char *name, double *q, size_t n);

// This thread's last error: the message of the last failed creation, or of a call given a
// null handle. Owned by hya; valid until the next hya call on this thread.
const char *hya_last_error(void);

// Chen's nonlinear disturbance observer (IEEE TIE 2000) with Mohammadi's gain `Y = gain · I`:
// `d̂̇ = Y M⁻¹(q) (d − d̂)`, stepped implicitly at `dt` (s), started at `qd0` (`n` = dof). Its
// updates need the measured `qd`.
//
// # Safety
// `model` is null or a live handle; `qd0` is null or holds `n` doubles; `out` is null or
// writable.
HyaStatus hya_observer_new_nonlinear(const HyaModel *model,
                                     double gain,
                                     double dt,
                                     const double *qd0,
                                     size_t n,
                                     HyaObserver **out);

// The generalised-momentum observer (De Luca; Haddadin 2017) with per-joint gains `gain` (1/s):
// `d̂ / d = k / (s + k)` per joint, at `dt` (s), started at `(q0, qd0, tau0)`; every array has
// `n` = dof entries. Its updates need the measured `qd`.
//
// # Safety
// `model` is null or a live handle; each non-null array holds `n` doubles; `out` is null or
// writable.
HyaStatus hya_observer_new_momentum(const HyaModel *model,
                                    const double *gain,
                                    double dt,
                                    const double *q0,
                                    const double *qd0,
                                    const double *tau0,
                                    size_t n,
                                    HyaObserver **out);

// The extended-state observer (Han; Gao) of bandwidth `bandwidth` (rad/s): `d̂ / d = ω³ / (s +
// ω)³` per joint, at `dt` (s), started at `q0` (`n` = dof). Needs no measured velocity.
//
// # Safety
// `model` is null or a live handle; `q0` is null or holds `n` doubles; `out` is null or
// writable.
HyaStatus hya_observer_new_extended_state(const HyaModel *model,
                                          double bandwidth,
                                          double dt,
                                          const double *q0,
                                          size_t n,
                                          HyaObserver **out);

// One tick: measured `q`, `qd` (null if not measured; the nonlinear and momentum observers
// need it) and `tau` in, the new `d̂` (N·m) out; `n` = dof each. A refused tick leaves the
// observer as it was.
//
// # Safety
// `observer` is null or a live handle; each non-null array holds `n` doubles.
HyaStatus hya_observer_update(HyaObserver *observer,
                              const double *q,
                              const double *qd,
                              const double *tau,
                              size_t n,
                              double *d_hat);

// The message of the observer's last failed call (empty if none); owned by the observer.
//
// # Safety
// `observer` is null or a live handle.
const char *hya_observer_error(const HyaObserver *observer);

// Frees an observer (null is a no-op).
//
// # Safety
// `observer` is null or a handle from `hya_observer_new_*`, not used afterwards.
void hya_observer_free(HyaObserver *observer);

#ifdef __cplusplus
}  // extern "C"
#endif  // __cplusplus

#endif  /* HYA_H */
