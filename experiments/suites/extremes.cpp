// "extremes": where each method breaks. Every case records success, its error, or the failure
// status (never a crash): step size up to and beyond the rotation update's domain (h |Omega0|
// from 0.01 to 6), fast spin (|Omega0| = 100 rad/s), near-symmetric and near-flat inertia
// (J3 -> J1 + J2, where J_d = tr(J)/2 I - J becomes singular), tiny steps (round-off growth),
// and the Euler-angle model through gimbal lock. All on the free body of free-body.toml.
#include <cmath>
#include <map>

#include "baselines/solver.hpp"
#include "experiments/scene/scene.hpp"
#include "experiments/suites/common.hpp"

namespace lgvi::experiments::suites {

namespace fs = std::filesystem;

namespace {

constexpr const char* kScene = "free-body";

/// Calls f(binding, model) on the scene's body: a system whose binding sets the inertia (the free
/// body); another system is refused.
template <class S, class F>
void with_body(S& scene, F&& f) {
  visit_binding(scene.model, [&](auto binding, auto& m) {
    using B = decltype(binding);
    if constexpr (requires(std::decay_t<decltype(m)>& edited) { B::set_inertia(edited, Mat3()); }) {
      f(binding, m);
    } else {
      throw InvalidInput("scene", scene.name + ": the extremes suite needs a free-body scene");
    }
  });
}

SceneEdit set_omega(const Vec3& omega, const std::string& description) {
  return {description, [omega](Scene& s) { with_body(s, [&](auto, auto& m) { m.initial.Omega = omega; }); }};
}

SceneEdit set_inertia_and_omega(const Vec3& J, const Vec3& omega, const std::string& description) {
  return {description, [J, omega](Scene& s) {
            with_body(s, [&](auto binding, auto& m) {
              decltype(binding)::set_inertia(m, J.asDiagonal().toDenseMatrix());
              m.initial.Omega = omega;
            });
          }};
}

std::string tag(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

/// Complete for a method expected to complete every case (its trait), else either outcome.
Expectation expected_outcome(const MethodSpec& m) {
  return m.info->must_complete_at_extremes ? Expectation::Complete : Expectation::Either;
}

}  // namespace

Suite extremes_suite(const SuiteParams& params) {
  Suite s;
  s.name = "extremes";
  s.description = "where methods break: large h|Omega|, fast spin, near-flat inertia, tiny steps, gimbal lock";
  s.columns = simulation_columns();
  const bool quick = params.quick;
  const Scene base = load_scene(resolve_scene(kScene, params.scenes_dir));
  Vec3 omega0;
  with_body(base, [&](auto, const auto& m) { omega0 = m.initial.Omega; });
  const auto add = [&](const std::string& group, const std::string& id, const SimulateSpec& spec, const MethodSpec& m,
                       Expectation e) { s.cases.push_back(simulate_case(group + "-" + id + "-" + m.id(), group, spec, m, e)); };

  // Step size: h |Omega0| from well inside to beyond the rotation update's domain. Small steps
  // must work; beyond 0.1 every outcome is a finding.
  {
    const std::vector<double> targets = quick ? std::vector<double>{0.01, 0.1, 0.5, 1, 2, 4}
                                              : std::vector<double>{0.01, 0.03, 0.1, 0.3, 0.5, 1, 1.5, 2, 3, 4, 6};
    const std::size_t steps = quick ? 200 : 2000;
    std::vector<MethodSpec> methods = lgvi_methods(quick);
    methods.push_back({"odeint-rk4", "quaternion", std::nullopt});
    methods.push_back({"odeint-rk4", "matrix", std::nullopt});
    methods.push_back({"gsl-rk4imp", "quaternion", std::nullopt});
    for (const double target : targets) {
      SimulateSpec spec;
      spec.scene = kScene;
      const double h = target / omega0.norm();
      spec.overrides.h = h;
      spec.overrides.t_final = static_cast<double>(steps) * h;
      spec.overrides.output_every = 1;
      for (const MethodSpec& m : methods) {
        add("step-size", "hw" + tag(target), spec, m, target <= 0.1 ? Expectation::Complete : Expectation::Either);
      }
    }
  }
  // Fast spin: |Omega0| = 100 rad/s along the scene's initial direction, h |Omega0| = 0.1.
  {
    SimulateSpec spec;
    spec.scene = kScene;
    spec.overrides.h = 1e-3;
    spec.overrides.t_final = quick ? 1.0 : 20.0;
    spec.overrides.output_every = quick ? 2 : 40;
    spec.edit = set_omega(100.0 * omega0.normalized(), "Omega0 norm 100 rad/s");
    for (const MethodSpec& m : long_run_methods(quick)) add("fast-spin", "w100", spec, m, expected_outcome(m));
  }
  // Inertia: near-symmetric (J1 ~ J2 ~ J3) and near-flat (J3 = (J1 + J2)(1 - eps): the third
  // eigenvalue of J_d = tr(J)/2 I - J is (J1 + J2 - J3)/2 -> 0).
  {
    struct Variant {
      std::string id;
      Vec3 J;
      std::string description;
    };
    std::vector<Variant> variants = {{"symmetric1e-6", Vec3(0.2, 0.2 * (1 + 1e-6), 0.2 * (1 + 2e-6)),
                                      "near-symmetric J = 0.2 diag(1 1+1e-6 1+2e-6)"}};
    for (const double eps : quick ? std::vector<double>{1e-3, 1e-6, 1e-9} : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-6,
                                                                                                  1e-8, 1e-9, 1e-12}) {
      variants.push_back({"flat" + tag(eps), Vec3(0.1, 0.2, 0.3 * (1 - eps)),
                          "near-flat J = diag(0.1 0.2 0.3(1-" + tag(eps) + "))"});
    }
    std::vector<MethodSpec> methods = quick ? std::vector<MethodSpec>{{"lgvi"},
                                                                      {"lgvi-yoshida4"},
                                                                      {"odeint-rk4", "quaternion", std::nullopt},
                                                                      {"cvode-bdf", "quaternion", std::nullopt}}
                                            : long_run_methods(false);
    for (const Variant& v : variants) {
      SimulateSpec spec;
      spec.scene = kScene;
      spec.overrides.h = 0.01;
      spec.overrides.t_final = quick ? 10.0 : 100.0;
      spec.overrides.output_every = 10;
      spec.edit = set_inertia_and_omega(v.J, Vec3(1.0, 1.0, 1.0), v.description + " with Omega0 = (1 1 1) rad/s");
      for (const MethodSpec& m : methods) add("inertia", v.id, spec, m, Expectation::Either);
    }
  }
  // Tiny steps: round-off accumulation over 10^5 (quick) or 10^7 steps.
  {
    const std::size_t steps = quick ? 100'000 : 10'000'000;
    const double h = quick ? 1e-5 : 1e-6;
    SimulateSpec spec;
    spec.scene = kScene;
    spec.overrides.h = h;
    spec.overrides.t_final = static_cast<double>(steps) * h;
    spec.overrides.output_every = static_cast<std::int64_t>(steps / 500);
    std::vector<MethodSpec> methods = {{"lgvi"},
                                       {"lgvi-yoshida4"},
                                       {"odeint-rk4", "quaternion", std::nullopt},
                                       {"odeint-rk4", "matrix", std::nullopt}};
    for (const MethodSpec& m : methods) add("tiny-steps", "h" + tag(h), spec, m, Expectation::Complete);
  }
  // Gimbal lock: a steady spin about the body's e2 axis turns the 3-2-1 pitch through 90 deg at
  // t = pi/4 s. The Euler-angle model must stop with a coordinate singularity; the LGVI and
  // the quaternion model must pass.
  {
    SimulateSpec spec;
    spec.scene = kScene;
    spec.overrides.h = 1e-3;
    spec.overrides.t_final = 2.0;
    spec.overrides.output_every = 10;
    spec.edit = set_omega(Vec3(0.0, 2.0, 0.0), "Omega0 = (0 2 0) rad/s: pitch 90 deg at t = 0.785 s");
    add("gimbal-lock", "pitch", spec, {"lgvi"}, Expectation::Complete);
    add("gimbal-lock", "pitch", spec, {"odeint-rk4", "quaternion", std::nullopt}, Expectation::Complete);
    std::vector<std::string> solvers = {"cvode-bdf", "odeint-rk4", "odeint-dopri5", "gsl-rk8pd"};
    if (!quick) {
      solvers.clear();  // every method that takes Euler angles
      for (const MethodInfo* info : methods_where([](const MethodInfo& i) {
             return std::ranges::find(i.models, baselines::CoordinateModel::Euler) != i.models.end();
           })) {
        solvers.push_back(info->name);
      }
    }
    for (const std::string& solver : solvers) add("gimbal-lock", "pitch", spec, {solver, "euler", std::nullopt}, Expectation::Fail);
  }

