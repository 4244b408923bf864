// depth_check.cpp: see depth_check.hpp.
#include "depth_check.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace {

Dir normalized(const Dir& v) {
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / l, v[1] / l, v[2] / l};
}

const std::vector<Dir>& fibonacci(int n) {
  static std::map<int, std::vector<Dir>> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  std::vector<Dir> pts(n);
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(std::max(0.0, 1 - z * z));
    pts[i] = {r * std::cos(golden * i), r * std::sin(golden * i), z};
  }
  return cache.emplace(n, std::move(pts)).first->second;
}

// Pattern search on the sphere from n (value f) with first step `step` (radians, about).
void refine(const cmp_body& b1, const cmp_body& b2, Dir& n, double& f, double step,
            long& evals) {
  const double step0 = step;
  double phase = 0;
  for (int it = 0; it < 600 && step > 1e-13; ++it) {
    // a tangent basis (u, v) at n
    const Dir a = std::fabs(n[0]) < 0.6 ? Dir{1, 0, 0} : Dir{0, 1, 0};
    const Dir u = normalized({n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2],
                              n[0] * a[1] - n[1] * a[0]});
    const Dir v = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2],
                   n[0] * u[1] - n[1] * u[0]};
    Dir best_n = n;
    double best_f = f;
    for (int k = 0; k < 12; ++k) {
      const double th = phase + 2 * M_PI * k / 12, c = step * std::cos(th), s = step * std::sin(th);
      const Dir m = normalized({n[0] + c * u[0] + s * v[0], n[1] + c * u[1] + s * v[1],
                                n[2] + c * u[2] + s * v[2]});
      const double fm = overlap_along(b1, b2, m);
      ++evals;
      if (fm < best_f) best_f = fm, best_n = m;
    }
    phase += M_PI * (3 - std::sqrt(5.0));
    if (best_f < f) {
      // a pattern move (Hooke-Jeeves): keep going the way the last move went, doubling while
      // it helps; in a V-shaped valley of f the moves zig-zag across the crease and this
      // follows it
      const Dir d = {best_n[0] - n[0], best_n[1] - n[1], best_n[2] - n[2]};
      n = best_n, f = best_f;
      for (double t = 1; t < 1e6; t *= 2) {
        const Dir m = normalized({n[0] + t * d[0], n[1] + t * d[1], n[2] + t * d[2]});
        const double fm = overlap_along(b1, b2, m);
        ++evals;
        if (!(fm < f)) break;
        n = m, f = fm;
      }
      step = std::min(step0, 1.5 * step);
    } else {
      step *= 0.5;
    }
  }
}

}  // namespace

double overlap_along(const cmp_body& b1, const cmp_body& b2, const Dir& n) {
  double p[3];
  const double m[3] = {-n[0], -n[1], -n[2]};
  return cmp_support_world(&b1, n.data(), p) + cmp_support_world(&b2, m, p);
}

IndependentDepth independent_depth(const cmp_body& b1, const cmp_body& b2,
                                   const std::vector<Dir>& candidates, int samples, int refine_n) {
  const std::vector<Dir>& fib = fibonacci(samples);
  std::vector<double> fv(fib.size());
  IndependentDepth out{INFINITY, {0, 0, 1}, INFINITY, 0};
  for (size_t i = 0; i < fib.size(); ++i) fv[i] = overlap_along(b1, b2, fib[i]);
  out.evaluations += static_cast<long>(fib.size());
  // the `refine_n` best samples that are not neighbours of a better one
  std::vector<size_t> order(fib.size());
  std::iota(order.begin(), order.end(), 0);
  const size_t top = std::min<size_t>(order.size(), 64);
  std::partial_sort(order.begin(), order.begin() + top, order.end(),
                    [&](size_t a, size_t b) { return fv[a] < fv[b]; });
  const double spacing = std::sqrt(4 * M_PI / samples);
  const double near_cos = std::cos(3 * spacing);
  std::vector<size_t> seeds;
  for (size_t k = 0; k < top && static_cast<int>(seeds.size()) < refine_n; ++k) {
    bool distinct = true;
    for (size_t s : seeds) {
      const Dir& a = fib[order[k]];
      const Dir& b = fib[s];
      if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > near_cos) distinct = false;
    }
    if (distinct) seeds.push_back(order[k]);
  }
  for (size_t s : seeds) {
    Dir n = fib[s];
    double f = fv[s];
    refine(b1, b2, n, f, spacing, out.evaluations);
    if (f < out.sampled) out.sampled = f;
    if (f < out.depth) out.depth = f, out.normal = n;
  }
  for (const Dir& c : candidates) {
    const double l = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(l > 0) || !std::isfinite(l)) continue;
    Dir n = normalized(c);
    double f = overlap_along(b1, b2, n);
    ++out.evaluations;
    refine(b1, b2, n, f, 1e-2, out.evaluations);
    if (f < out.depth) out.depth = f, out.normal = n;
  }
  return out;
}
