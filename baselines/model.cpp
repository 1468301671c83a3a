#include "baselines/model.hpp"

namespace lgvi::baselines {

const char* to_string(CoordinateModel model) {
  switch (model) {
    case CoordinateModel::Quaternion: return "quaternion";
    case CoordinateModel::QuaternionRenormalized: return "quaternion-renormalized";
    case CoordinateModel::Euler: return "euler";
    case CoordinateModel::Matrix: return "matrix";
  }
  return "unknown";
}

std::vector<std::string> coordinate_model_names() {
  return {"quaternion", "quaternion-renormalized", "euler", "matrix"};
}

CoordinateModel parse_coordinate_model(const std::string& name) {
  for (const CoordinateModel m : {CoordinateModel::Quaternion, CoordinateModel::QuaternionRenormalized,
                                  CoordinateModel::Euler, CoordinateModel::Matrix}) {
    if (name == to_string(m)) return m;
  }
  std::string known;
  for (const std::string& n : coordinate_model_names()) known += (known.empty() ? "" : ", ") + n;
  throw InvalidInput("model", "unknown model '" + name + "' (known: " + known + ")");
}

}  // namespace lgvi::baselines
