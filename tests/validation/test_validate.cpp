// The regression gate: the kinds' rules, the accepted file, and that the gate fails (exit 4,
// named metrics) on every planted defect (validate --degrade), and `suite --check-against` likewise.
#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "experiments/cli/cli.hpp"
#include "validation/validate.hpp"
#include "tests/experiments/cli/cli_support.hpp"

namespace lgvi::experiments {
namespace {

using test::TempDir;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

TEST(ValidateJudge, OrderBandIsAbsolutePointZeroFive) {
  EXPECT_EQ(judge(MetricKind::Order, 2.00, 2.04, 0, 2.0), Verdict::Pass);
  EXPECT_EQ(judge(MetricKind::Order, 2.00, 1.94, 0, 2.0), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::Order, 2.00, 2.06, 0, 2.0), Verdict::Regressed);  // farther from 2
  EXPECT_EQ(judge(MetricKind::Order, 1.90, 1.99, 0, 2.0), Verdict::Improved);   // nearer to 2
}

TEST(ValidateJudge, TruncationIsRelativeOneInAMillion) {
  EXPECT_EQ(judge(MetricKind::Truncation, 1e-6, 1e-6 * (1 + 0.9e-6), 0, {}), Verdict::Pass);
  EXPECT_EQ(judge(MetricKind::Truncation, 1e-6, 1e-6 * (1 + 2e-6), 0, {}), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::Truncation, 1e-6, 0.5e-6, 0, {}), Verdict::Improved);
}

TEST(ValidateJudge, RoundOffIsAFactorTenOverTheFloor) {
  const double floor = 1e-14;
  EXPECT_EQ(judge(MetricKind::RoundOff, 2e-15, 9e-14, floor, {}), Verdict::Pass);  // below 10 x floor
  EXPECT_EQ(judge(MetricKind::RoundOff, 2e-15, 1.1e-13, floor, {}), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::RoundOff, 1e-12, 9e-12, floor, {}), Verdict::Pass);
  EXPECT_EQ(judge(MetricKind::RoundOff, 1e-12, 9e-14, floor, {}), Verdict::Improved);
  EXPECT_EQ(judge(MetricKind::RoundOff, 2e-15, 1e-16, floor, {}), Verdict::Pass);  // at the floor: no "improved"
}

TEST(ValidateJudge, CostCountAndCondition) {
  EXPECT_EQ(judge(MetricKind::Cost, 7.3218752, 7.3218752 * (1 + 5e-10), 0, {}), Verdict::Pass);
  EXPECT_EQ(judge(MetricKind::Cost, 7.3218752, 7.3218752 * (1 + 2e-9), 0, {}), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::Cost, 7.3218752, 7.30, 0, {}), Verdict::Improved);
  EXPECT_EQ(judge(MetricKind::Count, 12, 13, 0, {}), Verdict::Pass);  // 12 + 0.6 + 0.5
  EXPECT_EQ(judge(MetricKind::Count, 12, 14, 0, {}), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::Count, 2.0, 2.4, 0, {}), Verdict::Pass);
  EXPECT_EQ(judge(MetricKind::Count, 2.0, 2.7, 0, {}), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::Condition, 100, 900, 0, {}), Verdict::Pass);
  EXPECT_EQ(judge(MetricKind::Condition, 100, 1100, 0, {}), Verdict::Regressed);
}

// A two-sided metric (it measures a reference as much as a method) fails when it moves down
// beyond its band: a reference drifting like the methods lowers their errors.
TEST(ValidateJudge, TwoSidedMetricsFailWhenTheyMoveDown) {
  EXPECT_EQ(judge(MetricKind::Truncation, 1e-6, 0.5e-6, 0, {}, true), Verdict::Changed);
  EXPECT_EQ(judge(MetricKind::Truncation, 1e-6, 2e-6, 0, {}, true), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::Truncation, 1e-6, 1e-6 * (1 + 0.9e-6), 0, {}, true), Verdict::Pass);
  EXPECT_EQ(judge(MetricKind::RoundOff, 1e-12, 9e-14, 1e-14, {}, true), Verdict::Changed);
  EXPECT_EQ(judge(MetricKind::RoundOff, 2e-15, 1e-16, 1e-14, {}, true), Verdict::Pass);  // at the floor
  std::vector<Metric> metrics(1);
  metrics[0] = {"exact/a/lgvi", MetricKind::Truncation, 0.5e-6, 0, {}, {}, true, 0, ""};
  AcceptedFile accepted;
  accepted.values["exact/a/lgvi"] = {MetricKind::Truncation, 1e-6};
  const ValidateReport r = compare(metrics, accepted, {});
  EXPECT_EQ(r.count(Verdict::Changed), 1u);
  EXPECT_TRUE(r.failed());
}

