// Python bindings (pybind11): the module `lgvi`. NumPy arrays in and out; every argument is
// checked at the boundary by the CLI's rules and a bad one raises ValueError naming it (the
// library's InvalidInput becomes ValueError with its "field: reason" text): arrays for their
// shape, every number for the scene files' magnitudes (lgvi/range.hpp: finite, 0 or of magnitude
// in [1e-100, 1e100]), steps for the step limit, tolerances for the adaptive methods' range
// (baselines/tolerance.hpp, through the solver's own validation), and the rows a call returns
// for the module's memory limit (python_limits.hpp).
//
// Exposed: so3 maths (hat, vee, exp, log, cayley), FreeRigidBody and Pendulum3D, the LGVI
// (step, simulate), one baseline run (simulate_baseline: every method and coordinate model of
// baselines/solver.hpp) and the indirect optimal control of the pendulum (solve_pendulum_transfer,
// sec. 3.2). Trajectories come back as dicts of arrays: t (n,), R (n, 3, 3), Omega (n, 3),
// energy (n,), and the run's stats as a dict. With the harness (LGVI_PYTHON_HARNESS): scenes,
// simulate of a scene with every method, the suites, validate and the ocp solvers
// (python/harness_bindings.cpp).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "baselines/model.hpp"
#include "baselines/solver.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/lgvi.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/so3.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"
#include "python_limits.hpp"

namespace py = pybind11;
using lgvi::Mat3;

#ifdef LGVI_PYTHON_HARNESS
void bind_harness(py::module_& m);  // python/harness_bindings.cpp
#endif
using lgvi::Vec3;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string shape_text(const Array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i > 0 ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// Entries of an array argument: finite, and 0 or of magnitude in [1e-100, 1e100] (the scene
/// files' numbers, lgvi/range.hpp); ValueError naming the argument and the entry.
template <class Derived>
void check_entries(const Eigen::MatrixBase<Derived>& m, const char* name) {
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      const std::string problem = lgvi::magnitude_problem(m(i, j));
      if (problem.empty()) continue;
      const std::string at = m.cols() == 1 ? "[" + std::to_string(i) + "]"
                                           : "[" + std::to_string(i) + "][" + std::to_string(j) + "]";
      throw py::value_error(std::string(name) + at + ": " + problem);
    }
  }
}

/// A scalar argument by the same rule; `positive`: also > 0.
double number(double x, const char* name, bool positive = false) {
  const std::string problem = lgvi::magnitude_problem(x);
  if (!problem.empty()) throw py::value_error(std::string(name) + ": " + problem);
  if (positive && !(x > 0.0)) throw py::value_error(std::string(name) + ": must be > 0 (got " + lgvi::Range::text(x) + ")");
  return x;
}

/// A (3,) array as a Vec3; ValueError naming `name` for another shape or a bad entry.
Vec3 vec3(const Array& a, const char* name) {
  if (a.ndim() != 1 || a.shape(0) != 3) {
    throw py::value_error(std::string(name) + ": expected shape (3,), got " + shape_text(a));
  }
  const Vec3 v(a.at(0), a.at(1), a.at(2));
  check_entries(v, name);
  return v;
}

/// A (3, 3) array as a Mat3 (row-major, as numpy prints it).
Mat3 mat3(const Array& a, const char* name) {
  if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) {
    throw py::value_error(std::string(name) + ": expected shape (3, 3), got " + shape_text(a));
  }
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = a.at(i, j);
  check_entries(m, name);
  return m;
}

/// An inertia given as (3,) principal moments or a (3, 3) matrix.
Mat3 inertia_matrix(const Array& a) {
  if (a.ndim() == 1) return vec3(a, "inertia").asDiagonal();
  return mat3(a, "inertia");
}

py::array_t<double> to_array(const Vec3& v) {
  py::array_t<double> a(3);
  for (int i = 0; i < 3; ++i) a.mutable_at(i) = v(i);
  return a;
}

py::array_t<double> to_array(const Mat3& m) {
  py::array_t<double> a({3, 3});
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.mutable_at(i, j) = m(i, j);
  return a;
}

