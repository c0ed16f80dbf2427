// The arm the loop drives: the shipped arm's rigid-body dynamics (through hya's forward
// dynamics) plus what its model does not know, joint friction and a load that appears at
// t = 1 s:
//
//   M(q) q̈ + C(q, q̇) + G(q) = τ + d,   d = −f_v q̇ − f_c tanh(q̇ / 0.01) + τ_load(t)
//
// integrated semi-implicitly (q̇ first, then q) in substeps of at most 0.1 ms. It reports
// the applied torque τ as the measured effort, as a torque-controlled arm's drives do, and the
// true d for comparison with the estimate.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "hya.hpp"

class SimulatedArm {
 public:
  SimulatedArm(const std::string& arm, std::vector<double> q0) : q_(std::move(q0)) {
    HyaModel* model = nullptr;
    hya::created(hya_model_from_arm(arm.c_str(), &model), "simulated " + arm);
    model_.reset(model);
    const size_t n = q_.size();
    qd_.assign(n, 0.0);
    tau_.assign(n, 0.0);
    d_.assign(n, 0.0);
    qdd_.assign(n, 0.0);
    drive_.assign(n, 0.0);
    // Friction and load shrink from the shoulder to the wrist, as joint sizes do.
    for (size_t i = 0; i < n; ++i) {
      const double size = 1.0 / (1.0 + static_cast<double>(i));
      viscous_.push_back(2.0 * size);
      coulomb_.push_back(3.0 * size);
      load_.push_back(6.0 * size * (i % 2 == 0 ? 1.0 : -1.0));
    }
  }

  void read(std::vector<double>& q, std::vector<double>& qd, std::vector<double>& effort) const {
    q = q_;
    qd = qd_;
    effort = tau_;
  }

  // Applies `tau` for `dt` seconds from time `t`; false (with the reason) if the dynamics fail.
  bool step(const std::vector<double>& tau, double t, double dt, std::string& why) {
    tau_ = tau;
    const int substeps = static_cast<int>(std::ceil(dt / 1e-4 - 1e-9));
    const double h = dt / substeps;
    for (int s = 0; s < substeps; ++s) {
      disturbance(t + s * h);
      for (size_t i = 0; i < q_.size(); ++i) {
        drive_[i] = tau_[i] + d_[i];
      }
      if (hya_model_forward_dynamics(model_.get(), q_.data(), qd_.data(), drive_.data(), q_.size(), qdd_.data()) !=
          HYA_OK) {
        why = hya_model_error(model_.get());
        return false;
      }
      for (size_t i = 0; i < q_.size(); ++i) {
        qd_[i] += h * qdd_[i];
        q_[i] += h * qd_[i];
      }
    }
    return true;
  }

  // The disturbance d acting now (friction at the current velocity, the load from t = 1 s).
  const std::vector<double>& true_disturbance(double t) {
    disturbance(t);
    return d_;
  }

 private:
  void disturbance(double t) {
    for (size_t i = 0; i < q_.size(); ++i) {
      d_[i] = -viscous_[i] * qd_[i] - coulomb_[i] * std::tanh(qd_[i] / 0.01) + (t >= 1.0 ? load_[i] : 0.0);
    }
  }

  hya::Model model_;
  std::vector<double> q_, qd_, tau_, d_, qdd_, drive_;
  std::vector<double> viscous_, coulomb_, load_;
};
