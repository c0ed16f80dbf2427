// A fixed-rate 1 kHz loop in C++ around hya's C ABI: the paper's disturbance estimator and
// computed-torque control (disturbance_rejection_controller.cpp) drive a simulated arm with
// friction and a load it does not model (simulated_arm.hpp).
//
// The loop sleeps to absolute deadlines (clock_nanosleep on CLOCK_MONOTONIC, TIMER_ABSTIME), so
// a late wake-up does not shift the following ones. As on a robot, the arm moves under the last
// command for as long as each period really lasted, and the estimator steps by the samples'
// timestamps (hya_estimator_update_at), so a late period is filtered over its true length. It
// prints:
//   - the period's jitter: |measured period − 1 ms| (median, p99, max) and the wake-up latency
//     after each deadline;
//   - the cost of one controller update (estimator + controller through the ABI; median, p99),
//     in the paced loop and back to back (caches warm, the CPU not idling between calls);
//   - tracking with and without d̂ (the run without d̂ is the same loop, unpaced);
// and exits 1 if the estimator does not follow the disturbance or compensation does not help.
//
//   examples/cpp/build.sh && target/release/hya_cpp_loop [--arm panda] [--seconds 3] [--fifo] [--fixed-step]
//
// --fixed-step filters every period as if it had lasted 1 ms (hya_estimator_update): cheaper, as
// no period needs a discretisation of its own, and wrong by the period's jitter.

#include <sched.h>
#include <sys/mman.h>
#include <sys/utsname.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "disturbance_rejection_controller.hpp"
#include "simulated_arm.hpp"

namespace {

constexpr double kPeriod = 1e-3;
constexpr long kPeriodNs = 1000000;

struct Options {
  std::string arm = "panda";
  double seconds = 3.0;
  bool fifo = false;
  bool fixed_step = false;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--arm" && i + 1 < argc) {
      o.arm = argv[++i];
    } else if (a == "--seconds" && i + 1 < argc) {
      o.seconds = std::atof(argv[++i]);
    } else if (a == "--fifo") {
      o.fifo = true;
    } else if (a == "--fixed-step") {
      o.fixed_step = true;
    } else {
      std::fprintf(stderr, "usage: %s [--arm NAME] [--seconds S] [--fifo] [--fixed-step]\n", argv[0]);
      std::exit(2);
    }
  }
  if (!(o.seconds >= 1.5 && o.seconds <= 600.0)) {
    std::fprintf(stderr, "--seconds must be between 1.5 and 600 (the load arrives at 1 s)\n");
    std::exit(2);
  }
  return o;
}

long long now_ns() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<long long>(t.tv_sec) * 1000000000LL + t.tv_nsec;
}

void advance(timespec& t, long ns) {
  t.tv_nsec += ns;
  while (t.tv_nsec >= 1000000000L) {
    t.tv_nsec -= 1000000000L;
    ++t.tv_sec;
  }
}

long long to_ns(const timespec& t) { return static_cast<long long>(t.tv_sec) * 1000000000LL + t.tv_nsec; }

// The q-th quantile (0..1) of `v` in microseconds, nearest rank.
double quantile_us(std::vector<long long> v, double q) {
  std::sort(v.begin(), v.end());
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1);
  return static_cast<double>(v[k]) / 1000.0;
}

// q_des = q0 + A (1 − cos ωt) / 2 per joint, from rest, with its derivatives.
void reference_at(double t, const std::vector<double>& q0, Reference& r) {
  for (size_t i = 0; i < q0.size(); ++i) {
    const double a = 0.3 / (1.0 + 0.3 * static_cast<double>(i));
    const double w = 2.0 * M_PI * (0.4 + 0.1 * static_cast<double>(i));
    r.position[i] = q0[i] + a * (1.0 - std::cos(w * t)) / 2.0;
    r.velocity[i] = a * w * std::sin(w * t) / 2.0;
    r.acceleration[i] = a * w * w * std::cos(w * t) / 2.0;
  }
}

std::string machine() {
  utsname u;
  uname(&u);
  std::string cpu = "unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  const bool rt = std::strstr(u.version, "PREEMPT_RT") != nullptr;
  return cpu + "; " + u.sysname + " " + u.release + " (" + (rt ? "PREEMPT_RT" : "not a real-time kernel") + ")";
}

struct Run {
  std::vector<long long> period_error_ns, latency_ns, cost_ns;
  std::vector<double> tracking_sq, estimate_error_sq, disturbance_sq;
  long long missed = 0;  // periods longer than 1.5 ms
  bool ok = true;
};

