#include "reports/scene_build.hpp"

#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numbers>

#include "input/vehicle.hpp"
#include "scenarios/details.hpp"
#include "models/ackermann.hpp"

namespace liftcheck::render {

namespace {

constexpr double kPi = std::numbers::pi;
using json = nlohmann::json;

struct Bounds {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  void add(const Vec2& p, double r = 0.0) {
    x0 = std::min(x0, p.x() - r), y0 = std::min(y0, p.y() - r);
    x1 = std::max(x1, p.x() + r), y1 = std::max(y1, p.y() + r);
  }
  bool empty() const { return !(x1 >= x0); }
};

double nice_step(double span) {
  const double raw = span / 6.0, p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) return m * p;
  return 10.0 * p;
}

void frame(Scene& s, const Bounds& b, double margin = 0.12) {
  const double aspect = static_cast<double>(s.width_px) / s.height_px;
  const double w = std::max(b.x1 - b.x0, 1e-3), h = std::max(b.y1 - b.y0, 1e-3);
  s.camera.kind = Camera::Kind::kTopDown;
  s.camera.centre = Vec2(0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1));
  s.camera.half_height_m = 0.5 * std::max(h, w / aspect) * (1.0 + 2.0 * margin);
  s.grid_step_m = nice_step(2.0 * s.camera.half_height_m);
}

Color lighten(const Color& c, float k) { return {c.r + (1 - c.r) * k, c.g + (1 - c.g) * k, c.b + (1 - c.b) * k, c.a}; }

/// Row of a trace nearest to time t (traces are sorted by time in column 0).
std::size_t row_at(const json& trace, double t) {
  std::size_t best = 0;
  double bd = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < trace.size(); ++i) {
    const double d = std::abs(trace[i][0].get<double>() - t);
    if (d < bd) bd = d, best = i;
  }
  return best;
}

void add_legend(Scene& s, const std::string& title, const std::string& engine, const Color& ink,
                const std::string& ref_name) {
  s.labels.push_back({title, Vec2(12, 10), true, 17.0f});
  s.labels.push_back({"━ " + engine, Vec2(12, 32), true, 14.0f, ink});
  s.labels.push_back({"▬ " + ref_name, Vec2(12, 50), true, 14.0f, Color{0.45f, 0.45f, 0.45f, 1.0f}});
}

// ---- car -----------------------------------------------------------------------------------

struct CarGeom {
  double R, l, track, width;
  bool four = false;      ///< two front wheels at +-track/2 (params wheels = 4)
  bool parallel = false;  ///< four wheels steered in parallel (params steering = parallel)
};

CarGeom geom_of(const RunResult& run) {
  const Params& p = run.params;
  const double R = p.num("R"), l = p.num("l");
  // Records from before the parameters existed: the tricycle with its track of 0.8 l.
  const double track = p.has("track") ? p.num("track") : 0.8 * l;
  return {R,
          l,
          track,
          0.3 * R,
          p.has("wheels") && p.str("wheels") == "4",
          p.has("steering") && p.str("steering") == "parallel"};
}

Vec2 front_of(const json& row) { return {row[3].get<double>(), row[4].get<double>()}; }
Vec2 rear_of(const json& row, double l) {
  const double phi = row[5].get<double>();
  return front_of(row) - l * Vec2(std::cos(phi), std::sin(phi));
}

/// Rear wheels' rolling angle: signed path length of the rear-axle centre up to row k, over R.
double rear_spin(const json& trace, std::size_t k, const CarGeom& g) {
  double s = 0.0;
  for (std::size_t i = 1; i <= k && i < trace.size(); ++i) {
    const Vec2 d = rear_of(trace[i], g.l) - rear_of(trace[i - 1], g.l);
    const double phi = trace[i][5].get<double>();
    s += (d.dot(Vec2(std::cos(phi), std::sin(phi))) >= 0 ? 1.0 : -1.0) * d.norm();
  }
  return s / g.R;
}

