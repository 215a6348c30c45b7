// What liftcheck reads from users without an engine: names suggested for typos, traces and
// results files checked field by field (harness/suggest, harness/trace, harness/results_file).
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <functional>

#include "input/read_file.hpp"
#include "input/results_codec.hpp"
#include "input/results_diff.hpp"
#include "input/results_file.hpp"
#include "input/standing.hpp"
#include "input/suggest.hpp"
#include "input/trace.hpp"
#include "results_fixture.hpp"

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

/// A results document of `runs` (run records as JSON), everything else a suite holds made valid.
nlohmann::json document_of(const nlohmann::json& runs) {
  SuiteResults empty = fixture::suite_of_every_kind();
  empty.runs.clear();
  nlohmann::json doc = encode_results(empty);
  doc["runs"] = runs;
  return doc;
}

/// The full reader's error on a document of `runs`; the index reader of `diff` must give the same.
std::string runs_error(const nlohmann::json& runs) {
  const std::string text = document_of(runs).dump();
  const std::string full = error_of([&] { parse_results(text, "base.json"); });
  EXPECT_EQ(error_of([&] { parse_results_index(text, "base.json"); }), full)
      << "the readers disagree on: " << text.substr(0, 300);
  return full;
}
/// The index reader's error on `text` (a document of any shape).
std::string index_error(const std::string& text) {
  return error_of([&] { parse_results_index(text, "base.json"); });
}
std::string trace_error(const std::string& text, Vehicle vehicle = Vehicle::kCar) {
  return error_of([&] { parse_trace(text, "trace.csv", vehicle); });
}

/// The run records of the fixture's suite, as results.json writes them.
nlohmann::json runs_of_every_kind() { return encode_results(fixture::suite_of_every_kind())["runs"]; }

