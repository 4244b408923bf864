// depth_check.hpp: an independent penetration depth for two overlapping posed bodies, from the
// support functions of c_tests/compare/compare_common.c only (no dcol, Coal or FCL code).
//
// The penetration depth (minimum translation distance) of overlapping convex bodies is
//     depth = min over unit n of  f(n) = h1(n) + h2(-n) - n.(r2 - r1),
// h_i the support functions of the bodies about their origins (cmp_support_world gives the
// world support h1(n) + n.r1 directly, so f(n) = hw1(n) + hw2(-n)). Every f(n) is an upper bound
// on the depth; the minimum over the sphere is a global problem (f restricted to the sphere has
// local minima), so it is searched by dense sampling (a Fibonacci sphere) and a local refinement
// (a pattern search on the sphere with a shrinking step: 12 directions turned by the golden
// angle each round, and a Hooke-Jeeves pattern move after each success to follow the V-shaped
// valleys (creases) of f) from the best samples and from the
// candidate directions the caller passes (e.g. the libraries' normals: candidates only, their
// value is f evaluated here).
#ifndef DCOL_BENCH_DEPTH_CHECK_HPP
#define DCOL_BENCH_DEPTH_CHECK_HPP

#include <array>
#include <vector>

#include "compare_common.h"

using Dir = std::array<double, 3>;

/// f(n) for a unit n (from body 1 to body 2): the overlap of the bodies' extents along n.
double overlap_along(const cmp_body& b1, const cmp_body& b2, const Dir& n);

struct IndependentDepth {
  double depth;        // the smallest f found (an upper bound on the true depth)
  Dir normal;          // where
  double sampled;      // the smallest f from the Fibonacci seeds alone (no caller candidates)
  long evaluations;    // f evaluations (two support calls each)
};

/// The depth by dense sampling (`samples` Fibonacci directions), then a local refinement from
/// the `refine` best samples and from each candidate (non-zero candidates only).
IndependentDepth independent_depth(const cmp_body& b1, const cmp_body& b2,
                                   const std::vector<Dir>& candidates, int samples = 2000,
                                   int refine = 3);

#endif  // DCOL_BENCH_DEPTH_CHECK_HPP
