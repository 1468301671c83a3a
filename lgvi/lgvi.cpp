#include "lgvi/lgvi.hpp"

#include <cstdio>

#include "lgvi/composition.hpp"
#include "lgvi/integrate.hpp"
#include "lgvi/systems/free_rigid_body.hpp"
#include "lgvi/systems/pendulum.hpp"

namespace lgvi {

// Every LGVI, plain and composed, is a flow map the driver accepts.
static_assert(FlowMap<AttitudeLgvi<FreeRigidBody>>);
static_assert(FlowMap<AttitudeLgvi<Pendulum3D>>);
static_assert(FlowMap<ComposedLgvi<AttitudeLgvi<FreeRigidBody>>>);
static_assert(FlowMap<ComposedLgvi<AttitudeLgvi<Pendulum3D>>>);
static_assert(FlowMap<ComposedLgvi<DumbbellLgvi>>);

const char* to_string(LgviForm f) { return f == LgviForm::Symmetric ? "symmetric" : "printed"; }

LgviForm parse_lgvi_form(const std::string& name) {
  if (name == "symmetric") return LgviForm::Symmetric;
  if (name == "printed") return LgviForm::Printed;
  throw InvalidInput("form", "must be 'symmetric' or 'printed' (got '" + name + "')");
}

const char* to_string(IntegrationStatus s) {
  switch (s) {
    case IntegrationStatus::Completed: return "completed";
    case IntegrationStatus::RotationUpdateFailed: return "rotation update failed";
    case IntegrationStatus::ObserverStopped: return "stopped by observer";
    case IntegrationStatus::SolverFailed: return "solver failed";
    case IntegrationStatus::CoordinateSingularity: return "coordinate singularity";
    case IntegrationStatus::NonFiniteState: return "non-finite state";
    case IntegrationStatus::StepFailed: return "step failed";
  }
  return "unknown";
}

std::string Stats::brief() const {
  char buf[512];
  if (status == IntegrationStatus::RotationUpdateFailed) {
    std::snprintf(buf, sizeof buf, "rotation update failed at step %zu (t = %.17g): %s", failed_step,
                  failed_time, failure.brief().c_str());
    if (failure.axis_ratio > 1.0 && step_size > 0.0) {
      char more[128];
      std::snprintf(more, sizeof more, "; largest admissible h about %.3g (h = %.6g)", step_size / failure.axis_ratio,
                    step_size);
      return buf + std::string(more);
    }
  } else if (status == IntegrationStatus::NonFiniteState || status == IntegrationStatus::StepFailed) {
    std::snprintf(buf, sizeof buf, "%s at step %zu (t = %.17g): ", to_string(status), failed_step, failed_time);
    return buf + failure_detail;
  } else if (status == IntegrationStatus::SolverFailed || status == IntegrationStatus::CoordinateSingularity) {
    std::snprintf(buf, sizeof buf, "%s at t = %.17g after %zu steps: ", to_string(status), failed_time,
                  failed_step);
    return buf + failure_detail;
  } else if (rhs_evaluations > 0) {
    // A continuous-time baseline: its cost is right-hand sides, Jacobians and Newton iterations.
    std::snprintf(buf, sizeof buf,
                  "%s %zu steps, %zu RHS evaluations, %zu Jacobian evaluations, %zu Newton iterations, "
                  "%zu rejected steps, %.3g s",
                  to_string(status), steps, rhs_evaluations, jacobian_evaluations, nonlinear_iterations,
                  rejected_steps, wall_seconds);
  } else {
    std::snprintf(buf, sizeof buf,
                  "%s %zu steps, %zu Newton iterations (max %d per step, %zu fallbacks), "
                  "%zu potential evaluations, %.3g s",
                  to_string(status), steps, newton_iterations, max_newton_iterations, fallbacks,
                  potential_evaluations, wall_seconds);
  }
  return buf;
}

CompositionScheme composition_scheme(const std::string& name) {
  namespace c = composition_coefficients;
  if (name == "yoshida4") return {"yoshida4", 4, c::yoshida4};
  if (name == "suzuki4") return {"suzuki4", 4, c::suzuki4};
  if (name == "yoshida6") return {"yoshida6", 6, c::yoshida6};
  if (name == "kahan-li6") return {"kahan-li6", 6, c::kahan_li6};
  throw InvalidInput("composition",
                     "unknown scheme '" + name + "' (known: yoshida4, suzuki4, yoshida6, kahan-li6)");
}

}  // namespace lgvi