/// The run record of `scenario` on `engine` among `runs`.
nlohmann::json& run_in(nlohmann::json& runs, const std::string& scenario, const std::string& engine) {
  for (auto& r : runs)
    if (r["scenario"] == scenario && r["engine"] == engine) return r;
  throw std::logic_error("no such run");
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

// A suite written and read back is the same suite: every field of every record, the verdicts
// decided again and agreeing with the written ones.
TEST(ResultsFile, ReadsBackWhatItWrites) {
  const SuiteResults suite = fixture::suite_of_every_kind();
  const std::string text = results_text(suite);
  const SuiteResults back = parse_results(text, "r.json");
  ASSERT_EQ(back.runs.size(), suite.runs.size());
  for (std::size_t i = 0; i < suite.runs.size(); ++i) {
    EXPECT_EQ(encode_run(back.runs[i]), encode_run(suite.runs[i])) << i;
    EXPECT_EQ(back.runs[i].verdict(), suite.runs[i].verdict()) << i;
  }
  EXPECT_EQ(results_text(back), text);
  // Summarised from the records read, whatever the file's summary says.
  nlohmann::json doc = nlohmann::json::parse(text);
  doc["summary"]["total"] = 528;
  doc["summary"]["unexpected"] = 0;
  EXPECT_EQ(summarize(parse_results(doc.dump(), "r.json")).total, static_cast<int>(suite.runs.size()));
  EXPECT_EQ(summarize(parse_results(doc.dump(), "r.json")).runs_unexpected, 3);
}

// results.json keeps each distinct reference trace once; reading it back gives every run its own.
TEST(ResultsFile, SharedReferencesReadBackAsWritten) {
  const nlohmann::json lift = nlohmann::json::array({{0.0, 1.0}, {0.5, 1.25}}), slide = {{0.0, 2.0}};
  SuiteResults suite = fixture::suite_of_every_kind();
  suite.runs.resize(4);
  suite.runs[0].details = {{"reference", lift}, {"trace", lift}};
  suite.runs[1].details = {{"reference", slide}, {"trace", slide}};
  suite.runs[2].details = {{"reference", lift}, {"trace", lift}};  // suite.runs[3]: no details
  const nlohmann::json doc = nlohmann::json::parse(results_text(suite));
  ASSERT_EQ(doc["shared_references"].size(), 2u);
  EXPECT_EQ(doc["runs"][2]["details"]["reference"], (nlohmann::json{{"shared", 0}}));
  EXPECT_EQ(doc["runs"][1]["details"]["reference"], (nlohmann::json{{"shared", 1}}));
  EXPECT_EQ(doc["runs"][2]["details"]["trace"], lift);  // only the reference is shared
  const SuiteResults back = parse_results(doc.dump(), "r.json");
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(back.runs[i].details, suite.runs[i].details) << i;
  nlohmann::json bad = doc;
  bad["runs"][1]["details"]["reference"]["shared"] = 2;
  EXPECT_EQ(error_of([&] { parse_results(bad.dump(), "r.json"); }),
            "r.json: runs[1].details.reference: 'shared' must be an index into 'shared_references' (below 2), not 2");
}

// The drawn traces: at most kDrawnRows rows with the first and the last, 9 digits, and thinning
// what was thinned changes nothing (merge and report write what validate wrote).
TEST(ResultsFile, DrawnTracesThinOnce) {
  for (const std::size_t n : {std::size_t{5}, kDrawnRows, kDrawnRows + 1, std::size_t{240}, std::size_t{359},
                              std::size_t{480}, std::size_t{4001}}) {
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t i = 0; i < n; ++i) rows.push_back({0.001 * i, 1.0 / 3.0 + i, 2.0});
    nlohmann::json details = {{"trace", rows}, {"runs", {{{"trace", rows}}}}};
    thin_drawn_traces(details);
    const nlohmann::json& kept = details["trace"];
    EXPECT_LE(kept.size(), kDrawnRows) << n;
    EXPECT_EQ(kept.size(), n <= kDrawnRows ? n : kept.size()) << n;
    EXPECT_EQ(kept.front()[0], 0.0);
    EXPECT_DOUBLE_EQ(kept.back()[0].get<double>(), 0.001 * (n - 1)) << n;
    EXPECT_EQ(kept.front()[1], 0.333333333);  // 9 significant digits
    EXPECT_EQ(details["runs"][0]["trace"], kept);
    const nlohmann::json once = details;
    thin_drawn_traces(details);
    EXPECT_EQ(details, once) << n;
  }
}

TEST(ResultsFile, NamesFileFieldAndProblem) {
  EXPECT_EQ(index_error("{").find('\n'), std::string::npos);  // one line
  EXPECT_EQ(index_error("{").rfind("base.json: is not JSON (parse error at line 1, column 2", 0), 0u)
      << index_error("{");
  EXPECT_EQ(index_error("[]"), "base.json: is not a liftcheck results file (the top level is an array, not an object)");
  EXPECT_EQ(index_error("{}"), "base.json: is not a liftcheck results file (no \"runs\")");
  EXPECT_EQ(index_error(R"({"runs": 3})"), "base.json: 'runs' is a number, not an array");
  EXPECT_EQ(runs_error({nullptr}), "base.json: runs[0]: is null, not an object");
  nlohmann::json runs = runs_of_every_kind();
  const auto broken = [&](const std::function<void(nlohmann::json&)>& change) {
    nlohmann::json copy = runs;
    change(run_in(copy, "s.one", "alpha"));
    return runs_error(copy);
  };
  const std::string at = "base.json: runs[5]";
  EXPECT_EQ(broken([](auto& r) { r.erase("scenario"); }), at + ": missing 'scenario'");
  EXPECT_EQ(broken([](auto& r) { r["scenario"] = 1; }), at + ": 'scenario' is a number, not a string");
  EXPECT_EQ(broken([](auto& r) { r["status"] = "ok"; }),
            at + ": 'status' is 'ok', not one of pass|fail|error|skip (s.one on alpha)");
  EXPECT_EQ(broken([](auto& r) { r["as_expected"] = "yes"; }),
            at + ": 'as_expected' is a string, not a boolean (s.one on alpha)");
  EXPECT_EQ(broken([](auto& r) { r["verdict"] = 0; }), at + ": 'verdict' is a number, not a string (s.one on alpha)");
  const std::string metric = at + ".metrics.a";
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["b"].erase("rel_error"); }),
            at + ".metrics.b: missing 'rel_error' (s.one on alpha)");
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["a"].erase("tolerance_kind"); }),
            metric + ": missing 'tolerance_kind' (s.one on alpha)");
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["a"]["tolerance_kind"] = "relative"; }),
            metric + ": 'tolerance_kind' is 'relative', not one of rel|abs (s.one on alpha)");
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["a"]["tolerance"] = "0.1"; }),
            metric + ": 'tolerance' is a string, not a number or null (s.one on alpha)");
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["a"]["floor"] = nullptr; }),
            metric + ": 'floor' is null, not a number (s.one on alpha)");
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["a"]["informational"] = 1; }),
            metric + ": 'informational' is a number, not a boolean (s.one on alpha)");
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["a"] = nlohmann::json::array(); }),
            at + ".metrics: 'a' is an array, not an object (s.one on alpha)");
  // An absolute metric needs no relative error.
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["a"].erase("rel_error"); }), "");
  // A name with a line break is shown on one line.
  EXPECT_EQ(broken([](auto& r) { r["metrics"]["a\nb"] = 1; }),
            at + ".metrics: 'a?b' is a number, not an object (s.one on alpha)");
}

