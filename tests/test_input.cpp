// What liftcheck reads from users without an engine: names suggested for typos, traces and
// results files checked field by field (harness/suggest, harness/trace, harness/results_file).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "input/read_file.hpp"
#include "input/record_view.hpp"
#include "input/results_file.hpp"
#include "input/suggest.hpp"
#include "input/trace.hpp"
#include "input/results_diff.hpp"

using namespace liftcheck;

namespace {

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// The full reader's error on `text`; the index reader of `diff` (no document) must give the same.
std::string results_error(const std::string& text) {
  const std::string full = error_of([&] { parse_results(text, "base.json"); });
  EXPECT_EQ(error_of([&] { parse_results_index(text, "base.json"); }), full)
      << "the readers disagree on: " << text.substr(0, 300);
  return full;
}
std::string trace_error(const std::string& text, Vehicle vehicle = Vehicle::kCar) {
  return error_of([&] { parse_trace(text, "trace.csv", vehicle); });
}

const char* kMetric =
    R"({"expected": 1, "measured": 1.1, "abs_error": 0.1, "rel_error": 0.1, "tolerance": 0.01, "tolerance_kind": "rel", "pass": false})";

std::string results_with(const std::string& metric, const std::string& run_extra = "") {
  return fmt::format(
      R"({{"runs": [{{"scenario": "car.circle", "engine": "ode", "status": "fail", "message": "m"{}, "metrics": {{"front_radius": {}}}}}]}})",
      run_extra, metric);
}

}  // namespace

TEST(Suggest, EditDistance) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("circel", "circle"), 1u);  // a transposition
  EXPECT_EQ(edit_distance("speeed", "speed"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  // Long inputs stay cheap: compared over their first 256 characters, the rest counted as edits.
  EXPECT_GE(edit_distance(std::string(100000, 'a'), std::string(100000, 'b')), 100000u);
}

TEST(Suggest, NearestOnlyWhenNear) {
  const std::vector<std::string> names{"car.circle", "car.cycle", "disks.copy"};
  EXPECT_EQ(nearest_name("car.circel", names), "car.circle");
  EXPECT_EQ(nearest_name("car.cylce", names), "car.cycle");
  EXPECT_EQ(nearest_name("CAR.CIRCLE", names), "car.circle");
  EXPECT_EQ(nearest_name("zzz", names), "");
  EXPECT_EQ(nearest_name("circle", names), "car.circle");  // the family left out
  EXPECT_EQ(nearest_name("circel", names), "car.circle");
  EXPECT_EQ(nearest_name("copy", names), "disks.copy");
  EXPECT_EQ(nearest_name("xy", names), "");
  EXPECT_EQ(nearest_name("", names), "");
  EXPECT_EQ(did_you_mean("disk.copy", names), "; did you mean 'disks.copy'?");
  EXPECT_EQ(did_you_mean("x", {}), "");
}

TEST(ResultsFile, AcceptsWhatDiffReads) {
  const nlohmann::json j = parse_results(results_with(kMetric), "base.json");
  EXPECT_EQ(j["runs"].size(), 1u);
  // liftcheck writes a non-finite error as null: read, and compared as an infinite error.
  const nlohmann::json head = parse_results(
      results_with(
          R"({"measured": null, "abs_error": null, "rel_error": null, "tolerance": 0.01, "tolerance_kind": "rel"})"),
      "head.json");
  const nlohmann::json d = diff_results(j, head);
  ASSERT_EQ(d["worse"].size(), 1u) << d.dump();
  EXPECT_EQ(d["worse"][0]["metric"], "front_radius");
  EXPECT_NO_THROW(diff_text(d));
  EXPECT_EQ(results_error(R"({"runs": []})"), "");
}

// results.json keeps each distinct reference trace once; reading it back gives every run its own.
TEST(ResultsFile, SharedReferencesReadBackAsWritten) {
  const nlohmann::json lift = nlohmann::json::array({{0.0, 1.0}, {0.5, 1.25}}), slide = {{0.0, 2.0}};
  nlohmann::json doc = nlohmann::json::parse(results_with(kMetric));
  nlohmann::json run = doc["runs"][0];
  doc["runs"] = nlohmann::json::array();
  for (const nlohmann::json* ref : {&lift, &slide, &lift}) {
    run["details"] = {{"reference", *ref}, {"trace", *ref}};
    doc["runs"].push_back(run);
  }
  run.erase("details");
  doc["runs"].push_back(run);  // a run without details
  const nlohmann::json written = doc;
  share_references(doc);
  ASSERT_EQ(doc["shared_references"].size(), 2u);
  EXPECT_EQ(doc["runs"][2]["details"]["reference"], (nlohmann::json{{"shared", 0}}));
  EXPECT_EQ(doc["runs"][1]["details"]["reference"], (nlohmann::json{{"shared", 1}}));
  EXPECT_EQ(doc["runs"][2]["details"]["trace"], lift);  // only the reference is shared
  EXPECT_EQ(parse_results(doc.dump(), "r.json"), written);
  doc["runs"][1]["details"]["reference"]["shared"] = 2;
  EXPECT_EQ(error_of([&] { parse_results(doc.dump(), "r.json"); }),
            "r.json: runs[1].details.reference: 'shared' must be an index into 'shared_references' (below 2), not 2");
}

// The drawn traces: at most kDrawnRows rows with the first and the last, 9 digits, and thinning
// what was thinned changes nothing (merge and report write what validate wrote).
TEST(ResultsFile, DrawnTracesThinOnce) {
  for (const std::size_t n : {std::size_t{5}, kDrawnRows, kDrawnRows + 1, std::size_t{240}, std::size_t{359},
                              std::size_t{480}, std::size_t{4001}}) {
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t i = 0; i < n; ++i) rows.push_back({0.001 * i, 1.0 / 3.0 + i, 2.0});
    nlohmann::json doc = {{"runs", {{{"details", {{"trace", rows}, {"runs", {{{"trace", rows}}}}}}}}}};
    thin_drawn_traces(doc);
    const nlohmann::json& kept = doc["runs"][0]["details"]["trace"];
    EXPECT_LE(kept.size(), kDrawnRows) << n;
    EXPECT_EQ(kept.size(), n <= kDrawnRows ? n : kept.size()) << n;
    EXPECT_EQ(kept.front()[0], 0.0);
    EXPECT_DOUBLE_EQ(kept.back()[0].get<double>(), 0.001 * (n - 1)) << n;
    EXPECT_EQ(kept.front()[1], 0.333333333);  // 9 significant digits
    EXPECT_EQ(doc["runs"][0]["details"]["runs"][0]["trace"], kept);
    const nlohmann::json once = doc;
    thin_drawn_traces(doc);
    EXPECT_EQ(doc, once) << n;
  }
}

