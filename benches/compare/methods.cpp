// methods.cpp: the methods bench_compare times, as closures over the current case (CaseCtx):
// dcol's queries at their tolerances, FCL's and Coal's distance and collide, the contact
// queries (dcol_contacts, ODE, Bullet) and libccd's GJK / MPR.
#include "bench_common.hpp"

void add_methods(std::vector<Method>& methods, CaseCtx& ctx) {
  // references to ctx's members: the closures capture them by reference, i.e. ctx's objects
  DCOL_BENCH_CASE_REFS(ctx);
  auto prox_with = [&](double tol) {
    return [&, tol](double* v) {
      dcol_options o = dcol_options_default();
      o.tolerance = tol;
      dcol_proximity_result r;
      bool ok = dcol_proximity(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &r) ==
                DCOL_OK;
      *v = r.alpha;
      return ok;
    };
  };
  auto dist_with = [&](double tol) {
    return [&, tol](double* v) {
      dcol_options o = dcol_options_default();
      o.tolerance = tol;
      dcol_distance_result r;
      bool ok = dcol_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &r) ==
                DCOL_OK;
      *v = r.distance;
      return ok;
    };
  };
  for (double t : kTols) methods.push_back({"dcol_proximity", t, false, false, prox_with(t), {}, 0});
  methods.push_back({"dcol_proximity (default tol)", 0, false, false, [&](double* v) {
                       dcol_proximity_result r;
                       bool ok = dcol_proximity(c.s1.handle, &c.b1.pose, c.s2.handle,
                                                &c.b2.pose, &defaults, &r) == DCOL_OK;
                       *v = r.alpha;
                       return ok;
                     }, {}, 0});
  methods.push_back({"dcol_gradient (default tol)", 0, false, false, [&](double* v) {
                       dcol_proximity_result r;
                       double g[14];
                       bool ok = dcol_gradient(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                               &defaults, &r, g) == DCOL_OK;
                       *v = r.alpha;
                       return ok;
                     }, {}, 0});
  methods.push_back({"dcol_jacobian (default tol)", 0, false, false, [&](double* v) {
                       dcol_proximity_result r;
                       double j[56];
                       bool ok = dcol_jacobian(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                               &defaults, &r, j) == DCOL_OK;
                       *v = r.alpha;
                       return ok;
                     }, {}, 0});
  methods.push_back({"dcol_distance (default tol)", 0, false, false, [&](double* v) {
                       dcol_distance_result r;
                       bool ok = dcol_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                               &defaults, &r) == DCOL_OK;
                       *v = r.distance;
                       return ok;
                     }, {}, 0});
  for (double t : kTols) methods.push_back({"dcol_distance", t, false, false, dist_with(t), {}, 0});
  // signed distance: timed on every case; its time on the overlapping cases is compared with
  // coal::distance's (default request: EPA) in the penetration-depth section
  methods.push_back({"dcol_signed_distance (default tol)", 0, false, false, [&](double* v) {
                       dcol_signed_distance_result r;
                       bool ok = dcol_signed_distance(c.s1.handle, &c.b1.pose, c.s2.handle,
                                                      &c.b2.pose, &defaults, &r) == DCOL_OK;
                       *v = r.distance;
                       return ok;
                     }, {}, 0});
  methods.push_back({"dcol_intersect (default tol)", 0, false, true, [&](double* v) {
                       int32_t hit = 0;
                       bool ok = dcol_intersect(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                                &defaults, &hit) == DCOL_OK;
                       *v = hit ? 1 : 0;
                       return ok;
                     }, {}, 0});
  for (double t : kFclTols)
    methods.push_back({"fcl::distance", t, true, false, [&, t](double* v) {
                         fcl::DistanceRequestd req;
                         req.gjk_solver_type = fcl::GST_LIBCCD;
                         req.distance_tolerance = t;
                         fcl::DistanceResultd res;
                         fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req, res);
                         *v = std::max(0.0, res.min_distance);
                         return true;
                       }, {}, 0});
  methods.push_back({"fcl::collide (default)", 0, true, true, [&](double* v) {
                       fcl::CollisionRequestd req;
                       req.gjk_solver_type = fcl::GST_LIBCCD;
                       fcl::CollisionResultd res;
                       fcl::collide(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req, res);
                       *v = res.isCollision() ? 1 : 0;
                       return true;
                     }, {}, 0});
