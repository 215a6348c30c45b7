// Scenes built from run records (results.json): snapshots at the key moments of each run, and a
// frame strip for the parking cycles with the net shift magnified and labelled.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "reports/scene.hpp"

namespace liftcheck::render {

/// A magnified view pasted onto a snapshot, its top-left corner at (x_px, y_px) of the snapshot.
struct Inset {
  Scene scene;
  int x_px = 0, y_px = 0;
};

struct Snapshot {
  std::string tag;  ///< start | contact | end
  std::string caption;
  Scene scene;
  std::vector<Inset> insets = {};
};

/// The inset of a car's end snapshot: the engine's end pose over the exact one (front-axle centre,
/// tie rod, front wheel's heading), magnified about the exact front-axle centre so that the offset
/// between them spans about a third of the inset's height, with its own scale bar.
Inset end_pose_inset(const nlohmann::json& run, const Color& ink, const Scene& main);

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