void add_car(Scene& s, const json& row, double rear_spin_rad, const CarGeom& g, float alpha = 1.0f) {
  const double a = row[1].get<double>(), beta = row[2].get<double>(), phi = row[5].get<double>();
  const Vec2 front = front_of(row), rear = rear_of(row, g.l), side(-std::sin(phi), std::cos(phi)), side_dir = side;
  const Color tyre{0.18f, 0.18f, 0.2f, alpha}, spokes{0.1f, 0.1f, 0.1f, alpha}, frame_c{0.35f, 0.37f, 0.42f, alpha};
  s.boxes.push_back({0.5 * (front + rear), phi, g.l, 0.05 * g.l, g.R * 0.9, 0.05 * g.l, frame_c});  // tie rod
  s.boxes.push_back({rear, phi + kPi / 2, g.track, 0.04 * g.l, g.R * 0.95, 0.04 * g.l, frame_c});   // rear axle
  if (g.four) {
    // Two front wheels at +-track/2, each at its Ackermann angle for the virtual beta (or at beta,
    // steered in parallel), on a front axle across the car.
    s.boxes.push_back({front, phi + kPi / 2, g.track, 0.04 * g.l, g.R * 0.95, 0.04 * g.l, frame_c});  // front axle
    for (const car::Side side : {car::Side::kLeft, car::Side::kRight}) {
      const double k = side == car::Side::kLeft ? 0.5 : -0.5;
      const double b = g.parallel ? beta : car::ackermann_wheel_angle(beta, g.l, g.track, side);
      s.wheels.push_back({front + k * g.track * side_dir, g.R, g.width, phi + b, a, tyre, spokes});
    }
  } else {
    s.boxes.push_back(
        {front, phi + beta + kPi / 2, 1.6 * g.width, 0.04 * g.l, g.R * 0.95, 0.04 * g.l, frame_c});  // front axle stub
    s.wheels.push_back({front, g.R, g.width, phi + beta, a, tyre, spokes});
  }
  for (double k : {-0.5, 0.5})
    s.wheels.push_back({rear + k * g.track * side, g.R, g.width, phi, rear_spin_rad, tyre, spokes});
  // Steering angle: an arc at the front axle from the tie rod's heading to the wheel's.
  if (std::abs(beta) > 1e-3) {
    Polyline arc{{}, Color{0.75f, 0.1f, 0.1f, alpha}, 2.0f};
    const double r = 1.4 * g.R;
    for (int k = 0; k <= 24; ++k) {
      const double ang = phi + beta * k / 24.0;
      arc.points.push_back(front + r * Vec2(std::cos(ang), std::sin(ang)));
    }
    arc.points.insert(arc.points.begin(), front);
    arc.points.push_back(front);
    s.lines.push_back(arc);
  }
}

/// Front- and rear-axle paths of a trace up to row `upto`.
void add_paths(Scene& s, const json& trace, std::size_t upto, const CarGeom& g, const Color& c, float width,
               Bounds* b) {
  Polyline f{{}, c, width}, r{{}, c, std::max(1.0f, width * 0.6f)};
  for (std::size_t i = 0; i <= upto && i < trace.size(); ++i) {
    f.points.push_back(front_of(trace[i]));
    r.points.push_back(rear_of(trace[i], g.l));
    if (b) b->add(f.points.back(), g.R), b->add(r.points.back(), g.R + 0.5 * g.track);
  }
  s.lines.push_back(f);
  s.lines.push_back(r);
}

Scene car_scene(const RunResult& run, const Color& ink, double t, bool full_paths) {
  Scene s;
  const CarGeom g = geom_of(run);
  const json& tr = run.details[detail_key::kTrace];
  const std::size_t k = row_at(tr, t);
  Bounds b;
  if (run.details.contains(detail_key::kReference)) {
    const json& ref = run.details[detail_key::kReference];
    add_paths(s, ref, full_paths ? ref.size() : row_at(ref, t), g, Color{0.55f, 0.55f, 0.55f, 0.55f}, 7.0f, &b);
  }
  add_paths(s, tr, full_paths ? tr.size() : k, g, ink, 2.0f, &b);
  add_car(s, tr[k], rear_spin(tr, k, g), g);
  b.add(front_of(tr[k]), g.l * 0.6);
  b.add(rear_of(tr[k], g.l), g.l * 0.6);
  frame(s, b);
  add_legend(s, fmt::format("{} · {} · t = {:.2f} s", run.scenario, run.engine, tr[k][0].get<double>()), run.engine,
             ink, "exact lift of the commanded path");
  return s;
}

// ---- disks ---------------------------------------------------------------------------------

