// Times Pinocchio's rnea, crba and aba on a URDF, the same way `hya bench` times hya:
// the median over 31 rounds of the mean time per call within a round of 2000 calls cycling
// through 64 pseudo-random states (q in ±π, v in ±2, a and τ in ±5). Batches, as `hya bench`
// times its batch calls: 1024 states per call (the 64 repeated), 8 calls per round, ns per
// state: rnea in a loop, and rneaInParallel (OpenMP over a pool of model copies) on one thread
// and on every core. With a frame name (a link), also computeFrameJacobian of that frame
// (LOCAL_WORLD_ALIGNED) and the analytic derivatives computeRNEADerivatives and
// computeABADerivatives. Prints one JSON object.
// Written for hya; built by tools/pinocchio_bench.sh against the `pin` wheel.
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/parallel/rnea.hpp>
#include <pinocchio/parsers/urdf.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

namespace {
constexpr int kRounds = 31;
constexpr int kCalls = 2000;
constexpr int kStates = 64;
constexpr int kBatch = 1024;
constexpr int kBatchCalls = 8;

template <typename F>
double median_ns(F&& f) {
  std::vector<double> rounds;
  for (int r = 0; r < kRounds; ++r) {
    auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < kCalls; ++k) f(k % kStates);
    std::chrono::duration<double, std::nano> elapsed = std::chrono::steady_clock::now() - start;
    rounds.push_back(elapsed.count() / kCalls);
  }
  std::nth_element(rounds.begin(), rounds.begin() + kRounds / 2, rounds.end());
  return rounds[kRounds / 2];
}

// Median over rounds of the mean ns per state of `f()`, one call over kBatch states.
template <typename F>
double median_batch_ns(F&& f) {
  std::vector<double> rounds;
  for (int r = 0; r < kRounds; ++r) {
    auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < kBatchCalls; ++k) f();
    std::chrono::duration<double, std::nano> elapsed = std::chrono::steady_clock::now() - start;
    rounds.push_back(elapsed.count() / (kBatchCalls * kBatch));
  }
  std::nth_element(rounds.begin(), rounds.begin() + kRounds / 2, rounds.end());
  return rounds[kRounds / 2];
}

// Keeps a value alive without letting the compiler fold the work away.
template <typename T>
void keep(T const& value) {
  asm volatile("" : : "g"(&value) : "memory");
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::cerr << "usage: pinocchio_bench ROBOT_NAME ROBOT.urdf [FRAME]\n";
    return 2;
  }
  pinocchio::Model model;
  pinocchio::urdf::buildModel(argv[2], model);
  pinocchio::Data data(model);
  std::uint64_t seed = 0x9e3779b97f4a7c15ULL;
  auto next = [&seed](double scale) {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return scale * (static_cast<double>(seed >> 11) / static_cast<double>(1ULL << 53) * 2.0 - 1.0);
  };
  std::vector<Eigen::VectorXd> q(kStates), v(kStates), a(kStates);
  for (int k = 0; k < kStates; ++k) {
    Eigen::VectorXd angles(model.nv), config = pinocchio::neutral(model);
    for (int i = 0; i < model.nv; ++i) angles[i] = next(3.141592653589793);
    // Revolute joints with limits have nq == nv; continuous ones take (cos, sin).
    for (pinocchio::JointIndex j = 1; j < model.joints.size(); ++j) {
      auto const& joint = model.joints[j];
      double value = angles[joint.idx_v()];
      if (joint.nq() == 2) {
        config[joint.idx_q()] = std::cos(value);
        config[joint.idx_q() + 1] = std::sin(value);
      } else {
        config[joint.idx_q()] = value;
      }
    }
    q[k] = config;
    v[k] = Eigen::VectorXd(model.nv);
    a[k] = Eigen::VectorXd(model.nv);
    for (int i = 0; i < model.nv; ++i) v[k][i] = next(2.0);
    for (int i = 0; i < model.nv; ++i) a[k][i] = next(5.0);
  }
  double rnea = median_ns([&](int k) { keep(pinocchio::rnea(model, data, q[k], v[k], a[k])); });
  double crba = median_ns([&](int k) { keep(pinocchio::crba(model, data, q[k])); });
  double aba = median_ns([&](int k) { keep(pinocchio::aba(model, data, q[k], v[k], a[k])); });
  // Batches: states as columns.
  Eigen::MatrixXd qs(model.nq, kBatch), vs(model.nv, kBatch), as(model.nv, kBatch), taus(model.nv, kBatch);
  for (int k = 0; k < kBatch; ++k) {
    qs.col(k) = q[k % kStates];
    vs.col(k) = v[k % kStates];
    as.col(k) = a[k % kStates];
  }
  double rnea_loop = median_batch_ns([&] {
    for (int k = 0; k < kBatch; ++k) taus.col(k) = pinocchio::rnea(model, data, qs.col(k), vs.col(k), as.col(k));
    keep(taus);
  });
  int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  pinocchio::ModelPool pool(model, cores);
  auto parallel = [&](int threads) {
    return median_batch_ns([&] {
      pinocchio::rneaInParallel(static_cast<size_t>(threads), pool, qs, vs, as, taus);
      keep(taus);
    });
  };
  double parallel_one = parallel(1);
  double parallel_all = parallel(cores);
  std::string kinematics;
  if (argc == 4) {
    if (!model.existFrame(argv[3], pinocchio::BODY)) {
      std::cerr << "no frame " << argv[3] << " in " << argv[2] << "\n";
      return 2;
    }
    auto frame = model.getFrameId(argv[3], pinocchio::BODY);
    pinocchio::Data::Matrix6x jacobian = pinocchio::Data::Matrix6x::Zero(6, model.nv);
    double frame_jacobian = median_ns([&](int k) {
      pinocchio::computeFrameJacobian(model, data, q[k], frame, pinocchio::LOCAL_WORLD_ALIGNED, jacobian);
      keep(jacobian);
    });
    Eigen::MatrixXd by_q = Eigen::MatrixXd::Zero(model.nv, model.nv), by_v = by_q, by_a = by_q;
    double rnea_derivatives = median_ns([&](int k) {
      pinocchio::computeRNEADerivatives(model, data, q[k], v[k], a[k], by_q, by_v, by_a);
      keep(by_q);
    });
    double aba_derivatives = median_ns([&](int k) {
      pinocchio::computeABADerivatives(model, data, q[k], v[k], a[k], by_q, by_v, by_a);
      keep(by_q);
    });
    kinematics = ", \"frame\": \"" + std::string(argv[3]) + "\", \"compute_frame_jacobian_ns\": " +
                 std::to_string(frame_jacobian) + ", \"compute_rnea_derivatives_ns\": " +
                 std::to_string(rnea_derivatives) + ", \"compute_aba_derivatives_ns\": " +
                 std::to_string(aba_derivatives);
  }
  std::cout << "{\"robot\": \"" << argv[1] << "\", \"rnea_ns\": " << rnea << ", \"crba_ns\": " << crba
            << ", \"aba_ns\": " << aba << ", \"rnea_loop_ns_per_state\": " << rnea_loop
            << ", \"rnea_parallel_1_ns_per_state\": " << parallel_one << ", \"rnea_parallel_threads\": " << cores
            << ", \"rnea_parallel_all_ns_per_state\": " << parallel_all << kinematics << "}" << std::endl;
  return 0;
}