// Nothing a verdict depends on is defaulted, and no field may contradict the others: each is
// refused with one line naming the file, the run and the field.
TEST(ResultsFile, RefusesAVerdictItsFieldsDoNotGive) {
  nlohmann::json runs = runs_of_every_kind();
  const auto broken = [&](const std::string& sc, const std::string& engine,
                          const std::function<void(nlohmann::json&)>& change) {
    nlohmann::json copy = runs;
    change(run_in(copy, sc, engine));
    return runs_error(copy);
  };
  // A passing run set to fail with its as_expected dropped: refused by the missing field, not
  // shown as expected; with it kept, by the status its metrics do not give.
  EXPECT_EQ(broken("s.one", "ref",
                   [](auto& r) {
                     r["status"] = "fail", r["verdict"] = "fail";
                     r.erase("as_expected");
                   }),
            "base.json: runs[0]: missing 'as_expected' (s.one on ref)");
  EXPECT_EQ(broken("s.one", "ref", [](auto& r) { r["status"] = "fail", r["verdict"] = "fail"; }),
            "base.json: runs[0]: 'status' is 'fail' but every counted metric passes (s.one on ref)");
  EXPECT_EQ(broken("s.one", "ref", [](auto& r) { r.erase("as_expected"); }),
            "base.json: runs[0]: missing 'as_expected' (s.one on ref)");
  EXPECT_EQ(broken("s.one", "ref", [](auto& r) { r.erase("verdict"); }),
            "base.json: runs[0]: missing 'verdict' (s.one on ref)");
  EXPECT_EQ(broken("s.one", "ref", [](auto& r) { r.erase("negative_control"); }),
            "base.json: runs[0]: missing 'negative_control' (s.one on ref)");
  EXPECT_EQ(broken("s.one", "beta", [](auto& r) { r["as_expected"] = true; }),
            "base.json: runs[10]: 'as_expected' is true but its status without a listing gives false (s.one on beta)");
  EXPECT_EQ(broken("s.one", "alpha", [](auto& r) { r["verdict"] = "fail"; }),
            "base.json: runs[5]: 'verdict' is 'fail' but its fields give 'known failure' (s.one on alpha)");
  // A ceiling the figure exceeds: the listing no longer gives a known failure.
  EXPECT_EQ(broken("s.one", "alpha", [](auto& r) { r["expectation"]["metrics"]["a"] = 1e-3; }),
            "base.json: runs[5]: 'as_expected' is true but its listing gives false (s.one on alpha)");
  EXPECT_EQ(broken("s.one", "alpha", [](auto& r) { r["metrics"]["a"]["pass"] = true; }),
            "base.json: runs[5].metrics.a: 'pass' is true but its absolute error 0.003 is over its tolerance 0.001 "
            "(s.one on alpha)");
  EXPECT_EQ(broken("s.two", "ref", [](auto& r) { r["status"] = "fail"; }),
            "base.json: runs[1]: 'status' is 'fail' but every counted metric passes (s.two on ref)");
  EXPECT_EQ(broken("s.control", "alpha", [](auto& r) { r["negative_control"] = false; }),
            "base.json: runs[9]: 'as_expected' is true but its status without a listing gives false (s.control on "
            "alpha)");
  // A run given twice, whatever its figures: one run, two positions.
  nlohmann::json twice = runs;
  twice.push_back(run_in(twice, "s.one", "ref"));
  twice.back()["metrics"]["a"]["measured"] = 2e-9, twice.back()["metrics"]["a"]["abs_error"] = 2e-9;
  EXPECT_EQ(runs_error(twice), "base.json: runs[15] repeats runs[0]: s.one on ref is one run, given twice");
  // A file of an older format is named as such.
  nlohmann::json old = document_of(runs);
  old.erase("liftcheck_results");
  EXPECT_EQ(error_of([&] { parse_results(old.dump(), "old.json"); }),
            "old.json: is in the results format 1 of another liftcheck; this one reads format 2 (write it again with "
            "this liftcheck's validate)");
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
  EXPECT_EQ(index_error("{\"runs\": " + deep + "}"), "base.json: JSON nested deeper than 64 levels");
  EXPECT_EQ(error_of([&] { parse_results("{\"runs\": " + deep + "}", "base.json"); }),
            "base.json: JSON nested deeper than 64 levels");
  const std::string ok = std::string(60, '[') + std::string(60, ']');
  EXPECT_EQ(trace_error(ok, Vehicle::kDisks),
            "trace.csv: row 1 is not an object with the columns t, cMx, cMy, cNx, cNy");
}

