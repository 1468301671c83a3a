// A rigid body moving in space under a potential U(R, x) in the harness (scene system
// "potential-body-se3"; lgvi/systems/potential_body_se3.hpp): uniform gravity or a spring from an
// anchor to a body point, with the dumbbell's time-dependent force and moment controls; Python's
// lgvi.potential_scene(..., mass=, force=) puts a user's potential in its place.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "experiments/systems/rigid_body.hpp"
#include "lgvi/systems/potential_body_se3.hpp"

namespace lgvi::experiments {

struct PotentialBodySE3Model {
  using State = RigidBodyInitial;
  static constexpr const char* name = "potential-body-se3";
  PotentialBodySE3 system;
  State initial;
  std::optional<TimeControl> force_control;   ///< u^f, inertial frame
  std::optional<TimeControl> moment_control;  ///< u^m, body frame
};

template <std::same_as<PotentialBodySE3Model> BoundModel>
struct SystemBinding<BoundModel> : RigidBodyBinding<PotentialBodySE3Model> {
  using M = PotentialBodySE3Model;
  static constexpr std::array<std::string_view, 7> kParameterKeys = {"mass",      "inertia", "potential", "gravity",
                                                                     "stiffness", "anchor",  "attachment"};

  /// [parameters]: mass, inertia and potential = "uniform-gravity" (gravity) or "anchored-spring"
  /// (stiffness, anchor, attachment); the other potential's keys are refused. [initial] and
  /// [control]: RigidBodyBinding's.
  static void check_keys(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial) {
    r.check_keys(parameters, kParameterKeys);
    check_initial_keys(r, initial);
  }
  static M read(const SceneReader& r, const SceneTable& parameters, const SceneTable& initial,
                const std::optional<SceneTable>& control) {
    const double mass = r.number(parameters, "mass");
    const Mat3 J = r.inertia(parameters, "inertia");
    const std::string kind = r.string(parameters, "potential");
    const auto refuse = [&](std::initializer_list<std::string_view> keys, const char* other) {
      for (const std::string_view key : keys) {
        if (r.has(parameters, key)) {
          r.fail("parameters." + std::string(key),
                 std::string("belongs to potential = \"") + other + "\" (this one is \"" + kind + "\")");
        }
      }
    };
    SE3Potential potential;
    if (kind == "uniform-gravity") {
      refuse({"stiffness", "anchor", "attachment"}, "anchored-spring");
      potential = UniformGravity{r.vec3(parameters, "gravity")};
    } else if (kind == "anchored-spring") {
      refuse({"gravity"}, "uniform-gravity");
      potential = AnchoredSpring{r.number(parameters, "stiffness"), r.vec3(parameters, "anchor"),
                                 r.vec3(parameters, "attachment")};
    } else {
      r.fail("parameters.potential", "must be \"uniform-gravity\" or \"anchored-spring\" (got \"" + kind + "\")");
    }
    M m{r.physics("parameters.", [&] { return PotentialBodySE3(mass, J, potential); }), read_initial(r, initial), {}, {}};
    read_controls_and_check(r, m, control);
    return m;
  }
  static MomentumMap momentum_map() {
    return {"angular momentum the potential conserves: R J Omega (gravity), (x - anchor) x m v + R J Omega "
            "(spring), x x m v + R J Omega (a user's potential)",
            momentum_columns()};
  }
  /// The potential's force and moment act at the printed step's end: first order.
  static int printed_order(const M&) { return 1; }
  static std::string units() { return "SI: kg, m, s, rad; energy J, momentum kg m^2/s"; }
  static SystemLabels labels() {
    return {"time [s]", "|E - E_0| [J]", "|L - L_0| [kg m^2/s],  L the conserved angular momentum", " s"};
  }
};

}  // namespace lgvi::experiments
