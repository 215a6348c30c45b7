// The renderer draws a known scene: pixel colours at known places, text, PNG output.
#include <gtest/gtest.h>
#include <png.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include <GL/osmesa.h>

#include "reports/gl_render.hpp"
#include "reports/plots.hpp"
#include "reports/scene_build.hpp"

#include <algorithm>
#include <cmath>

using namespace liftcheck::render;
using liftcheck::Params;
using liftcheck::RunResult;

namespace {

/// A run's record as the snapshots read it: its scenario, configuration, vehicle, parameters and details.
RunResult drawn_run(const std::string& scenario, liftcheck::Vehicle vehicle, const nlohmann::json& params,
                    const nlohmann::json& details) {
  RunResult r;
  r.scenario = scenario, r.engine = "ode", r.vehicle = vehicle;
  r.params = Params::from_json(params);
  r.details = details;
  return r;
}

/// Top-down 200 x 160 view of [-1.25, 1.25] x [-1, 1]: 80 px per metre, y up.
Scene known_scene() {
  Scene s;
  s.width_px = 200;
  s.height_px = 160;
  s.camera.kind = Camera::Kind::kTopDown;
  s.camera.centre = Vec2(0, 0);
  s.camera.half_height_m = 1.0;
  s.grid_step_m = 0.0;
  s.scale_bar = false;
  s.circles.push_back({Vec2(0.5, 0.0), 0.3, Color{0, 0, 0, 0}, Color{1, 0, 0, 1}});  // red disk
  s.lines.push_back({{Vec2(-1.0, 0.5), Vec2(0.0, 0.5)}, Color{0, 0, 1, 1}, 4.0f});   // blue line
  s.pucks.push_back({Vec2(-0.6, -0.5), 0.2, 0.3, Color{0, 0.8f, 0, 1}});             // green puck
  return s;
}

std::array<int, 3> rgb(const Image& img, double x_m, double y_m) {
  const int x = static_cast<int>(100 + 80 * x_m), y = static_cast<int>(80 - 80 * y_m);
  const auto* p = img.pixel(x, y);
  return {p[0], p[1], p[2]};
}

}  // namespace

TEST(Render, KnownSceneHasKnownColours) {
  Renderer r;
  const Image img = r.render(known_scene());
  ASSERT_EQ(img.width, 200);
  ASSERT_EQ(img.height, 160);
  const auto red = rgb(img, 0.5, 0.0);
  EXPECT_GT(red[0], 240);
  EXPECT_LT(red[1], 20);
  EXPECT_LT(red[2], 20);
  const auto blue = rgb(img, -0.5, 0.5);
  EXPECT_LT(blue[0], 60);
  EXPECT_GT(blue[2], 200);
  const auto green = rgb(img, -0.6, -0.5);  // the puck's top face, lit
  EXPECT_LT(green[0], 40);
  EXPECT_GT(green[1], 150);
  const auto ground = rgb(img, 1.0, -0.8);
  EXPECT_NEAR(ground[0], 247, 3);
  EXPECT_NEAR(ground[1], 247, 3);
  EXPECT_NEAR(ground[2], 242, 3);
  // Just outside the red disk (radius 0.3 m = 24 px) the ground shows again.
  const auto outside = rgb(img, 0.5 + 0.36, 0.0);
  EXPECT_GT(outside[1], 200);
  EXPECT_NE(r.gl_version().find("Mesa"), std::string::npos);
}

TEST(Render, TextDarkensItsBox) {
  Image img;
  img.width = 120;
  img.height = 40;
  img.rgba.assign(120 * 40 * 4, 255);
  draw_text(img, "β = 0.3", 5, 5, 20.0f, Color{0, 0, 0, 1});
  int dark = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 120; ++x) dark += img.pixel(x, y)[0] < 128 ? 1 : 0;
  EXPECT_GT(dark, 40);
  EXPECT_GT(text_width("β = 0.3", 20.0f), 40);
  EXPECT_LT(text_width("β = 0.3", 20.0f), 100);
}