// Reliability (issue 23). The JSON reader is linear (one pass of nlohmann's own DOM builder) and
// keeps the depth limit; a key repeated in one object is refused (the last would silently win, so
// a baseline ending in "runs": [] compared nothing and passed).
TEST(JsonReader, DuplicateKeysAreRefusedWithTheirPlace) {
  const std::string text = document_of(runs_of_every_kind()).dump();
  EXPECT_EQ(index_error(text + "x").rfind("base.json: is not JSON", 0), 0u);
  const std::string twice = text.substr(0, text.size() - 1) + R"(, "runs": []})";
  EXPECT_EQ(index_error(twice),
            "base.json: the top level: the key 'runs' appears twice in one object (which one is meant?)");
  EXPECT_EQ(error_of([&] { parse_results(twice, "base.json"); }), index_error(twice));
  EXPECT_EQ(index_error(R"({"runs": [{}, {"scenario": "a", "metrics": {"m": {"unit": "m", "unit": "s"}}}]})"),
            "base.json: runs[1].metrics.m: the key 'unit' appears twice in one object (which one is meant?)");
  EXPECT_EQ(trace_error(R"([{"t": 0, "t": 1}])", Vehicle::kDisks),
            "trace.csv: [0]: the key 't' appears twice in one object (which one is meant?)");
  // The same key in two objects is no repetition.
  EXPECT_EQ(index_error(R"({"liftcheck_results": 2, "runs": [], "context": {"runs": 1}})").find("appears twice"),
            std::string::npos);
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
// reader holds on the runs, with the same message, and the first bad run is the one reported.
TEST(ResultsIndex, RefusesWhatTheFullReaderRefusesWithItsMessage) {
  nlohmann::json runs = runs_of_every_kind();
  nlohmann::json bad = runs;
  bad[3]["scenario"] = 1;
  bad[7]["status"] = "great";
  EXPECT_EQ(runs_error(bad), "base.json: runs[3]: 'scenario' is a number, not a string");
  EXPECT_EQ(index_error(R"({"runs": [{"x": 1, "x": 2}]})"),
            "base.json: runs[0]: the key 'x' appears twice in one object (which one is meant?)");
  EXPECT_EQ(index_error(R"({"runs": [1]} x)").rfind("base.json: is not JSON", 0), 0u);
  nlohmann::json numbered = document_of(runs);
  numbered["runs"] = nlohmann::json::array({1, {{"x", 1}}});
  EXPECT_EQ(index_error(numbered.dump()), "base.json: runs[0]: is a number, not an object");
  EXPECT_EQ(index_error(R"({"liftcheck_results": 2, "runs": []})"), "base.json: missing 'context'");
  EXPECT_EQ(index_error(R"({"runs": 1, "x": {"runs": [1]}})"), "base.json: 'runs' is a number, not an array");
  EXPECT_EQ(index_error(R"({"context": {"runs": [1]}})"), "base.json: is not a liftcheck results file (no \"runs\")");
  EXPECT_EQ(index_error(R"("runs")"),
            "base.json: is not a liftcheck results file (the top level is a string, not an object)");
  EXPECT_EQ(index_error(""), error_of([] { parse_json_text("", "base.json"); }));
  nlohmann::json dup = runs;
  std::string text = document_of(dup).dump();
  const std::string needle = "\"metrics\":{\"a\":{";
  text.insert(text.find(needle) + needle.size(), "\"pass\":true,");
  EXPECT_EQ(error_of([&] { parse_results_index(text, "base.json"); }),
            "base.json: runs[0].metrics.a: the key 'pass' appears twice in one object (which one is meant?)");
}

namespace {

/// The diff of two suites, from their indexes as `diff` reads them and from the typed results.
std::pair<ResultsDiff, ResultsDiff> both_diffs(const SuiteResults& base, const SuiteResults& head) {
  const ResultsDiff typed = diff_results(index_of(base), index_of(head));
  const ResultsDiff indexed =
      diff_results(parse_results_index(results_text(base), "b"), parse_results_index(results_text(head), "h"));
  return {typed, indexed};
}

}  // namespace

// The index gives the diff the typed results give, finding for finding.
TEST(ResultsIndex, DiffsAsTheDocumentDoes) {
  const SuiteResults base = fixture::suite_of_every_kind();
  SuiteResults head = base;
  head.runs[0] = fixture::run("s.one", "ref", {fixture::metric("a", TolKind::kAbsolute, 0.0, 5e-3, 1e-3)});
  head.runs.erase(head.runs.begin() + 2);
  head.runs.push_back(fixture::run("s.new", "ref", {fixture::metric("a", TolKind::kAbsolute, 0.0, 1e-9, 1e-3)}));
  const SuiteResults* h0 = &head;
  for (const auto& [b, h] : {std::pair{&base, h0}, std::pair{h0, &base}, std::pair{&base, &base}}) {
    const auto [typed, indexed] = both_diffs(*b, *h);
    EXPECT_EQ(encode_diff(indexed).dump(), encode_diff(typed).dump());
    EXPECT_EQ(diff_text(indexed), diff_text(typed));
  }
  const ResultsDiff d = both_diffs(base, head).second;
  EXPECT_EQ(d.regressions.size(), 1u) << encode_diff(d).dump();  // s.one on ref: pass -> fail
  EXPECT_EQ(d.added.size(), 1u);
  EXPECT_EQ(d.removed.size(), 1u);
  EXPECT_FALSE(d.worse.empty());
}

// A change between two records made with different parameters or settings says so, whichever
// reader read them, and a measured figure prints to 4 significant digits, not 17.
TEST(ResultsIndex, DiffNamesTheSettingsThatDiffer) {
  SuiteResults base = fixture::suite_of_every_kind(), head = base;
  base.runs = {fixture::run("car.circle", "ode-quick",
                            {fixture::metric("m", TolKind::kAbsolute, 0.0, 0.12345678901234567 * 1e-4, 0.01)})};
  base.runs[0].settings = {{"iterations", "20"}};
  head.runs = {fixture::run("car.circle", "ode-quick",
                            {fixture::metric("m", TolKind::kAbsolute, 0.0, 0.2345678901234567 * 2, 0.01)})};
  head.runs[0].params = Params::from_json({{"dt", 0.002}, {"wheels", "3"}});
  head.runs[0].settings = {{"iterations", "5"}, {"w", "1"}};
  head.runs[0].judge();
  const auto [typed, d] = both_diffs(base, head);
  EXPECT_EQ(encode_diff(d).dump(), encode_diff(typed).dump());
  ASSERT_EQ(d.regressions.size(), 1u) << encode_diff(d).dump();
  EXPECT_EQ(d.regressions[0].settings_differ,
            (std::vector<std::string>{"dt 0.001 -> 0.002", "iterations 20 -> 5", "w (none) -> 1"}));
  const std::string text = diff_text(d);
  EXPECT_NE(text.find("REGRESSION car.circle on ode-quick: pass -> fail () [settings differ"), std::string::npos)
      << text;
  EXPECT_NE(text.find("m measured 0.4691 (was 1.235e-05), 46.9 of tolerance (was 0.00123) [settings differ:"),
            std::string::npos)
      << text;
  // The same run made alike on both sides names nothing.
  EXPECT_EQ(diff_text(both_diffs(base, base).second).find("settings differ"), std::string::npos);
}

// The figures every reader of a metric uses: the compared error by the tolerance's kind, its ratio
// (floor included), a lost figure as infinite, informational metrics not counted.
TEST(Metric, ComparedErrorRatioAndCounting) {
  using fixture::metric;
  const Metric radius = metric("radius", TolKind::kRelative, 2.0, 2.01, 0.002);
  Metric drift = metric("drift", TolKind::kAbsolute, 0.0, 3e-4, 1e-3);
  drift.floor = 1e-3;
  Metric creep = metric("creep", TolKind::kAbsolute, 0.0, 0.5, 0.1);
  creep.floor = 2.0;
  creep.pass = creep.passes_by_figures();
  Metric lost = metric("lost", TolKind::kAbsolute, 1.0, NAN, 0.1);
  const Metric shown = metric("shown", TolKind::kRelative, 1.0, 1.5, 0.1, "1", true);
  EXPECT_NEAR(radius.compared_error(), 0.005, 1e-15);  // rel_error, not abs_error 0.01
  EXPECT_NEAR(radius.ratio(), 2.5, 1e-12);
  EXPECT_FALSE(radius.pass);
  EXPECT_DOUBLE_EQ(drift.compared_error(), 3e-4);
  EXPECT_DOUBLE_EQ(drift.ratio(), 0.3);   // abs 3e-4 over the floor 1e-3 is 0.3 too
  EXPECT_DOUBLE_EQ(creep.ratio(), 0.25);  // 5 against the tolerance, 0.25 against the floor 2.0
  EXPECT_TRUE(creep.passes_by_figures());
  EXPECT_TRUE(std::isnan(lost.compared_error()));
  EXPECT_TRUE(std::isinf(lost.ratio()));  // a lost figure fails, never passes
  EXPECT_FALSE(lost.passes_by_figures());
  EXPECT_FALSE(shown.counted());
  const RunResult r = fixture::run("car.circle", "ode", {radius, drift, creep, lost, shown});
  EXPECT_EQ(r.failed_metrics(), (std::vector<std::string>{"radius", "lost"}));
  EXPECT_EQ(r.metrics_worst_first().front()->name, "lost");
  EXPECT_TRUE(std::isinf(r.worst_ratio()));
  EXPECT_EQ(encode_metric(lost)["measured"], nullptr);  // a lost figure is written as null
}
