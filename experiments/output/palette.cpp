#include "experiments/output/palette.hpp"

#include <array>
#include <cstdint>

namespace lgvi::experiments {

namespace {

// Colours distinguishable by the common forms of colour blindness (Okabe-Ito and P. Tol's sets)
// and in grey print, where the markers and dash types tell them apart.
constexpr std::array<const char*, 13> kColours = {"#000000", "#0072B2", "#56B4E9", "#009E73", "#E69F00",
                                                  "#D55E00", "#CC79A7", "#882255", "#332288", "#999933",
                                                  "#44AA99", "#AA4499", "#117733"};

struct Entry {
  std::string_view name;
  const char* colour;
  int point;
  int dash;
};

// One line per method of the registry (experiments/methods/registry.cpp), then the systems. No
// two entries share both colour and marker (tests/experiments/output/test_palette.cpp). Families
// share hues: the LGVIs black and blues (solid), the Lie group methods greens (dash-dot and
// dash-dot-dot), the splittings warm (dashed); a baseline's dash type is its model's.
constexpr Entry kTable[] = {
    {"lgvi", "#000000", 7, 1},
    {"lgvi-printed", "#E69F00", 7, 2},
    {"lgvi-yoshida4", "#0072B2", 5, 1},
    {"lgvi-suzuki4", "#56B4E9", 4, 1},
    {"lgvi-yoshida6", "#332288", 9, 1},
    {"lgvi-kahan-li6", "#882255", 11, 1},
    {"lie-euler", "#999933", 1, 4},
    {"rkmk2", "#44AA99", 2, 4},
    {"rkmk4", "#117733", 3, 4},
    {"cg3", "#999933", 8, 5},
    {"cg4", "#117733", 12, 5},
    {"cf4", "#44AA99", 13, 5},
    {"rkmk45", "#009E73", 10, 4},
    {"splitting-dlm", "#E69F00", 5, 2},
    {"splitting-exact", "#D55E00", 7, 2},
    {"nosquish", "#CC79A7", 9, 2},
    {"rattle", "#AA4499", 11, 2},
    {"cvode-adams", "#E69F00", 6, 1},
    {"cvode-bdf", "#D55E00", 4, 1},
    {"cvode-bdf-projected", "#D55E00", 12, 1},
    {"odeint-rk4", "#CC79A7", 8, 1},
    {"odeint-dopri5", "#0072B2", 6, 1},
    {"odeint-rkf78", "#56B4E9", 10, 1},
    {"odeint-bs", "#332288", 8, 1},
    {"gsl-rk8pd", "#882255", 4, 1},
    {"gsl-rk4imp", "#AA4499", 12, 1},
    {"gsl-msbdf", "#009E73", 6, 1},
    {"arkode-erk", "#117733", 14, 1},
    {"arkode-dirk", "#44AA99", 15, 1},
    // Figures with one curve per system (soak).
    {"free-body", "#0072B2", 7, 1},
    {"pendulum", "#D55E00", 5, 1},
    {"dumbbell", "#009E73", 9, 1},
    {"cart-pendulum", "#CC79A7", 11, 1},
    {"connected-bodies", "#E69F00", 13, 1},
    // Figures with one curve per optimal control method (suite ocp-comparison, method ids of
    // experiments/suites/ocp_comparison.cpp): the discrete methods solid, the continuous dashed.
    {"indirect-shooting", "#000000", 5, 1},
    {"slsqp", "#0072B2", 9, 1},
    {"ipopt", "#009E73", 5, 1},
    {"ddp", "#CC79A7", 7, 1},
    {"continuous-indirect", "#D55E00", 9, 2},
    {"collocation", "#882255", 13, 2},
};

struct ModelDash {
  std::string_view model;
  int dash;
};
constexpr ModelDash kModelDashes[] = {
    {"quaternion", 1}, {"matrix", 2}, {"euler", 3}, {"quaternion-renormalized", 4}};

constexpr int kPoints = 15;  // gnuplot's cairo point types 1..15
constexpr int kDashes = 5;   // dash types 1..5

/// FNV-1a, 64 bits: the same value on every platform and in every run (std::hash is neither).
std::uint64_t fnv1a(std::string_view s) {
  std::uint64_t h = 14695981039346656037ull;
  for (const char c : s) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

PlotStyle plot_style(std::string_view name, std::string_view model) {
  PlotStyle style;
  bool found = false;
  for (const Entry& e : kTable) {
    if (e.name == name) {
      style = {e.colour, e.point, e.dash};
      found = true;
      break;
    }
  }
  if (!found) {
    const std::uint64_t h = fnv1a(name);
    style.colour = kColours[h % kColours.size()];
    style.point = 1 + static_cast<int>((h / kColours.size()) % kPoints);
    style.dash = 1 + static_cast<int>((h / (kColours.size() * kPoints)) % kDashes);
  }
  if (!model.empty()) {
    bool known = false;
    for (const ModelDash& m : kModelDashes) {
      if (m.model == model) {
        style.dash = m.dash;
        known = true;
      }
    }
    if (!known) style.dash = 1 + static_cast<int>(fnv1a(model) % kDashes);
  }
  return style;
}

bool in_palette(std::string_view name) {
  for (const Entry& e : kTable) {
    if (e.name == name) return true;
  }
  return false;
}

}  // namespace lgvi::experiments
