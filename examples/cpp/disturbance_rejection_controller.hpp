// A controller shaped like a ros2_control controller (configure, activate, update(time,
// period)), running the paper's disturbance estimator and computed-torque control through
// hya's C ABI:
//
//   d̂ = ID(q̂, q̂̇, q̂̈) − τ̂                                  estimator (Lu, Sandy & Buchli)
//   τ = M(q) (q̈_des − K_D ė − K_P e) + C(q, q̇) + G(q) − d̂     controller, e = q − q_des
//
// Like a ros2_control controller it reads state interfaces (joint position, velocity and
// measured effort) and writes a command interface (effort) that the hardware layer owns; here
// they are plain arrays. configure() and activate() may allocate; update() does not.
#pragma once

#include <string>
#include <vector>

#include "hya.hpp"

// What a hardware layer exposes per joint, as ros2_control's state and command interfaces.
struct JointInterfaces {
  std::vector<double> position;  // state: rad
  std::vector<double> velocity;  // state: rad/s
  std::vector<double> effort;    // state: measured (or last commanded) torque, N·m
  std::vector<double> command;   // command: torque, N·m
};

// The desired motion at one instant.
struct Reference {
  std::vector<double> position, velocity, acceleration;
};

class DisturbanceRejectionController {
 public:
  struct Params {
    std::string arm = "panda";  // a shipped arm's name (hya_arm_name)
    double kp = 400.0;          // 1/s², the same on every joint
    double kd = 40.0;           // 1/s
    double zeta = 0.8;          // filter damping (the paper's)
    double omega = 50.0;        // filter bandwidth, rad/s (the paper's)
    double period = 1e-3;       // s
    bool compensate = true;     // subtract d̂ from the command
    bool timestamps = true;     // filter each period over its measured length (false: as `period`)
  };

  enum class Result { kOk, kError };

  // Makes the model, the estimator and the controller; throws with hya's message on failure.
  Result configure(const Params& params, JointInterfaces& interfaces);
  // Starts the estimator at rest at the current measurement, at `time` (s), and commands the
  // gravity torque G(q) until the first update.
  Result activate(double time);
  // One period at `time` (s, the sample's timestamp): estimate d̂ from the measured q and τ
  // (with `timestamps`, the filters advance over the time since the previous update, however
  // long it really was; without, over the configured period), then command τ. No allocation.
  Result update(double time, double period, const Reference& reference);

  size_t joints() const { return dof_; }
  const std::vector<double>& disturbance_estimate() const { return d_hat_; }
  // The message of the last failed call.
  std::string error() const { return error_; }

 private:
  Result fail(const char* message);

  Params params_;
  JointInterfaces* interfaces_ = nullptr;
  hya::Model model_;
  hya::Estimator estimator_;
  hya::Controller controller_;
  size_t dof_ = 0;
  std::vector<double> d_hat_;
  std::string error_;
};
