// bench_compare.cpp: time and accuracy of dcol against Coal 3 (when built with it), FCL 0.7 and
// libccd 2.1 on the same fixed-seed cases (36 unordered pair types of the eight dcol shapes; Coal
// and FCL have no padded polygon, so the 8 polygon pairs are skipped for both). Cases come from c_tests/compare/compare_common.c,
// shared with the agreement suite: a third separated, a third near touching, a third overlapping.
//
// Per case, every method is run `repeat` times in a row and timed with std::chrono::steady_clock
// (ns per call = total / repeat); methods are interleaved per case, starting at a rotating
// offset, so machine noise hits them all alike. Reported: medians over cases.
// Errors: alpha against a dcol solve at tolerance 1e-12 (self-referenced: only dcol computes
// alpha); distances, on separated cases, against an independent reference (FCL at 1e-12 where
// it agrees with Coal at 1e-12, else dcol at 1e-12 where it agrees with one of them; cases with
// none are left out and counted). Boolean methods count wrong answers against alpha* < 1
// outside the band |alpha* - 1| < 1e-6. Overlapping cases also get the penetration-depth
// comparison (penetration.hpp).
//
// Environment: DCOL_BENCH_CASES (per pair type, default 1500), DCOL_BENCH_REPEAT (default 5),
// DCOL_BENCH_SEED (default 20240501), DCOL_BENCH_OUT (results directory, default "results").
//
// The parts: bench_common.hpp (shared types and helpers), methods.cpp (the method table),
// this file (the cases, the references and the untimed checks per case), report.cpp and
// report_contacts.cpp (benchmark.md, time_vs_error.csv), penetration.cpp and depth_check.cpp
// (the penetration-depth comparison and its independent check).

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <exception>

#include "bench_common.hpp"
#include "depth_check.hpp"

