// Scenes built from run records (results.json): snapshots at the key moments of each run, and a
// frame strip for the parking cycles with the net shift magnified and labelled.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "input/run_result.hpp"
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
/// between them is drawn at a length that grows with its decade (inset_half_height_m), with its
/// own scale bar.
Inset end_pose_inset(const RunResult& run, const Color& ink, const Scene& main);

/// What a run is measured against, as rows like its trace (kReference; for the disks, after the
/// engine's first contact, the exact inelastic response from that contact on).
nlohmann::json own_reference(const nlohmann::json& details);

/// The end-pose inset's half-height [m] for an offset of `offset_m` in an inset `height_px` tall:
/// the offset is drawn 12 px long at 1 µm (and below) and 20 px longer per decade, at most half
/// the inset's height (reached at about 10 cm; beyond, only the scale bar and the label tell), so
/// up to there a larger offset looks larger (1 mm 72 px, 3 cm 102 px) on the same scale for
/// every engine.
double inset_half_height_m(double offset_m, int height_px);

struct Strip {
  std::string caption;
  std::vector<Scene> frames;
  int per_row = 6;
};

/// Snapshots for one run record (none when the record has no trace), its traces drawn in `ink`
/// (the configuration's colour from the results' context).
std::vector<Snapshot> snapshots_for(const RunResult& run, const Color& ink);
/// The frame strip of a parking-cycle run (car.cycle, car.iterated, car.iterated-beta); empty frames otherwise.
Strip strip_for(const RunResult& run, const Color& ink);

}  // namespace liftcheck::render
