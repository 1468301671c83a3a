// Hermite-Simpson collocation of the attitude transfers, solved by IPOPT (collocation.hpp).
#include "lgvi/ocp/collocation.hpp"

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include "lgvi/ocp/direct_ipopt.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <numbers>
#include <string>
#include <vector>

#include "lgvi/so3.hpp"

namespace lgvi::ocp {

namespace {

constexpr int NY = 7;       // (q, Omega)
constexpr int NU = 3;       // u
constexpr int kBlock = 2 * NY + 2 * NU + 1;  // y_k, u_k, y_m, u_m, mu_k
constexpr int kWindow = kBlock + NY + NU;    // an interval's variables: its block and y_{k+1}, u_{k+1}
constexpr int kRowsPerInterval = 2 * NY + 1;  // two defects and the norm at k + 1

using VecY = Eigen::Matrix<double, NY, 1>;
using Vec4 = Eigen::Matrix<double, 4, 1>;
using JacY = Eigen::Matrix<double, NY, NY + NU + 1>;

double cpu_now() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// R(q) = (w^2 - |v|^2) I + 2 v v^T + 2 w hat(v), degree 2 in q (baselines/coordinates.hpp).
Mat3 rotation(const Vec4& q) {
  const double w = q(0);
  const Vec3 v = q.tail<3>();
  return (w * w - v.squaredNorm()) * Mat3::Identity() + 2.0 * v * v.transpose() + 2.0 * w * so3::hat(v);
}

/// d R(q) / d q_i, i = 0..3.
std::array<Mat3, 4> rotation_derivatives(const Vec4& q) {
  const double w = q(0);
  const Vec3 v = q.tail<3>();
  std::array<Mat3, 4> D;
  D[0] = 2.0 * w * Mat3::Identity() + 2.0 * so3::hat(v);
  for (int i = 0; i < 3; ++i) {
    const Vec3 e = Vec3::Unit(i);
    D[1 + i] = -2.0 * v(i) * Mat3::Identity() + 2.0 * (e * v.transpose() + v * e.transpose()) + 2.0 * w * so3::hat(e);
  }
  return D;
}

/// The unit quaternion of R, scalar first, w >= 0.
Vec4 quaternion(const Mat3& R) {
  Eigen::Quaterniond e(R);
  e.normalize();
  Vec4 q(e.w(), e.x(), e.y(), e.z());
  return q(0) < 0.0 ? Vec4(-q) : q;
}

/// a (x) b, scalar first.
Vec4 multiply(const Vec4& a, const Vec4& b) {
  Vec4 r;
  r(0) = a(0) * b(0) - a.tail<3>().dot(b.tail<3>());
  r.tail<3>() = a(0) * b.tail<3>() + b(0) * a.tail<3>() + a.tail<3>().cross(b.tail<3>());
  return r;
}

// The applied moment M(R) + tau(R, u) of each system (its own functions) and its derivatives:
// with respect to R along dR (the directional derivative, linear in dR) and to u.
struct PendulumMoments {
  const Pendulum3D& s;
  Vec3 value(const Mat3& R, const Vec3& u) const { return s.moment(R) + s.control_moment(R, u); }
  /// M + tau = (m g rho - u) x a with a = R^T e3 = R.row(2) (pendulum.hpp).
  Vec3 along(const Mat3& /*R*/, const Mat3& dR, const Vec3& u) const {
    return (s.mass * s.gravity * s.rho - u).cross(dR.row(2).transpose());
  }
  Mat3 per_control(const Mat3& R) const { return so3::hat(R.row(2).transpose()); }
};
struct FreeBodyMoments {
  const FreeRigidBody& s;
  Vec3 value(const Mat3& R, const Vec3& u) const { return s.moment(R) + s.control_moment(R, u); }
  Vec3 along(const Mat3&, const Mat3&, const Vec3&) const { return Vec3::Zero(); }
  Mat3 per_control(const Mat3&) const { return Mat3::Identity(); }
};

template <class S, class Moments>
void rhs(const S& system, const Moments& moments, const VecY& y, const Vec3& u, double mu, VecY& f, JacY* J) {
  const Vec4 q = y.head<4>();
  const Vec3 Omega = y.tail<3>();
  const Vec3 v = q.tail<3>();
  const Mat3 R = rotation(q);
  const Mat3& Jb = system.inertia.J;
  const Mat3& Ji = system.inertia.J_inverse;
  f(0) = -0.5 * v.dot(Omega) + mu * q(0);
  f.segment<3>(1) = 0.5 * (q(0) * Omega + v.cross(Omega)) + mu * v;
  f.tail<3>() = Ji * ((Jb * Omega).cross(Omega) + moments.value(R, u));
  if (J == nullptr) return;
  J->setZero();
  // kinematics: d/dq = 1/2 [[0, -Omega^T], [Omega, -hat(Omega)]] + mu I, d/dOmega, d/dmu = q
  J->block<1, 3>(0, 1) = -0.5 * Omega.transpose();
  J->block<3, 1>(1, 0) = 0.5 * Omega;
  J->block<3, 3>(1, 1) = -0.5 * so3::hat(Omega);
  J->block<4, 4>(0, 0) += mu * Eigen::Matrix4d::Identity();
  J->block<1, 3>(0, 4) = -0.5 * v.transpose();
  J->block<3, 3>(1, 4) = 0.5 * (q(0) * Mat3::Identity() + so3::hat(v));
  J->block<4, 1>(0, NY + NU) = q;
  // Euler's equation: d/dq through R(q), d/dOmega J^{-1} (hat(J Omega) - hat(Omega) J), d/du
  const std::array<Mat3, 4> dR = rotation_derivatives(q);
  for (int i = 0; i < 4; ++i) J->block<3, 1>(4, i) = Ji * moments.along(R, dR[i], u);
  J->block<3, 3>(4, 4) = Ji * (so3::hat(Jb * Omega) - so3::hat(Omega) * Jb);
  J->block<3, 3>(4, NY) = Ji * moments.per_control(R);
}

Eigen::Matrix3d validated_weight(const Eigen::MatrixXd& W) {
  if (W.size() == 0) return Eigen::Matrix3d::Identity();
  if (W.rows() != 3 || W.cols() != 3) throw InvalidInput("W", "must be 3x3");
  require_finite(W, "W");
  if ((W - W.transpose()).cwiseAbs().maxCoeff() > 1e-12 * W.cwiseAbs().maxCoeff()) {
    throw InvalidInput("W", "is not symmetric (must be symmetric positive definite)");
  }
  const Eigen::Matrix3d Ws = 0.5 * (W + W.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(Ws, Eigen::EigenvaluesOnly);
  if (!(eig.eigenvalues()(0) > 1e-14 * eig.eigenvalues()(2))) throw InvalidInput("W", "is not positive definite");
  return Ws;
}

void require_rotation(const Mat3& R, const char* field) {
  require_finite(R, field);
  if (!so3::is_rotation(R, 1e-10)) throw InvalidInput(field, "is not a rotation matrix (R^T R != I or det R != 1)");
}


/// The transcription as IPOPT's TNLP (collocation.hpp: variables, rows, Jacobian).
template <class S, class Moments>
class CollocationNlp : public Ipopt::TNLP {
 public:
  CollocationNlp(const S& system, const Moments& moments, const TransferProblem& p, int K, const Eigen::Matrix3d& W,
                 CollocationResult& out)
      : system_(system), moments_(moments), p_(p), K_(K), h_(p.t_final / K), W_(W), out_(out) {
    q0_ = quaternion(p.R0);
    qf_ = quaternion(p.Rf);
    if (q0_.dot(qf_) < 0.0) qf_ = -qf_;
    n_ = kBlock * K + NY + NU;
    m_ = kRowsPerInterval * K + 6;
  }

  int n() const { return n_; }
  int m() const { return m_; }
  int y(int k) const { return kBlock * k; }             ///< offset of y_k (k = 0..K)
  int u(int k) const { return kBlock * k + NY; }        ///< offset of u_k
  int ym(int k) const { return kBlock * k + NY + NU; }  ///< offset of the midpoint's y
  int um(int k) const { return kBlock * k + 2 * NY + NU; }
  int mu(int k) const { return kBlock * k + 2 * NY + 2 * NU; }

  /// The defect rows of the constraint vector, evaluated at x (for the summary).
  Eigen::VectorXd constraints(const double* x) const {
    Eigen::VectorXd g(m_);
    evaluate(x, g.data(), nullptr);
    return g;
  }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& style) override {
    n = n_;
    m = m_;
    nnz_jac_g = nnz();
    nnz_h_lag = 0;
    style = C_STYLE;
    return true;
  }
  int nnz() const { return K_ * (2 * NY * kWindow + 4) + 4 * 3 + 3; }

  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override {
    for (Ipopt::Index i = 0; i < n; ++i) {
      x_l[i] = -1e19;
      x_u[i] = 1e19;
    }
    for (int i = 0; i < 4; ++i) x_l[i] = x_u[i] = q0_(i);
    for (int i = 0; i < 3; ++i) x_l[4 + i] = x_u[4 + i] = p_.Omega0(i);
    for (Ipopt::Index i = 0; i < m; ++i) g_l[i] = g_u[i] = 0.0;
    return true;
  }

  /// The rest-to-rest slew about the fixed body axis of conj(q0) (x) qf (collocation.hpp).
  bool get_starting_point(Ipopt::Index, bool, Ipopt::Number* x, bool, Ipopt::Number*, Ipopt::Number*, Ipopt::Index,
                          bool, Ipopt::Number*) override {
    Vec4 conj0 = q0_;
    conj0.tail<3>() *= -1.0;
    const Vec4 rel = multiply(conj0, qf_);
    const double s_half = rel.tail<3>().norm();
    const double theta = 2.0 * std::atan2(s_half, rel(0));
    const Vec3 axis = s_half > 0.0 ? Vec3(rel.tail<3>() / s_half) : Vec3::UnitX();
    const double T = p_.t_final;
    // A tilt about a body axis perpendicular to the turn's, out and back (half a radian at the
    // middle): a rotation about the vertical alone cannot be steered by the pendulum's control
    // (its moment R^T e3 x u has no vertical part), and from such a guess IPOPT finds the
    // linearized problem infeasible.
    const Vec3 perp = axis.cross(std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
    const auto attitude = [&](double t) {
      const double s = t / T - std::sin(2.0 * std::numbers::pi * t / T) / (2.0 * std::numbers::pi);
      const double tilt = 0.5 * std::sin(std::numbers::pi * s);
      Vec4 turn, lean;
      turn << std::cos(0.5 * s * theta), std::sin(0.5 * s * theta) * axis;
      lean << std::cos(0.5 * tilt), std::sin(0.5 * tilt) * perp;
      return Vec4(multiply(multiply(q0_, turn), lean));
    };
    const auto state = [&](double t, double* at) {
      const Vec4 q = attitude(t);
      const double dt = 1e-6 * T;
      Vec4 q_dot = (attitude(t + dt) - attitude(t - dt)) / (2.0 * dt);
      Vec4 conj = q;
      conj.tail<3>() *= -1.0;
      Eigen::Map<Vec4> q_at(at);
      Eigen::Map<Vec3> Omega_at(at + 4);
      q_at = q;
      Omega_at = 2.0 * multiply(conj, q_dot).tail<3>();  // q' = 1/2 q (0, Omega)
    };
    std::fill(x, x + n_, 0.0);
    for (int k = 0; k <= K_; ++k) {
      state(k * h_, x + y(k));
      if (k < K_) state((k + 0.5) * h_, x + ym(k));
    }
    Eigen::Map<Vec4>(x + y(0)) = q0_;
    Eigen::Map<Vec3>(x + y(0) + 4) = p_.Omega0;
    Eigen::Map<Vec4>(x + y(K_)) = qf_;
    Eigen::Map<Vec3>(x + y(K_) + 4) = p_.Omegaf;
    return true;
  }

  bool eval_f(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number& f) override {
    f = cost(x);
    return std::isfinite(f);
  }
  double cost(const double* x) const {
    double J = 0.0;
    const auto L = [&](int at) {
      const Eigen::Map<const Vec3> w(x + at);
      return 0.5 * w.dot(W_ * w);
    };
    for (int k = 0; k < K_; ++k) J += h_ / 6.0 * (L(u(k)) + 4.0 * L(um(k)) + L(u(k + 1)));
    return J;
  }
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number* g) override {
    std::fill(g, g + n, 0.0);
    for (int k = 0; k < K_; ++k) {
      Eigen::Map<Vec3>(g + u(k)) += h_ / 6.0 * (W_ * Eigen::Map<const Vec3>(x + u(k)));
      Eigen::Map<Vec3>(g + um(k)) += 4.0 * h_ / 6.0 * (W_ * Eigen::Map<const Vec3>(x + um(k)));
      Eigen::Map<Vec3>(g + u(k + 1)) += h_ / 6.0 * (W_ * Eigen::Map<const Vec3>(x + u(k + 1)));
    }
    return true;
  }
  bool eval_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Number* g) override {
    evaluate(x, g, nullptr);
    for (int i = 0; i < m_; ++i) {
      if (!std::isfinite(g[i])) return false;
    }
    return true;
  }
  bool eval_jac_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Index nele, Ipopt::Index* iRow,
                  Ipopt::Index* jCol, Ipopt::Number* values) override {
    if (values == nullptr) {
      int e = 0;
      for (int k = 0; k < K_; ++k) {
        const int row = kRowsPerInterval * k;
        for (int r = 0; r < 2 * NY; ++r) {
          for (int c = 0; c < kWindow; ++c) {
            iRow[e] = row + r;
            jCol[e++] = y(k) + c;
          }
        }
        for (int c = 0; c < 4; ++c) {
          iRow[e] = row + 2 * NY;
          jCol[e++] = y(k + 1) + c;
        }
      }
      const int row = kRowsPerInterval * K_;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) {
          iRow[e] = row + r;
          jCol[e++] = y(K_) + c;
        }
      }
      for (int r = 0; r < 3; ++r) {
        iRow[e] = row + 3 + r;
        jCol[e++] = y(K_) + 4 + r;
      }
      return e == nele;
    }
    std::vector<double> g(static_cast<std::size_t>(m_));
    evaluate(x, g.data(), values);
    for (Ipopt::Index i = 0; i < nele; ++i) {
      if (!std::isfinite(values[i])) return false;
    }
    return true;
  }
  bool eval_h(Ipopt::Index, const Ipopt::Number*, bool, Ipopt::Number, Ipopt::Index, const Ipopt::Number*, bool,
              Ipopt::Index, Ipopt::Index*, Ipopt::Index*, Ipopt::Number*) override {
    return false;  // limited-memory
  }
  bool intermediate_callback(Ipopt::AlgorithmMode, Ipopt::Index, Ipopt::Number obj, Ipopt::Number inf_pr,
                             Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number,
                             Ipopt::Index, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    out_.history_cost.push_back(obj);
    out_.history_infeasibility.push_back(inf_pr);
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x, const Ipopt::Number*,
                         const Ipopt::Number*, Ipopt::Index, const Ipopt::Number*, const Ipopt::Number*, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x_.assign(x, x + n);
  }
  const std::vector<double>& solution() const { return x_; }

  /// g (and, with jac non-null, the Jacobian's values in the order of eval_jac_g's structure).
  void evaluate(const double* x, double* g, double* jac) const {
    VecY f0, f1, fm;
    JacY J0, J1, Jm;
    int e = 0;
    const Eigen::Matrix<double, NY, NY> I = Eigen::Matrix<double, NY, NY>::Identity();
    for (int k = 0; k < K_; ++k) {
      const Eigen::Map<const VecY> yk(x + y(k)), yk1(x + y(k + 1)), ymk(x + ym(k));
      const Eigen::Map<const Vec3> uk(x + u(k)), uk1(x + u(k + 1)), umk(x + um(k));
      const double muk = x[mu(k)];
      rhs(system_, moments_, yk, uk, muk, f0, jac ? &J0 : nullptr);
      rhs(system_, moments_, yk1, uk1, muk, f1, jac ? &J1 : nullptr);
      rhs(system_, moments_, ymk, umk, muk, fm, jac ? &Jm : nullptr);
      const int row = kRowsPerInterval * k;
      Eigen::Map<VecY>(g + row) = ymk - 0.5 * (yk + yk1) - h_ / 8.0 * (f0 - f1);
      Eigen::Map<VecY>(g + row + NY) = yk1 - yk - h_ / 6.0 * (f0 + 4.0 * fm + f1);
      g[row + 2 * NY] = yk1.head<4>().squaredNorm() - 1.0;
      if (jac == nullptr) continue;
      // The window's columns: y_k (7), u_k (3), y_m (7), u_m (3), mu (1), y_{k+1} (7), u_{k+1} (3).
      Eigen::Matrix<double, NY, kWindow> A = Eigen::Matrix<double, NY, kWindow>::Zero(), B = A;
      A.block<NY, NY>(0, 0) = -0.5 * I - h_ / 8.0 * J0.leftCols<NY>();
      A.block<NY, NU>(0, NY) = -h_ / 8.0 * J0.middleCols<NU>(NY);
      A.block<NY, NY>(0, NY + NU) = I;
      A.col(2 * NY + 2 * NU) = -h_ / 8.0 * (J0.col(NY + NU) - J1.col(NY + NU));
      A.block<NY, NY>(0, kBlock) = -0.5 * I + h_ / 8.0 * J1.leftCols<NY>();
      A.block<NY, NU>(0, kBlock + NY) = h_ / 8.0 * J1.middleCols<NU>(NY);
      B.block<NY, NY>(0, 0) = -I - h_ / 6.0 * J0.leftCols<NY>();
      B.block<NY, NU>(0, NY) = -h_ / 6.0 * J0.middleCols<NU>(NY);
      B.block<NY, NY>(0, NY + NU) = -4.0 * h_ / 6.0 * Jm.leftCols<NY>();
      B.block<NY, NU>(0, 2 * NY + NU) = -4.0 * h_ / 6.0 * Jm.middleCols<NU>(NY);
      B.col(2 * NY + 2 * NU) = -h_ / 6.0 * (J0.col(NY + NU) + 4.0 * Jm.col(NY + NU) + J1.col(NY + NU));
      B.block<NY, NY>(0, kBlock) = I - h_ / 6.0 * J1.leftCols<NY>();
      B.block<NY, NU>(0, kBlock + NY) = -h_ / 6.0 * J1.middleCols<NU>(NY);
      for (int r = 0; r < NY; ++r)
        for (int c = 0; c < kWindow; ++c) jac[e++] = A(r, c);
      for (int r = 0; r < NY; ++r)
        for (int c = 0; c < kWindow; ++c) jac[e++] = B(r, c);
      for (int c = 0; c < 4; ++c) jac[e++] = 2.0 * yk1(c);
    }
    // vec(conj(q_f) (x) q) = w_f v - w vf - vf x v (linear in q), and Omega_K - Omega_f.
    const int row = kRowsPerInterval * K_;
    const Eigen::Map<const Vec4> qK(x + y(K_));
    const Vec3 vf = qf_.tail<3>();
    Eigen::Map<Vec3>(g + row) = qf_(0) * qK.tail<3>() - qK(0) * vf - vf.cross(qK.tail<3>());
    Eigen::Map<Vec3>(g + row + 3) = Eigen::Map<const Vec3>(x + y(K_) + 4) - p_.Omegaf;
    if (jac == nullptr) return;
    Eigen::Matrix<double, 3, 4> D;
    D.col(0) = -vf;
    D.rightCols<3>() = qf_(0) * Mat3::Identity() - so3::hat(vf);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) jac[e++] = D(r, c);
    for (int r = 0; r < 3; ++r) jac[e++] = 1.0;
  }

 private:
  const S& system_;
  Moments moments_;
  TransferProblem p_;
  int K_;
  double h_;
  Eigen::Matrix3d W_;
  CollocationResult& out_;
  Vec4 q0_, qf_;
  int n_ = 0, m_ = 0;
  std::vector<double> x_;
};

