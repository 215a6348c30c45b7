// Scenes built from run records (results.json): snapshots at the key moments of each run, and a
// frame strip for the parking cycles with the net shift magnified and labelled.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "reports/scene.hpp"

namespace liftcheck::render {

struct Snapshot {
  std::string tag;      ///< start | contact | end | perspective
  std::string caption;
  Scene scene;
};

struct Strip {
  std::string caption;
  std::vector<Scene> frames;
  int per_row = 6;
};

/// Snapshots for one run record (none when the record has no trace), its traces drawn in `ink`
/// (the configuration's colour from the results' context).
std::vector<Snapshot> snapshots_for(const nlohmann::json& run, const Color& ink);
/// The frame strip of a parking-cycle run (car.cycle, car.iterated, car.iterated-beta); empty frames otherwise.
Strip strip_for(const nlohmann::json& run, const Color& ink);

}  // namespace liftcheck::render
