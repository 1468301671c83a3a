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
  };
  return std::visit(Visitor{s}, model);
}

bool has_translation(const Model& model) { return std::holds_alternative<DumbbellModel>(model); }

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
  };
  return std::visit(Visitor{}, model);
}

std::vector<std::string> Recorder::columns(const Model& model) {
  std::vector<std::string> c = {"t"};
  for (int i = 1; i <= 3; ++i) {
    for (int j = 1; j <= 3; ++j) c.push_back(std::string("R").append(std::to_string(i)).append(std::to_string(j)));
  }
  for (const char* name : {"Omega", "x", "v"}) {
    if (std::string(name) != "Omega" && !has_translation(model)) continue;
    for (int i = 1; i <= 3; ++i) c.push_back(std::string(name).append(std::to_string(i)));
  }
  for (const char* name : {"energy", "energy_error", "orthogonality_error", "determinant_error"}) c.push_back(name);
  for (const std::string& name : momentum_map(model).columns) c.push_back(name);
  c.push_back("momentum_error");
  c.push_back("newton_iterations");
  return c;
}

Recorder::Recorder(const Model& model, std::size_t output_every, CsvWriter* csv)
    : model_(model), output_every_(output_every), csv_(csv), columns_(columns(model).size()) {}

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
  const double energy_error = c.energy - diagnostics_.energy0;
  const double orthogonality = so3::orthogonality_error(s.R);
  const double determinant = so3::determinant_error(s.R);
  const double momentum_error = (c.momentum - momentum0_).norm();
  Diagnostics& d = diagnostics_;
  d.max_abs_energy_error = std::max(d.max_abs_energy_error, std::abs(energy_error));
  d.max_orthogonality_error = std::max(d.max_orthogonality_error, orthogonality);
  d.max_determinant_error = std::max(d.max_determinant_error, determinant);
  d.max_momentum_error = std::max(d.max_momentum_error, momentum_error);

  if (csv_ != nullptr) {
    std::size_t n = 0;
    row_[n++] = s.t;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) row_[n++] = s.R(i, j);
    }
    for (int i = 0; i < 3; ++i) row_[n++] = s.Omega(i);
    if (has_translation(model_)) {
      for (int i = 0; i < 3; ++i) row_[n++] = s.x(i);
      for (int i = 0; i < 3; ++i) row_[n++] = s.v(i);
    }
    row_[n++] = c.energy;
    row_[n++] = energy_error;
    row_[n++] = orthogonality;
    row_[n++] = determinant;
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