// Runs the loop for `seconds`; paced to absolute 1 ms deadlines when `paced`.
Run run(const Options& o, bool compensate, bool paced) {
  std::vector<double> q0(7, 0.0);
  JointInterfaces io;
  DisturbanceRejectionController controller;
  DisturbanceRejectionController::Params params;
  params.arm = o.arm;
  params.compensate = compensate;
  params.timestamps = !o.fixed_step;
  params.period = kPeriod;
  controller.configure(params, io);
  const size_t n = controller.joints();
  q0.resize(n);
  hya::created(hya_arm_home(o.arm.c_str(), q0.data(), n), "home pose");
  SimulatedArm arm(o.arm, q0);
  arm.read(io.position, io.velocity, io.effort);
  Run r;
  if (controller.activate(0.0) != DisturbanceRejectionController::Result::kOk) {  // holds G(q) until the first update
    std::fprintf(stderr, "activate failed: %s\n", controller.error().c_str());
    r.ok = false;
    return r;
  }

  const size_t periods = static_cast<size_t>(std::lround(o.seconds / kPeriod));
  r.period_error_ns.reserve(periods);
  r.latency_ns.reserve(periods);
  r.cost_ns.reserve(periods);
  r.tracking_sq.assign(n, 0.0);
  r.estimate_error_sq.assign(n, 0.0);
  r.disturbance_sq.assign(n, 0.0);
  Reference ref{q0, q0, q0};
  std::string why;
  size_t counted = 0;

  timespec deadline;
  clock_gettime(CLOCK_MONOTONIC, &deadline);
  const long long start = to_ns(deadline);
  long long previous = start;
  double t = 0.0;  // the sample's time, s: the wall clock's when paced, k ms when not
  for (size_t k = 0; k < periods; ++k) {
    double period = kPeriod;
    if (paced) {
      advance(deadline, kPeriodNs);
      while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
      }
      const long long woke = now_ns();
      r.latency_ns.push_back(woke - to_ns(deadline));
      r.period_error_ns.push_back(std::llabs(woke - previous - kPeriodNs));
      r.missed += (woke - previous) > kPeriodNs * 3 / 2;
      period = static_cast<double>(woke - previous) * 1e-9;
      previous = woke;
    }
    // The arm moved under the last command for as long as the period really lasted.
    if (!arm.step(io.command, t, period, why)) {  // ◀ robot: the drives applied the command
      std::fprintf(stderr, "simulation failed at t = %.3f s: %s\n", t, why.c_str());
      r.ok = false;
      return r;
    }
    t += period;
    arm.read(io.position, io.velocity, io.effort);  // ◀ robot: read state interfaces
    reference_at(t, q0, ref);
    const long long before = now_ns();
    const auto result = controller.update(t, period, ref);  // ◀ robot: writes the command interface
    r.cost_ns.push_back(now_ns() - before);
    if (result != DisturbanceRejectionController::Result::kOk) {
      std::fprintf(stderr, "update failed at t = %.3f s: %s\n", t, controller.error().c_str());
      r.ok = false;
      return r;
    }
    // Statistics after the filters' start-up (0.5 s).
    if (t >= 0.5) {
      const std::vector<double>& d = arm.true_disturbance(t);
      for (size_t i = 0; i < n; ++i) {
        r.tracking_sq[i] += std::pow(io.position[i] - ref.position[i], 2);
        r.estimate_error_sq[i] += std::pow(controller.disturbance_estimate()[i] - d[i], 2);
        r.disturbance_sq[i] += d[i] * d[i];
      }
      ++counted;
    }
  }
  for (auto* v : {&r.tracking_sq, &r.estimate_error_sq, &r.disturbance_sq}) {
    for (double& x : *v) {
      x = std::sqrt(x / static_cast<double>(counted));
    }
  }
  return r;
}

void print_row(const char* label, const std::vector<double>& v, double scale) {
  std::printf("%s", label);
  for (double x : v) {
    std::printf(" %7.2f", x * scale);
  }
  std::printf("\n");
}

double norm(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) {
    s += x * x;
  }
  return std::sqrt(s);
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  std::string scheduling = "SCHED_OTHER, memory not locked";
  if (o.fifo) {
    sched_param p{};
    p.sched_priority = 80;
    const bool fifo = sched_setscheduler(0, SCHED_FIFO, &p) == 0;
    const bool locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
    scheduling = std::string(fifo ? "SCHED_FIFO priority 80" : "SCHED_FIFO refused (SCHED_OTHER)") + ", " +
                 (locked ? "memory locked" : "mlockall refused");
  }
  try {
    std::printf("hya C++ loop: %s at 1000 Hz for %.1f s; %s\n", o.arm.c_str(), o.seconds, machine().c_str());
    std::printf("scheduling: %s; estimator stepped %s\n", scheduling.c_str(),
                o.fixed_step ? "at the fixed 1 ms (--fixed-step)" : "by timestamps");
    const Run without = run(o, false, false);
    const Run with = run(o, true, true);
    if (!without.ok || !with.ok) {
      return 1;
    }
    std::printf("period jitter |T - 1 ms| (us): median %.1f  p99 %.1f  max %.1f  (%lld of %zu periods over 1.5 ms)\n",
                quantile_us(with.period_error_ns, 0.5), quantile_us(with.period_error_ns, 0.99),
                quantile_us(with.period_error_ns, 1.0), with.missed, with.period_error_ns.size());
    std::printf("wake-up latency after the deadline (us): median %.1f  p99 %.1f  max %.1f\n",
                quantile_us(with.latency_ns, 0.5), quantile_us(with.latency_ns, 0.99),
                quantile_us(with.latency_ns, 1.0));
    std::printf("update cost, estimator + controller (us): median %.2f  p99 %.2f  (back to back, unpaced: median %.2f)\n",
                quantile_us(with.cost_ns, 0.5), quantile_us(with.cost_ns, 0.99), quantile_us(without.cost_ns, 0.5));
    print_row("tracking RMS without d-hat (mrad):       ", without.tracking_sq, 1e3);
    print_row("tracking RMS with d-hat (mrad):          ", with.tracking_sq, 1e3);
    print_row("disturbance d RMS (N m):                 ", with.disturbance_sq, 1.0);
    print_row("estimate error d-hat - d RMS (N m):      ", with.estimate_error_sq, 1.0);

    const bool helps = norm(with.tracking_sq) < 0.5 * norm(without.tracking_sq);
    const bool follows = norm(with.estimate_error_sq) < 0.5 * norm(with.disturbance_sq);
    std::printf("check: compensation halves the tracking error: %s; d-hat follows d within half its RMS: %s\n",
                helps ? "yes" : "NO", follows ? "yes" : "NO");
    return helps && follows ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hya_cpp_loop: %s\n", e.what());
    return 1;
  }
}
