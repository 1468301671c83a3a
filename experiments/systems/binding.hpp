// System bindings: what the harness knows about each system, in one place per system
// (experiments/systems/<system>.hpp specializes SystemBinding<SceneModel>). The recorder, the
// methods and the suites consult the binding of the scene's model (visit_binding) instead of
// branching on the system. A new system: its binding file (its scene model, state record, scene
// tables' reader and the rest below) and its line in the list, systems.hpp. A binding sees only
// its own system's state record (M::State); the recorder's Sample holds one of them.
#pragma once

#include <algorithm>
#include <concepts>
#include <optional>
#include <cstddef>
#include <string>
#include <vector>

#include "experiments/input/scene_reader.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/rotation_update.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {

/// Energy and momentum map of a sample; the momentum has 1 (pendulum, cart) or 3 components.
struct Conserved {
  double energy;
  Vec3 momentum;
  int momentum_size;
};

/// Which momentum map a system conserves, as named in columns and summaries.
struct MomentumMap {
  const char* description;     ///< e.g. "spatial angular momentum R J Omega"
  std::vector<std::string> columns;
};

/// Axis labels of a system in its units (gnuplot enhanced text).
struct SystemLabels {
  std::string time, energy, momentum;
  std::string horizon_unit;  ///< after a horizon's value in a title: " s", " (orbit period 2π)"
};

/// SystemBinding<M> for a scene model M provides (static members; `State` is M::State, the
/// system's record in the paper's variables, a scene's initial state and the recorder's sample):
///   State                          M::State
///   check_keys(r, parameters, initial)   rejects unknown keys of the scene's [parameters] and
///                                  [initial] (before any value is read)
///   check_control_keys(r, control)  the same for [control]
///   read(r, parameters, initial, control)   the model from those tables, validated
///                                  (SceneReader: every error names the file, field and reason)
///   single_body                    no mass matrix to solve (a baseline's Jacobian text)
///   state_columns(c)               appends the CSV state columns after t (paper's symbols)
///   write_state(s, row, n)         writes those columns of state s into row[n..]; returns n
///   conserved(m, s, t)             energy and momentum map of a state at time t (the free
///                                  body's Jacobi integral in orbit depends on t)
///   momentum_map()                 the momentum map's description and columns
///   orthogonality_error(s), determinant_error(s)   the worst over the system's attitudes
///   final_state_error(s, ref)      dimensionless distance of two final states (see suite_jobs.hpp)
///   distance(a, b)                 sum of the parts' norms (Frobenius for attitudes)
///   initial_rate(m)                |Omega0| (the largest body's)
///   printed_order(m)               nominal order of the printed LGVI form on this model: 1
///                                  where a potential or control acts at the step's end, else 2
///   drop_controls(m)               removes the scene's controls (an uncontrolled run)
///   delay_controls(m, dt)          makes every open-loop control late by dt (validate's
///                                  control-timing degradation)
///   labels()                       figure axis labels
///   units()                        the CSV's "units" metadata
///   run_lgvi(m, form, rotation, drive)      the LGVI flow map, initial state, control and
///                                  state conversion of the system, handed to
///                                  drive(flow, flow_state, control, to_state) with
///                                  to_state(flow_state, State&)
///   run_baseline(m, chart)         the continuous mechanics and initial state, handed to
///                                  chart(mech, R, Omega, x, v) (baselines/mechanics.hpp)
///   from_chart(decoded, s)         a baseline's decoded state into a State
/// and, where a suite needs them (the suite asks whether the binding has them):
///   lgvi_attitude_compensated      constant true: the LGVI's attitude sum is compensated
///                                  (validate's bounded orthogonality floor)
///   as_pendulum(m)                 the system as a Pendulum3D (sensitivity suite)
///   set_inertia(m, J)              replaces the body's inertia (extremes suite)
/// A binding is a constrained partial specialization, `template <std::same_as<XModel> BoundModel>
/// struct SystemBinding<BoundModel>`, not an explicit one: its members are then templates,
/// instantiated only in the files that use them (every file that includes the list of systems
/// would otherwise compile every binding's flow maps and mechanics).
template <class M>
struct SystemBinding;

/// The non-template part of the list above (run_lgvi, run_baseline and from_chart are templates
/// on the driver's callbacks; their use in lgvi_method.cpp and baseline_method.cpp checks them).
template <class B, class M>
concept SystemBindingOf = std::same_as<typename B::State, typename M::State> &&
                          requires(const M& m, M& edited, const typename M::State& s, std::vector<std::string>& c,
                                   double* row, const SceneReader& r, const SceneTable& t,
                                   const std::optional<SceneTable>& control) {
  B::check_keys(r, t, t);
  B::check_control_keys(r, t);
  { B::read(r, t, t, control) } -> std::same_as<M>;
  { B::single_body } -> std::convertible_to<bool>;
  B::state_columns(c);
  { B::write_state(s, row, std::size_t{0}) } -> std::same_as<std::size_t>;
  { B::conserved(m, s, 0.0) } -> std::same_as<Conserved>;
  { B::momentum_map() } -> std::same_as<MomentumMap>;
  { B::orthogonality_error(s) } -> std::same_as<double>;
  { B::determinant_error(s) } -> std::same_as<double>;
  { B::final_state_error(s, s) } -> std::same_as<double>;
  { B::distance(s, s) } -> std::same_as<double>;
  { B::initial_rate(m) } -> std::same_as<double>;
  { B::printed_order(m) } -> std::same_as<int>;
  B::drop_controls(edited);
  B::delay_controls(edited, 1.0);
  { B::labels() } -> std::same_as<SystemLabels>;
  { B::units() } -> std::same_as<std::string>;
};

/// The state columns "<name>11".."<name>33" of a matrix and "<name>1".."<name>3" of a vector.
inline void matrix_columns(std::vector<std::string>& c, const std::string& name) {
  for (int i = 1; i <= 3; ++i) {
    for (int j = 1; j <= 3; ++j) c.push_back(name + std::to_string(i) + std::to_string(j));
  }
}
inline void vector_columns(std::vector<std::string>& c, const std::string& name) {
  for (int i = 1; i <= 3; ++i) c.push_back(name + std::to_string(i));
}
/// Writes M row by row into row[n..]; returns the new n.
inline std::size_t write_matrix(const Mat3& M, double* row, std::size_t n) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) row[n++] = M(i, j);
  }
  return n;
}
/// Writes every entry of the (fixed-size) vector v into row[n..]; returns the new n.
template <int N>
std::size_t write_vector(const Eigen::Matrix<double, N, 1>& v, double* row, std::size_t n) {
  for (int i = 0; i < N; ++i) row[n++] = v(i);
  return n;
}

/// |a - ref| / |ref|, absolute when |ref| = 0.
template <int N>
double relative_error(const Eigen::Matrix<double, N, 1>& a, const Eigen::Matrix<double, N, 1>& ref) {
  const double n = ref.norm();
  return n > 0.0 ? (a - ref).norm() / n : (a - ref).norm();
}

}  // namespace lgvi::experiments
