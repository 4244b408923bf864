// report.cpp: benchmark.md and time_vs_error.csv from one run (BenchRun): the headline
// ratios, the all-pairs table, the distance error reference, the CSV, dcol against FCL and Coal
// at equal error and per pair type, the Coal agreement, the penetration depth, the contact
// queries (report_contacts.cpp), which solver answered, and one table per pair type.
#include "bench_common.hpp"

int write_report(const BenchRun& R) {
  const std::vector<Method>& methods = R.methods;
  const long cases = R.cases, repeat = R.repeat, seed = R.seed;
  const std::string& outdir = R.outdir;
  const dcol_options& defaults = R.defaults;
  const size_t n_tol_rows = R.n_tol_rows;
  const auto& solver_count = R.solver_count;
  const auto& ip_iters = R.ip_iters;
  const std::vector<std::string>& pair_names = R.pair_names;
  const long made = R.made, failures = R.failures, ref_fallbacks = R.ref_fallbacks;
  const long dref_fcl = R.dref_fcl, dref_dcol = R.dref_dcol, dref_none = R.dref_none,
             dref_nopeer = R.dref_nopeer;
  const std::vector<double>& dref_spread = R.dref_spread;
  const std::vector<DepthRow>& depth_rows = R.depth_rows;
  const long* fcl_signed_threw = R.fcl_signed_threw;
  const double seconds = R.seconds;
  // ---- output ----------------------------------------------------------------------------
  const std::string md_path = outdir + "/benchmark.md", csv_path = outdir + "/time_vs_error.csv";
  FILE* md = fopen(md_path.c_str(), "w");
  FILE* csv = fopen(csv_path.c_str(), "w");
  if (!md || !csv) {
    fprintf(stderr, "cannot write %s or %s\n", md_path.c_str(), csv_path.c_str());
    return 1;
  }
  const Method* fcl_ref = nullptr;
  for (const Method& m : methods)
    if (m.name == "fcl::distance" && m.tol == kFclRefTol) fcl_ref = &m;
  const Stats ref_all = stats(*fcl_ref, [](const Sample&) { return true; });
  auto find = [&](const std::string& name, double tol) -> const Method* {
    for (const Method& m : methods)
      if (m.name == name && m.tol == tol) return &m;
    return nullptr;
  };
  const Method* coal_ref = find("coal::distance", kCoalRefTol);  // null without Coal
  const Stats coal_all =
      coal_ref ? stats(*coal_ref, [](const Sample&) { return true; }) : Stats{};

  fprintf(md, "# dcol vs Coal 3, FCL 0.7 and libccd 2.1: time and error\n\n");
  fprintf(md, "%s.%s\n\n", kCoalStatus,
          kHaveCoal ? " Coal comes from the libcoal wheel on PyPI (cmeel build, Release); "
                      "`coal::distance` and `coal::collide` with default requests (GJK + EPA; "
                      "the distance is signed, collide computes the contact), the distance also "
                      "at gjk_tolerance 1e-2 … 1e-12 (EPA at its default), "
                      "`coal::ComputeDistance` the functor that caches the shape pair's "
                      "function, `coal::collide (no contact)` a boolean request "
                      "(CollisionRequest(NO_REQUEST, 1)). Coal, like FCL, runs on the 28 pair "
                      "types without the padded polygon."
                    : " The tables below have no Coal columns.");
  fprintf(md,
          "dcol %s; %ld cases per pair type (seed %ld; a third separated, near touching, "
          "overlapping), %ld calls timed together per case (steady_clock), methods interleaved "
          "per case; %ld cases in all, %ld failures; %.1f s. Times are medians over cases in ns "
          "per call. Reference solves that fell back from 1e-12 to 1e-11 or 1e-10 (solver stalled): %ld; failed calls (dcol returned an error, e.g. a stall at 1e-12) are left out of a method's statistics and counted in the table. Errors: |alpha - alpha_ref| for proximity/gradient/jacobian against "
          "the dcol solve at tolerance 1e-12 (self-referenced: only dcol computes alpha, so "
          "these errors say how far a looser tolerance is from dcol's own tight answer, not "
          "from the truth); |max(0, d) - d_ind| for distances on separated cases only "
          "(alpha_ref > 1 + 1e-6) against an independent reference d_ind (see \"Distance error "
          "reference\" below; cases without one are left out of the distance errors). Wrong: boolean answers that disagree with alpha_ref < 1, "
          "cases with |alpha_ref - 1| < 1e-6 not counted. FCL runs on the 28 pair types without "
          "the padded polygon; libccd uses CCD_INIT defaults (mpr_tolerance 1e-4) with support "
          "functions from compare_common.c.\n\n",
          dcol_version(), cases, seed, repeat, made, failures, seconds, ref_fallbacks);

  {
    // headline ratios on the 28 FCL pair types, same cases, same run
    auto fcl_med = [&](const Method* m) {
      return stats(*m, [](const Sample& x) { return x.fcl_pair; }).med_ns;
    };
    const double fd = fcl_med(fcl_ref);
    const double fc = fcl_med(find("fcl::collide (default)", 0));
    fprintf(md, "## Headline (28 FCL pair types, medians in the same run)\n\n");
    fprintf(md, "| comparison | dcol ns | FCL ns | ratio dcol / FCL |\n|---|--:|--:|--:|\n");
    const Method* pd = find("dcol_proximity (default tol)", 0);
    fprintf(md, "| dcol_proximity (default tol) / fcl::distance @1e-06 | %.0f | %.0f | %.2f |\n",
            fcl_med(pd), fd, fcl_med(pd) / fd);
    for (double t : {1e-4, 1e-6}) {
      const Method* p = find("dcol_proximity", t);
      fprintf(md, "| dcol_proximity @%.0e / fcl::distance @1e-06 | %.0f | %.0f | %.2f |\n", t,
              fcl_med(p), fd, fcl_med(p) / fd);
    }
    const Method* di = find("dcol_intersect (default tol)", 0);
    fprintf(md, "| dcol_intersect / fcl::collide | %.0f | %.0f | %.2f |\n\n", fcl_med(di), fc,
            fcl_med(di) / fc);
    if (coal_ref) {
      const double cd = fcl_med(coal_ref);
      fprintf(md, "| comparison | dcol ns | Coal ns | ratio dcol / Coal |\n|---|--:|--:|--:|\n");
      const Method* dd = find("dcol_distance (default tol)", 0);
      for (const Method* m : {pd, dd})
        fprintf(md, "| %s / coal::distance (default) | %.0f | %.0f | %.2f |\n", m->name.c_str(),
                fcl_med(m), cd, fcl_med(m) / cd);
      for (const char* cn : {"coal::collide (default)", "coal::collide (no contact)"}) {
        const double cc = fcl_med(find(cn, 0));
        fprintf(md, "| dcol_intersect / %s | %.0f | %.0f | %.2f |\n", cn, fcl_med(di), cc,
                fcl_med(di) / cc);
      }
      fprintf(md, "\n");
    }
  }
  {
    const long sep = dref_fcl + dref_dcol + dref_none;
    const double spread_med = median(dref_spread);
    const double spread_max =
        dref_spread.empty() ? NAN : *std::max_element(dref_spread.begin(), dref_spread.end());
    fprintf(md, "## Distance error reference\n\n"
                "On the separated cases (alpha_ref > 1 + 1e-6) of the 28 pair types with an FCL "
                "shape: d_ind = FCL's distance (GST_LIBCCD) at distance_tolerance 1e-12 where it "
                "agrees with Coal's at gjk_tolerance 1e-12 to %.0e max(1, d) (%ld cases; there "
                "|FCL - Coal| has median %s and max %s); else dcol's at tolerance 1e-12 where it "
                "agrees with FCL's or Coal's to the same bound (%ld cases); else no reference "
                "(%ld cases, left out of the distance errors). %ld separated cases of the 8 "
                "padded-polygon pair types have no peer and no reference: the distance errors "
                "are over the 28 pair types. By construction FCL @1e-12 has error 0 on the "
                "cases where it is the reference (%.1f %% of them) and dcol @1e-12 on the "
                "others: the 1e-12 points of those two sweeps are not measurements.%s\n\n",
            kRefAgree, dref_fcl, fmt(spread_med, "%.1e").c_str(), fmt(spread_max, "%.1e").c_str(),
            dref_dcol, dref_none, dref_nopeer, sep ? 100.0 * dref_fcl / sep : NAN,
            kHaveCoal ? "" : " Without Coal no two peers can agree: the reference is dcol at "
                             "1e-12 where FCL at 1e-12 agrees with it.");
    printf("distance reference on %ld separated cases: FCL=Coal %ld, dcol (agrees with one) %ld, "
           "none %ld; |FCL - Coal| median %s max %s; %ld polygon cases without a peer\n", sep,
           dref_fcl, dref_dcol, dref_none, fmt(spread_med, "%.1e").c_str(),
           fmt(spread_max, "%.1e").c_str(), dref_nopeer);
  }
  fprintf(md, "## All pairs\n\n");
  fprintf(md,
          "`all 36`: every case the method ran on; `28 FCL pairs`: the pair types FCL supports, "
          "with the ratio to `fcl::distance @1e-06` (FCL's default tolerance) on the same cases.\n\n");
  fprintf(md, "| method | all 36: median ns | 28 FCL pairs: median ns | ratio to FCL distance | "
              "%smedian error | max error | wrong / compared | failed calls |\n|---|--:|--:|--:|%s--:|--:|--:|--:|\n",
          coal_ref ? "ratio to Coal distance | " : "", coal_ref ? "--:|" : "");
  for (const Method& m : methods) {
    if (m.contact) continue;  // their own table below
    const Stats a = stats(m, [](const Sample&) { return true; });
    const Stats f = stats(m, [](const Sample& x) { return x.fcl_pair; });
    const Stats e = m.fcl_only ? f : a;
    fprintf(md, "| %s | %s | %s | %s | %s%s | %s | %s | %ld |\n", label(m).c_str(),
            m.fcl_only ? "–" : fmt(a.med_ns, "%.0f").c_str(), fmt(f.med_ns, "%.0f").c_str(),
            fmt(f.med_ns / ref_all.med_ns, "%.2f").c_str(),
            coal_ref ? (fmt(f.med_ns / coal_all.med_ns, "%.2f") + " | ").c_str() : "",
            fmt(e.med_err, "%.1e").c_str(),
            fmt(e.max_err, "%.1e").c_str(),
            m.boolean ? (std::to_string(e.wrong) + " / " + std::to_string(e.compared)).c_str()
                      : "–",
            m.failures);
  }

  // CSV over the 28 FCL pair types (the same cases for every method)
  // quantity: alpha (self-referenced, dcol at 1e-12) or distance (the independent reference);
  // zero_error_share: the share of the errors that are exactly 0
  fprintf(csv, "method,tolerance,quantity,reference,median_ns,median_error,max_error,"
               "error_cases,zero_error_share\n");
  for (const Method& m : methods) {
    if (m.boolean || m.contact) continue;
    const Stats f = stats(m, [](const Sample& x) { return x.fcl_pair; });
    long n_err = 0, n_zero = 0;
    for (const Sample& x : m.samples)
      if (x.fcl_pair && !std::isnan(x.err)) n_err++, n_zero += x.err == 0;
    const bool alpha = m.name.rfind("dcol_proximity", 0) == 0 ||
                       m.name.rfind("dcol_gradient", 0) == 0 || m.name.rfind("dcol_jacobian", 0) == 0;
    fprintf(csv, "%s,%s,%s,%s,%.1f,%.6e,%.6e,%ld,%.4f\n", m.name.c_str(),
            m.tol > 0 ? fmt(m.tol, "%.0e").c_str() : "default", alpha ? "alpha" : "distance",
            alpha ? "dcol@1e-12 (self)" : "independent", f.med_ns, f.med_err, f.max_err, n_err,
            n_err ? static_cast<double>(n_zero) / n_err : NAN);
  }

  // dcol distance vs FCL (and Coal) distance at equal (median) error, on the 28 FCL pairs
  struct Pt { double err, ns; };
  auto curve_of = [&](const std::string& name) {
    std::vector<Pt> curve;
    for (const Method& m : methods)
      if (m.name == name) {
        const Stats f = stats(m, [](const Sample& x) { return x.fcl_pair; });
        curve.push_back({f.med_err, f.med_ns});
      }
    std::sort(curve.begin(), curve.end(), [](const Pt& a, const Pt& b) { return a.err < b.err; });
    return curve;
  };
  auto ns_at = [](const std::vector<Pt>& curve, double err) {
    double ns = NAN;
    for (size_t k = 0; k + 1 < curve.size(); ++k) {
      const Pt a = curve[k], b = curve[k + 1];
      if (a.err > 0 && b.err > a.err && err >= a.err && err <= b.err) {
        const double w = std::log(err / a.err) / std::log(b.err / a.err);
        ns = std::exp((1 - w) * std::log(a.ns) + w * std::log(b.ns));
      }
    }
    return ns;
  };
  const std::vector<Pt> fcl_curve = curve_of("fcl::distance"), coal_curve = curve_of("coal::distance");
  fprintf(md, "\n## dcol_distance vs fcl::distance%s at equal median error (28 FCL pairs)\n\n",
          coal_ref ? " and coal::distance" : "");
  fprintf(md, "The other library's time at dcol's median error, interpolated log-log along its "
              "tolerance sweep (– when dcol's error lies outside its range).\n\n");
  fprintf(md, "| dcol tolerance | dcol median error | dcol median ns | FCL ns at that error | "
              "ratio dcol / FCL |%s\n|---|--:|--:|--:|--:|%s\n",
          coal_ref ? " Coal ns at that error | ratio dcol / Coal |" : "", coal_ref ? "--:|--:|" : "");
  for (const Method& m : methods) {
    if (m.name != "dcol_distance" && m.name != "dcol_distance (default tol)") continue;
    const Stats f = stats(m, [](const Sample& x) { return x.fcl_pair; });
    const double fcl_ns = ns_at(fcl_curve, f.med_err), coal_ns = ns_at(coal_curve, f.med_err);
    fprintf(md, "| %s | %s | %.0f | %s | %s |", m.tol > 0 ? fmt(m.tol, "%.0e").c_str() : "default",
            fmt(f.med_err, "%.1e").c_str(), f.med_ns, fmt(fcl_ns, "%.0f").c_str(),
            fmt(f.med_ns / fcl_ns, "%.2f").c_str());
    if (coal_ref)
      fprintf(md, " %s | %s |", fmt(coal_ns, "%.0f").c_str(), fmt(f.med_ns / coal_ns, "%.2f").c_str());
    fprintf(md, "\n");
  }

  // dcol vs Coal (and FCL collide) per pair type: medians per pair type, then the median over
  // the 28 pair types (the project's "all-pairs median") and the worst pair type
  if (coal_ref) {
    const Method* pd = find("dcol_proximity (default tol)", 0);
    const Method* dd = find("dcol_distance (default tol)", 0);
    const Method* di = find("dcol_intersect (default tol)", 0);
    const Method* cc = find("coal::collide (default)", 0);
    const Method* cb = find("coal::collide (no contact)", 0);
    const Method* fc = find("fcl::collide (default)", 0);
    const Method* cols[] = {pd, dd, di, coal_ref, cc, cb, fc};
    fprintf(md, "\n## dcol vs Coal per pair type (28 pair types)\n\n"
                "Median ns per pair type; ratios of those medians. `all-pairs median`: the median "
                "over the 28 pair types of each column (ratios: the median of the per-pair "
                "ratios); `ratio of the all-pairs medians`: the all-pairs median times divided; "
                "`worst`: the largest per-pair ratio.\n\n");
    fprintf(md, "| pair | dcol proximity | dcol distance | dcol intersect | Coal distance | Coal "
                "collide | Coal collide (no contact) | FCL collide | proximity / Coal distance | "
                "distance / Coal distance | intersect / Coal collide | intersect / Coal collide "
                "(no contact) | intersect / FCL collide |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    std::vector<std::vector<double>> colv(7), ratv(5);
    std::vector<std::string> worst_pair(5);
    std::vector<double> worst(5, -1);
    for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
      double v[7];
      bool any = true;
      for (int k = 0; k < 7; ++k) {
        const Stats st = stats(*cols[k], [p](const Sample& x) { return x.pair == p; });
        v[k] = st.med_ns;
        if (st.n == 0) any = false;
      }
      if (!any) continue;
      const double r[5] = {v[0] / v[3], v[1] / v[3], v[2] / v[4], v[2] / v[5], v[2] / v[6]};
      fprintf(md, "| %s |", pair_names[p].c_str());
      for (int k = 0; k < 7; ++k) fprintf(md, " %.0f |", v[k]), colv[k].push_back(v[k]);
      for (int k = 0; k < 5; ++k) {
        fprintf(md, " %.2f |", r[k]);
        ratv[k].push_back(r[k]);
        if (r[k] > worst[k]) worst[k] = r[k], worst_pair[k] = pair_names[p];
      }
      fprintf(md, "\n");
    }
    fprintf(md, "| **all-pairs median** |");
    for (int k = 0; k < 7; ++k) fprintf(md, " **%.0f** |", median(colv[k]));
    for (int k = 0; k < 5; ++k) fprintf(md, " **%.2f** |", median(ratv[k]));
    {
      const double m[7] = {median(colv[0]), median(colv[1]), median(colv[2]), median(colv[3]),
                           median(colv[4]), median(colv[5]), median(colv[6])};
      fprintf(md, "\n| ratio of the all-pairs medians | | | | | | | | %.2f | %.2f | %.2f | %.2f | %.2f |",
              m[0] / m[3], m[1] / m[3], m[2] / m[4], m[2] / m[5], m[2] / m[6]);
    }
    fprintf(md, "\n| worst pair type | | | | | | | |");
    for (int k = 0; k < 5; ++k) fprintf(md, " %.2f (%s) |", worst[k], worst_pair[k].c_str());
    fprintf(md, "\n");
    const char* rname[5] = {"dcol proximity / Coal distance", "dcol distance / Coal distance",
                            "dcol intersect / Coal collide (default)",
                            "dcol intersect / Coal collide (no contact)",
                            "dcol intersect / FCL collide"};
    printf("all-pairs medians over the 28 pair types (ns): proximity %.0f, distance %.0f, "
           "intersect %.0f, Coal distance %.0f, Coal collide %.0f / no contact %.0f, FCL collide %.0f\n",
           median(colv[0]), median(colv[1]), median(colv[2]), median(colv[3]), median(colv[4]),
           median(colv[5]), median(colv[6]));
    for (int k = 0; k < 5; ++k)
      printf("  %s: median of per-pair ratios %.2f, worst %.2f (%s)\n", rname[k],
             median(ratv[k]), worst[k], worst_pair[k].c_str());
    // agreement with dcol
    fprintf(md, "\n## Coal agreement with dcol\n\n"
                "Distance: separated cases (alpha_ref > 1 + 1e-6) where |max(0, d) - d_ref| > "
                "tol max(1, d_ref), and overlapping cases (alpha_ref < 1 - 1e-6) where Coal's "
                "signed distance is > tol, tol = the request's gjk_tolerance (default %.0e). Collide: answers against alpha_ref < 1, "
                "|alpha_ref - 1| < 1e-6 not counted (dcol_intersect on the same cases for "
                "comparison).\n\n| method | separated: disagree / checked | beyond 10 tol | "
                "max \\|max(0, d) - d_dcol\\| (worst case) | overlapping: disagree / checked |\n|---|--:|--:|--:|--:|\n",
            kCoalAgree);
    printf("%s: agreement with dcol\n", kCoalStatus);
    for (const Method& m : methods) {
      if (m.agree_tol > 0) {
        fprintf(md, "| %s | %ld / %ld | %ld | %s (%s) | %ld / %ld |\n", label(m).c_str(),
                m.sep_disagree, m.sep_checked, m.sep_disagree10, fmt(m.worst_err, "%.1e").c_str(),
                m.worst_case.c_str(), m.ovl_disagree, m.ovl_checked);
        printf("  %s: separated %ld / %ld disagree, %ld beyond 10x tol (max error %s: %s), "
               "overlapping %ld / %ld\n", label(m).c_str(), m.sep_disagree, m.sep_checked,
               m.sep_disagree10, fmt(m.worst_err, "%.1e").c_str(), m.worst_case.c_str(),
               m.ovl_disagree, m.ovl_checked);
      }
    }
    fprintf(md, "\n| boolean method (28 pair types) | wrong / compared (band 1e-6) | wrong / "
                "compared outside \\|alpha_ref - 1\\| < 1e-4 | wrong with alpha_ref < 0.99 or > 1.01 |\n|---|--:|--:|--:|\n");
    for (const Method* m : {di, cc, cb, fc}) {
      const Stats st = stats(*m, [](const Sample& x) { return x.fcl_pair; });
      const Stats wide = stats(*m, [](const Sample& x) {
        return x.fcl_pair && std::fabs(x.alpha_ref - 1) >= 1e-4;
      });
      const Stats far = stats(*m, [](const Sample& x) {
        return x.fcl_pair && std::fabs(x.alpha_ref - 1) > 1e-2;
      });
      fprintf(md, "| %s | %ld / %ld | %ld / %ld | %ld |\n", m->name.c_str(), st.wrong, st.compared,
              wide.wrong, wide.compared, far.wrong);
      printf("  %s: %ld / %ld wrong (band 1e-6), %ld / %ld outside 1e-4, %ld with |alpha*-1| > 1e-2\n",
             m->name.c_str(), st.wrong, st.compared, wide.wrong, wide.compared, far.wrong);
    }
  } else {
    fprintf(md, "\n## dcol vs Coal\n\n%s\n", kCoalStatus);
  }
  printf("%s\n", kCoalStatus);

  // penetration depth, and the signed-distance timing on the overlapping cases
  {
    std::string timing;
    const Method* sdm = find("dcol_signed_distance (default tol)", 0);
    if (coal_ref && sdm) {
      auto ovl = [](const Sample& x) { return x.fcl_pair && x.alpha_ref < 1 - kBand; };
      const double all_d = stats(*sdm, ovl).med_ns, all_c = stats(*coal_ref, ovl).med_ns;
      std::vector<double> md_d, md_c, rat;
      double worst = -1;
      std::string worst_pair;
      char b[512];
      timing += "### Time on the overlapping poses: dcol_signed_distance vs coal::distance\n\n"
                "The same interleaved timing as the other tables (the methods `dcol_signed_distance "
                "(default tol)` and `coal::distance @1e-06`, Coal's default request), on the "
                "overlapping cases of the 28 pair types only. The project's target: dcol's signed "
                "distance <= 1.0x Coal's on overlapping poses.\n\n"
                "| pair | dcol_signed_distance ns | coal::distance ns | ratio |\n|---|--:|--:|--:|\n";
      for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
        auto pp = [p](const Sample& x) { return x.pair == p && x.fcl_pair && x.alpha_ref < 1 - kBand; };
        const Stats a = stats(*sdm, pp), g = stats(*coal_ref, pp);
        if (a.n == 0 || g.n == 0) continue;
        const double r = a.med_ns / g.med_ns;
        md_d.push_back(a.med_ns), md_c.push_back(g.med_ns), rat.push_back(r);
        if (r > worst) worst = r, worst_pair = pair_names[p];
        snprintf(b, sizeof b, "| %s | %.0f | %.0f | %.2f |\n", pair_names[p].c_str(), a.med_ns,
                 g.med_ns, r);
        timing += b;
      }
      snprintf(b, sizeof b, "| **all-pairs median** | **%.0f** | **%.0f** | **%.2f** |\n"
               "| median over all overlapping cases | %.0f | %.0f | %.2f |\n"
               "| worst pair type | | | %.2f (%s) |\n",
               median(md_d), median(md_c), median(rat), all_d, all_c, all_d / all_c, worst,
               worst_pair.c_str());
      timing += b;
      printf("signed distance on overlapping poses: dcol %.0f ns, Coal %.0f ns (all-pairs "
             "medians), median of per-pair ratios %.2f (target <= 1.0), over all cases %.2f, "
             "worst %.2f (%s)\n", median(md_d), median(md_c), median(rat), all_d / all_c, worst,
             worst_pair.c_str());
    } else {
      timing = std::string("No signed-distance timing against Coal: ") + kCoalStatus + ".\n";
    }
    if (fcl_signed_threw[0] || fcl_signed_threw[1])
      timing += "\nFCL signed distance threw (left out): libccd " +
                std::to_string(fcl_signed_threw[0]) + ", indep " +
                std::to_string(fcl_signed_threw[1]) + " cases.\n";
    write_depth_section(md, depth_rows, pair_names, kHaveCoal, defaults.tolerance, timing);
  }

  write_contact_section(md, R);

  // which solver answered dcol_proximity, per regime
  const char* cat_names[] = {"separated", "near touching", "overlapping"};
  fprintf(md, "\n## Which solver answered dcol_proximity, per regime\n\n"
              "The result's `solver` field on an untimed extra dcol_proximity call per case and "
              "tolerance (all 36 pair types): the share of calls answered by a closed form, the "
              "certified ray cast, the ray cast with a Newton polish, and the interior-point "
              "solver, with the interior-point iterations of the calls that solver answered "
              "(median / max; `iterations` counts interior-point iterations only, so it is 0 for "
              "the other solvers).\n\n"
              "| tolerance | regime | calls | closed form | ray cast | polish | interior point (calls) | "
              "interior-point iterations (its calls) |\n|---|---|--:|--:|--:|--:|--:|--:|\n");
  printf("dcol_proximity: which solver answered (closed form / ray cast / polish / interior "
         "point, %% of calls):\n");
  for (size_t t = 0; t < n_tol_rows; ++t) {
    const std::string tl = t < std::size(kTols) ? fmt(kTols[t], "%.0e")
                                                : "default (" + fmt(defaults.tolerance, "%.0e") + ")";
    printf("  tol %s:", tl.c_str());
    for (int k = 0; k < 3; ++k) {
      const std::array<long, 4>& n = solver_count[t][k];
      const long tot = n[0] + n[1] + n[2] + n[3];
      auto pct = [&](long x) { return fmt(tot ? 100.0 * x / tot : NAN, "%.1f %%"); };
      const auto& v = ip_iters[t][k];
      const double mx = v.empty() ? NAN : *std::max_element(v.begin(), v.end());
      fprintf(md, "| %s | %s | %ld | %s | %s | %s | %s | %s / %s |\n", tl.c_str(), cat_names[k],
              tot, pct(n[DCOL_SOLVER_CLOSED_FORM]).c_str(), pct(n[DCOL_SOLVER_RAY_CAST]).c_str(),
              pct(n[DCOL_SOLVER_POLISH]).c_str(),
              (pct(n[DCOL_SOLVER_INTERIOR_POINT]) + " (" +
               std::to_string(n[DCOL_SOLVER_INTERIOR_POINT]) + ")").c_str(),
              fmt(median(v), "%.0f").c_str(), fmt(mx, "%.0f").c_str());
      printf("  %s %s/%s/%s/%s", cat_names[k], pct(n[DCOL_SOLVER_CLOSED_FORM]).c_str(),
             pct(n[DCOL_SOLVER_RAY_CAST]).c_str(), pct(n[DCOL_SOLVER_POLISH]).c_str(),
             pct(n[DCOL_SOLVER_INTERIOR_POINT]).c_str());
    }
    printf("\n");
  }

  // per pair type
  fprintf(md, "\n## Per pair type\n");
  for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
    const Stats ref = stats(*fcl_ref, [p](const Sample& x) { return x.pair == p; });
    const Stats cref =
        coal_ref ? stats(*coal_ref, [p](const Sample& x) { return x.pair == p; }) : Stats{};
    fprintf(md, "\n### %s\n\n| method | median ns | ratio to FCL distance @1e-06 | %smedian error "
                "| max error | wrong / compared |\n|---|--:|--:|%s--:|--:|--:|\n",
            pair_names[p].c_str(), coal_ref ? "ratio to Coal distance (default) | " : "",
            coal_ref ? "--:|" : "");
    for (const Method& m : methods) {
      const Stats s = stats(m, [p](const Sample& x) { return x.pair == p; });
      if (s.n == 0) continue;
      fprintf(md, "| %s | %.0f | %s | %s%s | %s | %s |\n", label(m).c_str(), s.med_ns,
              fmt(s.med_ns / ref.med_ns, "%.2f").c_str(),
              coal_ref ? (fmt(s.med_ns / cref.med_ns, "%.2f") + " | ").c_str() : "",
              fmt(s.med_err, "%.1e").c_str(),
              fmt(s.max_err, "%.1e").c_str(),
              m.boolean ? (std::to_string(s.wrong) + " / " + std::to_string(s.compared)).c_str()
                        : "–");
    }
  }
  fclose(md);
  fclose(csv);
  // DCOL_BENCH_RAW=path: every sample's time (one row per method, case and pair type), for
  // what-if questions about the medians that the tables do not answer
  if (const char* raw_path = std::getenv("DCOL_BENCH_RAW"); raw_path && *raw_path) {
    FILE* raw = fopen(raw_path, "w");
    if (!raw) {
      fprintf(stderr, "cannot write %s\n", raw_path);
      return 1;
    }
    fprintf(raw, "method,tol,pair,category,fcl_pair,ns\n");
    for (const Method& m : methods)
      for (const Sample& x : m.samples)
        fprintf(raw, "\"%s\",%g,%s,%d,%d,%.1f\n", m.name.c_str(), m.tol,
                pair_names[x.pair].c_str(), x.cat, x.fcl_pair ? 1 : 0, x.ns);
    fclose(raw);
  }
  for (const Method& m : methods)
    if (m.failures) printf("%s: %ld failed calls\n", label(m).c_str(), m.failures);
  printf("reference fallbacks: %ld\n", ref_fallbacks);
  printf("%ld cases, %ld failures, %.1f s; wrote %s and %s\n", made, failures, seconds,
         md_path.c_str(), csv_path.c_str());
  return made > 0 ? 0 : 1;
}
