// penetration.cpp: see penetration.hpp.
#include "penetration.hpp"

#include <algorithm>
#include <cfloat>

namespace {

const char* const kPeerName[kPeerCount] = {"Coal", "FCL libccd", "FCL indep", "libccd MPR"};

std::string f1e(double v) {
  if (std::isnan(v)) return "–";
  char b[32];
  snprintf(b, sizeof b, "%.1e", v);
  return b;
}

void add(DepthPeerStats& t, const DepthPeerStats& a) {
  t.checked += a.checked, t.agree += a.agree, t.no_depth += a.no_depth;
  t.dcol_closer += a.dcol_closer, t.peer_closer += a.peer_closer, t.peer_deeper += a.peer_deeper;
  t.max_ind = std::max(t.max_ind, a.max_ind);
  t.max_short = std::max(t.max_short, a.max_short);
  if (a.max_diff > t.max_diff || t.worst.empty()) t.max_diff = a.max_diff, t.worst = a.worst;
}

}  // namespace

double depth_tolerance(int peer, double dcol_tol) {
  // Coal: EPA_DEFAULT_TOLERANCE 1e-6; FCL libccd: epa_tolerance = the request's
  // distance_tolerance (default 1e-6); FCL indep: GJKSolver_indep's epa_tolerance, eps^(7/8);
  // libccd MPR: CCD_INIT's mpr_tolerance 1e-4. Never tighter than dcol's own tolerance.
  const double peer_tol[kPeerCount] = {1e-6, 1e-6, std::pow(DBL_EPSILON, 7.0 / 8.0), 1e-4};
  return std::max(peer_tol[peer], dcol_tol);
}

void record_depth(DepthRow& row, const cmp_case& c, bool dcol_ok,
                  const dcol_signed_distance_result& sd, const PeerDepths& peers,
                  double dcol_tol, const std::string& where) {
  row.cases++;
  if (!dcol_ok) {
    row.dcol_failed++;
    return;
  }
  const double dd = -sd.distance;
  std::vector<Dir> cand = {{sd.normal[0], sd.normal[1], sd.normal[2]}};
  for (int k = 0; k < kPeerCount; ++k)
    if (!std::isnan(peers.depth[k])) cand.push_back(peers.normal[k]);
  const IndependentDepth ind = independent_depth(c.b1, c.b2, cand);
  row.evaluations += ind.evaluations;
  const double scale = std::max(1.0, ind.depth);
  const double diff = std::fabs(dd - ind.depth);
  row.ind_checked++;
  if (diff <= 1e-9 * scale) row.ind_within9++;
  if (diff <= 1e-6 * scale) row.ind_within6++;
  if (dd > ind.depth + 1e-9 * scale) row.dcol_deeper++;
  if (ind.sampled > ind.depth + 1e-9 * scale) row.sampling_missed++;
  row.sampling_gap_max = std::max(row.sampling_gap_max, ind.sampled - ind.depth);
  if (diff > row.ind_max || row.ind_worst.empty()) {
    char b[256];
    snprintf(b, sizeof b, "%s: dcol %.12g, independent %.12g", where.c_str(), dd, ind.depth);
    row.ind_max = diff, row.ind_worst = b;
  }
  const Dir n = {sd.normal[0], sd.normal[1], sd.normal[2]};
  row.own_normal_max = std::max(row.own_normal_max, std::fabs(overlap_along(c.b1, c.b2, n) - dd));
  for (int k = 0; k < kPeerCount; ++k) {
    if (std::isnan(peers.raw[k])) continue;  // not run
    DepthPeerStats& p = row.peer[k];
    p.checked++;
    const double pd = peers.depth[k];
    if (std::isnan(pd)) {
      p.no_depth++;
      continue;
    }
    const double e = std::fabs(pd - dd);
    p.max_ind = std::max(p.max_ind, std::fabs(pd - ind.depth));
    p.max_short = std::max(p.max_short, ind.depth - pd);
    if (e <= depth_tolerance(k, dcol_tol) * std::max(1.0, dd)) {
      p.agree++;
    } else {
      if (std::fabs(dd - ind.depth) <= std::fabs(pd - ind.depth))
        p.dcol_closer++;
      else
        p.peer_closer++;
      if (pd > ind.depth + depth_tolerance(k, dcol_tol) * std::max(1.0, ind.depth)) p.peer_deeper++;
    }
    if (e > p.max_diff || p.worst.empty()) {
      char b[256];
      snprintf(b, sizeof b, "%s: %s %.12g, dcol %.12g, independent %.12g", where.c_str(),
               kPeerName[k], pd, dd, ind.depth);
      p.max_diff = e, p.worst = b;
    }
  }
}