TEST(ResultsFile, NamesFileFieldAndProblem) {
  EXPECT_EQ(results_error("{").find('\n'), std::string::npos);  // one line
  EXPECT_EQ(results_error("{").rfind("base.json: is not JSON (parse error at line 1, column 2", 0), 0u)
      << results_error("{");
  EXPECT_EQ(results_error("[]"),
            "base.json: is not a liftcheck results file (the top level is an array, not an object)");
  EXPECT_EQ(results_error("{}"), "base.json: is not a liftcheck results file (no \"runs\")");
  EXPECT_EQ(results_error(R"({"runs": 3})"), "base.json: 'runs' is a number, not an array");
  EXPECT_EQ(results_error(R"({"runs": [null]})"), "base.json: runs[0]: is null, not an object");
  EXPECT_EQ(results_error(R"({"runs": [{"engine": "ode", "status": "pass"}]})"),
            "base.json: runs[0]: missing 'scenario'");
  EXPECT_EQ(results_error(R"({"runs": [{"scenario": 1, "engine": "ode", "status": "pass"}]})"),
            "base.json: runs[0]: 'scenario' is a number, not a string");
  EXPECT_EQ(results_error(R"({"runs": [{"scenario": "s", "engine": "ode", "status": "ok"}]})"),
            "base.json: runs[0]: 'status' is 'ok', not one of pass|fail|error|skip");
  EXPECT_EQ(results_error(results_with(kMetric, R"(, "as_expected": "yes")")),
            "base.json: runs[0]: 'as_expected' is a string, not a boolean");
  EXPECT_EQ(results_error(results_with(kMetric, R"(, "verdict": 0)")),
            "base.json: runs[0]: 'verdict' is a number, not a string");
  std::string m = kMetric;
  const auto without = [&](const std::string& key) {
    nlohmann::json j = nlohmann::json::parse(m);
    j.erase(key);
    return j.dump();
  };
  const auto with = [&](const std::string& key, const nlohmann::json& v) {
    nlohmann::json j = nlohmann::json::parse(m);
    j[key] = v;
    return j.dump();
  };
  EXPECT_EQ(results_error(results_with(without("rel_error"))),
            "base.json: runs[0].metrics.front_radius: missing 'rel_error'");
  EXPECT_EQ(results_error(results_with(without("tolerance_kind"))),
            "base.json: runs[0].metrics.front_radius: missing 'tolerance_kind'");
  EXPECT_EQ(results_error(results_with(with("tolerance_kind", "relative"))),
            "base.json: runs[0].metrics.front_radius: 'tolerance_kind' is 'relative', not one of rel|abs");
  EXPECT_EQ(results_error(results_with(with("tolerance", "0.1"))),
            "base.json: runs[0].metrics.front_radius: 'tolerance' is a string, not a number or null");
  EXPECT_EQ(results_error(results_with(with("floor", nullptr))),
            "base.json: runs[0].metrics.front_radius: 'floor' is null, not a number");
  EXPECT_EQ(results_error(results_with(with("informational", 1))),
            "base.json: runs[0].metrics.front_radius: 'informational' is a number, not a boolean");
  EXPECT_EQ(results_error(results_with("[]")), "base.json: runs[0].metrics.front_radius: is an array, not an object");
  // An absolute metric needs no relative error.
  m = with("tolerance_kind", "abs");
  EXPECT_EQ(results_error(results_with(without("rel_error"))), "");
  // A name with a line break is shown on one line.
  EXPECT_EQ(results_error(R"({"runs": [{"scenario": "s", "engine": "e", "status": "pass", "metrics": {"a\nb": 1}}]})"),
            "base.json: runs[0].metrics.a?b: is a number, not an object");
}