TEST(Render, WritesAPng) {
  Renderer r;
  const auto path = std::filesystem::temp_directory_path() / "liftcheck_render_test.png";
  write_png(path, r.render(known_scene()));
  std::ifstream in(path, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");
  EXPECT_GT(std::filesystem::file_size(path), 500u);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  // Read back by libpng: the 64-colour file is the rendered image to within a few levels.
  const Image want = r.render(known_scene());
  png_image read{};
  read.version = PNG_IMAGE_VERSION;
  ASSERT_TRUE(png_image_begin_read_from_file(&read, path.c_str()));
  read.format = PNG_FORMAT_RGBA;
  ASSERT_EQ(static_cast<int>(read.width), want.width);
  ASSERT_EQ(static_cast<int>(read.height), want.height);
  std::vector<std::uint8_t> got(PNG_IMAGE_SIZE(read));
  ASSERT_TRUE(png_image_finish_read(&read, nullptr, got.data(), 0, nullptr));
  double sum = 0;
  int worst = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const int d = std::abs(int(got[i]) - int(want.rgba[i]));
    sum += d, worst = std::max(worst, d);
  }
  EXPECT_LT(sum / got.size(), 1.0);  // mean level error
  EXPECT_LT(worst, 48);              // no colour replaced by a far one
  EXPECT_GT(worst, 0);               // it was reduced (a scene with antialiasing has more than 64 colours)
  std::filesystem::remove(path);
  EXPECT_THROW(write_png("/nonexistent-dir/x.png", r.render(known_scene())), std::runtime_error);
}

// A four-wheel run draws four wheels: the front pair at +-track/2 at their Ackermann angles for
// the recorded virtual beta (tan = l / (l cot beta -+ track/2)), the rear pair along the rod; the
// tricycle draws three.
TEST(Render, FourWheelRunDrawsFourWheels) {
  const double beta = 0.3, l = 1.0, track = 0.8;
  nlohmann::json params = {{"R", 0.3}, {"l", l}, {"track", track}, {"wheels", "4"}, {"steering", "ackermann"}};
  const nlohmann::json details = {{"trace", {{0.0, 0.0, beta, 0.0, 0.0, 0.0}, {1.0, 1.0, beta, 0.3, 0.05, 0.1}}}};
  RunResult run = drawn_run("car.circle", liftcheck::Vehicle::kCar, params, details);
  const auto four = snapshots_for(run, Color{0, 0, 1, 1});
  ASSERT_FALSE(four.empty());
  const auto& wheels = four.front().scene.wheels;
  ASSERT_EQ(wheels.size(), 4u);
  const double c = 1.0 / std::tan(beta);
  EXPECT_NEAR(wheels[0].heading_rad, std::atan(l / (c - 0.5 * track / l)), 1e-12);  // left: inner
  EXPECT_NEAR(wheels[1].heading_rad, std::atan(l / (c + 0.5 * track / l)), 1e-12);  // right: outer
  EXPECT_NEAR((wheels[0].centre - wheels[1].centre).norm(), track, 1e-12);
  EXPECT_NEAR(wheels[0].centre.y(), 0.5 * track, 1e-12);
  params["wheels"] = "3";
  run.params = Params::from_json(params);
  EXPECT_EQ(snapshots_for(run, Color{0, 0, 1, 1}).front().scene.wheels.size(), 3u);
}

