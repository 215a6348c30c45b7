// The small interface every engine implements. An engine offers vehicles (capabilities);
// the analytic model is one more engine.
#pragma once

#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <memory>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>


#include "input/params.hpp"
#include "input/vehicle.hpp"
#include "models/car.hpp"
#include "models/disks.hpp"
#include "models/lift.hpp"
#include "models/path.hpp"

namespace liftcheck {

/// What a setting is for, where the harness or a check needs to know it, whatever the engine calls
/// it: the solver's iteration count (the speed-accuracy map sweeps it on every configuration that
/// has one), a velocity damping the engine applies by default (the gravity check turns it off to
/// see gravity alone).
enum class SettingRole { kNone, kSolverIterations, kDamping };

/// A setting only some engines have (solver iterations, wheel shape, friction directions):
/// declared, typed and ranged by the engine that has it as a scenario parameter is (ParamSpec: the
/// one spec type), set with --set like a parameter, echoed in the record as applied, rejected for
/// an engine that does not declare it.
struct SettingSpec : ParamSpec {
  Vehicle vehicle = Vehicle::kCar;  ///< the vehicle it applies to
  SettingRole role = SettingRole::kNone;

  bool numeric() const { return kind != ParamKind::kChoice; }
  /// "1 to 10000", "(0, 2]" or "a | b": the range as a user reads it.
  std::string range_text() const;
  /// "integer", "real" or "choice": the kind as the protocol and results.json name it.
  const char* kind_name() const;
};
/// The kind named by kind_name(); nullopt for another name.
std::optional<ParamKind> setting_kind_named(const std::string& name);

/// Validated setting values by key, typed by their specs (a number or a choice), every declared
/// setting of the engine's vehicle present (resolve_settings makes them).
class Settings {
 public:
  using Value = std::variant<double, std::string>;
  double number(const std::string& key) const { return std::get<double>(values_.at(key)); }
  int integer(const std::string& key) const { return static_cast<int>(number(key)); }
  const std::string& choice(const std::string& key) const { return std::get<std::string>(values_.at(key)); }
  bool has(const std::string& key) const { return values_.count(key) > 0; }
  /// The value as the record and the protocol show it: a choice, or a number as "{:g}".
  std::string at(const std::string& key) const;
  Value& operator[](const std::string& key) { return values_[key]; }
  /// Every value as at() shows it, by key.
  std::map<std::string, std::string> texts() const;
  bool operator==(const Settings&) const = default;

 private:
  std::map<std::string, Value> values_;
};

/// Everything needed to build and drive one car (the shared scenario parameters).
struct CarSetup {
  car::CarDef car;              ///< R, l
  car::DriveDef drive;          ///< speed, steering rate, ramps
  double dt_s = 1e-3;           ///< engine time step
  double sample_dt_s = 0.01;    ///< spacing of the reported trace
  double mu = 1.0;              ///< Coulomb friction coefficient, wheel against ground
  double gravity_mps2 = 9.81;   ///< magnitude of gravity
  /// Unit direction of gravity in the world frame: down -Z, or tilted (car.slope tilts gravity
  /// instead of the ground, which stays the plane z = 0). Every engine adapter applies it.
  Eigen::Vector3d gravity_dir_W = -Eigen::Vector3d::UnitZ();
  /// 3: the paper's tricycle (one steered, driven front wheel at the front-axle centre); 4: two
  /// steered, driven front wheels at +-track/2 (Ackermann angles, electronic differential;
  /// models/ackermann.hpp). The analytic reference is the same for both.
  int wheels = 3;
  double track_m = 0.8;         ///< distance between the rear wheels (and between the front wheels of a four-wheel car)
  /// Four wheels only: both front wheels at the virtual angle beta instead of their Ackermann
  /// angles (they fight and scrub: a negative control).
  bool parallel_steering = false;
  /// The car's masses (car_params in scenarios/car_scenarios.cpp gives the defaults and why).
  double chassis_mass_kg = 40.0;
  double wheel_mass_kg = 2.0;     ///< each wheel
  double knuckle_mass_kg = 2.0;   ///< each steering knuckle (between the chassis and a steered wheel)