  s.render = [](const RenderContext& ctx, const std::vector<SummaryRow>& rows) {
    std::vector<fs::path> files;
    const auto groups = by_group(rows);
    for (const auto& [group, members] : groups) {
      if (group == "step-size") {
        for (const auto& [column, ylabel, name] :
             std::vector<std::array<std::string, 3>>{{"max_energy_error_relative", "max |E - E_0| / |E_0|", "energy"},
                                                     {"max_orthogonality_error", "max ||R^T R - I||_F", "orthogonality"}}) {
          std::vector<XyCurve> curves;
          std::map<std::string, std::size_t> where;
          for (const SummaryRow* r : members) {
            if (r->text("status") != "completed") continue;  // failures are in the table
            const auto [it, inserted] = where.emplace(r->text("label"), curves.size());
            if (inserted) curves.push_back({r->text("label"), {}, row_style(*r)});
            if (r->number("h_omega") && r->number(column)) {
              curves[it->second].points.emplace_back(*r->number("h_omega"), *r->number(column));
            }
          }
          files.push_back(plot_xy(ctx, "step-size-" + name,
                                  "free body: " + name + " error against the step (completed runs; failures in "
                                  "extremes-table.md)",
                                  "h |Ω_0| [rad]", ylabel, curves));
        }
      } else if (group == "tiny-steps" || group == "fast-spin") {
        const std::string& variant = members.front()->text("variant");
        files.push_back(plot_time_series(ctx, group + "-energy",
                                         "free body, " + group + ": energy error" + (variant.empty() ? "" : ", " + variant) +
                                             ", h = " + title_number(*members.front(), "h"),
                                         "|E - E_0| [J]", "energy_error", true, members));
      }
    }
    std::string table = "# Extremes: outcome of every case\n\n"
                        "| group | variant | method | h | h \\|Omega0\\| | expected | status | as expected | "
                        "max energy error | max orthogonality error | detail |\n"
                        "|---|---|---|---|---|---|---|---|---|---|---|\n";
    // '|' would split a markdown cell.
    const auto md = [](std::string text) {
      for (char& c : text) {
        if (c == '|') c = '/';
      }
      return text;
    };
    for (const SummaryRow& r : rows) {
      const auto num = [&](const char* c) { return r.number(c) ? fmt(*r.number(c)) : std::string(); };
      table += "| " + r.text("group") + " | " + md(r.text("variant")) + " | " + r.text("label") + " | " + num("h") +
               " | " + num("h_omega") + " | " + r.text("expected") + " | " + r.text("status") + " | " +
               r.text("as_expected") + " | " + num("max_energy_error_relative") + " | " + num("max_orthogonality_error") +
               " | " + md(r.text("detail")) + " |\n";
    }
    files.push_back(write_text_file(ctx, "extremes-table.md", table));
    return files;
  };
  return s;
}

}  // namespace lgvi::experiments::suites
