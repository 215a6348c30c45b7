#include "engines/engine.hpp"

namespace liftcheck {

Lack lacks(const EngineInfo& e, const Needs& needs) {
  if (needs.four_wheels && !e.four_wheels) return Lack::kFourWheels;
  if (needs.vehicle == Vehicle::kCar ? !e.make_car : !e.make_disks) return Lack::kVehicle;
  if (needs.contact_dynamics && !e.contact_dynamics) return Lack::kContactDynamics;
  if (needs.brakes && !e.brakes) return Lack::kBrakes;
  if (needs.raw_car && !e.make_raw_car) return Lack::kRawCar;
  return Lack::kNothing;
}

std::vector<Vehicle> vehicles_of(const EngineInfo& e) {
  std::vector<Vehicle> out;
  for (Vehicle v : kVehicles)
    if (lacks(e, {.vehicle = v}) == Lack::kNothing) out.push_back(v);
  return out;
}

std::string lack_text(Lack lack, const Needs& needs) {
  switch (lack) {
    case Lack::kNothing:
      return "";
    case Lack::kFourWheels:
      return "has no four-wheel car (wheels=4): it builds the tricycle only";
    case Lack::kVehicle:
      return needs.vehicle == Vehicle::kCar ? "has no car" : "has no two-disk vehicles";
    case Lack::kContactDynamics:
      return "simulates no contact forces";
    case Lack::kBrakes:
      return "holds no rear wheel with a brake of its own (EngineInfo::brakes; an outside engine's hello: \"brakes\")";
    case Lack::kRawCar:
      return "has no raw loop (EngineInfo::make_raw_car)";
  }
  return "";
}

}  // namespace liftcheck
