// Methods: the ways a scene can be integrated. The LGVI is the first; the continuous-time
// baselines (quaternion / Euler-angle / rotation-matrix models on CVODE, odeint, GSL) join it
// behind this interface. The choice is made at run time (CLI, suites), hence the virtual
// dispatch; inside run() everything is static.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "experiments/fields.hpp"
#include "experiments/recorder.hpp"
#include "experiments/scene.hpp"
#include "lgvi/integrate.hpp"

namespace lgvi::experiments {

class Method {
 public:
  virtual ~Method() = default;
  /// Short identifier used in file names, metadata and summaries: "lgvi".
  virtual std::string name() const = 0;
  /// The method's settings for a scene (CSV metadata and JSON summary), e.g. the LGVI form and
  /// the rotation-update tolerance.
  virtual Fields settings(const Scene& scene) const = 0;
  /// Integrates scene.horizon from the scene's initial state, passing the state at every grid
  /// time t_k (k = 0..steps, or up to the last good step) to `recorder`. Never prints.
  virtual Stats run(const Scene& scene, Recorder& recorder) const = 0;
};

/// The method names make_method accepts.
std::vector<std::string> method_names();

/// Method by name. Throws InvalidInput("method", ...) for an unknown name.
std::unique_ptr<Method> make_method(const std::string& name);

}  // namespace lgvi::experiments