Scene disk_scene(const RunResult& run, const Color& ink, double t, const std::string& moment) {
  Scene s;
  const json& d = run.details;
  const json& tr = d[detail_key::kTrace];
  const std::size_t k = row_at(tr, t);
  Bounds b;
  const auto cM = [](const json& row) { return Vec2(row[1].get<double>(), row[2].get<double>()); };
  const auto cN = [](const json& row) { return Vec2(row[3].get<double>(), row[4].get<double>()); };
  Polyline nline{{}, Color{0.5f, 0.5f, 0.5f, 1.0f}, 1.5f, true}, mline{{}, ink, 2.0f};
  for (const auto& row : tr) {
    nline.points.push_back(cN(row)), mline.points.push_back(cM(row));
    b.add(cN(row), 1.0), b.add(cM(row), 1.0);
  }
  if (d.contains(detail_key::kReference)) {
    const json exact = own_reference(d);
    Polyline ref{{}, Color{0.55f, 0.55f, 0.55f, 0.55f}, 7.0f};
    for (const auto& row : exact) ref.points.push_back(cM(row));
    s.lines.push_back(ref);
    // Where the exact answer has M at this moment: an outline the engine's M should fill.
    if (!exact.empty())
      s.circles.push_back(
          {cM(exact[row_at(exact, t)]), 1.0, Color{0.35f, 0.35f, 0.35f, 0.9f}, Color{0, 0, 0, 0}, 2.0f, true});
  }
  if (d.contains(detail_key::kCollisionCentre) && d[detail_key::kCollisionCentre].is_array()) {
    const Vec2 c(d[detail_key::kCollisionCentre][0].get<double>(), d[detail_key::kCollisionCentre][1].get<double>());
    const double r = d[detail_key::kCollisionRadius].get<double>();
    if (r < 1e3) {
      s.circles.push_back({c, r, Color{0.8f, 0.1f, 0.1f, 0.9f}, Color{0.9f, 0.2f, 0.2f, 0.18f}, 2.0f});
      s.labels.push_back({"D (Lemma 6.1)", c + Vec2(0.0, r * 1.05), false, 14.0f, Color{0.7f, 0.1f, 0.1f, 1.0f}});
      b.add(c, r);
    }
  }
  s.lines.push_back(nline);
  s.lines.push_back(mline);
  // The forbidden zone of c_M: the disk of radius 2 about c_N.
  s.circles.push_back({cN(tr[k]), 2.0, Color{0.45f, 0.45f, 0.45f, 0.9f}, Color{0, 0, 0, 0}, 1.5f, true});
  s.pucks.push_back({cN(tr[k]), 1.0, 0.25, Color{0.80f, 0.55f, 0.45f, 1.0f}});
  s.pucks.push_back({cM(tr[k]), 1.0, 0.25, lighten(ink, 0.45f)});
  s.labels.push_back({"N", cN(tr[k]) + Vec2(-0.15, 0.35), false, 16.0f});
  s.labels.push_back({"M", cM(tr[k]) + Vec2(-0.15, 0.35), false, 16.0f});
  if (d[detail_key::kTContactMeasured].is_number()) {
    const std::size_t kc = row_at(tr, d[detail_key::kTContactMeasured].get<double>());
    s.markers.push_back({0.5 * (cM(tr[kc]) + cN(tr[kc])), 0.25, colors::kContact});
  }
  frame(s, b, 0.08);
  add_legend(s, fmt::format("{} · {} · {} t = {:.2f} s", run.scenario, run.engine, moment, tr[k][0].get<double>()),
             run.engine, ink,
             d.contains(detail_key::kAfterContact)
                 ? "exact lift (21), after contact the exact response; dashed: exact M"
                 : "exact lift (21); dashed: exact M");
  return s;
}

/// car.covariance: every start of the manoeuvre (turned and shifted by E(2)) with its path, the start
/// pose faint and the end pose solid.
Scene covariance_scene(const RunResult& run, const Color& ink) {
  Scene s;
  const CarGeom g = geom_of(run);
  Bounds b;
  for (const auto& r : run.details[detail_key::kRuns]) {
    const json& tr = r[detail_key::kTrace];
    if (!tr.is_array() || tr.empty()) continue;
    add_paths(s, tr, tr.size(), g, ink, 2.0f, &b);
    add_car(s, tr.front(), 0.0, g, 0.25f);
    add_car(s, tr.back(), rear_spin(tr, tr.size() - 1, g), g);
  }
  frame(s, b, 0.05);
  add_legend(s, fmt::format("{} · {} · {} starts", run.scenario, run.engine, run.details[detail_key::kRuns].size()),
             run.engine, ink, "(faint: start poses)");
  return s;
}

