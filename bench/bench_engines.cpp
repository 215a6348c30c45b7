// Steps per second of the car on every stepping configuration, through liftcheck (the configuration's
// CarEngine as the runner drives it: make_car, reset, drive) and through a raw loop on the same
// bodies and settings that calls the engine's step function directly with the motors set once
// (engines/raw_car.hpp; each configuration declares its own, EngineInfo::make_raw_car): the
// physical limit. Reported: both rates and the overhead liftcheck time / raw time - 1, each from
// the fastest of five iterations, in CPU time of the benchmark's thread (the machine is shared:
// wall-clock ratios there move by 10% and more).
//
// The drive is car.circle's at its defaults, shortened to 2 m of front-wheel travel: beta0 = 0.3 rad,
// R = 0.3 m, l = 1 m, 0.5 m/s, dt = 1 ms; 0.5 s of settle, the path, 0.2 s of hold (5486 steps).
// Each run is checked: liftcheck's front wheel must end within 15 cm of the exact lift (4.1) (dart as
// shipped, the worst, ends 7 cm off after its 2 m: its circle is 0.5% too wide and its heading lags;
// a car that stalls, skids away or explodes misses by metres), and the raw car's front wheel must
// have moved the chord of the arc it drove at the commanded speed to 5%.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <sched.h>
#include <fmt/format.h>
#include <limits>
#include <string>

#include "engines/engine.hpp"
#include "engines/protocol/outside.hpp"
#include "engines/raw_car.hpp"
#include "engines/rigid_car.hpp"
#include "models/lift.hpp"

using namespace liftcheck;