template <class S, class Moments>
CollocationResult solve(const S& system, const Moments& moments, const TransferProblem& p,
                        const CollocationOptions& options) {
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = cpu_now();
  CollocationResult out;
  CollocationSummary& S_ = out.summary;
  Eigen::Matrix3d W;
  try {
    options.validate();
    W = validated_weight(options.W);
    require_rotation(p.R0, "R0");
    require_rotation(p.Rf, "Rf");
    require_finite(p.Omega0, "Omega0");
    require_finite(p.Omegaf, "Omegaf");
    if (!(std::isfinite(p.t_final) && p.t_final > 0.0)) throw InvalidInput("t_final", "must be positive and finite");
  } catch (const InvalidInput& e) {
    S_.status = CollocationStatus::InvalidInput;
    S_.message = e.what();
    return out;
  }
  const int K = options.intervals;
  Ipopt::SmartPtr<CollocationNlp<S, Moments>> nlp = new CollocationNlp<S, Moments>(system, moments, p, K, W, out);
  S_.intervals = K;
  S_.variables = nlp->n();
  S_.constraints = nlp->m();
  S_.jacobian_nonzeros = nlp->nnz();
  out.h = p.t_final / K;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& o = *app->Options();
  o.SetIntegerValue("print_level", 0);
  o.SetStringValue("sb", "yes");
  o.SetStringValue("hessian_approximation", "limited-memory");
  o.SetIntegerValue("max_iter", options.max_iterations);
  o.SetNumericValue("tol", 1e-9);
  o.SetNumericValue("constr_viol_tol", options.tolerance);
  o.SetNumericValue("acceptable_tol", 1e-6);
  o.SetNumericValue("acceptable_constr_viol_tol", options.tolerance);
  if (app->Initialize(std::string()) != Ipopt::Solve_Succeeded) {
    S_.status = CollocationStatus::Failed;
    S_.ipopt_status = "Initialize_Failed";
    return out;
  }
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(nlp);
  S_.ipopt_status = detail::ipopt_name(status);
  S_.iterations = static_cast<int>(out.history_cost.size()) - 1;
  const std::vector<double>& x = nlp->solution();
  if (static_cast<int>(x.size()) == nlp->n()) {
    const Eigen::VectorXd g = nlp->constraints(x.data());
    double defect = 0.0;
    for (int k = 0; k < K; ++k) defect = std::max(defect, g.segment(kRowsPerInterval * k, kRowsPerInterval).cwiseAbs().maxCoeff());
    S_.max_defect = defect;
    S_.cost = nlp->cost(x.data());
    out.states.resize(NY, K + 1);
    out.controls.resize(NU, 2 * K + 1);
    double drift = 0.0, normal = 0.0;
    for (int k = 0; k <= K; ++k) {
      out.states.col(k) = Eigen::Map<const VecY>(x.data() + nlp->y(k));
      out.controls.col(2 * k) = Eigen::Map<const Vec3>(x.data() + nlp->u(k));
      drift = std::max(drift, std::abs(out.states.col(k).head<4>().norm() - 1.0));
      if (k < K) {
        out.controls.col(2 * k + 1) = Eigen::Map<const Vec3>(x.data() + nlp->um(k));
        drift = std::max(drift, std::abs(Eigen::Map<const Vec4>(x.data() + nlp->ym(k)).norm() - 1.0));
        normal = std::max(normal, std::abs(x[static_cast<std::size_t>(nlp->mu(k))]));
      }
    }
    S_.quaternion_drift = drift;
    S_.max_normal_rate = normal;
    const Vec4 qK = out.states.col(K).head<4>();
    const Mat3 RK = rotation(qK.normalized());
    S_.residual.resize(6);
    S_.residual << so3::log(p.Rf.transpose() * RK), out.states.col(K).tail<3>() - p.Omegaf;
    S_.violation = S_.residual.norm();
    const double terminal = g.tail<6>().cwiseAbs().maxCoeff();
    const bool within = S_.max_defect <= options.tolerance && terminal <= options.tolerance;
    const bool success = status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level;
    S_.status = success && within ? CollocationStatus::Converged
                : status == Ipopt::Maximum_Iterations_Exceeded ? CollocationStatus::IterationLimit
                                                               : CollocationStatus::Failed;
  } else {
    S_.status = status == Ipopt::Maximum_Iterations_Exceeded ? CollocationStatus::IterationLimit
                                                             : CollocationStatus::Failed;
  }
  S_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  S_.cpu_seconds = cpu_now() - cpu0;
  return out;
}

}  // namespace

