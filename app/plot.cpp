// CSV and SVG of iteration histories (see plot.h).
#include "plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace untangle::app {

std::string fmt(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

// Escapes the characters XML gives a meaning to.
std::string xml_escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

// A round tick step (1, 2 or 5 times a power of ten) giving about `count` ticks over [0, top].
double tick_step(double top, int count) {
  const double raw = top / count;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * power >= raw) return m * power;
  return 10.0 * power;
}

std::string tick_label(double v) {
  if (v == 0.0) return "0";
  if (std::fabs(v) >= 1e5 || std::fabs(v) < 1e-3) return fmt("%.0e", v);
  return fmt("%.6g", v);
}

const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};

struct Panel {
  double x0, y0, width, height;  // plot area in SVG units (y0 = top)
};

// One panel: axes, ticks, labels and a polyline per series. `value` maps a record to the plotted
// quantity; with `log_scale`, y = log10(1 + value) and ticks at 0, 1, 10, 100, ...
std::string panel_svg(const Panel& p, const std::vector<HistorySeries>& series, double x_max,
                      const std::function<double(const IterationRecord&)>& value, bool log_scale,
                      const std::string& y_label) {
  auto transform = [&](double v) { return log_scale ? std::log10(1.0 + std::max(0.0, v)) : v; };
  double y_max = 0.0;
  for (const HistorySeries& s : series)
    for (const IterationRecord& r : s.history) y_max = std::max(y_max, value(r));
  std::vector<double> ticks;  // in data units
  if (log_scale) {
    ticks.push_back(0.0);
    for (double t = 1.0; t <= std::max(1.0, y_max) * 1.0001; t *= 10.0) ticks.push_back(t);
    if (ticks.back() < y_max) ticks.push_back(ticks.back() * 10.0);
  } else {
    const double top = y_max > 0.0 ? y_max : 1.0;
    const double step = tick_step(top, 5);
    for (int k = 0; k * step < top * 1.0001 + step; ++k) {
      ticks.push_back(k * step);
      if (k * step >= top) break;
    }
  }
  const double y_top = transform(ticks.back()) > 0.0 ? transform(ticks.back()) : 1.0;
  const double x_top = x_max > 0.0 ? x_max : 1.0;
  const double x_step = tick_step(x_top, 6);
  const double x_end = std::ceil(x_top / x_step - 1e-9) * x_step;
  auto sx = [&](double x) { return p.x0 + p.width * x / x_end; };
  auto sy = [&](double v) { return p.y0 + p.height * (1.0 - transform(v) / y_top); };

  std::string svg;
  svg += "<g font-family=\"sans-serif\" font-size=\"12\">\n";
  // grid and ticks
  for (double t : ticks) {
    const std::string y = fmt("%.2f", sy(t));
    svg += "<line x1=\"" + fmt("%.2f", p.x0) + "\" y1=\"" + y + "\" x2=\"" +
           fmt("%.2f", p.x0 + p.width) + "\" y2=\"" + y + "\" stroke=\"#e0e0e0\"/>\n";
    svg += "<text x=\"" + fmt("%.2f", p.x0 - 6) + "\" y=\"" + fmt("%.2f", sy(t) + 4) +
           "\" text-anchor=\"end\">" + tick_label(t) + "</text>\n";
  }
  for (double t = 0.0; t <= x_end * 1.0001; t += x_step) {
    const std::string x = fmt("%.2f", sx(t));
    svg += "<line x1=\"" + x + "\" y1=\"" + fmt("%.2f", p.y0) + "\" x2=\"" + x + "\" y2=\"" +
           fmt("%.2f", p.y0 + p.height) + "\" stroke=\"#e0e0e0\"/>\n";
    svg += "<text x=\"" + x + "\" y=\"" + fmt("%.2f", p.y0 + p.height + 18) +
           "\" text-anchor=\"middle\">" + tick_label(t) + "</text>\n";
  }
  // axes and labels
  svg += "<rect x=\"" + fmt("%.2f", p.x0) + "\" y=\"" + fmt("%.2f", p.y0) + "\" width=\"" +
         fmt("%.2f", p.width) + "\" height=\"" + fmt("%.2f", p.height) +
         "\" fill=\"none\" stroke=\"#333\"/>\n";
  svg += "<text x=\"" + fmt("%.2f", p.x0 + p.width / 2) + "\" y=\"" +
         fmt("%.2f", p.y0 + p.height + 38) + "\" text-anchor=\"middle\">elapsed ms</text>\n";
  const double ly = p.y0 + p.height / 2, lx = p.x0 - 52;
  svg += "<text x=\"" + fmt("%.2f", lx) + "\" y=\"" + fmt("%.2f", ly) +
         "\" text-anchor=\"middle\" transform=\"rotate(-90 " + fmt("%.2f", lx) + " " +
         fmt("%.2f", ly) + ")\">" + xml_escaped(y_label) + "</text>\n";
  // series
  for (std::size_t k = 0; k < series.size(); ++k) {
    const char* colour = kColours[k % 4];
    std::string points;
    for (const IterationRecord& r : series[k].history)
      points += fmt("%.2f", sx(r.elapsed_ms)) + "," + fmt("%.2f", sy(value(r))) + " ";
    if (!points.empty()) points.pop_back();
    svg += "<polyline class=\"" + xml_escaped(series[k].method) + "\" fill=\"none\" stroke=\"" +
           colour + "\" stroke-width=\"2\" points=\"" + points + "\"/>\n";
    for (const IterationRecord& r : series[k].history) {
      svg += "<circle cx=\"" + fmt("%.2f", sx(r.elapsed_ms)) + "\" cy=\"" +
             fmt("%.2f", sy(value(r))) + "\" r=\"3\" fill=\"" + colour + "\"><title>" +
             xml_escaped(series[k].method) + " iteration " + std::to_string(r.iteration) + ": " +
             tick_label(value(r)) + " at " + fmt("%.1f", r.elapsed_ms) + " ms</title></circle>\n";
    }
  }
  svg += "</g>\n";
  return svg;
}

}  // namespace