lgvi::LgviForm parse_form(const std::string& form) { return lgvi::parse_lgvi_form(form); }

py::dict stats_dict(const lgvi::Stats& s) {
  py::dict d;
  d["status"] = std::string(lgvi::to_string(s.status));
  d["brief"] = s.brief();
  d["steps"] = s.steps;
  d["rejected_steps"] = s.rejected_steps;
  d["potential_evaluations"] = s.potential_evaluations;
  d["newton_iterations"] = s.newton_iterations;
  d["max_newton_iterations"] = s.max_newton_iterations;
  d["rhs_evaluations"] = s.rhs_evaluations;
  d["jacobian_evaluations"] = s.jacobian_evaluations;
  d["wall_seconds"] = s.wall_seconds;
  if (!s.failure_detail.empty()) d["failure_detail"] = s.failure_detail;
  return d;
}

/// Samples of a trajectory, filled row by row, returned as a dict of arrays.
struct Trajectory {
  std::vector<double> t, R, Omega, energy;

  void add(double time, const Mat3& Rk, const Vec3& Omegak, double E) {
    t.push_back(time);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R.push_back(Rk(i, j));
    for (int i = 0; i < 3; ++i) Omega.push_back(Omegak(i));
    energy.push_back(E);
  }
  py::dict to_dict(const lgvi::Stats& stats) const {
    const auto n = static_cast<py::ssize_t>(t.size());
    py::dict d;
    d["t"] = py::array_t<double>(n, t.data());
    d["R"] = py::array_t<double>({n, py::ssize_t{3}, py::ssize_t{3}}, R.data());
    d["Omega"] = py::array_t<double>({n, py::ssize_t{3}}, Omega.data());
    d["energy"] = py::array_t<double>(n, energy.data());
    d["stats"] = stats_dict(stats);
    return d;
  }
};

/// h, steps and every of simulate, by the scene files' rules (a positive admissible h, at most
/// kMaxSteps steps, lgvi/range.hpp) and the module's row limit (python_limits.hpp).
std::size_t checked_steps(double h, long long steps, long long every) {
  number(h, "h", true);
  lgvi::Range::integers(0, lgvi::kMaxSteps).require(static_cast<double>(steps), "steps");
  lgvi::Range::integers(1, lgvi::kMaxSteps).require(static_cast<double>(every), "every");
  lgvi::python::require_rows(std::floor(static_cast<double>(steps) / static_cast<double>(every)) + 2.0, "every",
                             "steps / every");
  return static_cast<std::size_t>(steps);
}

/// The LGVI from (R0, Omega0), rows at k = 0, every, 2 every, ... and the last step.
template <class System>
py::dict simulate_lgvi(const System& system, const Array& R0, const Array& Omega0, double h, long long steps,
                       const std::string& form, long long every) {
  const std::size_t n = checked_steps(h, steps, every);
  const lgvi::AttitudeLgvi<System> integrator(system, parse_form(form));
  auto state = integrator.make_state(mat3(R0, "R0"), vec3(Omega0, "Omega0"));
  Trajectory out;
  const auto stride = static_cast<std::size_t>(every);
  lgvi::Stats stats;
  {
    py::gil_scoped_release release;  // pure C++ below: let other Python threads run
    stats = lgvi::integrate(integrator, state, 0.0, h, n, lgvi::zero_control<Vec3>(),
                            [&](std::size_t k, double t, const auto& s, const lgvi::RotationUpdateSummary&) {
                              if (k % stride == 0 || k == n) {
                                const Vec3 Omega = integrator.omega(s);
                                out.add(t, s.R, Omega, system.energy(s.R, Omega));
                              }
                              return true;
                            });
  }
  return out.to_dict(stats);
}

