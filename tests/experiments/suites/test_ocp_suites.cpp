// The optimal-control suites: their case lists (quick and full), one quick run of each end to end
// through the CLI, and properties of what they wrote: the LGVI linearization agrees with the
// central differences of its own flow within the differences' own error estimate and differs
// from the continuous transition matrix at second order in h; the decomposed shootings converge
// and the undecomposed ones end in the expected failure status.
#include <cmath>
#include <map>
#include <set>

#include "experiments/scene/scene.hpp"
#include "experiments/suites/suite.hpp"
#include "tests/experiments/cli/cli_support.hpp"

namespace lgvi::test {
namespace {

using experiments::Expectation;
using experiments::Suite;
using experiments::SuiteCase;
using experiments::SuiteParams;

Suite ocp_suite(const std::string& name, bool quick) {
  return experiments::make_suite(name, SuiteParams{quick, experiments::default_scenes_dir()});
}

std::string label_of(const SuiteCase& c, const std::string& key) {
  for (const experiments::Field& f : c.labels) {
    if (f.key == key) return experiments::to_text(f.value);
  }
  return "";
}

// --- case lists ----------------------------------------------------------------------------------

TEST(OcpSuiteCases, SensitivityCrossesSystemsHorizonsAndMethods) {
  for (const bool quick : {true, false}) {
    const Suite s = ocp_suite("sensitivity", quick);
    std::set<std::string> scenes, methods;
    std::set<double> horizons;
    std::map<std::string, std::set<std::string>> h_or_rtol;
    for (const SuiteCase& c : s.cases) {
      scenes.insert(label_of(c, "scene"));
      methods.insert(label_of(c, "method"));
      horizons.insert(std::stod(label_of(c, "T")));
      h_or_rtol[label_of(c, "method")].insert(label_of(c, label_of(c, "method") == "lgvi" ? "h" : "rtol"));
      EXPECT_EQ(c.expect, Expectation::Complete) << c.id;
    }
    EXPECT_EQ(scenes, (std::set<std::string>{"pendulum", "free-body"}));
    EXPECT_EQ(methods, (std::set<std::string>{"lgvi", "cvodes"}));
    EXPECT_GE(horizons.size(), 3u);
    EXPECT_GE(h_or_rtol["lgvi"].size(), 3u) << "an order needs three steps";
    EXPECT_GE(h_or_rtol["cvodes"].size(), 2u);
    EXPECT_EQ(s.cases.size(), scenes.size() * horizons.size() * (h_or_rtol["lgvi"].size() + h_or_rtol["cvodes"].size()));
    if (!quick) {
      EXPECT_GE(*horizons.rbegin(), 16.0) << "the full form reaches long horizons";
    }
  }
}

TEST(OcpSuiteCases, ShootingExpectsTheUndecomposedAndDegenerateRunsToFail) {
  for (const bool quick : {true, false}) {
    const Suite s = ocp_suite("shooting", quick);
    std::size_t complete = 0, fail = 0, dumbbell = 0, direct = 0;
    for (const SuiteCase& c : s.cases) {
      const bool undecomposed = c.id.find("-full-") != std::string::npos;
      const bool zero_pendulum = c.id.starts_with("pendulum-") && c.id.ends_with("-zero");
      if (undecomposed || zero_pendulum) {
        EXPECT_EQ(c.expect, Expectation::Fail) << c.id;
        ++fail;
      } else if (c.id.starts_with("pendulum-")) {
        EXPECT_EQ(c.expect, Expectation::Complete) << c.id;
        ++complete;
      }
      dumbbell += c.id.starts_with("dumbbell-") ? 1 : 0;
      direct += c.id.find("-direct-") != std::string::npos ? 1 : 0;
    }
    EXPECT_GE(complete, 3u);  // discrete decomposed, continuous from ones and from the discrete solution
    EXPECT_GE(fail, 3u);      // discrete and continuous undecomposed, continuous from zero
    EXPECT_GE(dumbbell, quick ? 1u : 2u);
    EXPECT_EQ(direct, 1u);
  }
}

// --- end to end ----------------------------------------------------------------------------------

// ocp-comparison: every example x every method is present, as runs or as one named n/a case (its
// binding has no such solver); 2 starts quick, 8 full (collocation: its one guess), the full form
// adding start 0 at 2h and h/2. The n/a cases report status n/a with the reason, run nothing.
TEST(OcpSuiteCases, ComparisonCoversEveryExampleAndMethodWithNamedGaps) {
  const std::set<std::string> examples = {"pendulum", "dumbbell", "cart-pendulum", "connected-bodies"};
  const std::set<std::string> methods = {"indirect-shooting", "continuous-indirect", "slsqp",
                                         "ipopt",             "ddp",                 "collocation"};
  for (const bool quick : {true, false}) {
    const Suite s = ocp_suite("ocp-comparison", quick);
    std::map<std::pair<std::string, std::string>, std::set<std::string>> seen;  // (example, method) -> ids
    for (const SuiteCase& c : s.cases) {
      EXPECT_EQ(c.expect, Expectation::Either) << c.id;
      seen[{label_of(c, "system"), label_of(c, "method")}].insert(c.id);
    }
    EXPECT_EQ(seen.size(), examples.size() * methods.size());
    for (const std::string& e : examples) {
      for (const std::string& m : methods) {
        const std::set<std::string>& ids = seen[std::make_pair(e, m)];
        ASSERT_FALSE(ids.empty()) << e << " " << m;
        if (ids.begin()->ends_with("-na")) {
          EXPECT_EQ(ids.size(), 1u) << e << " " << m;
          continue;
        }
        const std::size_t starts = m == "collocation" ? 1 : quick ? 2 : 8;
        const std::size_t variants = quick || m == "continuous-indirect" ? 0 : 2;
        EXPECT_EQ(ids.size(), starts + variants) << e << " " << m;
      }
    }
    // The applicability follows the bindings: the indirect examples have no direct solvers.
    const auto na = [&](const std::string& e, const std::string& m) {
      return seen[std::make_pair(e, m)].begin()->ends_with("-na");
    };
    EXPECT_TRUE(na("pendulum", "slsqp"));
    EXPECT_TRUE(na("connected-bodies", "indirect-shooting"));
    EXPECT_FALSE(na("pendulum", "collocation"));
    EXPECT_FALSE(na("cart-pendulum", "collocation"));
    EXPECT_FALSE(na("connected-bodies", "collocation"));
    EXPECT_FALSE(na("dumbbell", "collocation"));
    EXPECT_FALSE(na("dumbbell", "continuous-indirect"));
  }
  const Suite s = ocp_suite("ocp-comparison", true);
  for (const SuiteCase& c : s.cases) {
    if (c.id != "pendulum-ddp-na") continue;
    const experiments::JobResult r =
        c.job->run(experiments::JobContext{::testing::TempDir(), experiments::default_scenes_dir(), c.id, "test"});
    EXPECT_FALSE(r.completed);
    EXPECT_EQ(r.status, "n/a");
    EXPECT_NE(r.detail.find("no direct"), std::string::npos) << r.detail;
  }
}

TEST(OcpSuiteEndToEnd, QuickSensitivityAgreesWithDifferencesAndConvergesAtSecondOrder) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"suite", "sensitivity", "--quick", "--out", "res", "--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const fs::path res = dir.work() / "res";
  const Suite s = ocp_suite("sensitivity", true);
  const auto rows = experiments::read_summary_csv(res / "summary.csv");
  ASSERT_EQ(rows.size(), s.cases.size());
  // (scene, T) -> h -> continuous difference of the LGVI
  std::map<std::pair<std::string, double>, std::map<double, double>> lgvi;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const experiments::SummaryRow& row = rows[i];
    ASSERT_EQ(row.text("status"), "completed") << s.cases[i].id << ": " << row.text("detail");
    // The case's own file: the matrices, and its errors recomputed from them.
    const CsvParts csv = read_csv(res / row.text("csv_path"));
    ASSERT_EQ(csv.rows.size(), 36u) << row.text("csv_path");
    double diff = 0.0, norm = 0.0;
    for (const auto& v : csv.rows) {
      diff += std::pow(v[csv.column("phi")] - v[csv.column("phi_fd")], 2);
      norm += std::pow(v[csv.column("phi_fd")], 2);
    }
    const double fd_error = std::sqrt(diff / norm);
    EXPECT_NEAR(fd_error, *row.number("fd_error"), 1e-12 + 1e-9 * fd_error) << s.cases[i].id;
    // The differences resolve the transition matrix while a |Phi| is small (a = cbrt(eps) ~ 6e-6):
    // below |Phi| = 1e3 they must be conclusive.
    const bool conclusive = row.text("fd_conclusive") == "true";
    if (*row.number("phi_norm") < 1e3) {
      EXPECT_TRUE(conclusive) << s.cases[i].id << ": " << row.text("detail");
    }
    if (row.text("method") == "lgvi") {
      // The linearization is the flow's exact derivative: within the differences' own error.
      if (conclusive) {
        EXPECT_LE(fd_error, *row.number("fd_tolerance")) << s.cases[i].id;
      }
      lgvi[{row.text("scene"), *row.number("T")}][*row.number("h")] = *row.number("continuous_difference");
    } else {
      // CVODES at its rtol is close to CVODES at the reference rtol, and the differences of the
      // continuous flow agree with it to their own error plus CVODES's (triangle inequality,
      // with the reference's distance standing in for CVODES's error, a factor 2 for the
      // reference's own).
      if (conclusive) {
        const double cont = *row.number("continuous_difference");
        EXPECT_LT(cont, 1e-2) << s.cases[i].id;
        EXPECT_LE(fd_error, *row.number("fd_tolerance") + 2.0 * cont) << s.cases[i].id;
      }
    }
  }
  // Second order: halving h divides the LGVI-vs-continuous difference by ~4 (order within 0.3 of 2)
  // in the asymptotic regime: the difference small (below 1e-2, the trajectories still close) and
  // far above the reference's own error (~1e-12 rtol x growth).
  ASSERT_FALSE(lgvi.empty());
  for (const auto& [key, by_h] : lgvi) {
    ASSERT_GE(by_h.size(), 2u);
    for (auto it = std::next(by_h.begin()); it != by_h.end(); ++it) {
      const auto& [h_small, e_small] = *std::prev(it);
      const auto& [h_large, e_large] = *it;
      const double order = std::log(e_large / e_small) / std::log(h_large / h_small);
      std::cout << "[ measured ] " << key.first << ", T = " << key.second << ": h " << h_large << " -> " << h_small
                << ": " << e_large << " -> " << e_small << ", order " << order << "\n";
      if (e_large < 1e-2 && e_small > 1e-6) {
        EXPECT_NEAR(order, 2.0, 0.3) << key.first << " T = " << key.second;
      }
    }
  }
  for (const char* f : {"pendulum-fd-error.png", "pendulum-continuous-difference.png", "free-body-growth.png"}) {
    EXPECT_EQ(read_text(res / f).substr(1, 3), "PNG") << f;
  }
  EXPECT_NE(read_text(res / "sensitivity-table.md").find("| order |"), std::string::npos);
}