// The end snapshot's inset shows an end pose 1 mm off the exact one across at least 20 pixels, and
// a larger offset across more (3 cm at least 25 px more than 1 mm, 31 µm and 33.7 mm as unlike):
// its scale is read from the inset's scene (pixels over the metres its camera spans), and the
// offset is measured between the two front-axle crosses it draws.
TEST(Render, EndInsetShowsAMillimetreOffset) {
  std::vector<double> shown;
  for (const double offset_m : {31e-6, 1e-3, 4e-3, 0.03, 0.0337, 0.05}) {
    const nlohmann::json reference = {{0.0, 0.0, 0.3, 0.0, 0.0, 0.0}, {1.0, 1.0, 0.3, 0.3, 0.0, 0.0}};
    const nlohmann::json trace = {{0.0, 0.0, 0.3, 0.0, 0.0, 0.0}, {1.0, 1.0, 0.3, 0.3, offset_m, 0.0}};
    const RunResult run = drawn_run("car.circle", liftcheck::Vehicle::kCar, {{"R", 0.3}, {"l", 1.0}},
                                    {{"trace", trace}, {"reference", reference}});
    const auto shots = snapshots_for(run, Color{0, 0, 1, 1});
    const auto end = std::find_if(shots.begin(), shots.end(), [](const Snapshot& s) { return s.tag == "end"; });
    ASSERT_NE(end, shots.end());
    ASSERT_EQ(end->insets.size(), 1u);
    const Scene& in = end->insets.front().scene;
    ASSERT_EQ(in.camera.kind, Camera::Kind::kTopDown);
    const double px_per_m = in.height_px / (2.0 * in.camera.half_height_m);
    ASSERT_EQ(in.markers.size(), 2u);  // the exact front-axle centre, then the engine's
    const double shown_px = (in.markers[1].at - in.markers[0].at).norm() * px_per_m;
    EXPECT_NEAR((in.markers[1].at - in.markers[0].at).norm(), offset_m, 1e-12);
    EXPECT_GE(shown_px, 20.0) << "offset " << offset_m << " m";
    EXPECT_LE(shown_px, 0.9 * in.height_px) << "both poses inside the inset";
    EXPECT_TRUE(in.scale_bar);
    // Pasted inside the snapshot.
    EXPECT_GE(end->insets.front().x_px, 0);
    EXPECT_LE(end->insets.front().x_px + in.width_px, end->scene.width_px);
    shown.push_back(shown_px);
  }
  ASSERT_EQ(shown.size(), 6u);
  for (std::size_t i = 1; i < shown.size(); ++i) EXPECT_GT(shown[i], shown[i - 1]) << "larger offsets look larger";
  EXPECT_NEAR(shown[1], 72.0, 0.5);      // 1 mm: 12 px + 3 decades of 20 px
  EXPECT_GE(shown[3] - shown[1], 25.0);  // 3 cm against 1 mm
  EXPECT_GE(shown[4] - shown[0], 60.0);  // 33.7 mm against 31 µm
}

// A disk run is drawn and plotted against what its verdict measures: the exact lift before the
// engine's first contact and, from that contact on, the exact inelastic response
// (after_contact.reference), not the lift's path through N; the snapshot marks where that
// response has M at the moment shown.
TEST(Render, DisksAfterContactAgainstTheExactResponse) {
  const nlohmann::json lift = {
      {0.0, 0.0, 0.0, 5.0, 0.0}, {1.0, 1.0, 0.0, 5.0, 0.0}, {2.0, 2.0, 0.0, 5.0, 0.0}, {3.0, 3.0, 0.0, 5.0, 0.0}};
  const nlohmann::json response = {{1.5, 1.5, 0.0, 5.0, 0.0}, {2.0, 1.5, 0.4, 5.0, 0.0}, {3.0, 1.5, 1.4, 5.0, 0.0}};
  const nlohmann::json trace = {
      {0.0, 0.0, 0.0, 5.0, 0.0}, {1.0, 1.0, 0.0, 5.0, 0.0}, {2.0, 1.5, 0.41, 5.0, 0.0}, {3.0, 1.5, 1.39, 5.0, 0.0}};
  const nlohmann::json details = {{"trace", trace},
                                  {"reference", lift},
                                  {"after_contact", {{"from_t_s", 1.5}, {"reference", response}}},
                                  {"t_contact_measured_s", 1.5}};
  const nlohmann::json exact = own_reference(details);
  ASSERT_EQ(exact.size(), 5u);  // the lift's rows before 1.5 s, then the response's
  EXPECT_EQ(exact[1], lift[1]);
  EXPECT_EQ(exact[2], response[0]);
  EXPECT_EQ(exact[4], response[2]);
  EXPECT_EQ(own_reference({{"reference", lift}}), lift);  // no contact: the lift
  const RunResult run = drawn_run("disks.oblique", liftcheck::Vehicle::kDisks, nlohmann::json::object(), details);
  const auto shots = snapshots_for(run, Color{0, 0, 1, 1});
  const auto end = std::find_if(shots.begin(), shots.end(), [](const Snapshot& s) { return s.tag == "end"; });
  ASSERT_NE(end, shots.end());
  const auto exact_m = std::find_if(end->scene.circles.begin(), end->scene.circles.end(), [](const auto& c) {
    return std::abs(c.radius_m - 1.0) < 1e-12 && (c.centre - Vec2(1.5, 1.4)).norm() < 1e-12;
  });
  EXPECT_NE(exact_m, end->scene.circles.end()) << "the exact response's M at the end, outlined";
}

// A renderer leaves no destroyed context current on its thread.
TEST(Render, ReleasesItsContext) {
  {
    Renderer r;
    r.render(known_scene());
    ASSERT_NE(OSMesaGetCurrentContext(), nullptr);
  }
  EXPECT_EQ(OSMesaGetCurrentContext(), nullptr);
}

