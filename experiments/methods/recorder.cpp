#include "experiments/methods/recorder.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <span>

#include "experiments/methods/simulate.hpp"
#include "experiments/output/interrupt.hpp"
#include "experiments/systems/systems.hpp"
#include "lgvi/so3.hpp"

namespace lgvi::experiments {

double Diagnostics::max_energy_error() const {
  return energy_error_is_relative() ? max_abs_energy_error / std::abs(energy0) : max_abs_energy_error;
}

void EnergyTrend::add(std::size_t k, double t, double energy, double energy_error) {
  if (n == 0) t_first = t;
  ++n;
  const double nd = static_cast<double>(n);
  const double dt = t - mean_t;
  const double de = energy_error - mean_e;
  mean_t += dt / nd;
  mean_e += de / nd;
  // C += (x - mean_old)(y - mean_new): exact centred updates of the co-moments.
  c_tt += dt * (t - mean_t);
  c_te += dt * (energy_error - mean_e);
  c_ee += de * (energy_error - mean_e);
  t_last = t;
  last_step = k;
  max_abs_energy = std::max(max_abs_energy, std::abs(energy));
}

double EnergyTrend::slope() const { return n >= 2 && c_tt > 0.0 ? c_te / c_tt : 0.0; }

namespace {
double residual_sum_of_squares(const EnergyTrend& f) {
  return f.n >= 2 && f.c_tt > 0.0 ? std::max(0.0, f.c_ee - f.c_te * f.c_te / f.c_tt) : 0.0;
}
}  // namespace

double EnergyTrend::slope_standard_error() const {
  if (n < 3 || c_tt <= 0.0) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(residual_sum_of_squares(*this) / (static_cast<double>(n - 2) * c_tt));
}

double EnergyTrend::residual_rms() const {
  return n >= 2 ? std::sqrt(residual_sum_of_squares(*this) / static_cast<double>(n)) : 0.0;
}

double EnergyTrend::secular_change() const { return std::abs(slope()) * (t_last - t_first); }

double EnergyTrend::round_off_floor() const {
  return 10.0 * std::numeric_limits<double>::epsilon() * std::sqrt(static_cast<double>(last_step)) * max_abs_energy;
}

std::vector<std::string> Recorder::columns(const Model& model, bool quaternion_column) {
  std::vector<std::string> c = {"t"};
  visit_binding(model, [&](auto binding, const auto&) { decltype(binding)::state_columns(c); });
  for (const char* name : {"energy", "energy_error", "orthogonality_error", "determinant_error"}) c.emplace_back(name);
  if (quaternion_column) c.emplace_back("quaternion_norm_error");
  for (const std::string& name : momentum_map(model).columns) c.push_back(name);
  for (const char* name : {"momentum_error", "newton_iterations"}) c.emplace_back(name);
  return c;
}

Recorder::Recorder(const Model& model, std::size_t output_every, CsvWriter* csv, bool quaternion_column)
    : model_(model), output_every_(output_every), csv_(csv), column_names_(columns(model, quaternion_column)),
      last_(sample_of(model)), quaternion_column_(quaternion_column) {
  columns_ = column_names_.size();  // the column list built once (columns_ is declared before it)
  diagnostics_.quaternion_norm_recorded = quaternion_column;
  std::vector<std::string> state = {"t"};
  visit_binding(model, [&](auto binding, const auto&) { decltype(binding)::state_columns(state); });
  state_columns_ = state.size();
}

bool Recorder::record(std::size_t k, const Sample& s) {
  if (stop_on_interrupt_ && interrupt_signal() != 0) [[unlikely]] {
    interrupted_ = true;
    return false;  // the method stops; stop_on_non_finite leaves its stats alone
  }
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  // The system's energy, momentum map and attitude errors, and its state columns.
  Conserved c{};
  double orthogonality = 0.0;
  double determinant = 0.0;
  std::size_t n = 0;
  visit_binding(model_, [&](auto binding, const auto& m) {
    using B = decltype(binding);
    const auto& state = state_of<std::decay_t<decltype(m)>>(s);
    c = B::conserved(m, state, s.t);
    orthogonality = B::orthogonality_error(state);
    determinant = B::determinant_error(state);
    row_[n++] = s.t;
    n = B::write_state(state, row_.data(), n);
  });
  // The row before anything is kept: the errors against the first sample, then every value
  // checked finite (a finite state can still give an infinite energy: 0.5 m |v|^2 with
  // |v| = 1e155).
  const double energy0 = samples_ == 0 ? c.energy : diagnostics_.energy0;
  const Vec3 momentum0 = samples_ == 0 ? c.momentum : momentum0_;
  const double energy_error = c.energy - energy0;
  const double momentum_error = (c.momentum - momentum0).norm();
  row_[n++] = c.energy;
  row_[n++] = energy_error;
  row_[n++] = orthogonality;
  row_[n++] = determinant;
  if (quaternion_column_) row_[n++] = s.quaternion_norm_error;
  for (int i = 0; i < c.momentum_size; ++i) row_[n++] = c.momentum(i);
  row_[n++] = momentum_error;
  row_[n++] = s.newton_iterations;
  assert(n == columns_);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(row_[i])) [[unlikely]] {
      non_finite_step_ = k;
      non_finite_time_ = s.t;
      non_finite_column_ = &column_names_[i];
      seconds_ += std::chrono::duration<double>(Clock::now() - start).count();
      return false;
    }
  }
  if (samples_ == 0) {
    diagnostics_.energy0 = c.energy;
    momentum0_ = c.momentum;
    diagnostics_.momentum0_norm = c.momentum.norm();
  }
  ++samples_;
  last_ = s;
  Diagnostics& d = diagnostics_;
  d.max_abs_energy_error = std::max(d.max_abs_energy_error, std::abs(energy_error));
  d.energy_trend.add(k, s.t, c.energy, energy_error);
  d.max_orthogonality_error = std::max(d.max_orthogonality_error, orthogonality);
  d.max_determinant_error = std::max(d.max_determinant_error, determinant);
  d.max_momentum_error = std::max(d.max_momentum_error, momentum_error);
  if (quaternion_column_) d.max_quaternion_norm_error = std::max(d.max_quaternion_norm_error, s.quaternion_norm_error);

  if (csv_ != nullptr) {
    row_pending_ = true;
    if (k % output_every_ == 0) {
      csv_->write_row(std::span<const double>(row_.data(), n));
      row_pending_ = false;
    }
  }
  seconds_ += std::chrono::duration<double>(Clock::now() - start).count();
  return true;
}

void Recorder::stop_on_non_finite(Stats& stats) const {
  if (non_finite_column_ == nullptr) return;
  stats.status = IntegrationStatus::NonFiniteState;
  stats.failed_step = non_finite_step_;
  stats.failed_time = non_finite_time_;
  const bool of_state = static_cast<std::size_t>(non_finite_column_ - column_names_.data()) < state_columns_;
  stats.failure_detail = *non_finite_column_ +
                         (of_state ? " is not finite in the sample of this step (overflow: the state left the range of "
                                     "double)"
                                   : " is not finite in the sample of this step, though the state is (overflow: the "
                                     "quantity formed from the state left the range of double)");
}

void Recorder::finish() {
  if (csv_ != nullptr && row_pending_) {
    csv_->write_row(std::span<const double>(row_.data(), columns_));
    row_pending_ = false;
  }
}

}  // namespace lgvi::experiments
