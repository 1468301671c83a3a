// The literature problems' stored references (validation/literature_references.toml): for each
// shipped scene that is a test problem of the field (the Hairer-Lubich-Wanner rigid body, DETEST
// B5, ...), its state at the scene's t_final, how that state was computed and to how many digits
// it is trusted (Bari test-set style). `validate` grades the methods and the closed forms against
// them; `validate --write-literature-references FILE` computes the file again.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "lgvi/types.hpp"

namespace lgvi::experiments {

struct LiteratureReference {
  std::string scene;        ///< the shipped scene's name (experiments/scenes/SCENE.toml)
  std::string source;       ///< the problem's publication
  double t = 0.0;           ///< the scene's t_final
  Mat3 R = Mat3::Identity();  ///< the state at t: attitude (body to inertial)
  Vec3 Omega = Vec3::Zero();  ///< and body angular velocity
  std::string computed_by;  ///< how the state was computed (two independent ways)
  /// final-state distance between the two computations (max of ||dR||_F and the relative
  /// |dOmega|): the reference's own error bound.
  double agreement = 0.0;
  int digits = 0;           ///< floor(-log10(agreement)): the digits trusted
};

/// Reads the file: an array of tables [[problem]] with the keys scene, source, t, R (3 rows),
/// Omega, computed_by, agreement, digits (no other key). Throws SceneError naming the file,
/// field and reason; an unreadable file is one too.
std::vector<LiteratureReference> read_literature_references(const std::filesystem::path& file);

/// The TOML text of `references` (round-trip precision), with `header` as leading comment lines.
std::string literature_references_toml(const std::vector<LiteratureReference>& references, const std::string& header);

}  // namespace lgvi::experiments
