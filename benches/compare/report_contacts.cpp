// report_contacts.cpp: the section "Contact queries" of benchmark.md: dcol_contacts against
// ODE's dCollide and Bullet's GJK/EPA per pair type (times, ratios, agreement).
#include "bench_common.hpp"

void write_contact_section(FILE* md, const BenchRun& R) {
  const std::vector<Method>& methods = R.methods;
  const std::vector<std::string>& pair_names = R.pair_names;
  const std::vector<bool>& engine_pair_of = R.engine_pair_of;
  const std::vector<int>& ode_pair_of = R.ode_pair_of;
  const auto& agree = R.agree;
  const auto& self_agree = R.self_agree;
  // contact queries: dcol_contacts vs ODE dCollide vs Bullet GJK/EPA, per pair type
  {
    const Method* dc = nullptr;
    const Method* eng[2] = {nullptr, nullptr};
    for (const Method& m : methods)
      if (m.contact) (m.only == 0 ? dc : eng[m.only - 1]) = &m;
    const char* ename[2] = {"ODE", "Bullet"};
    const char* estat[2] = {kOdeStatus, kBulletStatus};
    fprintf(md, "\n## Contact queries: dcol_contacts vs ODE dCollide vs Bullet GJK/EPA\n\n");
    fprintf(md, "%s. %s.\n\n", kOdeStatus, kBulletStatus);
    fprintf(md,
            "On the same cases (the pair types of sphere, box, 12-facet polytope, capsule, "
            "cylinder: the kinds both engines have; ODE only where it has a collider), the same "
            "interleaved timing: `dcol_contacts` with margin 0 and capacity 4 (the manifold, "
            "default tolerance); ODE `dCollide(g1, g2, 4, ...)` with ODE's own geoms (capsule "
            "and cylinder along z, rotated as for FCL; polytope: dCreateConvex from its faces "
            "and planes); Bullet: one `btGjkPairDetector::getClosestPoints` (btVoronoiSimplexSolver, "
            "btGjkEpaPenetrationDepthSolver, maximum distance the sum of the margins as in "
            "btConvexConvexAlgorithm, reported distances > 0 dropped) on btSphereShape, btBoxShape, "
            "btCapsuleShapeX, btCylinderShapeX, btConvexHullShape (margins 0 on box, cylinder, "
            "hull), what btConvexConvexAlgorithm does for one contact point, with btScalar = "
            "float. Shapes are built outside the timed calls. Median ns per pair type; "
            "`all-pairs median`: the median over the pair types of each column (ratios: the "
            "median of the per-pair ratios); min / max: the per-pair extremes.\n\n"
            "Agreement with dcol_contacts, cases with |alpha* - 1| >= 1e-6: contact / no "
            "contact disagreements, and, when both report contact, the deepest point's depth "
            "differing by more than %.0e (max difference in the last columns; the worst case "
            "overall is printed with Coal's signed distance, default request, as a third opinion "
            "when Coal is there). `wrong`: contact against alpha* < 1 (same band). dcol_contacts "
            "calls that returned an error (not converged) are left out of its times and of the "
            "agreement counts (failed calls below).\n\n", kDepthAgree);
    fprintf(md, "| pair | dcol_contacts ns | ODE ns | Bullet ns | dcol / ODE | dcol / Bullet | "
                "ODE contact disagree / checked | ODE depth > 1e-4 / checked | Bullet contact "
                "disagree / checked | Bullet depth > 1e-4 / checked | max depth diff ODE | max "
                "depth diff Bullet | dcol_contacts depth vs dcol_signed_distance > 1e-4 / checked |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    std::vector<double> col[3], rat[2];
    double rmin[2] = {INFINITY, INFINITY}, rmax[2] = {-1, -1};
    std::string pmin[2], pmax[2];
    Agree tot[2];
    for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
      if (!engine_pair_of[p]) continue;
      double v[3];
      for (int k = 0; k < 3; ++k) {
        const Method* m = k == 0 ? dc : eng[k - 1];
        v[k] = m ? stats(*m, [p](const Sample& x) { return x.pair == p; }).med_ns : NAN;
        if (!std::isnan(v[k])) col[k].push_back(v[k]);
      }
      fprintf(md, "| %s | %s | %s | %s |", pair_names[p].c_str(), fmt(v[0], "%.0f").c_str(),
              fmt(v[1], "%.0f").c_str(), fmt(v[2], "%.0f").c_str());
      for (int e = 0; e < 2; ++e) {
        const double r = v[0] / v[e + 1];
        fprintf(md, " %s |", fmt(r, "%.2f").c_str());
        if (std::isnan(r)) continue;
        rat[e].push_back(r);
        if (r < rmin[e]) rmin[e] = r, pmin[e] = pair_names[p];
        if (r > rmax[e]) rmax[e] = r, pmax[e] = pair_names[p];
      }
      for (int e = 0; e < 2; ++e) {
        const Agree& a = agree[e][p];
        if (!eng[e] || a.contact_checked == 0)
          fprintf(md, " – | – |");
        else
          fprintf(md, " %ld / %ld | %ld / %ld |", a.contact_disagree, a.contact_checked,
                  a.depth_disagree, a.depth_checked);
        tot[e].contact_checked += a.contact_checked, tot[e].contact_disagree += a.contact_disagree;
        tot[e].contact_disagree4 += a.contact_disagree4;
        tot[e].sd_checked += a.sd_checked, tot[e].sd_disagree += a.sd_disagree;
        tot[e].depth_checked += a.depth_checked, tot[e].depth_disagree += a.depth_disagree;
        if (a.depth_max > tot[e].depth_max)
          tot[e].depth_max = a.depth_max, tot[e].worst = pair_names[p] + " " + a.worst;
      }
      for (int e = 0; e < 2; ++e)
        fprintf(md, " %s |", eng[e] && agree[e][p].depth_checked
                                 ? fmt(agree[e][p].depth_max, "%.1e").c_str() : "–");
      fprintf(md, " %ld / %ld |\n", self_agree[p].depth_disagree, self_agree[p].depth_checked);
    }
    const double m0 = median(col[0]), m1 = median(col[1]), m2 = median(col[2]);
    fprintf(md, "| **all-pairs median** | **%s** | **%s** | **%s** | **%s** | **%s** |",
            fmt(m0, "%.0f").c_str(), fmt(m1, "%.0f").c_str(), fmt(m2, "%.0f").c_str(),
            fmt(median(rat[0]), "%.2f").c_str(), fmt(median(rat[1]), "%.2f").c_str());
    for (int e = 0; e < 2; ++e)
      fprintf(md, " %ld / %ld | %ld / %ld |", tot[e].contact_disagree, tot[e].contact_checked,
              tot[e].depth_disagree, tot[e].depth_checked);
    Agree self_eng, self_all;
    for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
      for (Agree* t : {&self_all, &self_eng}) {
        if (t == &self_eng && !engine_pair_of[p]) continue;
        t->depth_checked += self_agree[p].depth_checked;
        t->depth_disagree += self_agree[p].depth_disagree;
        if (self_agree[p].depth_max > t->depth_max)
          t->depth_max = self_agree[p].depth_max, t->worst = self_agree[p].worst;
      }
    }
    fprintf(md, " %s | %s | %ld / %ld |\n", fmt(tot[0].depth_max, "%.1e").c_str(),
            fmt(tot[1].depth_max, "%.1e").c_str(), self_eng.depth_disagree, self_eng.depth_checked);
    fprintf(md, "| ratio of the all-pairs medians | | | | %s | %s |\n",
            fmt(m0 / m1, "%.2f").c_str(), fmt(m0 / m2, "%.2f").c_str());
    fprintf(md, "| min / max per-pair ratio | | | | %s (%s) / %s (%s) | %s (%s) / %s (%s) |\n\n",
            fmt(rat[0].empty() ? NAN : rmin[0], "%.2f").c_str(), pmin[0].c_str(),
            fmt(rat[0].empty() ? NAN : rmax[0], "%.2f").c_str(), pmax[0].c_str(),
            fmt(rat[1].empty() ? NAN : rmin[1], "%.2f").c_str(), pmin[1].c_str(),
            fmt(rat[1].empty() ? NAN : rmax[1], "%.2f").c_str(), pmax[1].c_str());
    printf("contact queries (all-pairs medians over the engine pair types, ns): dcol_contacts %s, "
           "ODE %s, Bullet %s\n", fmt(m0, "%.0f").c_str(), fmt(m1, "%.0f").c_str(),
           fmt(m2, "%.0f").c_str());
    printf("  dcol_contacts' deepest depth vs dcol_signed_distance: %ld / %ld differ by more than "
           "%.0e on the engine pair types, %ld / %ld on all 36 (largest %.2e: %s)\n",
           self_eng.depth_disagree, self_eng.depth_checked, kDepthAgree, self_all.depth_disagree,
           self_all.depth_checked, self_all.depth_max, self_all.worst.c_str());
    fprintf(md, "dcol_contacts' deepest depth against dcol_signed_distance on the same case "
                "(untimed): %ld / %ld differ by more than %.0e on these pair types, %ld / %ld on "
                "all 36 (largest %.2e: %s).\n\n", self_eng.depth_disagree,
            self_eng.depth_checked, kDepthAgree, self_all.depth_disagree, self_all.depth_checked,
            self_all.depth_max, self_all.worst.c_str());
    for (int e = 0; e < 2; ++e) {
      if (!eng[e]) {
        printf("  %s\n", estat[e]);
        fprintf(md, "%s: no %s columns.\n\n", estat[e], ename[e]);
        continue;
      }
      printf("  dcol_contacts / %s: median of per-pair ratios %.2f, ratio of medians %.2f, "
             "min %.2f (%s), max %.2f (%s)\n", ename[e], median(rat[e]),
             m0 / (e ? m2 : m1), rmin[e], pmin[e].c_str(), rmax[e], pmax[e].c_str());
      printf("  %s vs dcol_contacts: contact disagreements %ld / %ld (%ld with |alpha*-1| >= 1e-4), "
             "depth > %.0e: %ld / %ld (max %.2e, %s)\n", ename[e], tot[e].contact_disagree,
             tot[e].contact_checked, tot[e].contact_disagree4,
             kDepthAgree, tot[e].depth_disagree, tot[e].depth_checked, tot[e].depth_max,
             tot[e].worst.c_str());
      printf("  %s depth vs dcol_signed_distance: %ld / %ld off by more than %.0e\n", ename[e],
             tot[e].sd_disagree, tot[e].sd_checked, kDepthAgree);
      fprintf(md, "%s depth against dcol_signed_distance (where both dcol_contacts and %s report "
                  "contact and the signed distance converged): %ld / %ld off by more than %.0e.\n\n",
              ename[e], ename[e], tot[e].sd_disagree, tot[e].sd_checked, kDepthAgree);
      fprintf(md, "%s vs dcol_contacts: %ld / %ld contact disagreements (%ld of them with "
                  "|alpha* - 1| >= 1e-4), %ld / %ld depths off by "
                  "more than %.0e (largest %.2e: %s).\n\n", ename[e], tot[e].contact_disagree,
              tot[e].contact_checked, tot[e].contact_disagree4, tot[e].depth_disagree, tot[e].depth_checked, kDepthAgree,
              tot[e].depth_max, tot[e].worst.c_str());
    }
    fprintf(md, "| method | pair types | median ns (all its cases) | wrong / compared | failed "
                "calls |\n|---|--:|--:|--:|--:|\n");
    for (const Method* m : {dc, eng[0], eng[1]}) {
      if (!m) continue;
      const Stats all = stats(*m, [](const Sample&) { return true; });
      const Stats ep = stats(*m, [&](const Sample& x) { return engine_pair_of[x.pair]; });
      fprintf(md, "| %s (engine pair types) | %d | %.0f | %ld / %ld | %ld |\n", m->name.c_str(),
              static_cast<int>(m == eng[0] ? std::count(ode_pair_of.begin(), ode_pair_of.end(), true)
                                           : std::count(engine_pair_of.begin(), engine_pair_of.end(), true)),
              ep.med_ns, ep.wrong, ep.compared, m->failures);
      printf("  %s: %ld / %ld wrong against alpha* < 1\n", m->name.c_str(), ep.wrong, ep.compared);
      if (m == dc)
        fprintf(md, "| %s (all 36 pair types) | 36 | %.0f | %ld / %ld | |\n", m->name.c_str(),
                all.med_ns, all.wrong, all.compared);
    }
    if (eng[0])
      for (int p = 0; p < static_cast<int>(pair_names.size()); ++p)
        if (engine_pair_of[p] && !ode_pair_of[p])
          fprintf(md, "\nODE has no collider for %s: left out of its columns.\n",
                  pair_names[p].c_str());
  }
  printf("%s\n%s\n", kOdeStatus, kBulletStatus);
}