  Eigen::Vector3d gravity_W() const { return gravity_mps2 * gravity_dir_W; }  ///< m/s^2
};

/// How much one wheel's contact point slid over a drive, measured every engine step from the
/// engine's own body state: v_contact = v_hub + omega x (contact point - hub), split along the
/// wheel's rolling direction and across it (along the axle), both horizontal.
struct WheelSlip {
  std::string wheel;            ///< "front", "rear left", ...
  double along_max_mps = 0.0;   ///< largest |v_contact . rolling direction|
  double across_max_mps = 0.0;  ///< largest |v_contact . axle|
  double rms_mps = 0.0;         ///< root mean square of the horizontal |v_contact| over the steps
  /// False where the engine has no wheel spin of its own (a raycast vehicle derives the wheel's
  /// rotation from the chassis speed): the along-slip then compares a value with itself.
  bool along_measured = true;
};

/// A car in an engine: reset to a configuration, drive a base path, report (alpha, beta, x, y, phi).
class CarEngine {
 public:
  virtual ~CarEngine() = default;
  virtual void reset(const CarSetup& setup, const car::Config& q0) = 0;
  /// Drives `path` from the reset configuration; returns the realized configuration over time,
  /// starting at t = 0 and ending at the path's end, every setup.sample_dt_s.
  virtual std::vector<car::TimedConfig> drive(const car::BasePath& path) = 0;
  /// Contact-point slip of every wheel over the last drive (from t = 0 to its end). Every engine
  /// must say: empty only for a model without contact points to measure (the analytic lift rolls
  /// without slipping by construction; an outside simulator's trace has no wheel states).
  virtual std::vector<WheelSlip> slip() const = 0;
  /// True only for the analytic engine: it reports the commanded (alpha, beta) and their exact
  /// lift by construction, so comparing its trace with the command or with the lift of its own
  /// shape compares a value with itself (shown, not counted). Every engine that steps physics,
  /// whatever it derives its wheel angles from, is judged by those comparisons.
  virtual bool exact_by_construction() const { return false; }
  /// Simulated time the engine stepped since construction (settling included), s: the
  /// denominator of the cost per simulated second.
  virtual double simulated_s() const = 0;
  /// True for a trace read back from a simulator outside liftcheck: nothing inside it is known,
  /// so its whole path is compared with the exact lift at every sample.
  virtual bool replays_trace() const { return false; }
  /// Seconds the engine itself spent stepping, as an outside engine's adapter reports them
  /// (docs/protocol.md, `engine_s`): the cost per simulated second without the protocol's round
  /// trip. NaN for an engine in liftcheck's process, whose run's wall clock is its cost.
  virtual double reported_engine_s() const { return NAN; }
};

/// Two unit disks: N moves along a known path, M's velocity is commanded from a reaction rule.
/// Rigid-body engines realise M's commanded velocity with their own actuation and integrator and
/// detect contact with their own collision pipeline while stepping.
struct DiskSetup {
  double radius_m = 1.0;
  double dt_s = 1e-3;         ///< engine step
  double sample_dt_s = 0.02;  ///< spacing of the reported trace
};

struct DiskProblem {
  disks::Rule rule;
  disks::NPath path;
  disks::Vec2 cM0;
  double T_s = 6.0;
};

/// What an engine's own contact pipeline said over a stepped run. Distances are the engine's
/// reported centre distances |c_M - c_N| at the states its collision passes ran on.
struct DiskContactLog {
  double distance_at_first_m = NAN;  ///< at the state on which contact was first reported
  double overlap_unreported_m = 0.0; ///< largest 2 - |c_M - c_N| > 0 at any state reported free of contact
  double gap_reported_max_m = 0.0;   ///< largest |c_M - c_N| - 2 > 0 at any state reported in contact
  double depth_error_max_m = 0.0;    ///< largest |reported depth - (2 - |c_M - c_N|)| at states reported in contact
  double overlap_growth_first_m = 0.0; ///< overlap on the state after the first contact minus that at it (a response acting at once stops the approach)
  double penetration_max_m = 0.0;    ///< largest 2 - |c_M - c_N| from the first contact to T (the contact response bounds it)
  double depth_reported_max_m = 0.0; ///< deepest penetration the engine's contact points reported
  long steps_in_contact = 0;         ///< steps whose collision pass reported contact
  double n_path_error_max_m = 0.0;   ///< largest distance of N from its path, every step
  bool apart_at_end = false;         ///< after contact, |c_M - c_N| > 2 at T (the disks separated)
  /// Largest |(c_M after - c_M before) - v_cmd h| over the steps before the first reported contact:
  /// an engine that realises its command moves M by exactly the commanded velocity times the step.
  double step_displacement_error_max_m = 0.0;
  double step_displacement_error_at_s = 0.0;  ///< the start of the step where it was largest
  /// Contact was reported by the engine's own collision pipeline. False for a trace from outside,
  /// whose "contact" is read off its positions: comparing those with themselves measures nothing.
  bool reported_by_engine = true;
};

/// Disks apart by no more than this are touching (the round-off of |c_M - c_N| = 2 at these scales).
constexpr double kTouchRoundoff_m = 1e-9;
/// A contact has ended when the disks are apart by at least this much more than touching: a
/// micrometre, above the gaps of 0.2 um that Bullet's penetration recovery opens for a step while
/// its contact holds (the larger threshold is a tenth of a step of relative travel, DiskRun).
constexpr double kSeparation_m = 1e-6;

struct DiskRun {
  std::optional<double> t_contact_s;  ///< analytic: root; engines: the state on which contact was first reported
  /// M and N at t_contact_s (engines: the state their collision pass first reported contact on).
  std::optional<disks::Sample> contact_state;
  /// The end of the first contact: the first state after it with the disks apart by more than a
  /// tenth of a step of M's travel relative to N at contact, and at least kSeparation_m
  /// (models/disk_contact.hpp, kSeparationSteps; analytic: the root of the release); none while
  /// they touch to T.
  std::optional<double> t_release_s;
  double min_distance = 0.0;          ///< smallest |c_M - c_N| (analytic: refined on the dense output; engines: over their steps)
  std::vector<disks::Sample> trace;   ///< at t = i * sample_dt from 0 to T (and T)
  std::optional<DiskContactLog> contact_log;  ///< stepping engines only
};

class DiskEngine {
 public:
  virtual ~DiskEngine() = default;
  virtual DiskRun run(const DiskSetup& setup, const DiskProblem& problem) = 0;
  /// Simulated time stepped since construction, s (the exact model: the problems' horizons).
  virtual double simulated_s() const = 0;
  /// As CarEngine::reported_engine_s.
  virtual double reported_engine_s() const { return NAN; }
};

/// A body has blown up when it is faster than kRunawayFactor times the fastest speed the run
/// commands, or than kRunawaySpeed_mps where that is more. The stepping loops check it at every
/// step, with NaN and bodies through the ground.
constexpr double kRunawaySpeed_mps = 50.0;
constexpr double kRunawayFactor = 10.0;

/// Thrown by an engine whose simulation failed (NaN, explosion, bad setup): reported as an error run.
struct EngineError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One run target: an engine in a named configuration (the solver, joints, contact model and
/// defaults its users run). Everything the harness and the reports need to know about a target
/// is here, so adding one is its folder plus one registry line.
class RawCar;  // engines/raw_car.hpp
/// Makes a configuration's raw car at q0 with the given settings (its car knobs).
using RawCarFactory = std::unique_ptr<RawCar> (*)(const Settings&, const CarSetup&, const car::Config&);

struct EngineInfo {
  std::string name;          ///< configuration name, the run target ("ode-quick")
  std::string library;       ///< the engine it configures ("ODE"), for grouping
  std::string version;
  std::string description;
  std::string color;         ///< "#rrggbb": its traces in every plot and snapshot
  /// The exact model every other target is compared with (sweeps, outcome maps): tolerances
  /// for the reference are those of TolRole::kReference in the scenario data.
  bool is_reference = false;
  std::function<std::unique_ptr<CarEngine>(const Settings&)> make_car;  ///< empty: the engine has no car
  std::function<std::unique_ptr<DiskEngine>(const Settings&)> make_disks;  ///< empty: no two-disk vehicles
  /// Simulates contact forces with friction, so wheels can slip (the analytic model cannot).
  bool contact_dynamics = false;
  /// Fixed settings of the engine's model (joints, contact and friction handling), for the record.
  std::vector<std::pair<std::string, std::string>> settings;
  /// Settings a user may change, each used by this engine (a test checks that each changes a result).
  std::vector<SettingSpec> knobs = {};
  /// Builds four-wheel cars (CarSetup::wheels = 4); a configuration without them rejects
  /// wheels=4 as bad input rather than run a tricycle.
  bool four_wheels = false;
  /// The benchmark's raw loop (engines/raw_car.hpp): its car stepped by direct calls to the engine
  /// (null: none; the reference has none, it does not step).
  RawCarFactory make_raw_car = nullptr;
  /// The precision the engine stores positions in, "float64" or "float32": tolerances that check
  /// bookkeeping (MetricDef::bookkeeping) scale with it (bookkeeping_factor). Every compiled-in
  /// engine here is double precision.
  std::string precision = "float64";
  /// An engine outside liftcheck (engines/protocol/outside.hpp): its registration file and the
  /// argument vector that starts it; empty for a compiled-in configuration.
  std::string registration = {};
  std::vector<std::string> command = {};
  /// Which of a suite's points it joins besides its runs (an outside configuration's registration,
  /// "points"): every sweep, outcome case and map point (kAll); the speed-accuracy map's dt and
  /// iteration axes, no sweep or outcome point (kMap); or none, the map showing its default run
  /// (kRuns). validate --all-points gives every configuration all of them.
  enum class Points { kAll, kMap, kRuns };
  Points points = Points::kAll;
  /// False until an outside configuration's hello has been read (find_engine reads it).
  bool described = true;
  /// Why an outside configuration cannot run (its command did not start, its hello was wrong);
  /// its runs are error records saying so. Empty when it is available.
  std::string unavailable = {};

  /// Every knob of `vehicle` at its default.
  Settings defaults(Vehicle vehicle) const;
};

/// The settings of `engine` for `vehicle`: its knobs' defaults, overridden by `overrides` (each
/// key one of those knobs), validated as scenario parameters are (InputError naming the setting).
Settings resolve_settings(const EngineInfo& engine, Vehicle vehicle, const Overrides& overrides, const std::string& scenario);

/// What a run asks of a configuration, and the first thing a configuration lacks of it (checked in
/// this order). The runner, the conformance suite and the benchmark all ask `lacks`.
struct Needs {
  Vehicle vehicle = Vehicle::kCar;  ///< make_car or make_disks
  bool four_wheels = false;       ///< a four-wheel car (wheels=4)
  bool contact_dynamics = false;  ///< contact forces with friction (the negative controls)
  bool raw_car = false;           ///< the benchmark's raw loop
};
enum class Lack { kNothing, kFourWheels, kVehicle, kContactDynamics, kRawCar };
Lack lacks(const EngineInfo& e, const Needs& needs);
/// The vehicles `e` builds (make_car, make_disks), in kVehicles order.
std::vector<Vehicle> vehicles_of(const EngineInfo& e);
/// The lack as the end of a sentence about the configuration ("has no car").
std::string lack_text(Lack lack, const Needs& needs);

/// Every configuration compiled in, in a fixed order (the reference first), then every outside
/// configuration registered (engines/protocol/outside.hpp), in folder and file name order. An
/// outside configuration is described (its hello read) only once it is looked up by
/// find_engine or all are by described_engines(): listing the names starts no process.
const std::vector<EngineInfo>& engines();
/// engines(), every outside configuration described first.
const std::vector<EngineInfo>& described_engines();
/// The configuration named `name`, described; nullptr if there is none.
const EngineInfo* find_engine(const std::string& name);
/// Registration files that could not be used (malformed, a name taken twice), one line each.
const std::vector<std::string>& registration_problems();
/// The tolerance factor of bookkeeping metrics for an engine of this precision: 1 for float64;
/// 1e4 for float32 (docs/protocol.md, "precision").
double bookkeeping_factor(const std::string& precision);
/// The configuration marked is_reference (exactly one).
const EngineInfo& reference_engine();

}  // namespace liftcheck
