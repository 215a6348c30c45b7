#include "engines/trace/trace_engines.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "input/read_file.hpp"
#include "models/disk_contact.hpp"

namespace liftcheck {

namespace {

/// The times of a path written out and of the trace read back: every h from 0, and T.
std::vector<double> grid(double T_s, double h_s) {
  std::vector<double> t;
  const long n = static_cast<long>(std::ceil(T_s / h_s - 1e-9));
  for (long k = 0; k <= n; ++k) t.push_back(std::min(T_s, k * h_s));
  return t;
}

/// The trace must have one row at each time of the path it answers (as `liftcheck path` wrote them).
void check_grid(const Trace& tr, double T_s, double h_s) {
  const std::vector<double> want = grid(T_s, h_s);
  if (tr.rows.size() != want.size())
    throw InputError(
        fmt::format("{}: {} rows; the path has {} (every {:g} s from 0 to {:g} s): write one row per path row", tr.file,
                    tr.rows.size(), want.size(), h_s, T_s));
  for (std::size_t i = 0; i < want.size(); ++i)
    if (std::abs(tr.rows[i][0] - want[i]) > 1e-6 * std::max(1.0, want[i]))
      throw InputError(fmt::format("{}: row {} is at t = {:g} s; the path's row {} is at {:g} s", tr.file, i + 1,
                                   tr.rows[i][0], i + 1, want[i]));
}

/// A car trace must have a row at each time of the path (it may have more, at times in between,
/// as a lift that samples its path's corners does), and none outside [0, T].
void check_covers(const Trace& tr, double T_s, double h_s) {
  if (tr.rows.front()[0] < -1e-9 || tr.rows.back()[0] > T_s + 1e-6 * std::max(1.0, T_s))
    throw InputError(fmt::format("{}: the trace runs from t = {:g} to {:g} s; the path from 0 to {:g} s", tr.file,
                                 tr.rows.front()[0], tr.rows.back()[0], T_s));
  std::size_t i = 0;
  for (const double t : grid(T_s, h_s)) {
    while (i < tr.rows.size() && tr.rows[i][0] < t - 1e-6 * std::max(1.0, t)) ++i;
    if (i == tr.rows.size() || std::abs(tr.rows[i][0] - t) > 1e-6 * std::max(1.0, t))
      throw InputError(
          fmt::format("{}: no row at t = {:g} s; the path has a row every {:g} s from 0 to {:g} s: write one at each",
                      tr.file, t, h_s, T_s));
  }
}

InputError single_run_only(const std::string& scenario, int runs) {
  return InputError(fmt::format(
      "scenario '{}' drives {} runs; liftcheck path and score take scenarios with a single run", scenario, runs));
}

class ReplayCar final : public CarEngine {
 public:
  ReplayCar(std::string scenario, Trace trace) : scenario_(std::move(scenario)), trace_(std::move(trace)) {}
  void reset(const CarSetup& setup, const car::Config&) override { setup_ = setup; }
  std::vector<car::TimedConfig> drive(const car::BasePath& path) override {
    if (++drives_ > 1) throw single_run_only(scenario_, drives_);
    check_covers(trace_, path.duration_s(), setup_.sample_dt_s);
    std::vector<car::TimedConfig> out;
    for (const auto& r : trace_.rows) out.push_back({r[0], car::Config{r[1], r[2], r[3], r[4], r[5]}});
    simulated_s_ = trace_.rows.back()[0];
    return out;
  }
  double simulated_s() const override { return simulated_s_; }
  std::vector<WheelSlip> slip() const override { return {}; }  // a trace has no wheel states
  bool replays_trace() const override { return true; }

 private:
  std::string scenario_;
  Trace trace_;
  CarSetup setup_;
  int drives_ = 0;
  double simulated_s_ = 0.0;
};

class ReplayDisks final : public DiskEngine {
 public:
  ReplayDisks(std::string scenario, Trace trace) : scenario_(std::move(scenario)), trace_(std::move(trace)) {}
  DiskRun run(const DiskSetup& setup, const DiskProblem& pb) override {
    if (++runs_ > 1) throw single_run_only(scenario_, runs_);
    check_grid(trace_, pb.T_s, setup.dt_s);
    // The simulator's states every engine step, judged as a stepping engine's are, except that
    // its contact is read off its own positions (the first state overlapping): what its contact
    // pipeline reported is unknown, so only the geometry is checked (penetration, the approach
    // after contact, N on its path).
    const double touch = 2.0 * setup.radius_m;
    const long sample_every = std::max(1L, std::lround(setup.sample_dt_s / setup.dt_s));
    DiskRun r;
    DiskContactLog log;
    log.reported_by_engine = false;
    r.min_distance = INFINITY;
    double separation_m = kSeparation_m;
    for (std::size_t k = 0; k < trace_.rows.size(); ++k) {
      const auto& row = trace_.rows[k];
      const disks::Vec2 cM(row[1], row[2]), cN(row[3], row[4]);
      const double d = (cM - cN).norm();
      r.min_distance = std::min(r.min_distance, d);
      log.n_path_error_max_m = std::max(log.n_path_error_max_m, (cN - pb.path.position(row[0])).norm());
      // Touching to round-off is contact (an exact response holds |c_M - c_N| = 2 to round-off).
      const bool touching = d <= touch + kTouchRoundoff_m;
      if (r.t_contact_s && !r.t_release_s && d - touch > separation_m) r.t_release_s = row[0];
      if (!r.t_contact_s && touching) {
        r.t_contact_s = row[0];
        r.contact_state = disks::Sample{row[0], cM, cN};
        const disks::Vec2 vN = pb.path.velocity(row[0]);
        separation_m =
            std::max(kSeparation_m, disks::kSeparationSteps * (pb.rule(row[0], cM, cN, vN) - vN).norm() * setup.dt_s);
        log.distance_at_first_m = d;
        if (k + 1 < trace_.rows.size()) {
          const auto& nx = trace_.rows[k + 1];
          log.overlap_growth_first_m =
              (touch - (disks::Vec2(nx[1], nx[2]) - disks::Vec2(nx[3], nx[4])).norm()) - (touch - d);
        }
      }
      if (r.t_contact_s) {
        log.penetration_max_m = std::max(log.penetration_max_m, touch - d);
        log.steps_in_contact += touching ? 1 : 0;
      }
      if (k % sample_every == 0 || k + 1 == trace_.rows.size()) r.trace.push_back({row[0], cM, cN});
    }
    log.apart_at_end = r.t_contact_s && r.trace.back().cM != r.trace.back().cN &&
                       (r.trace.back().cM - r.trace.back().cN).norm() > touch;
    r.contact_log = log;
    simulated_s_ = trace_.rows.back()[0];
    return r;
  }
  double simulated_s() const override { return simulated_s_; }

