// Linearization of the LGVI flow maps (eq. 16): the rotation update's Jacobian, A_k and B_k of
// both forms of both systems against central differences of step().
#include <gtest/gtest.h>

#include <iostream>

#include "lgvi/group_newton.hpp"
#include "ocp_cases.hpp"

namespace lgvi::test {
namespace {

using ocp::DumbbellModel;
using ocp::PendulumModel;

// F hat(xi) J_d + J_d hat(xi) F^T = hat(L xi), L = (tr(F J_d) I - F J_d) F: the derivative of
// the rotation update's right-hand side (linearization.hpp (*)).
TEST(RotationUpdateJacobian, IdentityHoldsForRandomRotationsAndInertias) {
  auto rng = make_rng(501);
  std::uniform_real_distribution<double> moment(0.1, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    // A random inertia satisfying the triangle inequality, in a random body frame.
    const Vec3 d(moment(rng), moment(rng), moment(rng));
    if (d(0) + d(1) < d(2) || d(1) + d(2) < d(0) || d(0) + d(2) < d(1)) continue;
    const Mat3 Q = so3::random_rotation(rng);
    const Inertia I = Inertia::from(Q * d.asDiagonal() * Q.transpose());
    const Mat3 F = so3::random_rotation(rng);
    const Vec3 xi = random_vector<3>(rng, 1.0);
    const Mat3 lhs = F * so3::hat(xi) * I.Jd + I.Jd * so3::hat(xi) * F.transpose();
    const Vec3 rhs = ocp::J_hPi_xi(F, I.Jd) * xi;
    EXPECT_LT((lhs + lhs.transpose()).norm(), roundoff(lhs.norm(), 8));  // skew
    worst = std::max(worst, (so3::vee(lhs) - rhs).norm() / rhs.norm());
    // The rotation update's residual Jacobian is the same derivative (product order aside):
    // entries of two 3x3 products of O(1) matrices, a few roundings each.
    EXPECT_LT((J_G_xi(F, I.Jd) - ocp::J_hPi_xi(F, I.Jd)).norm(), roundoff(ocp::J_hPi_xi(F, I.Jd).norm(), 20));
  }
  std::cout << "[ measured ] max relative error of the identity: " << worst << "\n";
  EXPECT_LT(worst, roundoff(1.0, 20));
  // At F = I it is the linearized update J f = h p.
  const Inertia I = Inertia::from(Vec3(0.13, 0.28, 0.17).asDiagonal());
  EXPECT_LT((ocp::J_hPi_xi(Mat3::Identity(), I.Jd) - I.J).norm(), roundoff(1.0));
}

/// Central differences of one step in z coordinates with respect to the state (A) and to the
/// controls at both ends (B_k, B_k1); compares with the analytic Jacobians.
template <class Model>
void check_step_jacobians(const typename Model::System& system, LgviForm form, const Velocities& q,
                          const typename Model::VecU& u_k, const typename Model::VecU& u_k1, double h,
                          const char* label) {
  constexpr int ns = 2 * Model::nq;
  constexpr int nu = Model::nu;
  using VecS = Eigen::Matrix<double, ns, 1>;
  const Model model(system);
  const typename Model::Lgvi lgvi(system, form);
  const auto s = make(lgvi, q);
  ocp::StepJacobians<Model> jw;
  typename Model::State next;
  ASSERT_TRUE(ocp::linearize_step(model, lgvi, s, h, u_k, u_k1, jw, &next).converged());
  const ocp::StepJacobians<Model> jz = ocp::to_velocity_coordinates(model, jw);
  const Velocities q1 = velocities(lgvi, next);

  auto step_from = [&](const Velocities& qin, const typename Model::VecU& a, const typename Model::VecU& b) {
    typename Model::State out;
    EXPECT_TRUE(lgvi.step(make(lgvi, qin), h, Model::control(a), Model::control(b), out).converged());
    return velocities(lgvi, out);
  };
  // A: columns by central differences, step 1e-6 scaled by the size of the perturbed block.
  const double scale_R = 1.0;
  const double scale_x = std::max(1.0, q.x.norm());
  const double scale_Omega = std::max(1.0, q.Omega.norm());
  const double scale_v = std::max(1.0, q.v.norm());
  Eigen::Matrix<double, ns, ns> A_fd;
  for (int i = 0; i < ns; ++i) {
    double scale = scale_R;
    if (ns == 12) {
      scale = i < 3 ? scale_R : i < 6 ? scale_x : i < 9 ? scale_Omega : scale_v;
    } else {
      scale = i < 3 ? scale_R : scale_Omega;
    }
    const double a = kOcpFdStep * scale;
    const VecS dz = VecS::Unit(i) * a;
    const Velocities plus = step_from(perturbed<ns>(q, VecS(dz)), u_k, u_k1);
    const Velocities minus = step_from(perturbed<ns>(q, VecS(-dz)), u_k, u_k1);
    A_fd.col(i) = (difference<ns>(q1, plus) - difference<ns>(q1, minus)) / (2.0 * a);
  }
  Eigen::Matrix<double, ns, nu> Bk_fd, Bk1_fd;
  const double scale_u = std::max(1.0, std::max(u_k.norm(), u_k1.norm()));
  for (int i = 0; i < nu; ++i) {
    const double a = kOcpFdStep * scale_u;
    const typename Model::VecU du = Model::VecU::Unit(i) * a;
    Bk_fd.col(i) = (difference<ns>(q1, step_from(q, u_k + du, u_k1)) -
                    difference<ns>(q1, step_from(q, u_k - du, u_k1))) / (2.0 * a);
    Bk1_fd.col(i) = (difference<ns>(q1, step_from(q, u_k, u_k1 + du)) -
                     difference<ns>(q1, step_from(q, u_k, u_k1 - du))) / (2.0 * a);
  }
  const double eA = relative_error(jz.A, A_fd);
  const double eB1 = relative_error(jz.B_k1, Bk1_fd);
  std::cout << "[ measured ] " << label << " (" << to_string(form) << "): |A - A_fd|/|A_fd| = " << eA
            << ", B_k1 " << eB1;
  EXPECT_LT(eA, kOcpFdTolerance) << label;
  EXPECT_LT(eB1, kOcpFdTolerance) << label;
  if (form == LgviForm::Symmetric) {
    const double eB0 = relative_error(jz.B_k, Bk_fd);
    std::cout << ", B_k " << eB0;
    EXPECT_LT(eB0, kOcpFdTolerance) << label;
  } else {
    // The printed form applies no control at the start of the step.
    EXPECT_EQ(jz.B_k.norm(), 0.0);
    EXPECT_LT(Bk_fd.norm(), kOcpFdTolerance * Bk1_fd.norm());
  }
  std::cout << "\n";
}

TEST(StepJacobians, PendulumMatchesFiniteDifferences) {
  const Pendulum3D pendulum = Pendulum3D::paper();
  auto rng = make_rng(502);
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    for (int trial = 0; trial < 4; ++trial) {
      const Velocities q = pendulum_case(rng);
      const Vec3 u_k = random_vector<3>(rng, 2.0);
      const Vec3 u_k1 = random_vector<3>(rng, 2.0);
      check_step_jacobians<PendulumModel>(pendulum, form, q, u_k, u_k1, 0.01, "pendulum h = 0.01");
    }
    // The paper's step and a large one.
    const Velocities q = pendulum_case(rng);
    check_step_jacobians<PendulumModel>(pendulum, form, q, random_vector<3>(rng, 2.0), random_vector<3>(rng, 2.0),
                                        0.001, "pendulum h = 0.001");
    check_step_jacobians<PendulumModel>(pendulum, form, q, random_vector<3>(rng, 2.0), random_vector<3>(rng, 2.0),
                                        0.1, "pendulum h = 0.1");
  }
}

TEST(StepJacobians, DumbbellMatchesFiniteDifferences) {
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  auto rng = make_rng(503);
  for (const LgviForm form : {LgviForm::Symmetric, LgviForm::Printed}) {
    for (int trial = 0; trial < 4; ++trial) {
      const Velocities q = dumbbell_case(rng);
      const auto u_k = random_vector<6>(rng, 0.3);
      const auto u_k1 = random_vector<6>(rng, 0.3);
      check_step_jacobians<DumbbellModel>(dumbbell, form, q, u_k, u_k1, 0.01, "dumbbell h = 0.01");
    }
    const Velocities q = dumbbell_case(rng);
    check_step_jacobians<DumbbellModel>(dumbbell, form, q, random_vector<6>(rng, 0.3), random_vector<6>(rng, 0.3),
                                        0.05, "dumbbell h = 0.05");
  }
}

// The models' second derivatives H = d(G^T nu)/dq and C = d(B^T nu)/dq against differences of
// G and B (they enter only the sensitivities; tests/ocp/test_necessary_conditions checks those
// end to end).
template <class Model>
void check_second_derivatives(const typename Model::System& system, const Velocities& q,
                              const typename Model::VecU& u, const typename Model::VecQ& nu, const char* label) {
  constexpr int nq = Model::nq;
  const Model model(system);
  const typename Model::MatQ H = model.force_jacobian_transpose_derivative(q.R, q.x, u, nu);
  const typename Model::MatUQ C = model.control_matrix_transpose_derivative(q.R, q.x, nu);
  typename Model::MatQ H_fd;
  typename Model::MatUQ C_fd;
  for (int i = 0; i < nq; ++i) {
    const double a = kOcpFdStep;
    auto at = [&](double sgn) {
      Velocities p = q;
      if (i < 3) {
        p.R = q.R * so3::exp(sgn * a * Vec3::Unit(i));
      } else {
        p.x = q.x + sgn * a * Vec3::Unit(i - 3);
      }
      return p;
    };
    const Velocities plus = at(1.0), minus = at(-1.0);
    H_fd.col(i) = (model.force_jacobian(plus.R, plus.x, u).transpose() * nu -
                   model.force_jacobian(minus.R, minus.x, u).transpose() * nu) / (2.0 * a);
    C_fd.col(i) = (model.control_matrix(plus.R, plus.x).transpose() * nu -
                   model.control_matrix(minus.R, minus.x).transpose() * nu) / (2.0 * a);
  }
  const double eH = relative_error(H, H_fd);
  std::cout << "[ measured ] " << label << ": |H - H_fd|/|H_fd| = " << eH << "\n";
  EXPECT_LT(eH, kOcpFdTolerance) << label;
  EXPECT_LE((C - C_fd).norm(), kOcpFdTolerance * std::max(1.0, C_fd.norm())) << label;
  // G itself against differences of the generalized force phi + B u (through a kick).
}

TEST(ModelDerivatives, SecondDerivativesMatchFiniteDifferences) {
  auto rng = make_rng(504);
  const Pendulum3D pendulum = Pendulum3D::paper();
  const DumbbellSpacecraft dumbbell = DumbbellSpacecraft::paper();
  for (int trial = 0; trial < 3; ++trial) {
    check_second_derivatives<PendulumModel>(pendulum, pendulum_case(rng), random_vector<3>(rng, 2.0),
                                            random_vector<3>(rng, 1.0), "pendulum");
    check_second_derivatives<DumbbellModel>(dumbbell, dumbbell_case(rng), random_vector<6>(rng, 0.3),
                                            random_vector<6>(rng, 1.0), "dumbbell");
  }
}

}  // namespace
}  // namespace lgvi::test