void write_depth_section(FILE* md, const std::vector<DepthRow>& rows,
                         const std::vector<std::string>& pair_names, bool have_coal,
                         double dcol_tol, const std::string& timing) {
  fprintf(md, "\n## Penetration depth on overlapping poses: dcol_signed_distance vs Coal, FCL, "
              "libccd MPR and an independent check\n\n");
  fprintf(md,
          "Overlapping cases (alpha_ref < 1 - 1e-6), untimed. Depths (> 0): dcol: "
          "-`dcol_signed_distance(...).distance` (default options, tolerance %.0e); Coal: "
          "-`coal::distance` with the default DistanceRequest (GJK, then EPA on overlap, "
          "epa_tolerance 1e-6)%s; FCL libccd: -`fcl::distance` with enable_signed_distance = "
          "true and GST_LIBCCD (GJK, then libccd's EPA inside FCL's ccdGJKSignedDist, "
          "epa_tolerance = distance_tolerance = 1e-6; it returns exactly -1 when EPA fails); FCL "
          "indep: the same with GST_INDEP, whose shapeSignedDistance is the unsigned GJK "
          "distance (\"TODO: should implement the signed distance version\"), so on overlap "
          "FCL's distance() falls back to `collide` with contacts and returns minus the "
          "deepest contact's penetration depth (FCL's own EPA, epa_tolerance eps^(7/8) = "
          "2e-14). That fallback starts its maximum from numeric_limits<double>::min() (the "
          "smallest positive double), and FCL 0.7's GST_INDEP EPA reports its contacts with a "
          "negative penetration_depth on every pair without a special-cased collider, so no "
          "contact wins and the result is -DBL_MIN = -2.2e-308 (counted as no depth): a depth "
          "comes back on sphere-sphere, sphere-box, sphere-capsule, sphere-cylinder and "
          "box-box (FCL's own colliders) and on a few cases of the other pairs only. The Debian libfcl keeps the assert(index != -1) after that "
          "loop and aborts there, so the bench calls FCL's solver-templated distance() compiled "
          "here with NDEBUG (as a release build of FCL would run it); libccd MPR: the depth of `ccdMPRPenetration` (CCD_INIT, mpr_tolerance "
          "1e-4), which is the distance to the portal MPR found along the ray from the "
          "interior point (the centres' difference) to the origin, not the minimum "
          "translation distance in general: it is compared with the independent depth only.\n\n"
          "Independent depth: the minimum over unit n of h1(n) + h2(-n) - n.(r2 - r1) "
          "(h_i the support functions of compare_common.c, no library's code), by 2000 "
          "Fibonacci-sphere directions, then a pattern search on the sphere (12 directions "
          "per round, turned by the golden angle each round, a Hooke-Jeeves pattern move after "
          "each success, step halved down to 1e-13) from "
          "the 3 best separated samples and from each library's normal as a further starting "
          "point (their worth is f evaluated here). Every f(n) is an upper bound on the depth, "
          "so the independent depth is the smallest upper bound found: a library deeper than "
          "it by more than its tolerance is wrong for certain; one shallower can only be "
          "right if the search missed the global minimum.\n\n"
          "Agreement with dcol: |depth - dcol depth| <= tol max(1, depth), tol = the peer's "
          "tolerance, never below dcol's %.0e (Coal 1e-6, FCL libccd 1e-6, FCL indep %.0e, MPR "
          "1e-4). `no depth`: a non-negative distance on an overlapping pair, or FCL's -1 "
          "(EPA failure), or MPR reporting no penetration. Disagreements: `dcol : peer` = "
          "how many of them were closer to the independent depth.\n\n",
          dcol_tol, have_coal ? "" : " (not available in this build: no Coal columns)",
          dcol_tol, depth_tolerance(kPeerFclIndep, dcol_tol));
  fprintf(md, "| pair | cases | dcol vs independent: within 1e-9 / 1e-6 / checked | max \\|Δ\\| | "
              "dcol deeper than independent |");
  for (int k = 0; k < kPeerCount - 1; ++k)
    fprintf(md, " dcol vs %s: agree / checked (no depth) | disagreements dcol : %s closer | "
                "max \\|Δ dcol\\| | max \\|Δ independent\\| |", kPeerName[k], kPeerName[k]);
  fprintf(md, " MPR within 1e-4 of dcol / checked (no depth) | MPR max \\|Δ independent\\| |\n"
              "|---|--:|--:|--:|--:|");
  for (int k = 0; k < kPeerCount - 1; ++k) fprintf(md, "--:|--:|--:|--:|");
  fprintf(md, "--:|--:|\n");
  DepthRow tot;
  for (size_t p = 0; p < rows.size(); ++p) {
    const DepthRow& r = rows[p];
    if (r.cases == 0) continue;
    tot.cases += r.cases, tot.dcol_failed += r.dcol_failed, tot.ind_checked += r.ind_checked;
    tot.ind_within9 += r.ind_within9, tot.ind_within6 += r.ind_within6;
    tot.dcol_deeper += r.dcol_deeper, tot.sampling_missed += r.sampling_missed;
    tot.sampling_gap_max = std::max(tot.sampling_gap_max, r.sampling_gap_max);
    tot.evaluations += r.evaluations;
    tot.own_normal_max = std::max(tot.own_normal_max, r.own_normal_max);
    if (r.ind_max > tot.ind_max || tot.ind_worst.empty())
      tot.ind_max = r.ind_max, tot.ind_worst = r.ind_worst;
    for (int k = 0; k < kPeerCount; ++k) add(tot.peer[k], r.peer[k]);
  }
  auto line = [&](const std::string& name, const DepthRow& r, bool bold) {
    const char* b = bold ? "**" : "";
    fprintf(md, "| %s%s%s | %ld | %ld / %ld / %ld | %s | %ld |", b, name.c_str(), b, r.cases,
            r.ind_within9, r.ind_within6, r.ind_checked, f1e(r.ind_max).c_str(), r.dcol_deeper);
    for (int k = 0; k < kPeerCount; ++k) {
      const DepthPeerStats& s = r.peer[k];
      const bool ran = s.checked > 0;
      if (k == kPeerMpr) {
        fprintf(md, " %s | %s |\n",
                ran ? (std::to_string(s.agree) + " / " + std::to_string(s.checked) + " (" +
                       std::to_string(s.no_depth) + ")").c_str()
                    : "–",
                ran ? f1e(s.max_ind).c_str() : "–");
        continue;
      }
      if (!ran) {
        fprintf(md, " – | – | – | – |");
        continue;
      }
      fprintf(md, " %ld / %ld (%ld) | %ld : %ld | %s | %s |", s.agree, s.checked, s.no_depth,
              s.dcol_closer, s.peer_closer, f1e(s.max_diff).c_str(), f1e(s.max_ind).c_str());
    }
  };
  for (size_t p = 0; p < rows.size(); ++p)
    if (rows[p].cases) line(pair_names[p], rows[p], false);
  line("all pairs", tot, true);
  fprintf(md, "\ndcol_signed_distance failed (returned an error) on %ld of %ld overlapping "
              "cases. Independent search: %ld f evaluations in all; the refinement from the "
              "Fibonacci seeds alone ended more than 1e-9 above the final minimum (a library's "
              "normal led to a lower one: the pattern search still stalls on some creases of f) on %ld "
              "cases, by %.1e at most, so on those cases the independent depth is f at a "
              "refined library normal, evaluated here, and the check is that no lower f was "
              "found rather than a proof of the global minimum; dcol's own normal, evaluated with the independent support "
              "functions, reproduces dcol's depth to %.1e at worst. Largest dcol vs independent "
              "difference: %s.\n\n",
          tot.dcol_failed, tot.cases, tot.evaluations, tot.sampling_missed, tot.sampling_gap_max,
          tot.own_normal_max,
          tot.ind_worst.c_str());
  for (int k = 0; k < kPeerCount; ++k)
    if (tot.peer[k].checked)
      fprintf(md, "- %s: %ld disagreements with dcol, %ld of them deeper than the independent "
                  "depth by more than the tolerance (wrong for certain: the independent depth is "
                  "an upper bound), the others shallower; largest difference from dcol %.2e "
                  "(%s).\n", kPeerName[k], tot.peer[k].dcol_closer + tot.peer[k].peer_closer,
              tot.peer[k].peer_deeper, tot.peer[k].max_diff, tot.peer[k].worst.c_str());
  // where and why: per peer, the pair types of its disagreements (shallower / deeper than the
  // independent depth), then what the libraries do there
  auto where = [&](int k, bool deeper) {
    std::string out;
    for (size_t p = 0; p < rows.size(); ++p) {
      const DepthPeerStats& s = rows[p].peer[k];
      const long n = deeper ? s.peer_deeper : s.dcol_closer + s.peer_closer - s.peer_deeper;
      if (n > 0) out += (out.empty() ? "" : ", ") + pair_names[p] + " " + std::to_string(n);
    }
    return out.empty() ? std::string("none") : out;
  };
  fprintf(md, "\n**Where and why they differ.** dcol against the independent depth: %ld / %ld "
              "within 1e-9, never deeper (an upper bound), and f at dcol's own normal gives "
              "dcol's depth back to %.0e.",
          tot.ind_within9, tot.ind_checked, tot.own_normal_max);
  if (have_coal)
    fprintf(md, " Coal's disagreements, shallower than the independent depth: %s; deeper: "
                "%s. The shallow ones are on pairs with a curved shape, where Coal's depth comes "
                "from EPA: its polytope is built from support points, so it is inscribed in the "
                "curved Minkowski difference and the face it stops at lies inside it; the stop "
                "test (epa_tolerance 1e-6) bounds the gap to the next support point, not the "
                "error of the depth, which comes out short (at most by %.1e here). On polytope and box "
                "pairs the polytope can be exact (see the table). The deeper ones are wrong for "
                "certain; Coal's sphere-cylinder is special-cased "
                "(SHAPE_SHAPE_DISTANCE_SPECIALIZATION(Sphere, Cylinder), "
                "coal/internal/shape_shape_func.h), not EPA, and its depth on those deep "
                "overlaps is larger than f along a direction found here.",
            where(kPeerCoal, false).c_str(), where(kPeerCoal, true).c_str(),
            tot.peer[kPeerCoal].max_short);
  const DepthPeerStats& fc = tot.peer[kPeerFclCcd];
  fprintf(md, " FCL libccd (its EPA runs to epa_tolerance = distance_tolerance) disagrees with "
              "dcol beyond 1e-6 on %ld cases (shallower: %s; deeper: %s) and returns no depth "
              "(-1: EPA failed, or a distance >= 0) on %ld. FCL indep returns a depth almost "
              "only where it has its own collider (see above); where it returns one it is "
              "shallower on: %s; deeper on: %s (box-box comes from FCL's box-box contact generation, whose deepest "
              "contact is not the minimum translation distance). libccd MPR is deeper than the "
              "independent depth by more than 1e-4 on %ld of its %ld cases with a depth: its "
              "depth is taken along the ray from the centres' difference, i.e. f in one "
              "direction, an upper bound on the depth, equal to it only when that ray leaves "
              "through the nearest face.\n",
          fc.dcol_closer + fc.peer_closer, where(kPeerFclCcd, false).c_str(),
          where(kPeerFclCcd, true).c_str(), fc.no_depth, where(kPeerFclIndep, false).c_str(),
          where(kPeerFclIndep, true).c_str(), tot.peer[kPeerMpr].peer_deeper,
          tot.peer[kPeerMpr].checked - tot.peer[kPeerMpr].no_depth);
  if (!timing.empty()) fprintf(md, "\n%s", timing.c_str());
  printf("penetration depth on %ld overlapping cases: dcol vs independent %ld / %ld within 1e-9, "
         "%ld within 1e-6 (max %.2e), dcol deeper than independent %ld\n", tot.cases,
         tot.ind_within9, tot.ind_checked, tot.ind_within6, tot.ind_max, tot.dcol_deeper);
  for (int k = 0; k < kPeerCount; ++k) {
    const DepthPeerStats& s = tot.peer[k];
    if (!s.checked) continue;
    printf("  %s: agree with dcol %ld / %ld (tol %.0e), no depth %ld, disagreements dcol closer "
           "%ld : %s closer %ld (peer deeper than independent: %ld), max diff %.2e, max vs "
           "independent %.2e\n", kPeerName[k], s.agree, s.checked, depth_tolerance(k, dcol_tol),
           s.no_depth, s.dcol_closer, kPeerName[k], s.peer_closer, s.peer_deeper, s.max_diff,
           s.max_ind);
  }
}
