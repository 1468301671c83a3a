// The Poisson structure a fixed-step method's one-step map keeps, measured from the map's
// linearization: the defect of D B D^T = B' with D the Jacobian of one step (by finite
// differences of Method::run over a one-step horizon, so every method is measured through the
// same interface and nothing here knows a method), B the Poisson tensor at the step's start and
// B' at its end. A symplectic (Poisson) map has defect zero; an order-p method that is not has a
// one-step defect O(h^(p+1)) (its local error's derivative), so the measured defect is round-off
// for the one kind and falls like h^(p+1) for the other (docs/symplectic.md, "Structure
// preservation, measured"; tests/experiments/methods/test_structure_defect.cpp).
//
// Coordinates. The state is (R, Pi), Pi = J Omega the body angular momentum. About a point
// (R0, Pi0) the left-trivialized chart is R = R0 exp(hat(xi)), Pi = Pi0 + dPi, a 6-vector
// z = (xi, dPi). Hamilton's equations on T*SO(3) in the left trivialization,
//     R_dot = R hat(dH/dPi),   Pi_dot = Pi x dH/dPi - D_R H,
// (D_R H the left-trivialized derivative, d/ds H(R exp(s hat(e_i)), Pi) at s = 0) read at the
// chart's centre (xi = 0, where d exp = I and D_R H = dH/dxi) as
//     xi_dot = dH/dPi,   dPi_dot = -dH/dxi + hat(Pi) dH/dPi,   i.e.   z_dot = B(Pi) grad H,
//     B(Pi) = [[0, I], [-I, hat(Pi)]]        (6x6, hat(Pi) v = Pi x v; B^T = -B),
// the canonical Poisson tensor of T*SO(3) (its inverse is the symplectic form) in that chart.
// A map Phi is Poisson iff D B(z) D^T = B(Phi(z)) for D = dPhi/dz; with the input chart centred
// at the input point and the output chart at the output point (xi_out = log(R_nom^T R_out),
// dPi_out = Pi_out - Pi_nom around the nominal output), both tensors are read at a chart centre,
// where B has the form above: no d exp factor enters.
// The free body's Hamiltonian does not depend on R: its momentum map Pi_k -> Pi_{k+1} is the
// reduced map on so(3)*, whose Lie-Poisson tensor for Pi_dot = Pi x Omega is B = hat(Pi)
// ({Pi_i, Pi_j} = -eps_ijk Pi_k in the convention {F, G} = -Pi . (grad F x grad G); the other
// sign convention flips B on both sides of D B D^T = B' and changes nothing). Its defect uses the
// 3x3 Jacobian D_Pi (the momentum block of D).
//
// Scaling. xi is in radians, dPi in kg m^2/s: the Frobenius norm of a defect mixing them would
// depend on the units. The momentum is measured in units of s = |Pi_0| (StructureDefectOptions::
// momentum_scale): z_s = (xi, dPi / s), in which B becomes [[0, I/s], [-I/s, hat(Pi)/s^2]], i.e.
// (1/s) [[0, I], [-I, hat(Pi / s)]]; the factor 1/s multiplies both sides and drops out. So the
// defects below are unit-free, and every block of B and of D is O(1):
//     canonical:    ||D B(p_in) D^T - B(p_out)||_F / ||B(p_out)||_F,  p = Pi / s,
//     Lie-Poisson:  ||D_Pi hat(Pi_in) D_Pi^T - hat(Pi_out)||_F / ||hat(Pi_out)||_F.
// Relative to the tensor at the output: a map that scales B by (1 + c) has defect |c|.
//
// The Jacobian. Column j of D by the central difference D1(d) = (y(z + d e_j) - y(z - d e_j)) /
// (2 d), Richardson-extrapolated: D = (4 D1(d/2) - D1(d)) / 3 = dy/dz - d^4/480 y^(5) + ..., four
// one-step runs per column (24, plus the nominal). If one evaluation of y carries an error
// eps_y (StructureDefectOptions::evaluation_error, in the scaled coordinates where |y| ~ 1), the
// extrapolated entry's round-off is at most (4 (2 eps_y)/d + 2 eps_y/(2 d)) / 3 = 3 eps_y / d.
// Its truncation is d^4 |y^(5)| / 480 with |y^(5)| ~ 1 in the scaled chart (the map and the
// charts vary on the scale of a radian and of |Pi|). The sum 3 eps_y / d + d^4 / 480 is least at
//     d = (360 eps_y)^(1/5)       (eps_y = 16 eps: d = 4.2e-3, entry error e = 3.2e-12).
// The floor. An exact Poisson map, so differenced, has a defect from the Jacobian's error alone:
// D B D^T - B' = dD B D^T + D B dD^T to first order, so
//     canonical:   defect <= 2 ||dD||_F ||B(p_in)||_2 ||D||_2 / ||B(p_out)||_F,  ||dD||_F <= 6 e,
//     Lie-Poisson: defect <= 2 (3 e) |p_in| ||D_Pi||_2 / (sqrt(2) |p_out|)
// (||hat(p)||_2 = |p|, ||hat(p)||_F = sqrt(2) |p|): StructureDefect::floor, ~3e-11 and ~1e-11 at
// the default evaluation error. A method whose evaluation is noisier than eps_y (an implicit
// stage solved to a looser tolerance) has a proportionally higher floor.
#pragma once