/// The tie rod's line and the front wheel's heading through the front-axle centre of `row`, long
/// enough to cross a view `half_m` high, and a cross at the centre.
void add_pose_marks(Scene& s, const json& row, double half_m, const Color& c, float width) {
  const Vec2 f = front_of(row);
  const double phi = row[5].get<double>(), beta = row[2].get<double>();
  const double L = 4.0 * half_m;
  s.lines.push_back({{f - L * Vec2(std::cos(phi), std::sin(phi)), f}, c, width});
  s.lines.push_back({{f - 0.5 * L * Vec2(std::cos(phi + beta), std::sin(phi + beta)),
                      f + 0.5 * L * Vec2(std::cos(phi + beta), std::sin(phi + beta))},
                     c,
                     std::max(1.0f, width * 0.5f),
                     true});
  s.markers.push_back({f, 0.12 * half_m, c});
}

}  // namespace

/// What a run is measured against, as rows like its trace: the scenario's reference (the exact
/// lift, or what kReferenceLabel names), and for the disks after the engine's first contact the
/// exact inelastic response from that contact on (after_contact.reference), which the verdict
/// compares M's path with; the lift's path through N would not apply there.
json own_reference(const json& d) {
  const json& ref = d[detail_key::kReference];
  const auto ac = d.find(detail_key::kAfterContact);
  if (ac == d.end() || !ac->is_object() || !ac->contains(detail_key::kReference) ||
      !(*ac)[detail_key::kReference].is_array() || (*ac)[detail_key::kReference].empty() ||
      !ac->contains(detail_key::kFromT) || !(*ac)[detail_key::kFromT].is_number())
    return ref;
  const double from = (*ac)[detail_key::kFromT].get<double>();
  json rows = json::array();
  for (const auto& r : ref)
    if (r[0].get<double>() < from) rows.push_back(r);
  for (const auto& r : (*ac)[detail_key::kReference]) rows.push_back(r);
  return rows;
}

Inset end_pose_inset(const RunResult& run, const Color& ink, const Scene& main) {
  Inset in;
  Scene& s = in.scene;
  s.width_px = 300, s.height_px = 225;
  in.x_px = main.width_px - s.width_px - 14, in.y_px = 14;
  const json& tr = run.details[detail_key::kTrace];
  const json& ref = run.details.contains(detail_key::kReference) ? run.details[detail_key::kReference] : tr;
  const Vec2 fe = front_of(tr.back()), fx = front_of(ref.back());
  const double offset = (fe - fx).norm();
  const double half = inset_half_height_m(offset, s.height_px);
  s.camera.kind = Camera::Kind::kTopDown;
  s.camera.centre = 0.5 * (fe + fx);
  s.camera.half_height_m = half;
  s.grid_step_m = nice_step(2.0 * half);
  const auto tail = [&](const json& t, const Color& c, float w) {
    Polyline p{{}, c, w};
    for (std::size_t i = t.size() > 40 ? t.size() - 40 : 0; i < t.size(); ++i) p.points.push_back(front_of(t[i]));
    s.lines.push_back(p);
  };
  tail(ref, Color{0.55f, 0.55f, 0.55f, 0.55f}, 9.0f);
  tail(tr, ink, 2.0f);
  add_pose_marks(s, ref.back(), half, Color{0.45f, 0.45f, 0.45f, 0.9f}, 6.0f);
  add_pose_marks(s, tr.back(), half, ink, 2.5f);
  s.labels.push_back({fmt::format("end pose, offset {}", offset >= 1e-3 ? fmt::format("{:.3g} mm", offset * 1e3)
                                                                        : fmt::format("{:.3g} µm", offset * 1e6)),
                      Vec2(8, 6), true, 13.0f});
  s.labels.push_back({"grey: exact, colour: engine; +20 px a decade", Vec2(8, 24), true, 11.0f});
  return in;
}

double inset_half_height_m(double offset_m, int height_px) {
  const double offset = std::max(offset_m, 1e-6);
  const double drawn_px = std::clamp(12.0 + 20.0 * std::log10(offset / 1e-6), 12.0, 0.5 * height_px);
  return offset * 0.5 * height_px / drawn_px;  // the view spans 2 half over height_px
}