std::string history_csv(const std::vector<HistorySeries>& series) {
  std::string csv = "iteration,elapsed_ms,crossings,contour_length,method\n";
  for (const HistorySeries& s : series) {
    for (const IterationRecord& r : s.history) {
      csv += std::to_string(r.iteration) + "," + fmt("%.3f", r.elapsed_ms) + "," +
             std::to_string(r.crossings) + "," + fmt("%.9g", r.contour_length) + "," + s.method +
             "\n";
    }
  }
  return csv;
}

std::string history_svg(const std::string& title, const std::vector<HistorySeries>& series) {
  constexpr double kWidth = 1000.0, kHeight = 430.0;
  double x_max = 0.0;
  for (const HistorySeries& s : series)
    for (const IterationRecord& r : s.history) x_max = std::max(x_max, r.elapsed_ms);
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt("%.0f", kWidth) +
                    "\" height=\"" + fmt("%.0f", kHeight) + "\" viewBox=\"0 0 " +
                    fmt("%.0f", kWidth) + " " + fmt("%.0f", kHeight) + "\">\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += "<text x=\"" + fmt("%.0f", kWidth / 2) +
         "\" y=\"24\" font-family=\"sans-serif\" font-size=\"16\" text-anchor=\"middle\">" +
         xml_escaped(title) + ": error against time, per iteration</text>\n";
  const Panel left{80.0, 60.0, 380.0, 300.0}, right{580.0, 60.0, 380.0, 300.0};
  svg += panel_svg(left, series, x_max,
                   [](const IterationRecord& r) { return static_cast<double>(r.crossings); }, true,
                   "crossings (log scale)");
  svg += panel_svg(right, series, x_max, [](const IterationRecord& r) { return r.contour_length; },
                   false, "contour length (scene units)");
  // legend, under the title
  svg += "<g font-family=\"sans-serif\" font-size=\"13\">\n";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const double x = kWidth / 2 - 90.0 * series.size() / 2 + 90.0 * k;
    svg += "<line x1=\"" + fmt("%.0f", x) + "\" y1=\"44\" x2=\"" + fmt("%.0f", x + 24) +
           "\" y2=\"44\" stroke=\"" + kColours[k % 4] + "\" stroke-width=\"3\"/>\n";
    svg += "<text x=\"" + fmt("%.0f", x + 30) + "\" y=\"48\">" + xml_escaped(series[k].method) +
           "</text>\n";
  }
  svg += "</g>\n</svg>\n";
  return svg;
}

}  // namespace untangle::app