#include <cstddef>
#include <string>

#include "experiments/methods/method.hpp"
#include "experiments/scene/scene.hpp"
#include "lgvi/types.hpp"

namespace lgvi::experiments {

struct StructureDefectOptions {
  /// Error of one evaluation of the step map in the scaled output coordinates (a few unit
  /// round-offs of |y| ~ 1): sets the increment and the floor. 16 eps: the LGVI's rotation update
  /// converges to 16 eps relative (lgvi/rotation_update.hpp), an explicit step to a few eps.
  double evaluation_error = 16.0 * 2.220446049250313e-16;
  /// Finite-difference increment d in the scaled coordinates (radians; units of s for dPi);
  /// 0: from the error balance, (360 evaluation_error)^(1/5).
  double increment = 0.0;
  /// The momentum unit s; 0: |Pi_0| of the scene, or when that is zero ||J||_2 / h (a rotation of
  /// one radian per step).
  double momentum_scale = 0.0;
  /// The coordinate model of a baseline (MethodOptions::model); the Lie group methods take none.
  std::string model = "quaternion";

  /// Throws InvalidInput("evaluation_error" | "increment" | "momentum_scale", ...) for a value
  /// that is not finite and > 0 (the increment and the scale may also be 0: the default).
  void validate() const;
};

struct StructureDefect {
  std::string method;
  std::string system;  ///< "free-body" or "pendulum"
  double h = 0.0;
  /// "Lie-Poisson so(3)*" (free body: `defect` is lie_poisson_defect) or "canonical T*SO(3)"
  /// (pendulum: `defect` is canonical_defect).
  std::string structure;
  /// The system's structure's defect (the relative Frobenius norms at the top of this file).
  double defect = 0.0;
  /// What an exact Poisson map would show from the finite differences' error alone (above):
  /// a defect at or below it is round-off. For `defect`'s structure.
  double floor = 0.0;
  double canonical_defect = 0.0;  ///< of the 6x6 map on T*SO(3), for both systems
  double canonical_floor = 0.0;
  double lie_poisson_defect = 0.0;  ///< of the free body's momentum map; NaN on the pendulum
  double lie_poisson_floor = 0.0;   ///< NaN on the pendulum
  double increment = 0.0;       ///< d used (scaled coordinates)
  double momentum_scale = 0.0;  ///< s used [kg m^2/s]
  double jacobian_norm = 0.0;       ///< ||D||_2 (scaled coordinates)
  double jacobian_condition = 0.0;  ///< sigma_max(D) / sigma_min(D)
  std::size_t evaluations = 0;      ///< one-step runs
  Mat6 jacobian = Mat6::Zero();     ///< D = dy/dz, z = (xi, dPi / s), y likewise at the output

  /// Within the floor: the map keeps the structure to round-off.
  bool round_off() const { return defect <= floor; }
  /// One line: "lgvi on pendulum, h = 0.02: canonical T*SO(3) defect 3.1e-13 (floor 2.9e-11, ...)".
  std::string brief() const;
};

/// The defect of `method`'s one-step map at the scene's h from the scene's initial state: the
/// scene is run over one step (t_final = h, output_every = 1) from 25 perturbed initial states.
/// The scene's system must be the free body or the pendulum, uncontrolled (a moment that is a
/// function of time is not Hamiltonian), without the free body's orbit. Throws InvalidInput
/// ("system", ...) for another scene, std::runtime_error naming the method and the run's failure
/// when a step fails. `name` labels the result (the method's name when empty).
StructureDefect structure_defect(const Scene& scene, const Method& method, const StructureDefectOptions& options = {},
                                 const std::string& name = "");
/// The same for a registered fixed-step method, made with options.model when it takes a
/// coordinate model. Throws InvalidInput("method", ...) for an adaptive method (not a one-step
/// map at a fixed h) or one that does not apply to the scene's system.
StructureDefect structure_defect(const Scene& scene, const MethodInfo& info, const StructureDefectOptions& options = {});

/// The scenes the defects are measured on (docs/symplectic.md's table, the tests): "free-body"
/// (J = diag(0.13, 0.28, 0.17) kg m^2, a generic attitude, Omega = (1.2, -0.8, 2.0) rad/s) or
/// "pendulum" (the paper's pendulum tilted by ZYX Euler angles (0.3, 0.5, -0.4) rad, Omega =
/// (1.0, -1.5, 2.0) rad/s), with horizon one step of h, symmetric LGVI form. Throws
/// InvalidInput("system", ...) for another name.
Scene structure_probe_scene(const std::string& system, double h);

}  // namespace lgvi::experiments