/// One LGVI step from (R, Omega) without control: returns (R1, Omega1).
template <class System>
py::tuple step_lgvi(const System& system, const Array& R, const Array& Omega, double h, const std::string& form) {
  number(h, "h", true);
  const lgvi::AttitudeLgvi<System> integrator(system, parse_form(form));
  const auto s0 = integrator.make_state(mat3(R, "R"), vec3(Omega, "Omega"));
  typename lgvi::AttitudeLgvi<System>::State s1;
  const Vec3 zero = Vec3::Zero();
  const lgvi::RotationUpdateSummary summary = integrator.step(s0, h, zero, zero, s1);
  // Outside the rotation update's domain (h |p| too large for the inertia, lgvi/rotation_update.hpp):
  // a ValueError for the arguments, as the CLI's failed run is a status, not a crash.
  if (!summary.converged()) {
    throw py::value_error("h: the rotation update failed (" + summary.brief() +
                          "): take a smaller h for this angular velocity");
  }
  return py::make_tuple(to_array(s1.R), to_array(integrator.omega(s1)));
}

/// A continuous-time baseline (baselines/solver.hpp) on the given coordinate model, sampled at
/// t = 0, h_out, 2 h_out, ..., t_final.
template <class System>
py::dict simulate_baseline(const System& system, const Array& R0_in, const Array& Omega0_in, double t_final,
                           long long samples, const std::string& method, const std::string& model,
                           std::optional<double> rtol, std::optional<double> atol, std::optional<double> h,
                           long long max_steps) {
  namespace b = lgvi::baselines;
  // t_final and h by the scene files' rules; rtol, atol and the steps h gives over t_final by
  // the solvers' own validation (resolve_settings, integrate: the CLI's ranges).
  number(t_final, "t_final", true);
  if (h) number(*h, "h", true);
  lgvi::Range::integers(1, lgvi::python::kMaxRows - 1).require(static_cast<double>(samples), "samples");
  const Mat3 R0 = mat3(R0_in, "R0");
  const Vec3 Omega0 = vec3(Omega0_in, "Omega0");
  b::SolverSettings settings;
  settings.rtol = rtol;
  settings.atol = atol;
  settings.h = h;
  // The step budget over the run (the CLI's, baselines/solver.hpp): an adaptive method's steps
  // grow with |Omega| t_final / rtol^(1/order), so a call that must return soon lowers it and
  // reads the status the budget ends the run with.
  const double default_budget = static_cast<double>(b::SolverSettings{}.max_steps);
  lgvi::Range::integers(1, default_budget).require(static_cast<double>(max_steps), "max_steps");
  settings.max_steps = static_cast<std::size_t>(max_steps);
  std::vector<double> times(static_cast<std::size_t>(samples) + 1);
  for (std::size_t i = 0; i < times.size(); ++i) {
    times[i] = t_final * static_cast<double>(i) / static_cast<double>(samples);
  }
  using Mechanics = b::AttitudeMechanics<System>;
  const Mechanics mechanics(system);
  Trajectory out;
  auto run = [&](const auto& ode) {
    const auto y0 = ode.initial_state({R0}, {Omega0});
    py::gil_scoped_release release;
    return b::integrate(method, ode, std::span<const double>(y0.data(), y0.size()), times, settings,
                        [&](std::size_t, double t, const double* y) {
                          const auto d = ode.decode(y);
                          out.add(t, d.config.R[0], d.rates.Omega[0], system.energy(d.config.R[0], d.rates.Omega[0]));
                          return true;
                        });
  };
  lgvi::Stats stats;
  switch (b::parse_coordinate_model(model)) {
    case b::CoordinateModel::Quaternion: stats = run(b::CoordinateOde<b::QuaternionChart, Mechanics>(mechanics)); break;
    case b::CoordinateModel::QuaternionRenormalized:
      stats = run(b::CoordinateOde<b::QuaternionChart, Mechanics>(mechanics, true));
      break;
    case b::CoordinateModel::Euler: stats = run(b::CoordinateOde<b::EulerChart, Mechanics>(mechanics)); break;
    case b::CoordinateModel::Matrix: stats = run(b::CoordinateOde<b::MatrixChart, Mechanics>(mechanics)); break;
  }
  return out.to_dict(stats);
}

py::array_t<double> vector_array(const Eigen::VectorXd& v) { return py::array_t<double>(v.size(), v.data()); }