// The context is made current once and kept while pictures keep their size: two renderers on one
// thread, alternating, and one renderer changing size, draw each picture as a renderer of its own.
TEST(Render, AlternatingRenderersAndSizesDrawTheirOwnPictures) {
  Scene red = known_scene(), blue = known_scene(), large = known_scene();
  blue.circles.front().fill = Color{0, 0, 1, 1};
  large.width_px = 320, large.height_px = 240;
  const auto alone = [](const Scene& s) {
    Renderer r;
    return r.render(s);
  };
  const Image want_red = alone(red), want_blue = alone(blue), want_large = alone(large);
  ASSERT_NE(want_red.rgba, want_blue.rgba);
  Renderer a, b;
  // Each draws a picture of the size the other just drew, in turn.
  EXPECT_EQ(a.render(red).rgba, want_red.rgba);
  EXPECT_EQ(b.render(blue).rgba, want_blue.rgba);
  EXPECT_EQ(a.render(blue).rgba, want_blue.rgba);
  EXPECT_EQ(b.render(red).rgba, want_red.rgba);
  // One renderer changing size and back.
  EXPECT_EQ(a.render(large).rgba, want_large.rgba);
  EXPECT_EQ(a.render(red).rgba, want_red.rgba);
}

// Names reach gnuplot's script as single-quoted data: a quote doubled, a line break a space.
TEST(Plots, QuotesNamesAsData) {
  EXPECT_EQ(liftcheck::gnuplot_quote("ode"), "'ode'");
  EXPECT_EQ(liftcheck::gnuplot_quote("it's"), "'it''s'");
  EXPECT_EQ(liftcheck::gnuplot_quote("x', system('touch F'), '"), "'x'', system(''touch F''), '''");
  EXPECT_EQ(liftcheck::gnuplot_quote("a\nb\r`c`"), "'a b `c`'");
  EXPECT_EQ(liftcheck::gnuplot_quote(""), "''");
}

#include "reports/ci.hpp"

