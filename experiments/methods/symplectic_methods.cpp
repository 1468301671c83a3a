// The symplectic rigid-body methods of baselines/splitting.hpp as Methods, run by the one-step
// driver (one_step.hpp) at the scene's h: splitting-dlm, splitting-exact, nosquish, rattle. They
// need a separable Hamiltonian, a single body with a constant mass matrix: the free body, the
// 3D pendulum (and the Lagrange top, a pendulum scene) and the dumbbell; the cart-pendulum and
// the connected bodies are refused, by their traits (MethodInfo::systems) and at run time.
#include <stdexcept>
#include <string>
#include <utility>

#include "baselines/splitting.hpp"
#include "experiments/methods/one_step.hpp"

namespace lgvi::experiments {

namespace {

namespace sp = baselines::splitting;

/// The systems with a separable Hamiltonian, and why the others are not.
constexpr const char* kSeparable =
    "needs a separable Hamiltonian, a single body with a constant mass matrix (free-body, pendulum, dumbbell, "
    "potential-body, potential-body-se3); "
    "the cart-pendulum's and the connected bodies' mass matrices depend on the configuration";

template <template <class> class FlowTemplate, const char* Description>
struct SeparableScheme {
  template <class Mech>
  static constexpr bool applies = baselines::SeparableMechanics<Mech>;
  static constexpr const char* applies_to_what = kSeparable;
  static constexpr const char* description = Description;
  template <class Mech>
  using Flow = FlowTemplate<Mech>;
};

constexpr char kDlm[] = "kick h/2, principal-axis rotations 3 2 1 2 3 (h/2 h/2 h h/2 h/2, moments ascending), kick h/2";
constexpr char kExact[] = "kick h/2, exact free-body flow h (Jacobi elliptic functions), kick h/2";
constexpr char kNoSquish[] =
    "kick h/2, quaternion and conjugate momentum rotated about principal axes 3 2 1 2 3, kick h/2";
constexpr char kRattle[] = "RATTLE on R with J_d: the multiplier of R^T R = I by Newton to eps (or its round-off floor)";

template <class Scheme>
MethodInfo symplectic(const char* name, const char* legend) {
  MethodInfo info{name, MethodFamily::OneStep, 2, 1, baselines::StepControl::Fixed, false, {}, false, false, legend, {}};
  info.symmetric = true;
  info.symplectic = true;
  info.stays_on_group = true;
  info.preserves_momentum_map = true;
  info.systems = {"free-body", "pendulum", "dumbbell", "potential-body", "potential-body-se3"};
  return mechanics_flow_method_info<Scheme>(std::move(info));
}

static_assert(!scheme_applies<SeparableScheme<sp::DlmFlow, kDlm>, baselines::CartPendulumMechanics>());

}  // namespace

MethodInfo symplectic_method_info(const std::string& name) {
  if (name == "splitting-dlm") return symplectic<SeparableScheme<sp::DlmFlow, kDlm>>(name.c_str(), "splitting (DLM)");
  if (name == "splitting-exact") {
    MethodInfo info = symplectic<SeparableScheme<sp::ExactFreeFlow, kExact>>(name.c_str(), "splitting (exact free flow)");
    info.exact_for_free_body = true;
    return info;
  }
  if (name == "nosquish") return symplectic<SeparableScheme<sp::NoSquishFlow, kNoSquish>>(name.c_str(), "NO_SQUISH");
  if (name == "rattle") return symplectic<SeparableScheme<sp::RattleFlow, kRattle>>(name.c_str(), "RATTLE");
  throw std::logic_error("symplectic_method_info: no symplectic method '" + name + "'");
}

}  // namespace lgvi::experiments