// A comparison in which no metric has an accepted value gates nothing: it fails (a mistyped
// --accepted file must not pass), and a missing accepted file is bad input.
TEST(ValidateAcceptedFile, NothingAcceptedFailsAndAMissingFileIsAnError) {
  std::vector<Metric> metrics(1);
  metrics[0] = {"energy/a/lgvi", MetricKind::Truncation, 1e-7, 0, {}, {}, false, 0, ""};
  const ValidateReport r = compare(metrics, AcceptedFile{}, {});
  EXPECT_EQ(r.count(Verdict::New), 1u);
  EXPECT_EQ(r.gated(), 0u);
  EXPECT_TRUE(r.failed());
  TempDir dir;
  EXPECT_THROW(read_accepted(dir.work() / "no-such-file.txt"), InvalidInput);
  EXPECT_TRUE(read_accepted(dir.work() / "no-such-file.txt", true).values.empty());
  EXPECT_THROW(read_accepted("/dev/null"), InvalidInput);  // not a regular file
  for (const std::string file : {"no-such-file.txt", "/dev/zero"}) {
    const test::CliResult cli = test::run_testbed(dir, {"validate", "--quick", "--only", "order", "--accepted", file});
    EXPECT_EQ(cli.exit_code, kExitBadInput) << file << ": " << cli.out << cli.err;
    EXPECT_NE(cli.err.find(file), std::string::npos) << cli.err;
  }
}

TEST(ValidateJudge, AFailedRunRegresses) {
  EXPECT_EQ(judge(MetricKind::Truncation, 1e-6, kNan, 0, {}), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::Order, 2.0, kNan, 0, 2.0), Verdict::Regressed);
  EXPECT_EQ(judge(MetricKind::Order, kNan, kNan, 0, 2.0), Verdict::Pass);
}

TEST(ValidateAcceptedFile, RoundTripsSortedAndReportsChanges) {
  TempDir dir;
  const auto file = dir.work() / "accepted.txt";
  std::vector<Metric> metrics(3);
  metrics[0] = {"order/b/lgvi", MetricKind::Order, 2.0012345678901234, 0, 2.0, {}, false, 0, ""};
  metrics[1] = {"energy/a/lgvi", MetricKind::Truncation, 1.2345678901234567e-7, 0, {}, {}, false, 0, ""};
  metrics[2] = {"momentum/a/lgvi", MetricKind::RoundOff, 3e-15, 1e-14, {}, {}, false, 0, ""};
  write_accepted(file, metrics, "quick", "v1");
  const AcceptedFile a = read_accepted(file);
  EXPECT_EQ(a.accepted_at, "v1");
  EXPECT_EQ(a.form, "quick");
  ASSERT_EQ(a.values.size(), 3u);
  EXPECT_EQ(a.values.at("energy/a/lgvi").value, 1.2345678901234567e-7);  // round trip
  EXPECT_EQ(a.values.at("order/b/lgvi").kind, MetricKind::Order);
  // Sorted by name: the diff-friendly order.
  const auto lines = test::lines_of(test::read_text(file));
  std::vector<std::string> names;
  for (const auto& l : lines) {
    if (!l.empty() && l[0] != '#') names.push_back(l.substr(0, l.find(' ')));
  }
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));

  metrics[1].value = 2e-7;
  metrics.pop_back();
  metrics.push_back({"newton/a/lgvi", MetricKind::Count, 2.0, 0, {}, {}, false, 0, ""});
  const std::vector<std::string> diff = accepted_diff(a, metrics);
  ASSERT_EQ(diff.size(), 3u);
  EXPECT_EQ(diff[0].substr(0, 2), "~ ");  // energy/a/lgvi changed
  EXPECT_EQ(diff[1].substr(0, 2), "- ");  // momentum/a/lgvi removed
  EXPECT_EQ(diff[2].substr(0, 2), "+ ");  // newton/a/lgvi added

  const ValidateReport r = compare(metrics, a, {});
  EXPECT_EQ(r.count(Verdict::Regressed), 1u);  // energy doubled
  EXPECT_EQ(r.count(Verdict::New), 1u);
  EXPECT_EQ(r.count(Verdict::Missing), 1u);
  EXPECT_EQ(r.count(Verdict::Pass), 1u);
}