TEST(Trace, CsvNamesLineColumnAndProblem) {
  const std::string head = "# a comment\nt,alpha,beta,x,y,phi\n";
  EXPECT_EQ(trace_error(head + "0,0,0,0,0,0\n0.01,0,0,abc,0,0\n"), "trace.csv:4: column 'x' is not a number: 'abc'");
  EXPECT_EQ(trace_error(head + "0,0,0,0,0,0\n0.01,0,0,1e400,0,0\n"),
            "trace.csv:4: column 'x' is out of the range of a double: '1e400'");
  EXPECT_EQ(trace_error(head + "0,0,0,0,0,0\n0.01,0,0,inf,0,0\n"), "trace.csv:4: column 'x' is not finite: 'inf'");
  EXPECT_EQ(trace_error(head + "0,0,0,0,0,0\n0.01,0,0,0,0\n"), "trace.csv:4: 5 columns, the header has 6");
  EXPECT_EQ(trace_error(head + "0,0,0,0,0,0\n0,0,0,0,0,0\n"), "trace.csv:4: time goes from 0 to 0 s: it must increase");
  EXPECT_EQ(trace_error(head + "0,0,0,0,0,0\n"), "trace.csv: 1 rows; a trace needs at least 2");
  EXPECT_EQ(trace_error("t,alpha,beta,x,y\n"),
            "trace.csv:1: the header has no column 'phi' (needs t,alpha,beta,x,y,phi)");
  EXPECT_EQ(trace_error(""), "trace.csv: no header line (needs t,alpha,beta,x,y,phi)");
  EXPECT_EQ(trace_error(head + "0,0,0,0,0,0\n0.01,0,0,\x01\n"), "trace.csv:4: 4 columns, the header has 6");
  EXPECT_EQ(trace_error(head + "0,0,0,0,0,0\n0.01,0,0,a\x01,0,0\n"), "trace.csv:4: column 'x' is not a number: 'a?'");
  const Trace tr = parse_trace(head + "0,0,0,0,0,0\r\n+0.01, 1,2,3,4,5\n", "trace.csv", Vehicle::kCar);
  ASSERT_EQ(tr.rows.size(), 2u);
  EXPECT_EQ(tr.rows[1], (std::vector<double>{0.01, 1, 2, 3, 4, 5}));
}