int run() {
  const long cases = cmp_env_long("DCOL_BENCH_CASES", 1500);
  const long repeat = std::max(1L, cmp_env_long("DCOL_BENCH_REPEAT", 5));
  const long seed = cmp_env_long("DCOL_BENCH_SEED", 20240501);
  const char* outdir_env = std::getenv("DCOL_BENCH_OUT");
  const std::string outdir = outdir_env && *outdir_env ? outdir_env : "results";

  BenchRun R;
  R.cases = cases, R.repeat = repeat, R.seed = seed, R.outdir = outdir;
#ifdef DCOL_BENCH_HAVE_ODE
  dInitODE2(0);
#endif
  // The current case, seen by the method closures.
  CaseCtx ctx;
  DCOL_BENCH_CASE_REFS(ctx);
  std::vector<Method>& methods = R.methods;
  const size_t n_tol_rows = R.n_tol_rows;
  auto& solver_count = R.solver_count;
  auto& ip_iters = R.ip_iters;
  std::vector<std::string>& pair_names = R.pair_names;
  std::vector<bool>& engine_pair_of = R.engine_pair_of;
  std::vector<int>& ode_pair_of = R.ode_pair_of;
  auto& agree = R.agree;
  auto& self_agree = R.self_agree;
  long &made = R.made, &failures = R.failures, &ref_fallbacks = R.ref_fallbacks;
  long &dref_fcl = R.dref_fcl, &dref_dcol = R.dref_dcol, &dref_none = R.dref_none,
       &dref_nopeer = R.dref_nopeer;
  std::vector<double>& dref_spread = R.dref_spread;
  std::vector<DepthRow>& depth_rows = R.depth_rows;
  long* fcl_signed_threw = R.fcl_signed_threw;
  add_methods(methods, ctx);
  const auto t_start = std::chrono::steady_clock::now();
  int pair = 0;
  for (int k1 = 0; k1 < CMP_KIND_COUNT; ++k1)
    for (int k2 = k1; k2 < CMP_KIND_COUNT; ++k2, ++pair) {
      pair_names.push_back(std::string(cmp_kind_name((cmp_kind)k1)) + "-" +
                           cmp_kind_name((cmp_kind)k2));
      const bool fcl_pair = k1 != CMP_POLYGON && k2 != CMP_POLYGON;
      const bool engine_pair = engine_kind(k1) && engine_kind(k2);
      engine_pair_of.push_back(engine_pair);
      // does ODE have a collider for this pair type? (dCollide on two concentric shapes)
      int ode_pair = -1;  // -1: not yet checked
#ifndef DCOL_BENCH_HAVE_ODE
      ode_pair = 0;
#endif
      if (!engine_pair) ode_pair = 0;
      cmp_rng rng;
      cmp_rng_seed(&rng, (uint64_t)seed * 1000003u + (uint64_t)(k1 * 16 + k2));
      for (long i = 0; i < cases; ++i) {
        const int rc = cmp_case_make(&c, (cmp_kind)k1, (cmp_kind)k2, (int)i, &rng);
        if (rc < 0) continue;
        if (rc > 0) {
          failures++;
          fprintf(stderr, "%s: case %ld: dcol refused while making it: %s\n",
                  pair_names.back().c_str(), i, dcol_last_error_message());
          cmp_case_release(&c);
          continue;
        }
        // the reference: a tight dcol solve (alpha and distance) at 1e-12; when the solver stalls
        // short of that (it reports an error), 1e-11 then 1e-10 (counted as fallbacks)
        dcol_proximity_result pr;
        dcol_distance_result dr;
        bool ref_ok = false;
        for (double rt : {1e-12, 1e-11, 1e-10}) {
          dcol_options o = dcol_options_default();
          o.tolerance = rt;
          if (dcol_proximity(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &pr) ==
                  DCOL_OK &&
              dcol_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &dr) ==
                  DCOL_OK) {
            ref_ok = true;
            if (rt > kTight) ref_fallbacks++;
            break;
          }
        }
        if (!ref_ok) {
          failures++;
          fprintf(stderr, "%s: case %ld: reference solve failed: %s\n",
                  pair_names.back().c_str(), i, dcol_last_error_message());
          cmp_case_release(&c);
          continue;
        }
        made++;
        const double alpha_ref = pr.alpha, dist_ref = dr.distance;
        const bool in_band = std::fabs(alpha_ref - 1) < kBand;
        const int truth = alpha_ref < 1;
        if (fcl_pair) f1 = to_fcl(c.b1), f2 = to_fcl(c.b2);
#ifdef DCOL_BENCH_HAVE_ODE
        if (engine_pair) {
          o1 = to_ode(c.b1), o2 = to_ode(c.b2);
          if (ode_pair < 0) {
            // two concentric copies: any collider reports a contact
            auto q1 = to_ode(c.b1), q2 = to_ode(c.b2);
            dGeomSetPosition(q1->geom, 0, 0, 0);
            dGeomSetPosition(q2->geom, 0, 0, 0);
            dContactGeom cg[4];
            ode_pair = dCollide(q1->geom, q2->geom, 4, cg, sizeof(dContactGeom)) > 0;
            if (!ode_pair)
              printf("ODE: no collider for %s (dCollide reports no contact for concentric "
                     "shapes): left out\n", pair_names.back().c_str());
          }
        }
#endif
#ifdef DCOL_BENCH_HAVE_BULLET
        if (engine_pair) u1 = to_bullet(c.b1), u2 = to_bullet(c.b2);
#endif
#ifdef DCOL_BENCH_HAVE_COAL
        if (fcl_pair) {
          g1 = to_coal(c.b1), g2 = to_coal(c.b2);
          coal_dist_functor = std::make_unique<coal::ComputeDistance>(g1.geom.get(), g2.geom.get());
        }
#endif
        // the independent distance reference on separated cases: FCL at distance_tolerance
        // 1e-12 where it agrees with Coal at gjk_tolerance 1e-12 to kRefAgree max(1, d), else
        // dcol at 1e-12 where it agrees with one of them; else none (left out of the errors)
        double dist_ind = NAN;
        if (alpha_ref > 1 + kBand) {
          if (!fcl_pair) {
            dref_nopeer++;
          } else {
            const double df = fcl_distance_at(f1, f2, kTight);
            double dc = NAN;
#ifdef DCOL_BENCH_HAVE_COAL
            {
              coal::DistanceRequest req;
              req.gjk_tolerance = kTight;
              coal::DistanceResult res;
              dc = std::max(0.0, coal::distance(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res));
            }
#endif
            auto close = [](double a, double b) {
              return std::fabs(a - b) <= kRefAgree * std::max(1.0, std::fabs(b));
            };
            if (close(df, dc)) {
              dist_ind = df, dref_fcl++;
              dref_spread.push_back(std::fabs(df - dc));
            } else if (close(dist_ref, df) || close(dist_ref, dc)) {
              dist_ind = dist_ref, dref_dcol++;
            } else if (dref_none++ < 5) {
              fprintf(stderr, "%s case %ld: no distance reference: FCL@1e-12 %.17g, Coal@1e-12 "
                      "%.17g, dcol@1e-12 %.17g\n", pair_names.back().c_str(), i, df, dc, dist_ref);
            }
          }
        }
        for (size_t t = 0; t < n_tol_rows; ++t) {
          dcol_options o = dcol_options_default();
          if (t < std::size(kTols)) o.tolerance = kTols[t];
          dcol_proximity_result r;
          if (dcol_proximity(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &r) ==
              DCOL_OK) {
            if (r.solver < 4) solver_count[t][c.category][r.solver]++;
            if (r.solver == DCOL_SOLVER_INTERIOR_POINT)
              ip_iters[t][c.category].push_back(r.iterations);
          }
        }
        const size_t nm = methods.size();
        const size_t start = static_cast<size_t>(made) % nm;
        for (size_t j = 0; j < nm; ++j) {
          Method& m = methods[(start + j) % nm];
          if (m.fcl_only && !fcl_pair) continue;
          if ((m.only == 1 && ode_pair != 1) || (m.only == 2 && !engine_pair)) continue;
          m.last_ok = false;
          double v = NAN;
          bool ok = true;
          const auto t0 = std::chrono::steady_clock::now();
          for (long r = 0; r < repeat; ++r) ok = m.run(&v) && ok;
          const auto t1 = std::chrono::steady_clock::now();
          Sample s;
          s.ns = std::chrono::duration<double, std::nano>(t1 - t0).count() / repeat;
          s.pair = pair;
          s.cat = c.category;
          s.alpha_ref = alpha_ref;
          s.fcl_pair = fcl_pair;
          s.err = NAN;
          s.wrong = -1;
          if (!ok) {
            m.failures++;
            fprintf(stderr, "%s: %s failed on case %ld: %s\n", pair_names.back().c_str(),
                    label(m).c_str(), i, dcol_last_error_message());
            continue;
          }
          if (m.contact) {
            if (!in_band) s.wrong = ((v > kNoContact) != (truth != 0));
            m.last = v, m.last_ok = true;
          } else if (m.boolean) {
            if (!in_band) s.wrong = (static_cast<int>(v) != truth);
            if (s.wrong == 1 && m.name.rfind("coal::", 0) == 0 && ++m.wrong_shown <= 8)
              fprintf(stderr, "%s: %s case %ld: says %s, alpha* %.17g\n",
                      pair_names.back().c_str(), label(m).c_str(), i, v ? "collision" : "free",
                      alpha_ref);
          } else if (m.name.rfind("dcol_proximity", 0) == 0 || m.name.rfind("dcol_gradient", 0) == 0 ||
                     m.name.rfind("dcol_jacobian", 0) == 0) {
            s.err = std::fabs(v - alpha_ref);
          } else if (alpha_ref > 1 + kBand) {
            s.err = std::fabs(std::max(0.0, v) - dist_ind);  // distance errors: separated only
            s.dcol_diff = std::fabs(std::max(0.0, v) - dist_ref);
          }
          if (m.agree_tol > 0) {
            if (alpha_ref > 1 + kBand) {
              m.sep_checked++;
              if (s.dcol_diff > m.worst_err) {
                // a third opinion for the worst case: FCL at distance_tolerance 1e-12 (untimed)
                fcl::DistanceRequestd req;
                req.gjk_solver_type = fcl::GST_LIBCCD;
                req.distance_tolerance = 1e-12;
                fcl::DistanceResultd res;
                fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req, res);
                char b[256];
                snprintf(b, sizeof b, "%s case %ld: %.17g vs dcol %.17g, FCL@1e-12 %.17g",
                         pair_names.back().c_str(), i, v, dist_ref, res.min_distance);
                m.worst_err = s.dcol_diff, m.worst_case = b;
              }
              if (s.dcol_diff > 10 * m.agree_tol * std::max(1.0, dist_ref)) m.sep_disagree10++;
              if (s.dcol_diff > m.agree_tol * std::max(1.0, dist_ref)) {
                if (m.sep_disagree++ < 5)
                  fprintf(stderr, "%s: %s case %ld: distance %.17g, dcol %.17g (alpha* %.17g)\n",
                          pair_names.back().c_str(), label(m).c_str(), i, v, dist_ref, alpha_ref);
              }
            } else if (alpha_ref < 1 - kBand) {
              m.ovl_checked++;
              if (v > m.agree_tol) {
                if (m.ovl_disagree++ < 5)
                  fprintf(stderr, "%s: %s case %ld: distance %.17g on an overlapping pair "
                          "(alpha* %.17g)\n", pair_names.back().c_str(), label(m).c_str(), i, v,
                          alpha_ref);
              }
            }
          }
          m.samples.push_back(s);
        }
        // penetration depth on the overlapping cases (untimed): dcol_signed_distance against
        // Coal, FCL (libccd and indep solvers), libccd MPR and the independent check
        if (alpha_ref < 1 - kBand) {
          PeerDepths pdp;
          if (fcl_pair) {
#ifdef DCOL_BENCH_HAVE_COAL
            {
              coal::DistanceRequest req;
              coal::DistanceResult res;
              const double d = coal::distance(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
              pdp.raw[kPeerCoal] = d;
              if (d < 0) pdp.depth[kPeerCoal] = -d;
              pdp.normal[kPeerCoal] = {res.normal[0], res.normal[1], res.normal[2]};
            }
#endif
            for (int k : {kPeerFclCcd, kPeerFclIndep}) {
              // fcl::distance(..., request, result) as FCL 0.7 does it (the solver set up from
              // the request), but through the solver-templated overload compiled here: the
              // instantiation inside the Debian libfcl keeps its assert()s, and GST_INDEP
              // aborts on `index != -1` when its collide fallback finds no contact; with
              // NDEBUG, as in a release build of FCL, it returns -DBL_MIN instead
              fcl::DistanceRequestd req;
              req.enable_signed_distance = true;
              req.gjk_solver_type = k == kPeerFclCcd ? fcl::GST_LIBCCD : fcl::GST_INDEP;
              fcl::DistanceResultd res;
              try {
                if (k == kPeerFclCcd) {
                  fcl::detail::GJKSolver_libccd<double> solver;
                  solver.distance_tolerance = req.distance_tolerance;
                  fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, &solver, req, res);
                } else {
                  fcl::detail::GJKSolver_indep<double> solver;
                  solver.gjk_tolerance = req.distance_tolerance;
                  fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, &solver, req, res);
                }
              } catch (const std::exception& e) {
                if (fcl_signed_threw[k - kPeerFclCcd]++ < 3)
                  fprintf(stderr, "%s case %ld: FCL signed distance threw: %s\n",
                          pair_names.back().c_str(), i, e.what());
                continue;
              }
              const double d = res.min_distance;
              pdp.raw[k] = d;
              // -1: libccd's EPA failed; > -1e-300: FCL's collide fallback found no contact
              if (d < -1e-300 && d != -1.0) pdp.depth[k] = -d;
            }
          }
          {
            ccd_real_t depth;
            ccd_vec3_t dir, pos;
            const int rc = ccdMPRPenetration(&c.b1, &c.b2, &ccd, &depth, &dir, &pos);
            pdp.raw[kPeerMpr] = rc == 0 ? depth : -1;
            if (rc == 0) {
              pdp.depth[kPeerMpr] = depth;
              pdp.normal[kPeerMpr] = {dir.v[0], dir.v[1], dir.v[2]};
            }
          }
          dcol_signed_distance_result osd{};
          const bool osd_ok = dcol_signed_distance(c.s1.handle, &c.b1.pose, c.s2.handle,
                                                   &c.b2.pose, &defaults, &osd) == DCOL_OK;
          record_depth(depth_rows[pair], c, osd_ok, osd, pdp, defaults.tolerance,
                       pair_names.back() + " case " + std::to_string(i));
        }
        // contact agreement with dcol_contacts (this case's values)
        dcol_signed_distance_result sd{};
        bool sd_ok = false;
        if (!in_band) {
          const Method* dm = nullptr;
          for (const Method& m : methods)
            if (m.contact && m.only == 0) dm = &m;
          sd_ok = dcol_signed_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                       &defaults, &sd) == DCOL_OK;
          if (dm->last_ok && dm->last > kNoContact && sd_ok) {
            Agree& a = self_agree[pair];
            a.depth_checked++;
            const double e = std::fabs(dm->last + sd.distance);
            if (e > kDepthAgree) a.depth_disagree++;
            if (e > a.depth_max) {
              char b[200];
              snprintf(b, sizeof b, "%s case %ld: %.9g vs %.9g, alpha* %.6g",
                       pair_names.back().c_str(), i, dm->last, -sd.distance, alpha_ref);
              a.depth_max = e, a.worst = b;
            }
          }
        }
        if (engine_pair && !in_band) {
          const Method* dm = nullptr;
          for (const Method& m : methods)
            if (m.contact && m.only == 0) dm = &m;
          for (const Method& m : methods) {
            if (!m.contact || m.only == 0 || !dm->last_ok || !m.last_ok) continue;
            Agree& a = agree[m.only - 1][pair];
            const bool hd = dm->last > kNoContact, he = m.last > kNoContact;
            a.contact_checked++;
            if (hd != he) {
              if (std::fabs(alpha_ref - 1) >= 1e-4) a.contact_disagree4++;
              if (a.contact_disagree++ < 3)
                fprintf(stderr, "%s: %s case %ld: %s, dcol_contacts %s (alpha* %.17g)\n",
                        pair_names.back().c_str(), m.name.c_str(), i, he ? "contact" : "none",
                        hd ? "contact" : "none", alpha_ref);
            } else if (hd) {
              // the engine's depth against dcol_signed_distance (-distance), when it certified
              if (sd_ok && sd.distance < 0) {
                a.sd_checked++;
                if (std::fabs(m.last + sd.distance) > kDepthAgree) a.sd_disagree++;
              }
              a.depth_checked++;
              const double e = std::fabs(m.last - dm->last);
              if (e > kDepthAgree) a.depth_disagree++;
              if (e > a.depth_max) {
                char b[320];
                dcol_signed_distance_result sd{};
                dcol_signed_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &defaults,
                                     &sd);
                snprintf(b, sizeof b, "case %ld: %.9g vs dcol_contacts %.9g (dcol_signed_distance "
                         "%.9g), alpha* %.6g", i, m.last, dm->last, -sd.distance, alpha_ref);
#ifdef DCOL_BENCH_HAVE_COAL
                {
                  // a third opinion: Coal's signed distance (default request, EPA), untimed
                  coal::DistanceRequest req;
                  coal::DistanceResult res;
                  const double d = coal::distance(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
                  snprintf(b + strlen(b), sizeof b - strlen(b), ", Coal %.9g", -d);
                }
#endif
                a.depth_max = e, a.worst = b;
              }
            }
          }
        }
        cmp_case_release(&c);
      }
      ode_pair_of.push_back(ode_pair == 1);
      fprintf(stderr, "%s done (%ld cases so far)\n", pair_names.back().c_str(), made);
    }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  R.seconds = seconds;
  return write_report(R);
}

int main() {
  const int rc = run();
  fflush(stdout);
  fflush(stderr);
  // With Coal, the process holds two octomap builds: the system's 1.9 (through libfcl) and the
  // wheel's 1.10 (through libcoal). Their static objects share symbols, so both libraries
  // construct and destroy the same ones and the exit-time destructors end in a double free.
  // Nothing here uses octomap: skip the static destructors (the outputs are closed and flushed).
  // Done with or without Coal (a build directory configured before may still link both).
  std::_Exit(rc);
}
