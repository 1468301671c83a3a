#include "experiments/recorder.hpp"

#include <cassert>
#include <chrono>
#include <cmath>
#include <span>

#include "lgvi/so3.hpp"

namespace lgvi::experiments {

namespace {

/// Energy and momentum map of a sample; the momentum has 1 (pendulum) or 3 components.
struct Conserved {
  double energy;
  Vec3 momentum;
  int momentum_size;
};

Conserved conserved(const Model& model, const Sample& s) {
  struct Visitor {
    const Sample& s;
    Conserved operator()(const FreeBodyModel& m) const {
      return {m.system.energy(s.R, s.Omega), m.system.spatial_momentum(s.R, s.Omega), 3};
    }
    Conserved operator()(const PendulumModel& m) const {
      return {m.system.energy(s.R, s.Omega), Vec3(m.system.vertical_momentum(s.R, s.Omega), 0.0, 0.0), 1};
    }
    Conserved operator()(const DumbbellModel& m) const {
      return {m.system.energy(s.R, s.x, s.Omega, s.v), m.system.angular_momentum(s.R, s.x, s.Omega, s.v), 3};
    }
    Conserved operator()(const CartPendulumModel& m) const {
      const Vec2 q = s.x.head<2>(), q_dot = s.v.head<2>();
      Vec3 Pi;
      Vec2 p;
      m.system.momenta(s.R, s.Omega, q_dot, Pi, p);
      return {m.system.energy(s.R, s.Omega, q_dot), Vec3(m.system.vertical_momentum(s.R, q, Pi, p), 0.0, 0.0), 1};
    }
    Conserved operator()(const ConnectedBodiesModel& m) const {
      Vec3 Pi1, Pi2;
      m.system.momenta(s.R, s.R2, s.Omega, s.Omega2, Pi1, Pi2);
      return {m.system.energy(s.R, s.R2, s.Omega, s.Omega2),
              ConnectedBodies::total_angular_momentum(s.R, s.R2, Pi1, Pi2), 3};
    }
  };
  return std::visit(Visitor{s}, model);
}

/// The state columns after t, in the paper's symbols (two bodies prefixed with the body).
std::vector<std::string> state_columns(const Model& model) {
  std::vector<std::string> c;
  const auto matrix = [&](const std::string& name) {
    for (int i = 1; i <= 3; ++i) {
      for (int j = 1; j <= 3; ++j) c.push_back(name + std::to_string(i) + std::to_string(j));
    }
  };
  const auto vector = [&](const std::string& name) {
    for (int i = 1; i <= 3; ++i) c.push_back(name + std::to_string(i));
  };
  if (std::holds_alternative<ConnectedBodiesModel>(model)) {
    matrix("R1_");
    matrix("R2_");
    vector("Omega1_");
    vector("Omega2_");
    return c;
  }
  matrix("R");
  vector("Omega");
  if (std::holds_alternative<DumbbellModel>(model)) {
    vector("x");
    vector("v");
  }
  if (std::holds_alternative<CartPendulumModel>(model)) {
    for (const char* name : {"x", "y", "xdot", "ydot"}) c.push_back(name);
  }
  return c;
}

/// Writes the state columns of `state_columns` into row[n...]; returns the new n.
std::size_t write_state(const Model& model, const Sample& s, double* row, std::size_t n) {
  const auto matrix = [&](const Mat3& M) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) row[n++] = M(i, j);
    }
  };
  const auto vector = [&](const Vec3& v, int size) {
    for (int i = 0; i < size; ++i) row[n++] = v(i);
  };
  if (std::holds_alternative<ConnectedBodiesModel>(model)) {
    matrix(s.R);
    matrix(s.R2);
    vector(s.Omega, 3);
    vector(s.Omega2, 3);
    return n;
  }
  matrix(s.R);
  vector(s.Omega, 3);
  if (std::holds_alternative<DumbbellModel>(model)) {
    vector(s.x, 3);
    vector(s.v, 3);
  }
  if (std::holds_alternative<CartPendulumModel>(model)) {
    vector(s.x, 2);
    vector(s.v, 2);
  }
  return n;
}

}  // namespace

double Diagnostics::max_energy_error() const {
  return energy_error_is_relative() ? max_abs_energy_error / std::abs(energy0) : max_abs_energy_error;
}

