// The fuzz targets' properties (fuzz_properties.hpp), compiled once for the five targets and the
// test that replays their regression inputs.
#include "tests/fuzz/fuzz_properties.hpp"

#include <cmath>
#include <cstddef>
#include <optional>
#include <set>
#include <sstream>

#include "experiments/cli/cli.hpp"
#include "experiments/input/toml_reader.hpp"
#include "experiments/scene/ocp_scene.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/study.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::fuzz {

namespace fs = std::filesystem;
using experiments::SceneError;

namespace {

/// "" when `what` is one line starting with "FILE: ".
std::string one_line_error(const std::string& what, const std::string& file) {
  if (what.find('\n') != std::string::npos || what.find('\r') != std::string::npos) {
    return "an error message of more than one line: " + what;
  }
  if (what.rfind(file + ": ", 0) != 0) return "an error message not starting with '" + file + ": ': " + what;
  return "";
}

/// The starting values of a system's state record are finite (R, Omega; x, v; q, q_dot; two bodies').
template <class State>
bool state_finite(const State& s) {
  bool ok = true;
  if constexpr (requires { s.R; }) ok = ok && s.R.allFinite() && s.Omega.allFinite();
  if constexpr (requires { s.x; }) ok = ok && s.x.allFinite() && s.v.allFinite();
  if constexpr (requires { s.q; }) ok = ok && s.q.allFinite() && s.q_dot.allFinite();
  if constexpr (requires { s.R1; }) {
    ok = ok && s.R1.allFinite() && s.R2.allFinite() && s.Omega1.allFinite() && s.Omega2.allFinite();
  }
  return ok;
}

/// The attitudes of a state record are rotations (to the readers' tolerance, loosely).
template <class State>
bool state_rotations(const State& s) {
  if constexpr (requires { s.R1; }) return so3::is_rotation(s.R1, 1e-6) && so3::is_rotation(s.R2, 1e-6);
  if constexpr (requires { s.R; }) return so3::is_rotation(s.R, 1e-6);
  return true;
}

/// A loaded [ocp] definition is one its solver accepts: the target state finite with rotations,
/// W empty or n x n, finite, symmetric and positive definite, the solver's numbers finite and in
/// their ranges (the checks of lgvi/ocp's solvers, which would refuse it later without naming the
/// file).
std::string ocp_definition_property(const experiments::OcpDefinition& d) {
  std::string why;
  std::visit(
      [&](const auto& target) {
        if (!state_finite(target)) why = "an [ocp] target with a non-finite value";
        if (why.empty() && !state_rotations(target)) why = "an [ocp] target attitude that is not a rotation";
      },
      d.target);
  if (!why.empty()) return why;
  const Eigen::MatrixXd& W = d.W();
  if (W.size() > 0) {
    if (W.rows() != W.cols() || !W.allFinite()) return "an [ocp] W that is not a finite square matrix";
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (W + W.transpose()), Eigen::EigenvaluesOnly);
    if (!(eig.eigenvalues()(0) > 0.0)) return "an [ocp] W that is not positive definite";
  }
  if (d.method == experiments::OcpMethod::Indirect) {
    const auto& o = d.indirect;
    if (!o.initial_multiplier.allFinite()) return "an [ocp] multiplier guess with a non-finite value";
    if (!(std::isfinite(o.tolerance) && o.tolerance > 0.0)) return "an [ocp] indirect tolerance not finite and > 0";
    if (!(std::isfinite(o.lm_initial_damping) && o.lm_initial_damping > 0.0)) {
      return "an [ocp] lm_damping not finite and > 0";
    }
    if (o.max_iterations < 1 || o.nonmonotone_memory < 1) return "an [ocp] indirect count below 1";
  } else {
    const auto& o = d.direct;
    if (!(std::isfinite(o.tolerance) && o.tolerance > 0.0)) return "an [ocp] direct tolerance not finite and > 0";
    if (!o.initial_knots.allFinite()) return "[ocp] initial knots with a non-finite value";
    if (o.knots < 3 || o.starts < 1 || o.max_evaluations < 1 || o.shooting_interval < 1) {
      return "an [ocp] direct count out of its range";
    }
  }
  return "";
}

}  // namespace

