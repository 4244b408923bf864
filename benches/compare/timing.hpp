// The clock and the median the pose-set, hull and trajectory benchmarks share.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace cmp_timing {

// Nanoseconds on the steady clock.
inline double now_ns() {
  return static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                 std::chrono::steady_clock::now().time_since_epoch())
                                 .count());
}

// The upper median (NAN for none).
inline double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace cmp_timing