TEST(OcpSuiteEndToEnd, QuickShootingConvergesDecomposedAndFailsAsExpectedWithout) {
  TempDir dir;
  const CliResult r = run_testbed(dir, {"suite", "shooting", "--quick", "--out", "res", "--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const fs::path res = dir.work() / "res";
  const Suite s = ocp_suite("shooting", true);
  const auto rows = experiments::read_summary_csv(res / "summary.csv");
  ASSERT_EQ(rows.size(), s.cases.size());
  std::map<std::string, const experiments::SummaryRow*> by_id;
  for (const auto& row : rows) {
    by_id[row.text("case")] = &row;
    EXPECT_EQ(row.text("as_expected"), "true") << row.text("case") << ": " << row.text("detail");
    const CsvParts csv = read_csv(res / row.text("csv_path"));
    ASSERT_FALSE(csv.rows.empty()) << row.text("case");
    // The indirect history's last violation is the summary's (the direct history lists SQP
    // iterates and the constraint rows handed to SLSQP, the summary the returned point's full
    // terminal condition).
    if (row.text("solver") != "direct") {
      EXPECT_EQ(csv.rows.back()[csv.column("violation")], *row.number("violation")) << row.text("case");
    }
  }
  const auto* decomposed = by_id.at("pendulum-discrete-symmetric-n1000-decomposed-ones");
  EXPECT_EQ(decomposed->text("status"), "completed");
  EXPECT_LE(*decomposed->number("violation"), *decomposed->number("tolerance"));
  EXPECT_LT(*decomposed->number("cond_max"), 1e6) << "the shape block is well conditioned";
  const auto* full = by_id.at("pendulum-discrete-symmetric-n1000-full-ones");
  EXPECT_EQ(full->text("status"), "line search failed") << full->text("detail");
  // rank 5: the full sensitivity's condition number is beyond any double-precision solve
  EXPECT_GT(*full->number("first_cond_full"), 1.0 / 2.220446049250313e-16);
  // The continuous optimum agrees with the discrete one to the discretization error: symmetric
  // form, J_h - J ~ c h^2, lgvi/ocp/README.md: J_0.001 - J_0.0005 = -6.5e-5, so |J_h - J| ~ 8.7e-5
  // = 1.2e-5 relative at h = 0.001; the bound leaves a factor 8.
  const auto* cont = by_id.at("pendulum-continuous-rtol1e-10-decomposed-discrete-solution");
  EXPECT_EQ(cont->text("status"), "completed");
  EXPECT_NEAR(*cont->number("cost"), *decomposed->number("cost"), 1e-4 * *decomposed->number("cost"));
  EXPECT_EQ(by_id.at("pendulum-continuous-rtol1e-10-decomposed-zero")->text("as_expected"), "true");
  // The direct method converges too; the dumbbell converges or stalls at its round-off floor.
  EXPECT_EQ(by_id.at("cart-pendulum-direct-n200")->text("status"), "completed");
  for (const char* f : {"pendulum-violation.png", "pendulum-cond-inverted.png", "pendulum-cond-full.png",
                        "cart-pendulum-violation.png", "dumbbell-violation.png"}) {
    EXPECT_EQ(read_text(res / f).substr(1, 3), "PNG") << f;
  }
}

}  // namespace
}  // namespace lgvi::test
