#include "disturbance_rejection_controller.hpp"

using Result = DisturbanceRejectionController::Result;

Result DisturbanceRejectionController::configure(const Params& params, JointInterfaces& interfaces) {
  params_ = params;
  interfaces_ = &interfaces;
  HyaModel* model = nullptr;
  hya::created(hya_model_from_arm(params.arm.c_str(), &model), "model " + params.arm);
  model_.reset(model);
  dof_ = hya_model_dof(model);
  d_hat_.assign(dof_, 0.0);

  const std::vector<double> kp(dof_, params.kp), kd(dof_, params.kd);
  HyaController* controller = nullptr;
  hya::created(hya_controller_new(model, kp.data(), kd.data(), dof_, HYA_PD_INSIDE_MASS_MATRIX, &controller),
               "controller");
  controller_.reset(controller);
  for (auto* v : {&interfaces.position, &interfaces.velocity, &interfaces.effort, &interfaces.command}) {
    v->assign(dof_, 0.0);
  }
  return Result::kOk;
}

Result DisturbanceRejectionController::activate(double time) {
  HyaEstimator* estimator = nullptr;
  const double* q = interfaces_->position.data();
  const double* tau = interfaces_->effort.data();
  const double zeta = params_.zeta, omega = params_.omega, dt = params_.period;
  hya::created(params_.timestamps
                   ? hya_estimator_new_timed(model_.get(), zeta, omega, omega, dt, time, q, tau, dof_, &estimator)
                   : hya_estimator_new(model_.get(), zeta, omega, omega, dt, q, tau, dof_, &estimator),
               "estimator");
  estimator_.reset(estimator);
  d_hat_.assign(dof_, 0.0);
  if (hya_model_gravity(model_.get(), interfaces_->position.data(), dof_, interfaces_->command.data()) != HYA_OK) {
    return fail(hya_model_error(model_.get()));
  }
  return Result::kOk;
}

// With timestamps, a late period is filtered over its true length (with its own discretisation,
// cached for lengths that recur), not as if it had been on time.
Result DisturbanceRejectionController::update(double time, double /*period*/, const Reference& reference) {
  JointInterfaces& io = *interfaces_;
  const double *q = io.position.data(), *tau = io.effort.data();
  const HyaStatus estimated = params_.timestamps
                                  ? hya_estimator_update_at(estimator_.get(), time, q, tau, dof_, d_hat_.data(), nullptr)
                                  : hya_estimator_update(estimator_.get(), q, tau, dof_, d_hat_.data());
  if (estimated != HYA_OK) {
    return fail(hya_estimator_error(estimator_.get()));
  }
  const double* d_hat = params_.compensate ? d_hat_.data() : nullptr;
  if (hya_controller_command(controller_.get(), io.position.data(), io.velocity.data(), reference.position.data(),
                             reference.velocity.data(), reference.acceleration.data(), d_hat, dof_,
                             io.command.data()) != HYA_OK) {
    return fail(hya_controller_error(controller_.get()));
  }
  return Result::kOk;
}

Result DisturbanceRejectionController::fail(const char* message) {
  error_ = message;  // may allocate: the loop stops on an error anyway
  return Result::kError;
}
