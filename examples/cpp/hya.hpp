// C++ ownership for hya's C handles: each handle in a std::unique_ptr whose deleter is the
// matching hya_*_free, and a check that turns a failed creation into an exception (creation
// happens in configure, outside the real-time loop; per-period calls return their status).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "hya.h"

namespace hya {

struct ModelFree {
  void operator()(HyaModel* m) const { hya_model_free(m); }
};
struct EstimatorFree {
  void operator()(HyaEstimator* e) const { hya_estimator_free(e); }
};
struct ControllerFree {
  void operator()(HyaController* c) const { hya_controller_free(c); }
};

using Model = std::unique_ptr<HyaModel, ModelFree>;
using Estimator = std::unique_ptr<HyaEstimator, EstimatorFree>;
using Controller = std::unique_ptr<HyaController, ControllerFree>;

// Throws with hya's message if a creation call failed.
inline void created(HyaStatus status, const std::string& what) {
  if (status != HYA_OK) {
    throw std::runtime_error(what + ": " + hya_last_error());
  }
}

}  // namespace hya