#ifdef DCOL_BENCH_HAVE_COAL
  // Coal: default requests (signed distance, EPA on overlap; collide with contact = EPA), the
  // distance at gjk_tolerance 1e-2 ... 1e-12; the values are the raw signed distances (errors
  // are taken on max(0, d) on separated cases, as for FCL).
  for (double t : kCoalTols) {
    methods.push_back({"coal::distance", t, true, false, [&, t](double* v) {
                         coal::DistanceRequest req;
                         req.gjk_tolerance = t;
                         coal::DistanceResult res;
                         *v = coal::distance(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
                         return true;
                       }, {}, 0});
    methods.back().agree_tol = t;
  }
  methods.push_back({"coal::ComputeDistance (default)", 0, true, false, [&](double* v) {
                       coal::DistanceRequest req;
                       coal::DistanceResult res;
                       *v = (*coal_dist_functor)(g1.tf, g2.tf, req, res);
                       return true;
                     }, {}, 0});
  methods.back().agree_tol = kCoalAgree;
  methods.push_back({"coal::collide (default)", 0, true, true, [&](double* v) {
                       coal::CollisionRequest req;
                       coal::CollisionResult res;
                       coal::collide(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
                       *v = res.isCollision() ? 1 : 0;
                       return true;
                     }, {}, 0});
  methods.push_back({"coal::collide (no contact)", 0, true, true, [&](double* v) {
                       coal::CollisionRequest req(coal::NO_REQUEST, 1);
                       coal::CollisionResult res;
                       coal::collide(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
                       *v = res.isCollision() ? 1 : 0;
                       return true;
                     }, {}, 0});
#endif
  // contact queries: dcol_contacts (margin 0, capacity 4) on every pair type; ODE's dCollide
  // (4 contacts) and Bullet's GJK/EPA (one point) on the pair types of sphere, box, polytope,
  // capsule, cylinder. Value: the deepest depth (> 0 penetrating), kNoContact when none.
  methods.push_back({"dcol_contacts (margin 0, capacity 4)", 0, false, false, [&](double* v) {
                       dcol_contact cs[4];
                       size_t n = 0;
                       const dcol_status st = dcol_contacts(c.s1.handle, &c.b1.pose, c.s2.handle,
                                                            &c.b2.pose, 0.0, &defaults, cs, 4, &n);
                       *v = kNoContact;
                       for (size_t k = 0; k < n; ++k) *v = std::max(*v, cs[k].depth);
                       return st == DCOL_OK;
                     }, {}, 0});
  methods.back().contact = true;
#ifdef DCOL_BENCH_HAVE_ODE
  methods.push_back({"ODE dCollide (4 contacts)", 0, false, false, [&](double* v) {
                       dContactGeom cg[4];
                       const int n = dCollide(o1->geom, o2->geom, 4, cg, sizeof(dContactGeom));
                       *v = kNoContact;
                       for (int k = 0; k < n; ++k) *v = std::max(*v, static_cast<double>(cg[k].depth));
                       return true;
                     }, {}, 0});
  methods.back().contact = true;
  methods.back().only = 1;
#endif
#ifdef DCOL_BENCH_HAVE_BULLET
  methods.push_back({"Bullet GJK/EPA (1 point)", 0, false, false, [&](double* v) {
                       BulletContact res;
                       bullet_contact(*u1, *u2, res);
                       *v = res.hit ? -static_cast<double>(res.depth) : kNoContact;
                       return true;
                     }, {}, 0});
  methods.back().contact = true;
  methods.back().only = 2;
#endif
  CCD_INIT(&ccd);
  ccd.support1 = support_fn;
  ccd.support2 = support_fn;
  ccd.center1 = center_fn;
  ccd.center2 = center_fn;
  methods.push_back({"ccdGJKIntersect", 0, false, true, [&](double* v) {
                       *v = ccdGJKIntersect(&c.b1, &c.b2, &ccd) ? 1 : 0;
                       return true;
                     }, {}, 0});
  methods.push_back({"ccdMPRIntersect", 0, false, true, [&](double* v) {
                       *v = ccdMPRIntersect(&c.b1, &c.b2, &ccd) ? 1 : 0;
                       return true;
                     }, {}, 0});
  methods.push_back({"ccdMPRPenetration", 0, false, true, [&](double* v) {
                       ccd_real_t depth;
                       ccd_vec3_t dir, pos;
                       *v = ccdMPRPenetration(&c.b1, &c.b2, &ccd, &depth, &dir, &pos) == 0 ? 1
                                                                                           : 0;
                       return true;
                     }, {}, 0});
}
