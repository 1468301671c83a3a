// The dumbbell spacecraft in the harness (scene system "dumbbell"): one rigid body on SE(3).
#pragma once

#include "experiments/systems/rigid_body.hpp"

namespace lgvi::experiments {

struct DumbbellModel {
  using State = RigidBodyInitial;
  static constexpr const char* name = "dumbbell";
  DumbbellSpacecraft system;
  State initial;
  std::optional<TimeControl> force_control;   ///< u^f, inertial frame
  std::optional<TimeControl> moment_control;  ///< u^m, body frame
};

template <std::same_as<DumbbellModel> BoundModel>
struct SystemBinding<BoundModel> : RigidBodyBinding<DumbbellModel> {
  using M = DumbbellModel;

  /// [parameters]: mass, mu, rho, sphere_radius (J follows); [initial] and [control]: RigidBodyBinding's.
  static void check_keys(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial) {
    r.check_keys(parameters, {"mass", "mu", "rho", "sphere_radius"});
    check_initial_keys(r, initial);
  }
  static M read(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                const std::optional<SceneTable>& control) {
    const double mass = r.number(parameters, "mass");
    const double mu = r.number(parameters, "mu");
    const Vec3 rho = r.vec3(parameters, "rho");
    const double radius = r.number(parameters, "sphere_radius");
    const State init = read_initial(r, initial);
    M m{r.physics("parameters.", [&] { return DumbbellSpacecraft(mass, mu, rho, radius); }), init, {}, {}};
    read_controls_and_check(r, m, control);
    return m;
  }
  static MomentumMap momentum_map() {
    return {"total angular momentum x cross m v + R J Omega", momentum_columns()};
  }
  /// The gravity force and moment act at the printed step's end: first order.
  static int printed_order(const M&) { return 1; }
  static std::string units() {
    return "normalized: mass 1, reference orbit radius 1, mu = 1 (period 2 pi); t, x, v, Omega, energy, "
           "momentum in these units";
  }
  static SystemLabels labels() {
    return {"time [normalized: orbit period 2π]", "|E - E_0| [normalized]",
            "|H - H_0| [normalized],  H = x × m v + R J Ω", " (orbit period 2π)"};
  }
};

}  // namespace lgvi::experiments
