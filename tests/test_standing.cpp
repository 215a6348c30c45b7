// One figure of merit: a configuration's counts and worst failure, and the figure that decided each
// run, are computed once (input/standing.hpp) and every output names the same: the index's matrix,
// the scenario pages, summary.md and JUnit (the console's closing lines: tests/cli_test.sh).
#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>

#include "input/standing.hpp"
#include "reports/ci.hpp"
#include "reports/escape.hpp"
#include "reports/html.hpp"
#include "results_fixture.hpp"

using namespace liftcheck;

namespace {

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(Standing, OneWorstFailurePerConfiguration) {
  const SuiteResults suite = fixture::suite_of_every_kind();
  const std::vector<Standing> all = standings(suite);
  ASSERT_EQ(all.size(), 3u);
  // The reference passes everything; alpha's worst is its 40x failure, not the 5000x negative
  // control, the zero tolerance or the listed error; beta has three runs not as expected.
  EXPECT_EQ(all[0].counts_text(), "5 pass, 0 known, 0 skip");
  EXPECT_EQ(all[0].worst, nullptr);
  EXPECT_EQ(all[1].counts_text(), "0 pass, 5 known, 0 skip");
  EXPECT_EQ(all[1].controls, 1);
  EXPECT_EQ(all[1].worst_text(), "40× s.two b");
  EXPECT_EQ(all[2].counts_text(), "0 pass, 1 known, 1 skip, 3 not as expected");
  EXPECT_EQ(all[2].unexpected_in, (std::vector<std::string>{"s.one", "s.two", "s.four"}));
  const Summary sum = summarize(suite);
  EXPECT_EQ(sum.total, 15);
  EXPECT_EQ(sum.pass, 5);
  EXPECT_EQ(sum.known, 6);  // alpha's five (the control among them) and beta's control
  EXPECT_EQ(sum.runs_unexpected, 3);
  // The figure that decided each kind of run.
  EXPECT_EQ(deciding_of(*suite.run("s.three", "alpha")).text(), "87 N against a zero tolerance (c)");
  EXPECT_EQ(deciding_of(*suite.run("s.one", "beta")).text(), "12× (a)");
  EXPECT_EQ(deciding_of(*suite.run("s.four", "alpha")).text(), "");  // a listed error has no metric
  EXPECT_EQ(standing_rank(*suite.run("s.three", "alpha"), deciding_of(*suite.run("s.three", "alpha"))), 0.0);
}

TEST(Standing, EveryOutputNamesTheSameStanding) {
  SuiteResults suite = fixture::suite_of_every_kind();
  suite.report = ReportInfo{};
  const std::string index = index_html(suite), summary = summary_markdown(suite, ""), junit = junit_xml(suite);
  for (const Standing& s : standings(suite)) {
    SCOPED_TRACE(s.engine);
    const std::string worst = s.worst_text();
    if (!worst.empty()) {
      // The index row names it whole in its title and shows the figure and scenario (a listed
      // error, or a zero tolerance, whole): it must fit its column.
      const std::string shown = s.worst_short_text();
      EXPECT_NE(shown.find(s.worst->scenario), std::string::npos);
      EXPECT_NE(index.find("worst <span class=\"worst\" title=\"" + escape_markup(worst) + "\">" +
                           escape_markup(shown) + "</span>"),
                std::string::npos)
          << shown;
      EXPECT_NE(summary.find(fmt::format("| {} | {} | {} | {} | 0 | {} |", s.engine, s.pass, s.known, s.skip, worst)),
                std::string::npos)
          << summary;
      EXPECT_NE(junit.find(escape_markup(s.counts_text() + "; worst " + worst)), std::string::npos);
      // The worst run's scenario page names the figure that decided it, for this configuration.
      const std::string page = scenario_html(suite, s.worst->scenario);
      EXPECT_NE(page.find(fmt::format("<a href=\"#{0}\">{0}</a>", s.engine)), std::string::npos);
      EXPECT_NE(page.find("<td class=\"l decided\">" + escape_markup(s.worst_figure.text()) + "</td>"),
                std::string::npos);
    } else {
      EXPECT_NE(junit.find(escape_markup(s.counts_text())), std::string::npos);
    }
    if (s.unexpected > 0) {
      EXPECT_NE(index.find(fmt::format("{} not as expected", s.unexpected)), std::string::npos);
      EXPECT_NE(summary.find(fmt::format("| **{}** |", s.unexpected)), std::string::npos);
    }
  }
  // The counts of the whole suite, the same in each.
  const Summary sum = summarize(suite);
  EXPECT_NE(index.find(fmt::format("<b>{} runs</b>: {} pass", sum.total, sum.pass)), std::string::npos);
  EXPECT_NE(summary.find(fmt::format("**{} unexpected** — {} runs: {} pass, {} known failures", sum.unexpected(),
                                     sum.total, sum.pass, sum.known)),
            std::string::npos)
      << summary;
  // JUnit: a <failure> or <error> for each run not as expected, never for one that is.
  EXPECT_EQ(count_of(junit, "<testcase classname=\"s."), 15u);
  // beta's s.one fail, s.two unexpected pass, s.four listed as an error that failed its metric instead
  EXPECT_EQ(count_of(junit, "<failure type="), 3u);
  EXPECT_EQ(count_of(junit, "<error message="), 0u);
  EXPECT_EQ(count_of(junit, "type=\"known-failure\""), 6u);
  EXPECT_EQ(count_of(junit, "type=\"not-applicable\""), 1u);
}
