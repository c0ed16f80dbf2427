// Times Pinocchio's rnea, crba and aba on a URDF, the same way `hya bench` times hya:
// the median over 31 rounds of the mean time per call within a round of 2000 calls cycling
// through 64 pseudo-random states (q in ±π, v in ±2, a and τ in ±5). Prints one JSON object.
// Written for hya; built by tools/pinocchio_bench.sh against the `pin` wheel.
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/parsers/urdf.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

namespace {
constexpr int kRounds = 31;
constexpr int kCalls = 2000;
constexpr int kStates = 64;

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

// Keeps a value alive without letting the compiler fold the work away.
template <typename T>
void keep(T const& value) {
  asm volatile("" : : "g"(&value) : "memory");
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: pinocchio_bench ROBOT_NAME ROBOT.urdf\n";
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
  std::cout << "{\"robot\": \"" << argv[1] << "\", \"rnea_ns\": " << rnea << ", \"crba_ns\": " << crba
            << ", \"aba_ns\": " << aba << "}" << std::endl;
  return 0;
}