// The trace header may say the simulator's precision and settings (the road of a trace learns
// what a stepped engine's hello says); without one a trace is float64 with no settings.
TEST(Trace, HeaderCarriesPrecisionAndSettings) {
  const std::string rows = "t,alpha,beta,x,y,phi\n0,0,0,0,0,0\n0.01,0,0,0,0,0\n";
  const Trace plain = parse_trace(rows, "trace.csv", Vehicle::kCar);
  EXPECT_EQ(plain.precision, "float64");
  EXPECT_TRUE(plain.settings.empty());
  const Trace csv = parse_trace("# precision: float32\n# setting: iterations=20\n" + rows, "trace.csv", Vehicle::kCar);
  EXPECT_EQ(csv.precision, "float32");
  EXPECT_EQ(csv.settings, (std::vector<std::pair<std::string, std::string>>{{"iterations", "20"}}));
  EXPECT_EQ(trace_error("# precision: half\n" + rows), "trace.csv:1: precision 'half' must be float32 or float64");
  EXPECT_EQ(trace_error("# setting: iterations\n" + rows), "trace.csv:1: '# setting:' needs KEY=VALUE");
  const Trace js = parse_trace(R"({"precision": "float32", "settings": {"solver": "pgs"}, "rows": [
      {"t": 0, "alpha": 0, "beta": 0, "x": 0, "y": 0, "phi": 0}, {"t": 0.01, "alpha": 0, "beta": 0, "x": 0, "y": 0, "phi": 0}]})",
                               "trace.json", Vehicle::kCar);
  EXPECT_EQ(js.precision, "float32");
  EXPECT_EQ(js.settings, (std::vector<std::pair<std::string, std::string>>{{"solver", "pgs"}}));
}

TEST(Trace, JsonNamesRowColumnAndProblem) {
  EXPECT_EQ(
      trace_error(
          R"([{"t": 0, "cMx": 0, "cMy": 0, "cNx": 3, "cNy": 0}, {"t": 1, "cMx": "0", "cMy": 0, "cNx": 3, "cNy": 0}])",
          Vehicle::kDisks),
      "trace.csv: row 2: column 'cMx' is not a finite number");
  EXPECT_EQ(trace_error(R"({"rows": [{"t": 0}]})", Vehicle::kDisks), "trace.csv: row 1 has no column 'cMx'");
  EXPECT_EQ(trace_error(R"({"rows": 5})", Vehicle::kDisks),
            "trace.csv: JSON trace needs an array of rows (or {\"rows\": [...]})");
  EXPECT_EQ(trace_error(R"([1, 2])", Vehicle::kDisks),
            "trace.csv: row 1 is not an object with the columns t, cMx, cMy, cNx, cNy");
  EXPECT_EQ(trace_error("[", Vehicle::kDisks).rfind("trace.csv: is not JSON (parse error at line 1, column 2", 0), 0u)
      << trace_error("[", Vehicle::kDisks);
}

// Found by hand beyond the fuzzers' 4 kB inputs: a JSON trace nested 300000 deep overflowed the
// stack (the document was copied, recursively). Documents nested deeper than 64 levels are refused,
// and the trace's rows are read in place.
TEST(Trace, DeepJsonIsRefusedNotACrash) {
  const std::string deep = std::string(300000, '[') + std::string(300000, ']');
  EXPECT_EQ(trace_error(deep, Vehicle::kDisks), "trace.csv: JSON nested deeper than 64 levels");
  EXPECT_EQ(results_error("{\"runs\": " + deep + "}"), "base.json: JSON nested deeper than 64 levels");
  const std::string ok = std::string(60, '[') + std::string(60, ']');
  EXPECT_EQ(trace_error(ok, Vehicle::kDisks),
            "trace.csv: row 1 is not an object with the columns t, cMx, cMy, cNx, cNy");
}