 private:
  std::string scenario_;
  Trace trace_;
  int runs_ = 0;
  double simulated_s_ = 0.0;
};

}  // namespace

std::vector<car::TimedConfig> RecordingCar::drive(const car::BasePath& path) {
  if (++drives_ > 1) throw single_run_only(scenario_, drives_);
  const double h = setup_.sample_dt_s;
  for (const double t : grid(path.duration_s(), h)) {
    const car::BaseSample s = path.at(t);
    recorded.rows.push_back({t, s.alpha_rad, s.beta_rad});
  }
  recorded.start = {
      {"alpha", q0_.alpha_rad}, {"beta", q0_.beta_rad}, {"x", q0_.x_m}, {"y", q0_.y_m}, {"phi", q0_.phi_rad}};
  car::LiftDef def;
  def.sample_dt_s = h;
  return car::lift(setup_.car, path, q0_, def);
}

DiskRun RecordingDisks::run(const DiskSetup& setup, const DiskProblem& pb) {
  if (++runs_ > 1) throw single_run_only(scenario_, runs_);
  // Every engine step: a disk trace is scored like a stepping engine's states (so the path lists
  // every step, and the samples' limit holds for the steps).
  if (!(pb.T_s / setup.dt_s <= kMaxRunSamples))
    throw InputError(
        fmt::format("parameter 'dt' = {:g} s asks for {:.3g} rows of the path (one per engine step) over the run's "
                    "{:g} s: at most {:g} (dt >= {:.3g} s here)",
                    setup.dt_s, pb.T_s / setup.dt_s, pb.T_s, kMaxRunSamples, pb.T_s / kMaxRunSamples));
  for (const double t : grid(pb.T_s, setup.dt_s)) {
    const disks::Vec2 c = pb.path.position(t);
    recorded.rows.push_back({t, c.x(), c.y()});
  }
  recorded.start = {{"cMx", pb.cM0.x()}, {"cMy", pb.cM0.y()}, {"T", pb.T_s}};
  disks::LiftDef def;
  def.sample_dt_s = setup.sample_dt_s;
  const disks::LiftResult r = disks::lift(pb.rule, pb.path, pb.cM0, pb.T_s, def);
  DiskRun out;
  out.t_contact_s = r.t_contact_s;
  out.min_distance = r.min_distance;
  out.trace = r.trace;
  return out;
}

/// A simulator outside liftcheck as a configuration, without its vehicles.
EngineInfo outside_engine(const std::string& name, const std::string& description) {
  // The name is printed on the console, in summary.md's table and the report, and recorded in JSON.
  require_utf8(name, "configuration name");
  if (std::any_of(name.begin(), name.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
    throw InputError(
        fmt::format("configuration name '{}' holds a control character (a line break?): it would forge lines of the "
                    "console and the "
                    "summary; rename it",
                    printable(name)));
  EngineInfo e;
  e.name = name;
  e.library = "external";
  e.version = "-";
  e.description = description;
  e.color = "#e7298a";
  // Its contact forces are unknown to liftcheck (no wheel states, no contact log): scenarios that
  // need contact dynamics (the negative control) are skipped for it.
  e.contact_dynamics = false;
  return e;
}

EngineInfo replay_engine(const std::string& name, const std::string& scenario, Vehicle vehicle, const Trace& trace) {
  EngineInfo e =
      outside_engine(name, fmt::format("a simulator outside liftcheck, scored from its trace ({})", trace.file));
  e.settings = {{"trace", trace.file}};
  e.precision = trace.precision;  // the trace header's, float64 unless it says otherwise
  for (const auto& [k, v] : trace.settings) e.settings.emplace_back("setting " + k, v);
  if (vehicle == Vehicle::kCar)
    e.make_car = [scenario, trace](const Settings&) { return std::make_unique<ReplayCar>(scenario, trace); };
  else
    e.make_disks = [scenario, trace](const Settings&) { return std::make_unique<ReplayDisks>(scenario, trace); };
  return e;
}

}  // namespace liftcheck