/// The paper's pendulum transfer (sec. 3.2) by indirect shooting: the summary and the optimal
/// trajectory (R, Omega at the nodes, controls u_0..u_N, multipliers lambda_0..lambda_N).
py::dict solve_pendulum_transfer(const lgvi::Pendulum3D& pendulum, double h, const std::string& form,
                                 std::optional<Array> initial_multiplier, double tolerance, int max_iterations) {
  namespace o = lgvi::ocp;
  const o::TransferProblem problem = o::TransferProblem::pendulum_paper();
  o::ShootingOptions options;
  options.form = parse_form(form);
  options.h = number(h, "h", true);  // the steps 1 / h are the solver's (at most kMaxOcpSteps)
  options.tolerance = tolerance;
  options.max_iterations = max_iterations;
  if (initial_multiplier) {
    const Array& g = *initial_multiplier;
    if (g.ndim() != 1 || g.shape(0) != 6) {
      throw py::value_error("initial_multiplier: expected shape (6,), got " + shape_text(g));
    }
    options.initial_multiplier = Eigen::Map<const Eigen::VectorXd>(g.data(), 6);
  } else {
    // At lambda_0 = 0 every control vanishes and the sensitivity at rest is singular: the CLI's
    // default guess (lgvi-testbed ocp pendulum).
    options.initial_multiplier = Eigen::VectorXd::Ones(6);
  }
  o::ShootingResult<o::PendulumModel> result;
  {
    py::gil_scoped_release release;
    result = o::solve_indirect(pendulum, problem, options);
  }
  const o::ShootingSummary& s = result.summary;
  if (s.status == o::ShootingStatus::InvalidInput) throw py::value_error(s.message);
  py::dict summary;
  summary["status"] = std::string(o::to_string(s.status));
  summary["converged"] = s.converged();
  summary["message"] = s.message;
  summary["brief"] = s.brief();
  summary["form"] = std::string(lgvi::to_string(s.form));
  summary["h"] = s.h;
  summary["steps"] = s.steps;
  summary["iterations"] = s.iterations;
  summary["inner_iterations"] = s.inner_iterations;
  summary["cost"] = s.cost;
  summary["violation"] = s.violation;
  summary["residual"] = vector_array(s.residual);
  summary["multiplier"] = vector_array(s.multiplier);
  summary["wall_seconds"] = s.wall_seconds;

  const auto& sweep = result.sweep;
  Trajectory traj;
  for (std::size_t k = 0; k < sweep.states.size(); ++k) {
    const auto& st = sweep.states[k];
    const Vec3 Omega = pendulum.inertia.J_inverse * st.Pi;
    traj.add(static_cast<double>(k) * s.h, st.R, Omega, pendulum.energy(st.R, Omega));
  }
  py::dict d = traj.to_dict(lgvi::Stats{});
  d.attr("pop")("stats");
  const auto nodes = static_cast<py::ssize_t>(sweep.controls.size());
  py::array_t<double> u({nodes, py::ssize_t{3}});
  for (py::ssize_t k = 0; k < nodes; ++k)
    for (int i = 0; i < 3; ++i) u.mutable_at(k, i) = sweep.controls[static_cast<std::size_t>(k)](i);
  d["u"] = u;
  d["summary"] = summary;
  return d;
}

}  // namespace