MomentumMap momentum_map(const Model& model) {
  struct Visitor {
    MomentumMap operator()(const FreeBodyModel&) const {
      return {"spatial angular momentum R J Omega",
              {"spatial_momentum1", "spatial_momentum2", "spatial_momentum3"}};
    }
    MomentumMap operator()(const PendulumModel&) const {
      return {"vertical angular momentum e3^T R J Omega", {"vertical_momentum"}};
    }
    MomentumMap operator()(const DumbbellModel&) const {
      return {"total angular momentum x cross m v + R J Omega",
              {"angular_momentum1", "angular_momentum2", "angular_momentum3"}};
    }
    MomentumMap operator()(const CartPendulumModel&) const {
      return {"vertical angular momentum e3^T R Pi + x p_y - y p_x (momenta of eq. 37)", {"vertical_momentum"}};
    }
    MomentumMap operator()(const ConnectedBodiesModel&) const {
      return {"total angular momentum R1 Pi1 + R2 Pi2 (momenta of eq. 47)",
              {"angular_momentum1", "angular_momentum2", "angular_momentum3"}};
    }
  };
  return std::visit(Visitor{}, model);
}

std::vector<std::string> Recorder::columns(const Model& model, bool quaternion_column) {
  std::vector<std::string> c = {"t"};
  for (std::string& name : state_columns(model)) c.push_back(std::move(name));
  for (const char* name : {"energy", "energy_error", "orthogonality_error", "determinant_error"}) c.push_back(name);
  if (quaternion_column) c.push_back("quaternion_norm_error");
  for (const std::string& name : momentum_map(model).columns) c.push_back(name);
  c.push_back("momentum_error");
  c.push_back("newton_iterations");
  return c;
}

Recorder::Recorder(const Model& model, std::size_t output_every, CsvWriter* csv, bool quaternion_column)
    : model_(model), output_every_(output_every), csv_(csv), columns_(columns(model, quaternion_column).size()),
      quaternion_column_(quaternion_column) {
  diagnostics_.quaternion_norm_recorded = quaternion_column;
}

void Recorder::record(std::size_t k, const Sample& s) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const Conserved c = conserved(model_, s);
  if (samples_ == 0) {
    diagnostics_.energy0 = c.energy;
    momentum0_ = c.momentum;
    diagnostics_.momentum0_norm = c.momentum.norm();
  }
  ++samples_;
  last_ = s;
  const double energy_error = c.energy - diagnostics_.energy0;
  // Two bodies: the worse of the two attitudes.
  const bool two_bodies = std::holds_alternative<ConnectedBodiesModel>(model_);
  const double orthogonality =
      std::max(so3::orthogonality_error(s.R), two_bodies ? so3::orthogonality_error(s.R2) : 0.0);
  const double determinant =
      std::max(so3::determinant_error(s.R), two_bodies ? so3::determinant_error(s.R2) : 0.0);
  const double momentum_error = (c.momentum - momentum0_).norm();
  Diagnostics& d = diagnostics_;
  d.max_abs_energy_error = std::max(d.max_abs_energy_error, std::abs(energy_error));
  d.max_orthogonality_error = std::max(d.max_orthogonality_error, orthogonality);
  d.max_determinant_error = std::max(d.max_determinant_error, determinant);
  d.max_momentum_error = std::max(d.max_momentum_error, momentum_error);
  if (quaternion_column_) d.max_quaternion_norm_error = std::max(d.max_quaternion_norm_error, s.quaternion_norm_error);

  if (csv_ != nullptr) {
    std::size_t n = 0;
    row_[n++] = s.t;
    n = write_state(model_, s, row_.data(), n);
    row_[n++] = c.energy;
    row_[n++] = energy_error;
    row_[n++] = orthogonality;
    row_[n++] = determinant;
    if (quaternion_column_) row_[n++] = s.quaternion_norm_error;
    for (int i = 0; i < c.momentum_size; ++i) row_[n++] = c.momentum(i);
    row_[n++] = momentum_error;
    row_[n++] = s.newton_iterations;
    assert(n == columns_);
    row_pending_ = true;
    if (k % output_every_ == 0) {
      csv_->write_row(std::span<const double>(row_.data(), n));
      row_pending_ = false;
    }
  }
  seconds_ += std::chrono::duration<double>(Clock::now() - start).count();
}

void Recorder::finish() {
  if (csv_ != nullptr && row_pending_) {
    csv_->write_row(std::span<const double>(row_.data(), columns_));
    row_pending_ = false;
  }
}

}  // namespace lgvi::experiments