// Reliability (issue 23). The JSON reader is linear (one pass of nlohmann's own DOM builder) and
// keeps the depth limit; a key repeated in one object is refused (the last would silently win, so
// a baseline ending in "runs": [] compared nothing and passed).
TEST(JsonReader, DuplicateKeysAreRefusedWithTheirPlace) {
  EXPECT_EQ(results_error(results_with(kMetric) + "x").rfind("base.json: is not JSON", 0), 0u);
  const std::string text = results_with(kMetric);
  const std::string twice = text.substr(0, text.size() - 1) + R"(, "runs": []})";
  EXPECT_EQ(results_error(twice),
            "base.json: the top level: the key 'runs' appears twice in one object (which one is meant?)");
  EXPECT_EQ(
      results_error(
          R"({"runs": [{}, {"scenario": "a", "engine": "e", "status": "pass", "metrics": {"m": {"unit": "m", "unit": "s"}}}]})"),
      "base.json: runs[1].metrics.m: the key 'unit' appears twice in one object (which one is meant?)");
  EXPECT_EQ(trace_error(R"([{"t": 0, "t": 1}])", Vehicle::kDisks),
            "trace.csv: [0]: the key 't' appears twice in one object (which one is meant?)");
  // The same key in two objects is no repetition.
  EXPECT_EQ(results_error(R"({"runs": [], "context": {"runs": 1}})"), "");
  const std::string ok = std::string(64, '[') + std::string(64, ']');
  EXPECT_EQ(error_of([&] { parse_json_text(ok, "f"); }), "");
  EXPECT_EQ(error_of([&] { parse_json_text("[" + ok + "]", "f"); }), "f: JSON nested deeper than 64 levels");
}

// A CSV trace with a UTF-8 byte-order mark is read (as results.json is); UTF-16 and NUL bytes are
// refused naming the encoding, not "no column 't'".
TEST(Trace, ByteOrderMarksAndUtf16) {
  const std::string csv = "t,alpha,beta,x,y,phi\n0,0,0,0,0,0\n0.01,0,0,1,0,0\n";
  EXPECT_EQ(parse_trace("\xEF\xBB\xBF" + csv, "trace.csv", Vehicle::kCar).rows.size(), 2u);
  EXPECT_EQ(parse_trace("\xEF\xBB\xBF[{\"t\": 0, \"cMx\": 0, \"cMy\": 0, \"cNx\": 3, \"cNy\": 0}, {\"t\": 1, \"cMx\": "
                        "0, \"cMy\": 0, \"cNx\": 3, \"cNy\": 0}]",
                        "trace.json", Vehicle::kDisks)
                .rows.size(),
            2u);
  std::string utf16 = "\xFF\xFE";
  for (char c : csv) utf16 += std::string{c, '\0'};
  EXPECT_EQ(trace_error(utf16),
            "trace.csv: is UTF-16 or UTF-32 (it starts with that byte-order mark): save it as UTF-8");
  EXPECT_EQ(
      trace_error(utf16.substr(2)),
      "trace.csv: holds a NUL byte (at byte 1): not UTF-8 text (UTF-16 without a byte-order mark?); save it as UTF-8");
}

// Every file is read with a limit, a folder is named as one, an OS error with its reason.
TEST(ReadFile, BoundedAndWithReasons) {
  EXPECT_EQ(error_of([] { read_text_file("/dev/zero", 1 << 20, "trace"); }),
            "trace '/dev/zero' is larger than the limit of 1 MiB for a trace (stopped reading there)");
  // (the CLI test reads /dev/zero as a trace and as a baseline at the real limits)
  EXPECT_EQ(error_of([] { read_trace("/tmp", Vehicle::kCar); }), "trace '/tmp' is a folder, not a file");
  EXPECT_EQ(error_of([] { read_results("/nonexistent/r.json"); }),
            "cannot read results file '/nonexistent/r.json': No such file or directory");
  EXPECT_EQ(read_text_file("/dev/null", 10, "trace"), "");
}

