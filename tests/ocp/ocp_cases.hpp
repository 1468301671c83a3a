// Shared cases for the optimal-control tests: generic states and controls of both systems, and
// finite differences of the LGVI step in z = [eta; dx; dOmega; dv] coordinates (eq. 16).
#pragma once

#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "lgvi/lgvi.hpp"
#include "lgvi/ocp/indirect.hpp"
#include "lgvi/ocp/linearization.hpp"
#include "lgvi/ocp/models.hpp"
#include "lgvi/so3.hpp"
#include "test_support.hpp"

namespace lgvi::test {

/// A state given by the paper's variables, perturbed in z coordinates by dz.
struct Velocities {
  Mat3 R;
  Vec3 x = Vec3::Zero();
  Vec3 Omega;
  Vec3 v = Vec3::Zero();
};

inline AttitudeState make(const AttitudeLgvi<Pendulum3D>& lgvi, const Velocities& q) {
  return lgvi.make_state(q.R, q.Omega);
}
inline RigidBodyState make(const DumbbellLgvi& lgvi, const Velocities& q) {
  return lgvi.make_state(q.R, q.x, q.Omega, q.v);
}
inline Velocities velocities(const AttitudeLgvi<Pendulum3D>& lgvi, const AttitudeState& s) {
  return {s.R, Vec3::Zero(), lgvi.omega(s), Vec3::Zero()};
}
inline Velocities velocities(const DumbbellLgvi& lgvi, const RigidBodyState& s) {
  return {s.R, s.x, lgvi.omega(s), s.v};
}

/// q perturbed by dz = [eta; dx; dOmega; dv] (attitude-only: [eta; dOmega]).
template <int NS>
Velocities perturbed(const Velocities& q, const Eigen::Matrix<double, NS, 1>& dz) {
  Velocities p = q;
  p.R = q.R * so3::exp(dz.template head<3>());
  if constexpr (NS == 12) {
    p.x = q.x + dz.template segment<3>(3);
    p.Omega = q.Omega + dz.template segment<3>(6);
    p.v = q.v + dz.template segment<3>(9);
  } else {
    p.Omega = q.Omega + dz.template tail<3>();
  }
  return p;
}

/// z coordinates of b relative to a.
template <int NS>
Eigen::Matrix<double, NS, 1> difference(const Velocities& a, const Velocities& b) {
  Eigen::Matrix<double, NS, 1> z;
  z.template head<3>() = so3::log(a.R.transpose() * b.R);
  if constexpr (NS == 12) {
    z.template segment<3>(3) = b.x - a.x;
    z.template segment<3>(6) = b.Omega - a.Omega;
    z.template segment<3>(9) = b.v - a.v;
  } else {
    z.template tail<3>() = b.Omega - a.Omega;
  }
  return z;
}

/// w coordinates [eta; dx; dPi; dp] of b relative to a (the multipliers' coordinates).
template <class Model>
typename Model::VecS momentum_difference(const Model& model, const typename Model::State& a,
                                         const typename Model::State& b) {
  typename Model::VecS w;
  w.template head<3>() = so3::log(a.R.transpose() * b.R);
  if constexpr (Model::has_translation) w.template segment<3>(3) = b.x - a.x;
  w.template tail<Model::nq>() = model.momenta(b) - model.momenta(a);
  return w;
}

/// Relative error |A - B|_F / |B|_F.
template <class A, class B>
double relative_error(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).norm() / b.norm();
}

/// Generic states of the paper's systems (away from equilibria and symmetric configurations).
inline Velocities pendulum_case(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return {so3::random_rotation(rng), Vec3::Zero(), Vec3(n(rng), n(rng), n(rng)) * 2.0, Vec3::Zero()};
}
inline Velocities dumbbell_case(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Velocities q;
  q.R = so3::random_rotation(rng);
  q.x = Vec3(1.0, 0.0, 0.0) + 0.1 * Vec3(n(rng), n(rng), n(rng));
  q.Omega = Vec3(n(rng), n(rng), n(rng));
  q.v = Vec3(0.0, 0.98, 0.0) + 0.1 * Vec3(n(rng), n(rng), n(rng));
  return q;
}
template <int N>
Eigen::Matrix<double, N, 1> random_vector(std::mt19937_64& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v(i) = n(rng);
  return v;
}

}  // namespace lgvi::test
