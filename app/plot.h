// Speed against error of one scene: the iteration history of each method as CSV and as an SVG
// chart (crossings and contour length against elapsed milliseconds). Hand-written SVG, no
// dependency. Pure functions: the caller writes the text.
#pragma once

#include <string>
#include <vector>

#include "untangle/fix.h"

namespace untangle::app {

// `value` printed with a printf `format` ("%.3g").
std::string fmt(const char* format, double value);
// `text` with the characters XML and HTML give a meaning to (& < > ") escaped.
std::string xml_escaped(const std::string& text);

struct HistorySeries {
  std::string method;  // legend label, e.g. "region"
  std::vector<IterationRecord> history;
};

// Header `iteration,elapsed_ms,crossings,contour_length,method`, then one row per record, the
// series one after the other.
std::string history_csv(const std::vector<HistorySeries>& series);

// Two panels side by side: crossings (log scale, 0 included) and contour length (linear) against
// elapsed ms; one polyline with point markers per series, axes with ticks and labels, a legend.
std::string history_svg(const std::string& title, const std::vector<HistorySeries>& series);

}  // namespace untangle::app