// Names reach JSON, which holds UTF-8 only: anything else is refused up front, never an encoding
// error after the suite; messages show a stray byte as '?'.
TEST(Names, Utf8) {
  EXPECT_TRUE(is_utf8("caf\xC3\xA9 \xE2\x9C\x85"));
  EXPECT_FALSE(is_utf8("caf\xE9"));
  EXPECT_FALSE(is_utf8("\xC0\xAF"));      // overlong '/'
  EXPECT_FALSE(is_utf8("\xED\xA0\x80"));  // a surrogate
  EXPECT_EQ(printable("a\xE9"
                      "b\n\xC3\xA9"),
            "a?b?\xC3\xA9");
  EXPECT_EQ(error_of([] { require_utf8("x\xFFy", "--name"); }),
            "--name 'x?y' is not valid UTF-8: liftcheck records names in JSON, which holds UTF-8 only (rename it)");
  EXPECT_EQ(error_of([] { read_trace("/tmp/\xFF.csv", Vehicle::kCar); }),
            "trace file name '/tmp/?.csv' is not valid UTF-8: liftcheck records names in JSON, which holds UTF-8 only "
            "(rename it)");
}

// `diff` reads a file into an index of what it compares (no document): every check of the full
// reader holds, with the same message, and the first one the full reader reports is the one
// reported (a syntax error anywhere before a run's field, a run before a later one, the top level
// before any run, a run's own fields before its metrics, its metrics in name order).
TEST(ResultsIndex, RefusesWhatTheFullReaderRefusesWithItsMessage) {
  const std::string bad_run = R"({"scenario": 1, "engine": "e", "status": "pass"})";
  EXPECT_EQ(results_error(R"({"runs": [)" + bad_run + R"(, {"x": 1, "x": 2}]})"),
            "base.json: runs[1]: the key 'x' appears twice in one object (which one is meant?)");
  EXPECT_EQ(results_error(R"({"runs": [)" + bad_run + R"(, 1]} x)").rfind("base.json: is not JSON", 0), 0u);
  EXPECT_EQ(results_error(R"({"runs": [)" + bad_run + R"(, 1]})"),
            "base.json: runs[0]: 'scenario' is a number, not a string");
  EXPECT_EQ(results_error(R"({"runs": [1, )" + bad_run + "]}"), "base.json: runs[0]: is a number, not an object");
  EXPECT_EQ(results_error(R"({"runs": [{"scenario": "s", "engine": "e", "status": "pass", "scenario": "t"}]})"),
            "base.json: runs[0]: the key 'scenario' appears twice in one object (which one is meant?)");
  EXPECT_EQ(
      results_error(results_with(R"({"pass": true, "pass": false})")),
      "base.json: runs[0].metrics.front_radius: the key 'pass' appears twice in one object (which one is meant?)");
  EXPECT_EQ(
      results_error(R"({"runs": [{"scenario": "s", "engine": "e", "status": "pass", "metrics": {"z": 1, "a": []}}]})"),
      "base.json: runs[0].metrics.a: is an array, not an object");
  EXPECT_EQ(results_error(R"({"runs": [{"metrics": [], "scenario": "s", "status": "pass"}]})"),
            "base.json: runs[0]: missing 'engine'");
  EXPECT_EQ(
      results_error(
          R"({"runs": [{"scenario": "s", "engine": "e", "status": "pass", "metrics": {"m": {"tolerance_kind": "abs", "tolerance": 1, "abs_error": 0}}}]})"),
      "base.json: runs[0].metrics.m: missing 'measured'");
  EXPECT_EQ(results_error(R"({"runs": 1, "x": {"runs": [1]}})"), "base.json: 'runs' is a number, not an array");
  EXPECT_EQ(results_error(R"({"context": {"runs": [1]}})"), "base.json: is not a liftcheck results file (no \"runs\")");
  EXPECT_EQ(results_error(R"("runs")"),
            "base.json: is not a liftcheck results file (the top level is a string, not an object)");
  EXPECT_EQ(results_error(""), error_of([] { parse_json_text("", "base.json"); }));
  std::string many = R"({"runs": [{"scenario": "s", "engine": "e", "status": "pass", "params": {)";
  for (int i = 0; i < 40; ++i) many += fmt::format(R"("k{}": {}, )", i, i);
  EXPECT_EQ(results_error(many + R"("k7": 0}}]})"),
            "base.json: runs[0].params: the key 'k7' appears twice in one object (which one is meant?)");
  EXPECT_EQ(results_error(many + R"("k40": 0}}]})"), "");
}