std::vector<Snapshot> snapshots_for(const RunResult& run, const Color& ink) {
  std::vector<Snapshot> out;
  if (!run.details.is_object()) return out;
  if (run.details.value(detail_key::kDrawing, "") == detail_key::kDrawingStarts &&
      run.details.contains(detail_key::kRuns)) {
    out.push_back({"end", "all starts (turned over the full circle, every other one shifted) and their paths",
                   covariance_scene(run, ink)});
    return out;
  }
  if (!run.details.contains(detail_key::kTrace)) return out;
  const json& tr = run.details[detail_key::kTrace];
  if (!tr.is_array() || tr.size() < 2) return out;
  const double t0 = tr.front()[0].get<double>(), t1 = tr.back()[0].get<double>();
  if (run.vehicle == Vehicle::kDisks) {
    out.push_back({"start", "start", disk_scene(run, ink, t0, "start")});
    if (run.details[detail_key::kTContactMeasured].is_number()) {
      const double tc = run.details[detail_key::kTContactMeasured].get<double>();
      out.push_back({"contact", fmt::format("first contact, t = {:.3f} s", tc), disk_scene(run, ink, tc, "contact")});
    }
    out.push_back({"end", "end", disk_scene(run, ink, t1, "end")});
    return out;
  }
  out.push_back({"start", "start", car_scene(run, ink, t0, false)});
  Snapshot end{"end", "end, with the whole paths; inset: the end pose magnified, the engine's over the exact one",
               car_scene(run, ink, t1, true)};
  end.insets.push_back(end_pose_inset(run, ink, end.scene));
  out.push_back(end);
  return out;
}

Strip strip_for(const RunResult& run, const Color& ink) {
  Strip st;
  // A parking cycle records its number of steps: a frame at the start and after each step.
  if (!run.details.is_object() || !run.details.contains(detail_key::kSteps) ||
      !run.details.contains(detail_key::kTrace))
    return st;
  const json& tr = run.details[detail_key::kTrace];
  const CarGeom g = geom_of(run);
  const int n = run.details[detail_key::kSteps].get<int>() + 1;
  Bounds b;
  for (const auto& row : tr) b.add(front_of(row), 1.2 * g.R), b.add(rear_of(row, g.l), 0.5 * g.track + 1.2 * g.R);
  for (int i = 0; i < n; ++i) {
    Scene s;
    s.width_px = 320;
    s.height_px = 240;
    const std::size_t k = (tr.size() - 1) * i / (n - 1);
    add_car(s, tr[k], rear_spin(tr, k, g), g);
    frame(s, b, 0.05);
    s.labels.push_back({fmt::format("t = {:.2f} s", tr[k][0].get<double>()), Vec2(8, 6), true, 13.0f});
    st.frames.push_back(std::move(s));
  }
  // The last frame: start pose as a ghost, the net shift as arrows magnified to about l/2.
  Scene s;
  s.width_px = 320;
  s.height_px = 240;
  add_car(s, tr.front(), 0.0, g, 0.25f);
  add_car(s, tr.back(), rear_spin(tr, tr.size() - 1, g), g);
  const Vec2 p0 = front_of(tr.front()), p1 = front_of(tr.back());
  const double shift = (p1 - p0).norm();
  const json& ex = run.details[detail_key::kErrors][detail_key::kCommandedLiftEnd];
  const Vec2 pe(ex[0].get<double>(), ex[1].get<double>());
  // The magnification is a power of ten that keeps the longer arrow (exact or engine) within half
  // the tie rod, so that both stay in the frame.
  const double longest = std::max(shift, (pe - p0).norm());
  double mag = 1.0;
  if (longest > 0) mag = std::pow(10.0, std::floor(std::log10(0.5 * g.l / longest)));
  s.arrows.push_back({p0, p0 + mag * (pe - p0), Color{0.5f, 0.5f, 0.5f, 0.8f}, 7.0f});
  s.arrows.push_back({p0, p0 + mag * (p1 - p0), ink, 3.0f});
  b.add(p0 + mag * (pe - p0), 0.1 * g.l), b.add(p0 + mag * (p1 - p0), 0.1 * g.l);
  frame(s, b, 0.05);
  s.labels.push_back({fmt::format("shift {:.3g} mm, arrows ×{:g}", shift * 1e3, mag), Vec2(8, 6), true, 13.0f});
  st.frames.push_back(std::move(s));
  st.caption = fmt::format(
      "{} steps of the cycle; last frame: the start pose (faint) and the net shift of the front axle, "
      "magnified ×{:g} (grey: exact holonomy, colour: {})",
      n - 1, mag, run.engine);
  st.per_row = 6;
  return st;
}

}  // namespace liftcheck::render
