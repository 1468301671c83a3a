// The one palette of the figures: a method (its registry name, and its coordinate model for a
// baseline) keeps its colour, marker and line style in every figure, whatever the other curves
// of the figure and their order. The table is in palette.cpp; a name not in it gets a style
// derived from a hash of the name (the same in every run and on every machine).
#pragma once

#include <string>
#include <string_view>

namespace lgvi::experiments {

/// How a curve is drawn: a gnuplot colour "#rrggbb", a point type (markers) and a dash type.
struct PlotStyle {
  std::string colour;
  int point = 1;
  int dash = 1;
  bool operator==(const PlotStyle&) const = default;
};

/// The style of `name`: a registered method ("lgvi", "cvode-bdf", ...; "lgvi-printed" for the
/// LGVI in its printed form), a system ("free-body", "pendulum", ...) for the figures with one
/// curve per system, or any other name (hashed into the same colours, markers and dashes).
/// `model` (a baseline's coordinate model: quaternion, quaternion-renormalized, matrix, euler)
/// sets the dash type, so the same solver on two models has one colour and marker and two line
/// styles; empty: the name's own dash type.
PlotStyle plot_style(std::string_view name, std::string_view model = {});

/// True if `name` is in the palette's table (a name not in it is hashed).
bool in_palette(std::string_view name);

}  // namespace lgvi::experiments