std::string scene_property(std::string_view text, const std::string& file) {
  try {
    const experiments::Scene scene = experiments::parse_scene(text, file);
    if (!(std::isfinite(scene.horizon.h) && std::isfinite(scene.horizon.t_final) && scene.horizon.h > 0.0 &&
          scene.horizon.t_final > 0.0)) {
      return "a scene loaded with a step or horizon not finite and > 0";
    }
    std::string why;
    std::visit([&](const auto& m) { if (!state_finite(m.initial)) why = "a scene loaded with a non-finite value"; },
               scene.model);
    if (!why.empty()) return why;
    for (const std::string& w : scene.warnings) {
      if (const std::string e = one_line_error(w, file); !e.empty()) return "warning: " + e;
    }
    if (scene.ocp) return ocp_definition_property(*scene.ocp);
  } catch (const SceneError& e) {
    return one_line_error(e.what(), file);
  }
  return "";
}

std::string study_property(std::string_view text, const fs::path& file, const fs::path& scenes_dir) {
  const std::string name = file.string();
  for (const bool quick : {false, true}) {
    const std::string form = quick ? " (quick form)" : "";
    try {
      const experiments::Suite suite = experiments::parse_study(text, file, {quick, scenes_dir});
      if (suite.cases.empty()) return "a study loaded without cases" + form;
      std::set<std::string> ids;
      for (const experiments::SuiteCase& c : suite.cases) {
        if (c.id.empty() || c.id.find_first_of("/\\\n\r") != std::string::npos) {
          return "a case id that is no file name: '" + c.id + "'" + form;
        }
        if (!ids.insert(c.id).second) return "a case id twice: " + c.id + form;
      }
      // The first cases as a run checks them first (each loads its scene: a few only).
      for (std::size_t i = 0; i < suite.cases.size() && i < 4; ++i) {
        try {
          suite.cases[i].job->validate(scenes_dir);
        } catch (const std::exception& e) {
          return "the study loaded, but its case " + suite.cases[i].id + " does not validate: " + e.what() + form;
        }
      }
    } catch (const SceneError& e) {
      if (std::string why = one_line_error(e.what(), name); !why.empty()) return why + form;
    }
  }
  return "";
}

std::string control_samples_property(std::string_view bytes) {
  const experiments::TomlReader reader("fuzz.toml");
  for (const int dim : {3, 2}) {
    try {
      const auto samples = reader.parse_samples(bytes, "fuzz.csv", "control.file", dim);
      for (double e = -300.0; e <= 300.0; e += 25.0) {
        for (const double sign : {1.0, -1.0}) {
          const double t = sign * std::pow(10.0, e);
          if (!(*samples)(t).allFinite()) return "samples evaluated to a non-finite value at t = " + std::to_string(t);
        }
      }
      if (!(*samples)(0.0).allFinite()) return "samples evaluated to a non-finite value at t = 0";
      if (dim == 2 && (*samples)(1.0)(2) != 0.0) return "a third component from two-component samples";
    } catch (const SceneError& e) {
      if (std::string why = one_line_error(e.what(), "fuzz.toml"); !why.empty()) return why;
      if (std::string(e.what()).rfind("fuzz.toml: control.file: ", 0) != 0) {
        return "an error not naming the field control.file: " + std::string(e.what());
      }
    }
  }
  return "";
}

std::vector<std::string> split_arguments(std::string_view bytes) {
  std::vector<std::string> args{"lgvi-testbed"};
  std::string current;
  for (const char c : bytes) {
    if (c == '\0' || c == '\n') {
      args.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  if (!current.empty()) args.push_back(current);
  return args;
}

std::string cli_property(std::string_view bytes) {
  const std::vector<std::string> args = split_arguments(bytes);
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out;
  std::ostringstream err;
  const std::optional<int> code = experiments::parse_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  const std::string e = err.str();
  const std::string command = experiments::quote_command_line(static_cast<int>(argv.size()), argv.data());
  if (!code || *code == experiments::kExitOk) {
    if (!e.empty()) return command + ": accepted, with an error stream: " + e;
    return "";
  }
  if (*code != experiments::kExitBadInput) return command + ": exit status " + std::to_string(*code) + ": " + e;
  if (e.rfind("error: ", 0) != 0 || e.empty() || e.back() != '\n' || e.find_first_of("\n\r") != e.size() - 1) {
    return command + ": refused without one 'error:' line: " + e;
  }
  return "";
}

}  // namespace lgvi::fuzz