// The index gives the diff the full reader's document gives, finding for finding.
TEST(ResultsIndex, DiffsAsTheDocumentDoes) {
  const auto run = [](const std::string& scenario, const std::string& engine, const std::string& status,
                      const std::string& rest) {
    return fmt::format(R"({{"scenario": "{}", "engine": "{}", "status": "{}"{}}})", scenario, engine, status, rest);
  };
  const std::string m1 =
      R"(, "metrics": {"b": {"measured": 2, "abs_error": 0.5, "tolerance": 0.01, "tolerance_kind": "abs"}, )"
      R"("a": {"measured": 1.5e300, "abs_error": 1, "rel_error": null, "tolerance": 1, "tolerance_kind": "rel", "floor": 2}})";
  const std::string m2 =
      R"(, "message": "boom", "verdict": "known failure", "as_expected": true, "metrics": {"a": {"measured": null, "abs_error": 1e-9, )"
      R"("rel_error": 1e-9, "tolerance": 1, "tolerance_kind": "rel"}, "b": {"measured": 3, "abs_error": 1e-6, "tolerance": 0.01, "tolerance_kind": "abs", "informational": false}})";
  const std::string base = "{\"runs\": [" + run("s2", "ode", "pass", m2) + "," + run("s1", "ode", "fail", m1) + "," +
                           run("s1", "ode", "pass", m2) + "," + run("s3", "x", "skip", "") + "," +
                           run("s0", "e", "error", R"(, "metrics": {})") + "]}";
  const std::string head = "{\"runs\": [" + run("s1", "ode", "fail", m1 + R"(, "message": "worse")") + "," +
                           run("s2", "ode", "pass", m1) + "," + run("s4", "y", "pass", m2) + "," +
                           run("s0", "e", "pass", m2) + "," + run("s0", "e", "error", R"(, "metrics": {})") + "]}";
  for (const auto& [b, h] : {std::pair{base, head}, std::pair{head, base}, std::pair{base, base}}) {
    const nlohmann::json from_documents = diff_results(parse_results(b, "b"), parse_results(h, "h"));
    const nlohmann::json from_indexes = diff_results(parse_results_index(b, "b"), parse_results_index(h, "h"));
    EXPECT_EQ(from_indexes.dump(), from_documents.dump());
    EXPECT_EQ(diff_text(from_indexes), diff_text(from_documents));
  }
  const nlohmann::json d = diff_results(parse_results_index(base, "b"), parse_results_index(head, "h"));
  EXPECT_EQ(d["regressions"].size(), 1u) << d.dump();  // s1 on ode: the later record (pass) wins in base
  EXPECT_EQ(d["added"].size(), 1u);
  EXPECT_EQ(d["removed"].size(), 1u);
  EXPECT_FALSE(d["worse"].empty());
}