TEST(ValidateAcceptedFile, MalformedLineNamesFileAndLine) {
  TempDir dir;
  const auto file = dir.work() / "accepted.txt";
  test::write_text(file, "# form: quick\norder/a/lgvi order two\n");
  try {
    read_accepted(file);
    FAIL() << "malformed value accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
}

// The gate fails on a degraded solver: the single-body LGVIs with the rotation update's
// tolerance loosened to 1e-9 and no polishing step must regress named conservation metrics
// against the committed accepted values, and exit 4.
TEST(ValidateCli, DegradedRotationUpdateRegressesAndExitsFour) {
  TempDir dir;
  const test::CliResult r = test::run_testbed(
      dir, {"validate", "--quick", "--only", "conservation", "--degraded-rotation-update", "--json", "report.json"});
  EXPECT_EQ(r.exit_code, kExitRegressed) << r.out << r.err;
  const auto regressed_line = r.out.find("regressed:");
  ASSERT_NE(regressed_line, std::string::npos) << r.out;
  const std::string names = r.out.substr(regressed_line);
  EXPECT_NE(names.find("/pendulum/lgvi"), std::string::npos) << names;
  EXPECT_NE(names.find("/free-body/lgvi"), std::string::npos) << names;
  // The multibody LGVIs have their own Newton solver: untouched, they must not regress.
  EXPECT_EQ(names.find("/cart-pendulum/lgvi "), std::string::npos) << names;
  EXPECT_NE(test::read_text(dir.work() / "report.json").find("\"REGRESSED\""), std::string::npos);
}

TEST(ValidateCli, UnknownGroupAndAcceptWithOptionsAreBadInput) {
  TempDir dir;
  const test::CliResult r = test::run_testbed(dir, {"validate", "--quick", "--only", "nonsense"});
  EXPECT_EQ(r.exit_code, kExitBadInput);
  EXPECT_NE(r.err.find("--only"), std::string::npos) << r.err;
  const test::CliResult a = test::run_testbed(
      dir, {"validate", "--quick", "--accepted", "x.txt", "--accept", "--degraded-rotation-update"});
  EXPECT_EQ(a.exit_code, kExitBadInput);
  EXPECT_FALSE(std::filesystem::exists(dir.work() / "x.txt"));
}

// --accept writes where the user says; without --accepted only into a source checkout's own file,
// never into an installation's data (install_consumer_test.cmake runs the installed CLI).
TEST(ValidateAccept, WritesTheGivenFileAndRefusesAnInstalledDefault) {
  const std::filesystem::path installed = "/opt/lgvi/share/lgvi/validation/accepted-quick.txt";
  EXPECT_EQ(accept_destination("mine.txt", installed, true), std::filesystem::path("mine.txt"));
  EXPECT_EQ(accept_destination("", "src/validation/accepted-quick.txt", false),
            std::filesystem::path("src/validation/accepted-quick.txt"));
  try {
    accept_destination("", installed, true);
    FAIL() << "an installed default accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "--accepted") << e.what();
    EXPECT_NE(std::string(e.what()).find(installed.string()), std::string::npos) << e.what();
  }
  // The build tree's CLI reads the source tree's data: its default stays the checkout's file.
  EXPECT_EQ(accept_destination("", true), default_accepted_file(true));
}

// suite --check-against: a run against itself passes; against an edited accepted summary
// (an error doubled, a status changed) it exits 4 naming the metrics; another suite is refused.
TEST(SuiteCheckAgainst, PassesOnItselfAndCatchesEditedValues) {
  TempDir dir;
  const test::CliResult run = test::run_testbed(dir, {"suite", "default", "--quick", "--no-plots", "--out", "a"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const test::CliResult same = test::run_testbed(
      dir, {"suite", "default", "--quick", "--no-plots", "--out", "b", "--check-against", "a"});
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  EXPECT_NE(same.out.find("0 REGRESSED"), std::string::npos) << same.out;

  // Halve one case's accepted energy error: the run's value is then twice the accepted one.
  std::string text = test::read_text(dir.work() / "a" / "summary.jsonl");
  const std::string key = "\"max_energy_error\":";
  const auto at = text.find(key);
  ASSERT_NE(at, std::string::npos);
  const auto end = text.find_first_of(",}", at + key.size());
  const double value = std::stod(text.substr(at + key.size(), end - at - key.size()));
  text.replace(at + key.size(), end - at - key.size(), std::to_string(value / 2.0));
  test::write_text(dir.work() / "a" / "summary.jsonl", text);
  const test::CliResult edited = test::run_testbed(
      dir, {"suite", "default", "--quick", "--no-plots", "--out", "c", "--check-against", "a"});
  EXPECT_EQ(edited.exit_code, kExitRegressed) << edited.out << edited.err;
  EXPECT_NE(edited.out.find("max_energy_error"), std::string::npos);

  const test::CliResult other = test::run_testbed(
      dir, {"suite", "default", "--no-plots", "--out", "d", "--check-against", "a"});
  EXPECT_EQ(other.exit_code, kExitBadInput) << other.out;
  EXPECT_NE(other.err.find("quick"), std::string::npos) << other.err;
}

}  // namespace
}  // namespace lgvi::experiments

namespace lgvi::experiments {
namespace {

// Each degradation (validate --degrade NAME) plants one blind spot of the gate on purpose; the gate
// must fail (exit 4) and name the metrics that catch it. Every degradation has its case here.
struct PlantedDefect {
  const char* degrade;
  const char* only;                 ///< the groups whose metrics catch it
  std::vector<std::string> caught;  ///< each must be in the "regressed:" line
};

const std::vector<PlantedDefect>& planted_defects() {
  static const std::vector<PlantedDefect> cases = {
      // The badly conditioned body is where the rotation update's tolerance matters most (its
      // Newton counts drop with the looser tolerance: `improved`, one-sided; the energy shows it).
      {"rotation-update", "conservation",
       {"energy/free-body/lgvi", "energy/ill-conditioned-body/lgvi", "energy/ill-conditioned-body/lgvi-yoshida4"}},
      // The closed forms against the tight run and the stored references, and methods' errors
      // that a drifting reference lowers (CHANGED, two-sided).
      {"exact-reference", "exact,literature",
       {"exact/free-body/closed-form", "exact/lagrange-top/closed-form", "literature/hlw-rigid-body/closed-form",
        "literature/detest-b5/closed-form", "exact/lagrange-top/odeint-rk4-matrix"}},
      // A misplaced impulse: the order of the symmetric forms drops to 1 on every controlled
      // system (the cart-pendulum's symmetric control included), and the printed forms'
      // final states move.
      {"control-timing", "order",
       {"order/cart-pendulum-controlled/lgvi", "order/free-body-controlled/lgvi", "order/dumbbell-controlled/lgvi",
        "order/pendulum-controlled/lgvi", "order/connected-bodies-controlled/lgvi",
        "final/cart-pendulum-controlled/lgvi-printed",
        "final/free-body-controlled/lgvi-printed", "final/dumbbell-controlled/lgvi-printed",
        "final/pendulum-controlled/lgvi-printed"}},
      // The cart-pendulum's attitude random-walks off SO(3): above its bounded floor.
      {"uncompensated-attitude", "conservation", {"orthogonality/cart-pendulum/lgvi"}},
  };
  return cases;
}

TEST(ValidateMutation, EveryDegradationHasAPlantedCase) {
  for (const DegradationInfo& d : degradations()) {
    const bool found = std::any_of(planted_defects().begin(), planted_defects().end(),
                                   [&](const PlantedDefect& p) { return std::string(p.degrade) == d.name; });
    EXPECT_TRUE(found) << d.name << " has no planted case";
  }
  EXPECT_THROW(parse_degradation("nonsense"), InvalidInput);
}

class ValidateMutationCase : public ::testing::TestWithParam<PlantedDefect> {};

TEST_P(ValidateMutationCase, TheGateFailsAndNamesTheMetricsThatCatchIt) {
  const PlantedDefect& p = GetParam();
  TempDir dir;
  const test::CliResult r = test::run_testbed(dir, {"validate", "--quick", "--only", p.only, "--degrade", p.degrade});
  EXPECT_EQ(r.exit_code, kExitRegressed) << r.out << r.err;
  const auto line = r.out.find("regressed:");
  ASSERT_NE(line, std::string::npos) << r.out;
  const std::string names = r.out.substr(line, r.out.find('\n', line) - line) + " ";
  for (const std::string& metric : p.caught) {
    EXPECT_NE(names.find(" " + metric + " "), std::string::npos) << p.degrade << ": " << metric << " not caught in "
                                                                 << names;
  }
}

INSTANTIATE_TEST_SUITE_P(Planted, ValidateMutationCase, ::testing::ValuesIn(planted_defects()), [](const auto& info) {
  std::string n = info.param.degrade;
  for (char& ch : n) {
    if (ch == '-') ch = '_';
  }
  return n;
});

}  // namespace
}  // namespace lgvi::experiments