namespace {

constexpr double kDrive_m = 2.0;
constexpr double kCheckLiftcheck_m = 0.15;
constexpr double kCheckRawRel = 0.05;

/// car.circle's defaults (scenarios/car_scenarios.cpp, setup_from).
CarSetup circle_setup() {
  CarSetup s;
  s.car = {0.3, 1.0};
  s.drive = {0.3, 0.5, 0.5, 1.0, 4.0};
  s.dt_s = 1e-3;
  s.sample_dt_s = 0.01;
  s.mu = 1.0;
  s.gravity_mps2 = 9.81;
  return s;
}
const car::Config kStart{0.0, 0.3, 0.0, 0.0, 0.0};

/// CPU time of the calling thread, s.
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void BM_CarSteps(benchmark::State& state, const EngineInfo* engine, RawCarFactory make_raw) {
  const CarSetup setup = circle_setup();
  const Settings settings = engine->defaults(Vehicle::kCar);
  const car::BasePath path({{kDrive_m / setup.car.R_m, 0.0}}, 0.0, kStart.beta_rad, setup.drive);
  const car::Config exact_end = car::lift_end(setup.car, path, kStart);
  // RigidCar::drive's step count: the settle, then the path and the hold.
  const ServoDef servo;
  const long settle_steps = std::lround(servo.settle_s / setup.dt_s);
  const long drive_steps = static_cast<long>(std::ceil((path.duration_s() + servo.hold_s) / setup.dt_s - 1e-9));
  const long steps = settle_steps + drive_steps;
  // The raw car drives at the cruise speed from the first step: its front wheel goes around the
  // circle of radius l / sin(beta0) (appendix D) through an arc of speed x drive time.
  const double rho_m = setup.car.l_m / std::sin(kStart.beta_rad);
  const double arc_m = setup.drive.speed_mps * drive_steps * setup.dt_s;
  const double chord_m = 2.0 * rho_m * std::sin(arc_m / (2.0 * rho_m));

  double best_liftcheck_s = std::numeric_limits<double>::infinity(), best_raw_s = best_liftcheck_s;
  long iteration = 0;
  for (auto _ : state) {
    // liftcheck, as the runner drives it; the build is not timed (nor is the raw car's). The two
    // take turns at going first, so neither always meets the caches the other left.
    double liftcheck_s = 0.0, raw_s = 0.0;
    std::string problem;
    const auto time_liftcheck = [&] {
      auto engine_car = engine->make_car(settings);
      engine_car->reset(setup, kStart);
      const double t0 = thread_cpu_s();
      const std::vector<car::TimedConfig> trace = engine_car->drive(path);
      liftcheck_s = thread_cpu_s() - t0;
      const double miss_m = std::hypot(trace.back().q.x_m - exact_end.x_m, trace.back().q.y_m - exact_end.y_m);
      if (!(miss_m < kCheckLiftcheck_m))
        problem = fmt::format("liftcheck's car ended {:.3g} m from the exact lift", miss_m);
    };
    const auto time_raw = [&] {
      auto raw = make_raw(settings, setup, kStart);
      const Eigen::Vector2d start = raw->front_xy_m();
      const double t0 = thread_cpu_s();
      raw->run(settle_steps, 0.0);
      raw->run(drive_steps, setup.drive.speed_mps / setup.car.R_m);
      raw_s = thread_cpu_s() - t0;
      const double moved_m = (raw->front_xy_m() - start).norm();
      if (!(std::abs(moved_m / chord_m - 1.0) < kCheckRawRel))
        problem = fmt::format("the raw car moved {:.4g} m, not {:.4g} m", moved_m, chord_m);
    };
    if (iteration++ % 2 == 0)
      time_liftcheck(), time_raw();
    else
      time_raw(), time_liftcheck();
    if (!problem.empty()) {
      state.SkipWithError(problem.c_str());
      break;
    }
    state.SetIterationTime(liftcheck_s);  // the reported time: liftcheck's CPU time per drive
    best_liftcheck_s = std::min(best_liftcheck_s, liftcheck_s);
    best_raw_s = std::min(best_raw_s, raw_s);
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["liftcheck_steps_per_s"] = steps / best_liftcheck_s;
  state.counters["raw_steps_per_s"] = steps / best_raw_s;
  state.counters["overhead_pct"] = 100.0 * (best_liftcheck_s / best_raw_s - 1.0);
}

void BM_NoRawLoop(benchmark::State& state) {
  for (auto _ : state) state.SkipWithError("no raw loop for this configuration (EngineInfo::make_raw_car)");
}

/// One benchmark per configuration that steps a car (the analytic reference integrates, it does not step).
const bool kRegistered = [] {
  for (const EngineInfo& e : engines()) {
    if (lacks(e, {.vehicle = Vehicle::kCar, .contact_dynamics = true}) != Lack::kNothing) continue;
    const std::string name = "BM_CarSteps/" + e.name;
    if (lacks(e, {.vehicle = Vehicle::kCar, .contact_dynamics = true, .raw_car = true}) == Lack::kRawCar) {
      benchmark::RegisterBenchmark(name.c_str(), BM_NoRawLoop);
      continue;
    }
    benchmark::RegisterBenchmark(name.c_str(), BM_CarSteps, &e, e.make_raw_car)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(5);
  }
  return true;
}();

}  // namespace

namespace {

/// Keeps the calling thread, and the engine processes it starts, on the core it runs on, as
/// validate keeps each worker with its outside engine (harness/worker_pool.cpp, bind_worker); the thread's
/// own affinity comes back at the end of the scope.
struct OnOneCore {
  cpu_set_t before{};
  bool ok = false;
  OnOneCore() {
    ok = sched_getaffinity(0, sizeof before, &before) == 0;
    const int cpu = sched_getcpu();
    if (!ok || cpu < 0) return;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    ok = sched_setaffinity(0, sizeof one, &one) == 0;
  }
  ~OnOneCore() {
    if (ok) sched_setaffinity(0, sizeof before, &before);
  }
};

/// The engine protocol's round trip per step: car.circle's drive on `ode` served by `liftcheck
/// serve ode` (a child process, JSON lines over pipes) against the same drive on `ode` in process,
/// wall clock (the engine runs in the other process). `protocol_us_per_step` is what the protocol
/// adds to a step; `engine_us_per_step` the server's own stepping time as it reports it
/// (engine_s, the cost the tables count for an outside engine).
void BM_ProtocolRoundTrip(benchmark::State& state) {
  const OnOneCore pinned;
  static const EngineInfo served = outside_engine("ode-protocol", {LIFTCHECK_EXE, "serve", "ode"}, ".");
  const EngineInfo* ode = find_engine("ode");
  if (!served.outside.unavailable.empty()) {
    for (auto _ : state) state.SkipWithError(served.outside.unavailable.c_str());
    return;
  }
  const CarSetup setup = circle_setup();
  const car::BasePath path({{kDrive_m / setup.car.R_m, 0.0}}, 0.0, kStart.beta_rad, setup.drive);
  const auto wall_s = [](auto&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  double best_protocol_s = INFINITY, best_direct_s = INFINITY, engine_s = 0.0, steps = 0.0, client_cpu_s = INFINITY;
  for (auto _ : state) {
    auto over = served.make_car(served.defaults(Vehicle::kCar));
    auto direct = ode->make_car(ode->defaults(Vehicle::kCar));
    over->reset(setup, kStart);
    direct->reset(setup, kStart);
    const double cpu0 = thread_cpu_s();
    const double p = wall_s([&] { over->drive(path); });
    client_cpu_s = std::min(client_cpu_s, thread_cpu_s() - cpu0);
    const double d = wall_s([&] { direct->drive(path); });
    state.SetIterationTime(p);
    if (p < best_protocol_s) best_protocol_s = p, engine_s = over->reported_engine_s();
    best_direct_s = std::min(best_direct_s, d);
    steps = std::round(over->simulated_s() / setup.dt_s);
  }
  state.counters["steps"] = steps;
  state.counters["protocol_us_per_step"] = 1e6 * (best_protocol_s - best_direct_s) / steps;
  state.counters["in_process_us_per_step"] = 1e6 * best_direct_s / steps;
  state.counters["engine_us_per_step"] = 1e6 * engine_s / steps;
  // liftcheck's side of the round trip in CPU time (its servo and bookkeeping, the request's
  // encoding and the reply's parsing), apart from the waits for the other process.
  state.counters["client_cpu_us_per_step"] = 1e6 * client_cpu_s / steps;
}
BENCHMARK(BM_ProtocolRoundTrip)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(5);

/// The same round trip to each outside configuration of the default suite (engines/outside/suite:
/// Rapier, Jolt, Havok, cannon-es and MuJoCo 3 under Node): the engine's own stepping time as its
/// adapter reports it (engine_s, the step timed inside the adapter: the engine's own loop) against
/// the wall clock per step over the protocol, which adds the request's encoding and the reply's
/// reading on both sides, the pipes and the waits for the other process. Both processes on one core,
/// as validate runs them; the engine process is started before the first iteration and warm in the
/// others (the fastest of five counts). Skipped where Node or the npm packages are missing.
void BM_ProtocolOutside(benchmark::State& state, const std::string& name) {
  const EngineInfo* outside = find_engine(name);  // read its hello (its knobs, or why it cannot run)
  if (!outside->outside.unavailable.empty()) {
    for (auto _ : state) state.SkipWithError(outside->outside.unavailable.c_str());
    return;
  }
  const OnOneCore pinned;
  const CarSetup setup = circle_setup();
  const car::BasePath path({{kDrive_m / setup.car.R_m, 0.0}}, 0.0, kStart.beta_rad, setup.drive);
  double best_wall_s = INFINITY, engine_s = 0.0, steps = 0.0, client_cpu_s = INFINITY;
  for (auto _ : state) {
    auto over = outside->make_car(outside->defaults(Vehicle::kCar));
    over->reset(setup, kStart);
    const double cpu0 = thread_cpu_s();
    const auto t0 = std::chrono::steady_clock::now();
    over->drive(path);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    client_cpu_s = std::min(client_cpu_s, thread_cpu_s() - cpu0);
    state.SetIterationTime(wall);
    if (wall < best_wall_s) best_wall_s = wall, engine_s = over->reported_engine_s();
    steps = std::round(over->simulated_s() / setup.dt_s);
  }
  state.counters["steps"] = steps;
  state.counters["wall_us_per_step"] = 1e6 * best_wall_s / steps;
  state.counters["engine_us_per_step"] = 1e6 * engine_s / steps;
  state.counters["protocol_us_per_step"] = 1e6 * (best_wall_s - engine_s) / steps;
  state.counters["protocol_share_pct"] = 100.0 * (best_wall_s - engine_s) / best_wall_s;
  state.counters["client_cpu_us_per_step"] = 1e6 * client_cpu_s / steps;
}

const bool kOutsideRegistered = [] {
  for (const EngineInfo& e : engines())
    if (!e.outside.registration.empty())
      benchmark::RegisterBenchmark(("BM_ProtocolOutside/" + e.name).c_str(), BM_ProtocolOutside, e.name)
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond)
          ->Iterations(5);
  return true;
}();

}  // namespace