// A change between two records made with different parameters or settings says so, whichever
// reader read them, and a measured figure prints to 4 significant digits, not 17.
TEST(ResultsIndex, DiffNamesTheSettingsThatDiffer) {
  const std::string metric =
      R"("metrics": {"m": {"measured": %M, "abs_error": %E, "tolerance": 0.01, "tolerance_kind": "abs"}})";
  const auto run = [&](const std::string& status, const std::string& params, const std::string& settings,
                       const std::string& measured, const std::string& error) {
    std::string m = metric;
    m.replace(m.find("%M"), 2, measured);
    m.replace(m.find("%E"), 2, error);
    return fmt::format(R"({{"runs": [{{"scenario": "car.circle", "engine": "ode-quick", "status": "{}", )"
                       R"("params": {}, "settings": {}, {}}}]}})",
                       status, params, settings, m);
  };
  const std::string base =
      run("pass", R"({"dt": 0.001, "speed": 2})", R"({"iterations": "20"})", "0.12345678901234567", "1e-5");
  const std::string head =
      run("fail", R"({"dt": 0.002, "speed": 2})", R"({"iterations": "5", "w": "1"})", "0.2345678901234567", "0.5");
  const nlohmann::json from_documents = diff_results(parse_results(base, "b"), parse_results(head, "h"));
  const nlohmann::json d = diff_results(parse_results_index(base, "b"), parse_results_index(head, "h"));
  EXPECT_EQ(d.dump(), from_documents.dump());
  ASSERT_EQ(d["regressions"].size(), 1u) << d.dump();
  EXPECT_EQ(d["regressions"][0]["settings_differ"],
            nlohmann::json({"dt 0.001 -> 0.002", "iterations 20 -> 5", "w (none) -> 1"}));
  const std::string text = diff_text(d);
  EXPECT_NE(text.find("REGRESSION car.circle on ode-quick: pass -> fail () [settings differ: dt 0.001 -> 0.002, "
                      "iterations 20 -> 5, w (none) -> 1]"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("m measured 0.2346 (was 0.1235), 50 of tolerance (was 0.001) [settings differ:"),
            std::string::npos)
      << text;
  // The same run made alike on both sides names nothing.
  const nlohmann::json same = diff_results(parse_results_index(base, "b"), parse_results_index(base, "b"));
  EXPECT_EQ(diff_text(same).find("settings differ"), std::string::npos);
}

// The typed view every reader of a record goes through: the compared error by the tolerance's
// kind, its ratio (floor included), a null figure as infinite, informational metrics not counted.
TEST(RecordView, ComparedErrorRatioAndCounting) {
  const nlohmann::json rec = nlohmann::json::parse(R"({"scenario": "car.circle", "status": "fail", "metrics": {
    "radius": {"expected": 2.0, "measured": 2.01, "abs_error": 0.01, "rel_error": 0.005, "tolerance": 0.002, "tolerance_kind": "rel", "pass": false},
    "drift":  {"expected": 0.0, "measured": 3e-4, "abs_error": 3e-4, "rel_error": null, "tolerance": 1e-3, "tolerance_kind": "abs", "pass": true, "floor": 1e-3},
    "creep":  {"expected": 0.0, "measured": 0.5, "abs_error": 0.5, "rel_error": null, "tolerance": 0.1, "tolerance_kind": "abs", "floor": 2.0, "pass": false},
    "lost":   {"expected": 1.0, "measured": null, "abs_error": null, "rel_error": null, "tolerance": 0.1, "tolerance_kind": "abs", "pass": false},
    "shown":  {"expected": 1.0, "measured": 1.5, "abs_error": 0.5, "rel_error": 0.5, "tolerance": 0.1, "tolerance_kind": "rel", "pass": false, "informational": true}}})");
  const liftcheck::RecordView r(rec);
  EXPECT_EQ(r.verdict(), "fail");  // a file from before verdicts: its status
  ASSERT_TRUE(r.has("radius"));
  EXPECT_FALSE(r.has("heading"));
  const liftcheck::MetricView radius = r.metric("radius"), drift = r.metric("drift"), creep = r.metric("creep");
  EXPECT_TRUE(radius.relative());
  EXPECT_DOUBLE_EQ(radius.compared_error(), 0.005);  // rel_error, not abs_error 0.01
  EXPECT_DOUBLE_EQ(radius.ratio(), 2.5);
  EXPECT_FALSE(drift.relative());
  EXPECT_DOUBLE_EQ(drift.compared_error(), 3e-4);
  EXPECT_DOUBLE_EQ(drift.ratio(), 0.3);   // abs 3e-4 over the floor 1e-3 is 0.3 too
  EXPECT_DOUBLE_EQ(creep.ratio(), 0.25);  // 5 against the tolerance, 0.25 against the floor 2.0
  EXPECT_TRUE(std::isnan(r.metric("lost").compared_error()));
  EXPECT_TRUE(std::isinf(r.metric("lost").ratio()));  // a lost figure fails, never passes
  EXPECT_TRUE(r.metric("lost").written_compared_error().is_null());
  EXPECT_FALSE(r.metric("shown").counted());
  EXPECT_TRUE(radius.counted());
  int counted = 0;
  r.each_metric([&](const std::string&, const liftcheck::MetricView& m) { counted += m.counted() && !m.pass(); });
  EXPECT_EQ(counted, 3);  // radius, creep, lost
  const nlohmann::json point = radius.point_figures();
  EXPECT_DOUBLE_EQ(point.at("rel_error").get<double>(), 0.005);
  EXPECT_DOUBLE_EQ(liftcheck::MetricView(point).rel_error(), 0.005);  // a sweep's point reads the same way
}
