// An engine configuration as the harness knows it (EngineInfo: what it is, the vehicles it makes,
// its settings, and for an outside engine how it is started), what a run needs of it, and the
// registry. The vehicles themselves: engines/vehicle.hpp; the settings: engines/settings.hpp.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "engines/settings.hpp"
#include "engines/vehicle.hpp"
#include "input/params.hpp"
#include "input/vehicle.hpp"

namespace liftcheck {

/// One run target: an engine in a named configuration (the solver, joints, contact model and
/// defaults its users run). Everything the harness and the reports need to know about a target
/// is here, so adding one is its folder plus one registry line.
class RawCar;  // engines/raw_car.hpp
/// Makes a configuration's raw car at q0 with the given settings (its car knobs).
using RawCarFactory = std::unique_ptr<RawCar> (*)(const Settings&, const CarSetup&, const car::Config&);

/// Which of a suite's points a configuration joins besides its runs: every sweep, outcome case and
/// map point (kAll); the speed-accuracy map's dt and iteration axes, no sweep or outcome point
/// (kMap); or none, the map showing its default run (kRuns). An outside engine's registration
/// says it ("points"); a compiled-in configuration whose steps cost hundreds of microseconds
/// declares kRuns. validate --all-points gives every configuration all of them.
enum class SuitePoints { kAll, kMap, kRuns };

/// What only an engine outside liftcheck has (engines/protocol/outside.hpp): its registration file,
/// the argument vector that starts it, and whether its hello was read.
struct OutsideEngine {
  std::string registration = {};
  std::vector<std::string> command = {};
  /// False until its hello has been read (find_engine reads it).
  bool described = true;
  /// Why it cannot run (its command did not start, its hello was wrong); its runs are error
  /// records saying so. Empty when it is available.
  std::string unavailable = {};
};

struct EngineInfo {
  std::string name;     ///< configuration name, the run target ("ode-quick")
  std::string library;  ///< the engine it configures ("ODE"), for grouping
  std::string version;
  std::string description;
  std::string color;  ///< "#rrggbb": its traces in every plot and snapshot
  /// The exact model every other target is compared with (sweeps, outcome maps): tolerances
  /// for the reference are those of TolRole::kReference in the scenario data.
  bool is_reference = false;
  std::function<std::unique_ptr<CarEngine>(const Settings&)> make_car;     ///< empty: the engine has no car
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
  /// Holds its rear wheels' spin with a motor of its own when a braked run asks
  /// (ServoDef::rear_brake_torque_max_Nm > 0): the braked slides need it.
  bool brakes = false;
  /// The benchmark's raw loop (engines/raw_car.hpp): its car stepped by direct calls to the engine
  /// (null: none; the reference has none, it does not step).
  RawCarFactory make_raw_car = nullptr;
  /// The precision the engine stores positions in, "float64" or "float32": tolerances that check
  /// bookkeeping (MetricDef::bookkeeping) scale with it (bookkeeping_factor). Every compiled-in
  /// engine here is double precision.
  std::string precision = "float64";
  /// The suite points it joins besides its runs.
  SuitePoints points = SuitePoints::kAll;
  /// What only an engine outside liftcheck has; empty (registration "") for a compiled-in one.
  OutsideEngine outside = {};
  /// An engine outside liftcheck, started over the engine protocol.
  bool is_outside() const { return !outside.registration.empty(); }

  /// Every knob of `vehicle` at its default.
  Settings defaults(Vehicle vehicle) const;
};

/// The settings of `engine` for `vehicle`: its knobs' defaults, overridden by `overrides` (each
/// key one of those knobs), validated as scenario parameters are (InputError naming the setting).
Settings resolve_settings(const EngineInfo& engine, Vehicle vehicle, const Overrides& overrides,
                          const std::string& scenario);

/// What a run asks of a configuration, and the first thing a configuration lacks of it (checked in
/// this order). The runner, the conformance suite and the benchmark all ask `lacks`.
struct Needs {
  Vehicle vehicle = Vehicle::kCar;  ///< make_car or make_disks
  bool four_wheels = false;         ///< a four-wheel car (wheels=4)
  bool contact_dynamics = false;    ///< contact forces with friction (the negative controls)
  bool brakes = false;              ///< rear wheels held by the engine's own motors (the braked slides)
  bool raw_car = false;             ///< the benchmark's raw loop
};
enum class Lack { kNothing, kFourWheels, kVehicle, kContactDynamics, kBrakes, kRawCar };
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
