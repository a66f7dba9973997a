// Best and median of repeated timings: what `untangle bench` and bench/bench_detect report.
// Header-only so that the stand-alone benchmarks can include it ("app/best_median.h").
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace untangle::app {

struct Stat {
  double best = 0.0;
  double median = 0.0;  // the mean of the two middle values for an even count
};

inline Stat stat_of(std::vector<double> values) {
  Stat s;
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  s.best = values.front();
  const std::size_t n = values.size();
  s.median = n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return s;
}

}  // namespace untangle::app
