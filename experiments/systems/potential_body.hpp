// A rigid body in a parametric attitude potential in the harness (scene system
// "potential-body"; lgvi/systems/potential_body.hpp): an attitude spring or a magnetic dipole in
// a uniform field, with the free body's controls and feedback.
#pragma once

#include <string>

#include "experiments/systems/attitude.hpp"
#include "experiments/systems/exact_reference.hpp"
#include "lgvi/systems/potential_body.hpp"

namespace lgvi::experiments {

struct PotentialBodyModel {
  using State = AttitudeInitial;
  static constexpr const char* name = "potential-body";
  PotentialBody system;
  State initial;
  std::optional<TimeControl> control = std::nullopt;        ///< body-frame moment
  std::optional<AttitudeFeedback> feedback = std::nullopt;  ///< body-frame moment tau(R, Omega)
};

template <std::same_as<PotentialBodyModel> BoundModel>
struct SystemBinding<BoundModel> : AttitudeBinding<PotentialBodyModel> {
  static constexpr std::array<std::string_view, 6> kParameterKeys = {"inertia", "potential", "stiffness",
                                                                     "target",  "dipole",    "field"};
  /// The potential's moment acts at the printed step's end: first order.
  static int printed_order(const PotentialBodyModel&) { return 1; }
  /// [parameters] inertia and potential = "attitude-spring" (stiffness, target: a 3x3 rotation,
  /// rows) or "magnetic-dipole" (dipole, field); the other potential's keys are refused.
  static PotentialBody read_parameters(const SceneReader& r, const SceneTable& parameters) {
    const Mat3 J = r.inertia(parameters, "inertia");
    const std::string kind = r.string(parameters, "potential");
    const auto refuse = [&](std::string_view key, const char* other) {
      if (r.has(parameters, key)) {
        r.fail("parameters." + std::string(key), std::string("belongs to potential = \"") + other + "\" (this one is \"" +
                                                     kind + "\")");
      }
    };
    if (kind == "attitude-spring") {
      refuse("dipole", "magnetic-dipole");
      refuse("field", "magnetic-dipole");
      AttitudeSpring spring;
      spring.stiffness = r.number(parameters, "stiffness");
      spring.target = r.matrix(parameters, "target", 3);
      return r.physics("parameters.", [&] { return PotentialBody(J, spring); });
    }
    if (kind == "magnetic-dipole") {
      refuse("stiffness", "attitude-spring");
      refuse("target", "attitude-spring");
      const MagneticDipole dipole{r.vec3(parameters, "dipole"), r.vec3(parameters, "field")};
      return r.physics("parameters.", [&] { return PotentialBody(J, dipole); });
    }
    r.fail("parameters.potential", "must be \"attitude-spring\" or \"magnetic-dipole\" (got \"" + kind + "\")");
  }
  /// The energy; the angular momentum about a dipole's field (the spring conserves none).
  static Conserved conserved(const PotentialBodyModel& m, const State& s, double /*t*/) {
    Vec3 about_field = Vec3::Zero();
    if (const auto* dipole = std::get_if<MagneticDipole>(&m.system.term); dipole && dipole->field.norm() > 0.0) {
      about_field(0) = dipole->field.normalized().dot(m.system.spatial_momentum(s.R, s.Omega));
    }
    return {m.system.energy(s.R, s.Omega), about_field, 1};
  }
  static MomentumMap momentum_map() {
    // B^T R J Omega / |B| for the dipole, 0 for the spring (the y axis label gives the formula).
    return {"field-axis angular momentum", {"field_momentum"}};
  }
  static SystemLabels labels() {
    return {"time [s]", "|E - E_0| [J]", "|B^T R J Ω - (B^T R J Ω)_0| / |B| [kg m^2/s]", " s"};
  }
  /// No closed form.
  static std::optional<ExactReference> exact_solution(const PotentialBodyModel&, std::string& why_not) {
    why_not = "no closed form for a body in a parametric potential";
    return std::nullopt;
  }
};

}  // namespace lgvi::experiments