PYBIND11_MODULE(_lgvi, m) {
  m.doc() =
      "Lie group variational integrators and discrete optimal control of rigid bodies (Lee, Leok, "
      "McClamroch). Arrays are numpy float64; R is a (3, 3) rotation matrix (body to inertial), Omega "
      "the (3,) body angular velocity.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const lgvi::InvalidInput& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::module_ so3 = m.def_submodule("so3", "SO(3): hat/vee, exp/log (Rodrigues), Cayley");
  so3.def("hat", [](const Array& w) { return to_array(lgvi::so3::hat(vec3(w, "w"))); }, py::arg("w"),
          "The skew matrix hat(w), hat(w) v = w x v.");
  so3.def("vee", [](const Array& W) { return to_array(lgvi::so3::vee(mat3(W, "W"))); }, py::arg("W"),
          "The inverse of hat (of the skew part of W).");
  so3.def("exp", [](const Array& w) { return to_array(lgvi::so3::exp(vec3(w, "w"))); }, py::arg("w"),
          "The rotation exp(hat(w)) (Rodrigues' formula).");
  so3.def("log",
          [](const Array& R) {
            // The library's precondition, checked as simulate checks R0 (lgvi/lgvi.hpp).
            const Mat3 rotation = mat3(R, "R");
            if (!lgvi::so3::is_rotation(rotation, 1e-10)) {
              throw py::value_error("R: not a rotation matrix (R^T R != I or det R != 1, to 1e-10)");
            }
            return to_array(lgvi::so3::log(rotation));
          },
          py::arg("R"),
          "The rotation vector w with exp(hat(w)) = R, |w| <= pi; ValueError if R is not a rotation (to 1e-10).");
  so3.def("cayley", [](const Array& f) { return to_array(lgvi::so3::cayley(vec3(f, "f"))); }, py::arg("f"),
          "The Cayley transform of the rotation-update parametrization (lgvi/so3.hpp).");

  py::class_<lgvi::FreeRigidBody>(m, "FreeRigidBody", "A free rigid body: no potential.")
      .def(py::init([](const Array& inertia, bool nonphysical_inertia) {
             return lgvi::FreeRigidBody(inertia_matrix(inertia), nonphysical_inertia
                                                                     ? lgvi::InertiaDomain::PositiveDefinite
                                                                     : lgvi::InertiaDomain::Physical);
           }),
           py::arg("inertia"), py::arg("nonphysical_inertia") = false,
           "inertia: (3,) principal moments or a (3, 3) matrix [kg m^2]; validated (symmetric positive definite, "
           "and the triangle inequality unless nonphysical_inertia: the Euler equations of a test-set body).")
      .def_property_readonly("inertia", [](const lgvi::FreeRigidBody& b) { return to_array(b.inertia.J); })
      .def("energy",
           [](const lgvi::FreeRigidBody& b, const Array& R, const Array& Omega) {
             return b.energy(mat3(R, "R"), vec3(Omega, "Omega"));
           },
           py::arg("R"), py::arg("Omega"))
      .def("spatial_momentum",
           [](const lgvi::FreeRigidBody& b, const Array& R, const Array& Omega) {
             return to_array(b.spatial_momentum(mat3(R, "R"), vec3(Omega, "Omega")));
           },
           py::arg("R"), py::arg("Omega"), "R J Omega, conserved.");

  py::class_<lgvi::Pendulum3D>(m, "Pendulum3D", "3D pendulum on a fixed pivot in uniform gravity (sec. 3.2).")
      .def(py::init([](double mass, const Array& inertia, const Array& rho, double gravity) {
             return lgvi::Pendulum3D(number(mass, "mass"), inertia_matrix(inertia), vec3(rho, "rho"),
                                     number(gravity, "gravity"));
           }),
           py::arg("mass"), py::arg("inertia"), py::arg("rho"), py::arg("gravity") = 9.81)
      .def_static("paper", &lgvi::Pendulum3D::paper, "The paper's pendulum (m = 1, J = diag(0.13, 0.28, 0.17)).")
      .def_readonly("mass", &lgvi::Pendulum3D::mass)
      .def_readonly("gravity", &lgvi::Pendulum3D::gravity)
      .def_property_readonly("inertia", [](const lgvi::Pendulum3D& p) { return to_array(p.inertia.J); })
      .def_property_readonly("rho", [](const lgvi::Pendulum3D& p) { return to_array(p.rho); })
      .def("energy",
           [](const lgvi::Pendulum3D& p, const Array& R, const Array& Omega) {
             return p.energy(mat3(R, "R"), vec3(Omega, "Omega"));
           },
           py::arg("R"), py::arg("Omega"))
      .def("vertical_momentum",
           [](const lgvi::Pendulum3D& p, const Array& R, const Array& Omega) {
             return p.vertical_momentum(mat3(R, "R"), vec3(Omega, "Omega"));
           },
           py::arg("R"), py::arg("Omega"), "e3^T R J Omega, conserved.");

  const char* step_doc = "One LGVI step without control (eqs. 8-10; form 'symmetric' or 'printed'): (R1, Omega1).";
  m.def("step", &step_lgvi<lgvi::FreeRigidBody>, py::arg("system"), py::arg("R"), py::arg("Omega"), py::arg("h"),
        py::arg("form") = "symmetric", step_doc);
  m.def("step", &step_lgvi<lgvi::Pendulum3D>, py::arg("system"), py::arg("R"), py::arg("Omega"), py::arg("h"),
        py::arg("form") = "symmetric", step_doc);
  const char* simulate_doc =
      "Integrates `steps` LGVI steps of size h from (R0, Omega0) without control; rows at k = 0, every, "
      "2 every, ... and the last step. Returns {t, R, Omega, energy, stats}.";
  m.def("simulate", &simulate_lgvi<lgvi::FreeRigidBody>, py::arg("system"), py::arg("R0"), py::arg("Omega0"),
        py::arg("h"), py::arg("steps"), py::arg("form") = "symmetric", py::arg("every") = 1, simulate_doc);
  m.def("simulate", &simulate_lgvi<lgvi::Pendulum3D>, py::arg("system"), py::arg("R0"), py::arg("Omega0"),
        py::arg("h"), py::arg("steps"), py::arg("form") = "symmetric", py::arg("every") = 1, simulate_doc);

  const char* baseline_doc =
      "A continuous-time baseline: method (baseline_methods()) on a coordinate model ('quaternion', "
      "'quaternion-renormalized', 'euler', 'matrix'), sampled at samples + 1 equally spaced times on "
      "[0, t_final]. Adaptive methods take rtol/atol, fixed-step ones h. max_steps bounds the steps over the run "
      "(at most 50,000,000, the default; a run that reaches it stops with that status in stats). Returns {t, R, "
      "Omega, energy, stats}.";
  m.def("simulate_baseline", &simulate_baseline<lgvi::FreeRigidBody>, py::arg("system"), py::arg("R0"),
        py::arg("Omega0"), py::arg("t_final"), py::arg("samples") = 100, py::arg("method") = "odeint-dopri5",
        py::arg("model") = "quaternion", py::arg("rtol") = py::none(), py::arg("atol") = py::none(),
        py::arg("h") = py::none(), py::arg("max_steps") = static_cast<long long>(lgvi::baselines::SolverSettings{}.max_steps), baseline_doc);
  m.def("simulate_baseline", &simulate_baseline<lgvi::Pendulum3D>, py::arg("system"), py::arg("R0"),
        py::arg("Omega0"), py::arg("t_final"), py::arg("samples") = 100, py::arg("method") = "odeint-dopri5",
        py::arg("model") = "quaternion", py::arg("rtol") = py::none(), py::arg("atol") = py::none(),
        py::arg("h") = py::none(), py::arg("max_steps") = static_cast<long long>(lgvi::baselines::SolverSettings{}.max_steps), baseline_doc);
  m.def("baseline_methods", &lgvi::baselines::solver_names, "The baseline methods' names.");

  m.def("solve_pendulum_transfer", &solve_pendulum_transfer, py::arg_v("pendulum", lgvi::Pendulum3D::paper(), "Pendulum3D.paper()"),
        py::arg("h") = 1e-3, py::arg("form") = "symmetric", py::arg("initial_multiplier") = py::none(),
        py::arg("tolerance") = 1e-12, py::arg("max_iterations") = 100,
        "The paper's pendulum transfer (sec. 3.2: rest to rest, 180 deg about the vertical in 1 s) by "
        "indirect shooting (Newton-Armijo on lambda_0). Returns {t, R, Omega, energy, u, summary}.");
  m.attr("has_harness") = false;
#ifdef LGVI_PYTHON_HARNESS
  bind_harness(m);
  m.attr("has_harness") = true;
#endif
}