namespace {

using liftcheck::Expectation;
using liftcheck::Metric;
using liftcheck::Status;
using liftcheck::SuiteResults;
using liftcheck::TolKind;

/// A configuration named with a '|' and an error message with a line break and an ANSI escape:
/// summary.md keeps its lines and its table's columns, junit.xml holds no character XML forbids.
SuiteResults odd_results() {
  RunResult run = liftcheck::error_result("car.circle", "a|b", liftcheck::Vehicle::kCar, "boom\nFAIL forged | \x1b[2J");
  run.wall_s = 0.1;
  SuiteResults results;
  results.context.engines.push_back({.name = "a|b"});
  results.runs = {run};
  return results;
}

TEST(Escape, SummaryMarkdownKeepsItsLinesAndColumns) {
  const std::string md = liftcheck::summary_markdown(odd_results(), "");
  std::istringstream lines(md);
  std::string line;
  int bullets = 0;
  while (std::getline(lines, line)) {
    EXPECT_NE(line.rfind("FAIL", 0), 0u) << line;
    if (line.rfind("- **car.circle**", 0) == 0) {
      ++bullets;
      EXPECT_NE(line.find("boom?FAIL forged \\| ?\\[2J"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(bullets, 1);
  EXPECT_NE(md.find("| a\\|b | 0 | 0 | 0 | **1** |  |\n"), std::string::npos) << md;
  EXPECT_EQ(md.find('\x1b'), std::string::npos);
}

TEST(Escape, JunitHoldsNoControlCharacter) {
  const std::string xml = liftcheck::junit_xml(odd_results());
  for (char c : xml) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20 && c != '\n') << static_cast<int>(c);
  EXPECT_NE(xml.find("<error message=\"boom\nFAIL forged | ?[2J\"/>"), std::string::npos)
      << xml;  // a line break is allowed in XML
}

/// A metric as score() gives it: an absolute tolerance, expected 0.
Metric metric(const std::string& name, double measured, double tolerance) {
  Metric m;
  m.name = name, m.kind = TolKind::kAbsolute, m.expected = 0.0, m.measured = measured;
  m.abs_error = measured, m.tolerance = tolerance;
  m.pass = m.passes_by_figures();
  return m;
}

/// A run of `scenario` on `engine` ending in `status` with `message`, judged against `listing`.
RunResult judged_run(const std::string& scenario, const std::string& engine, Status status, const std::string& message,
                     std::vector<Metric> metrics = {}, std::optional<Expectation> listing = std::nullopt) {
  RunResult r;
  r.scenario = scenario, r.engine = engine, r.status = status, r.message = message;
  r.metrics = std::move(metrics);
  r.expectation = std::move(listing);
  r.judge();
  return r;
}

// junit.xml counts errors and failures only where validate would exit 1: a listed known failure,
// even an error record, is a <skipped type="known-failure">, a run that does not apply a
// <skipped type="not-applicable">; a failure's message and each case's metrics go worst first.
TEST(Junit, ErrorsAndFailuresOnlyWhereNotAsExpected) {
  // An error listed by the start of its message (its reason "listed"), a true skip, a failure not listed.
  const RunResult known_error = judged_run("car.slope", "e1", Status::kError, "blew up", {},
                                           Expectation{.error = "blew", .reason = "listed", .measured = "an error"});
  ASSERT_EQ(known_error.verdict(), liftcheck::Verdict::kKnownFailure);
  const RunResult skip = judged_run("car.slip", "e1", Status::kSkip, "no forces");
  const RunResult fail = judged_run("car.circle", "e2", Status::kFail, "out of tolerance",
                                    {metric("a_small", 2.0, 1.0), metric("b_large", 30.0, 1.0)});
  ASSERT_EQ(fail.verdict(), liftcheck::Verdict::kFail);
  SuiteResults results;
  results.runs = {known_error, skip};
  std::string xml = liftcheck::junit_xml(results);
  EXPECT_NE(xml.find("errors=\"0\">"), std::string::npos) << xml;
  EXPECT_EQ(xml.find("<error"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<skipped type=\"known-failure\" message=\"known failure: listed\"/>"), std::string::npos);
  EXPECT_NE(xml.find("<skipped type=\"not-applicable\" message=\"no forces\"/>"), std::string::npos);
  results.runs.push_back(fail);
  xml = liftcheck::junit_xml(results);
  EXPECT_NE(xml.find("failures=\"1\" errors=\"0\">"), std::string::npos) << xml;
  const std::size_t large = xml.find("b_large: expected"), small = xml.find("a_small: expected");
  ASSERT_NE(large, std::string::npos);
  ASSERT_NE(small, std::string::npos);
  EXPECT_LT(large, small) << "worst first";
  EXPECT_NE(xml.find("b_large: expected 0, measured 30, absolute error 30, tolerance 1, 30 x tolerance OUT"),
            std::string::npos)
      << xml;
  // A known failure and a true skip differ in structure: the <skipped> element's type, which
  // Jenkins' schema allows (it has no properties on a test case).
  EXPECT_NE(xml.find("name=\"e1\" time=\"0.000000\"><skipped type=\"known-failure\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<skipped type=\"not-applicable\""), std::string::npos) << xml;
}

// validate exits 1 on a baseline regression or a report it could not build: junit.xml fails a case
// for each, so its root counts are zero exactly when validate exits 0.
TEST(Junit, BaselineRegressionsAndReportErrorsAreFailures) {
  SuiteResults results;
  std::string xml = liftcheck::junit_xml(results);
  EXPECT_NE(xml.find("<testsuites name=\"liftcheck\" tests=\"2\" failures=\"0\" errors=\"0\">"), std::string::npos)
      << xml;
  // Three regressions against the baseline (what the summary counts as its problems), a plot that failed.
  liftcheck::BaselineComparison baseline{.file = "baseline.json", .worse_factor = 10.0};
  for (const char* engine : {"e1", "e2", "e3"})
    baseline.diff.regressions.push_back({.scenario = "car.circle", .engine = engine, .from = "pass", .to = "fail"});
  ASSERT_EQ(baseline.diff.problems(), 3);
  results.baseline = baseline;
  results.report = liftcheck::ReportInfo{.errors = {"plots: gnuplot died"}};
  xml = liftcheck::junit_xml(results);
  EXPECT_NE(xml.find("<testsuites name=\"liftcheck\" tests=\"2\" failures=\"2\" errors=\"0\">"), std::string::npos)
      << xml;
  EXPECT_NE(xml.find("name=\"baseline\" time=\"0\"><failure message=\"3 regressions"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<failure message=\"plots: gnuplot died\"/>"), std::string::npos) << xml;
}

}  // namespace