void CollocationOptions::validate() const {
  kIntervals.require(intervals, "intervals");
  kTolerance.require(tolerance, "tolerance");
  kMaxIterations.require(max_iterations, "max_iterations");
}

const char* to_string(CollocationStatus s) {
  switch (s) {
    case CollocationStatus::Converged: return "converged";
    case CollocationStatus::IterationLimit: return "iteration limit";
    case CollocationStatus::Failed: return "failed";
    case CollocationStatus::InvalidInput: return "invalid input";
  }
  return "?";
}

std::string CollocationSummary::brief() const {
  if (status == CollocationStatus::InvalidInput) return std::string("invalid input: ") + message;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s (%s) in %d iterations, %d intervals: cost %.10g, violation %.3g, max defect %.3g, |q| drift %.3g, "
                "%.3g s CPU",
                to_string(status), ipopt_status.c_str(), iterations, intervals, cost, violation, max_defect,
                quaternion_drift, cpu_seconds);
  return buf;
}

CollocationResult solve_collocation(const Pendulum3D& system, const TransferProblem& problem,
                                    const CollocationOptions& options) {
  return solve(system, PendulumMoments{system}, problem, options);
}

CollocationResult solve_collocation(const FreeRigidBody& system, const TransferProblem& problem,
                                    const CollocationOptions& options) {
  return solve(system, FreeBodyMoments{system}, problem, options);
}

namespace collocation_detail {
void attitude_rhs(const Pendulum3D& system, const Eigen::Matrix<double, 7, 1>& y, const Vec3& u, double mu,
                  Eigen::Matrix<double, 7, 1>& f, Eigen::Matrix<double, 7, 11>* jacobian) {
  rhs(system, PendulumMoments{system}, y, u, mu, f, jacobian);
}
void attitude_rhs(const FreeRigidBody& system, const Eigen::Matrix<double, 7, 1>& y, const Vec3& u, double mu,
                  Eigen::Matrix<double, 7, 1>& f, Eigen::Matrix<double, 7, 11>* jacobian) {
  rhs(system, FreeBodyMoments{system}, y, u, mu, f, jacobian);
}
}  // namespace collocation_detail

}  // namespace lgvi::ocp
