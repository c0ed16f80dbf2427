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

Result DisturbanceRejectionController::activate() {
  HyaEstimator* estimator = nullptr;
  hya::created(hya_estimator_new(model_.get(), params_.zeta, params_.omega, params_.omega, params_.period,
                                 interfaces_->position.data(), interfaces_->effort.data(), dof_, &estimator),
               "estimator");
  estimator_.reset(estimator);
  d_hat_.assign(dof_, 0.0);
  return Result::kOk;
}

// The estimator is discretised for the configured period: a late period is filtered as if it had
// been on time (the loop counts them), as a fixed-rate controller does.
Result DisturbanceRejectionController::update(double /*time*/, double /*period*/, const Reference& reference) {
  JointInterfaces& io = *interfaces_;
  if (hya_estimator_update(estimator_.get(), io.position.data(), io.effort.data(), dof_, d_hat_.data()) != HYA_OK) {
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
