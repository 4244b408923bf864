// The ODE user geom class wrapping dcol shapes: see dcol_ode.hpp.
#include "dcol_ode.hpp"

#include <cmath>
#include <cstdio>

namespace dcol_ode {
namespace {

struct GeomData {
  const dcol_shape *shape;
  double radius;
};

int g_class = -1;
unsigned long g_calls = 0;
// ODE's planes as a dcol half-space of depth 1 (made once by init(), never freed: it lives as long
// as the geom class).
dcol_shape *g_halfspace = nullptr;

GeomData *data(dGeomID g) { return static_cast<GeomData *>(dGeomGetClassData(g)); }

dcol_pose pose_of(dGeomID g) {
  const dReal *p = dGeomGetPosition(g);
  dQuaternion q;
  dGeomGetQuaternion(g, q);  // ODE quaternions are (w, x, y, z), like dcol's
  dcol_pose out;
  for (int i = 0; i < 3; ++i) out.position[i] = p[i];
  for (int i = 0; i < 4; ++i) out.quaternion[i] = q[i];
  return out;
}

// Writes dcol's contacts (shape 1 = o1) as ODE contact geoms: ODE's normal points into o1.
int write_contacts(dGeomID o1, dGeomID o2, const dcol_contact *cs, std::size_t n, dContactGeom *contact,
                   int skip) {
  int written = 0;
  for (std::size_t i = 0; i < n; ++i) {
    dContactGeom *c = reinterpret_cast<dContactGeom *>(reinterpret_cast<char *>(contact) + written * skip);
    for (int k = 0; k < 3; ++k) {
      c->pos[k] = cs[i].position[k];
      c->normal[k] = -cs[i].normal[k];
    }
    c->depth = cs[i].depth;
    c->g1 = o1;
    c->g2 = o2;
    c->side1 = -1;
    c->side2 = -1;
    ++written;
  }
  return written;
}

std::size_t max_contacts(int flags) {
  std::size_t n = static_cast<std::size_t>(flags & 0xffff);
  if (n == 0) n = 1;
  return n < DCOL_MAX_CONTACTS ? n : DCOL_MAX_CONTACTS;
}

int collide_dcol(dGeomID o1, dGeomID o2, int flags, dContactGeom *contact, int skip) {
  ++g_calls;
  const dcol_pose p1 = pose_of(o1);
  const dcol_pose p2 = pose_of(o2);
  dcol_contact cs[DCOL_MAX_CONTACTS];
  std::size_t n = 0;
  const dcol_status st =
      dcol_contacts(data(o1)->shape, &p1, data(o2)->shape, &p2, 0.0, nullptr, cs, max_contacts(flags), &n);
  if (st != DCOL_OK && st != DCOL_ERROR_NOT_CONVERGED) {
    std::fprintf(stderr, "dcol_ode: %s\n", dcol_last_error_message());
    return 0;
  }
  return write_contacts(o1, o2, cs, n, contact, skip);
}

// The plane a·x = d (solid below, normal (a, b, c) out of it) as the dcol half-space of depth 1
// whose boundary is the plane: origin at the foot of the shape's centre on the plane, one unit
// below it, attitude turning e_z to the normal.
int collide_plane(dGeomID o1, dGeomID o2, int flags, dContactGeom *contact, int skip) {
  ++g_calls;
  dVector4 plane;
  dGeomPlaneGetParams(o2, plane);
  const dcol_pose p1 = pose_of(o1);
  const double r = data(o1)->radius;
  const double n[3] = {plane[0], plane[1], plane[2]};
  const double h = n[0] * p1.position[0] + n[1] * p1.position[1] + n[2] * p1.position[2] - plane[3];
  if (h > r) return 0;
  if (!g_halfspace) return 0;
  dcol_pose pb;
  for (int k = 0; k < 3; ++k) pb.position[k] = p1.position[k] - (h + 1.0) * n[k];
  // q = (1 + ez.n, ez x n) normalised; ez x n = (-n_y, n_x, 0).
  double w = 1.0 + n[2], x = -n[1], y = n[0], z = 0.0;
  if (w < 1e-12) {
    w = 0.0;
    x = 1.0;
    y = 0.0;
  }
  const double len = std::sqrt(w * w + x * x + y * y + z * z);
  pb.quaternion[0] = w / len;
  pb.quaternion[1] = x / len;
  pb.quaternion[2] = y / len;
  pb.quaternion[3] = z / len;
  dcol_contact cs[DCOL_MAX_CONTACTS];
  std::size_t count = 0;
  // Shape 1 = the plane's half-space, shape 2 = o1: dcol's normal points from the plane to o1,
  // i.e. into o1, which is ODE's convention for (o1, plane): write it unchanged.
  const dcol_status st = dcol_contacts(g_halfspace, &pb, data(o1)->shape, &p1, 0.0, nullptr, cs, max_contacts(flags), &count);
  if (st != DCOL_OK && st != DCOL_ERROR_NOT_CONVERGED) return 0;
  int written = write_contacts(o1, o2, cs, count, contact, skip);
  for (int i = 0; i < written; ++i) {
    dContactGeom *c = reinterpret_cast<dContactGeom *>(reinterpret_cast<char *>(contact) + i * skip);
    for (int k = 0; k < 3; ++k) c->normal[k] = -c->normal[k];
  }
  return written;
}

dColliderFn *get_collider(int num) {
  if (num == g_class) return &collide_dcol;
  if (num == dPlaneClass) return &collide_plane;
  return nullptr;
}

void aabb(dGeomID g, dReal box[6]) {
  const dReal *p = dGeomGetPosition(g);
  const double r = data(g)->radius;
  for (int i = 0; i < 3; ++i) {
    box[2 * i] = p[i] - r;
    box[2 * i + 1] = p[i] + r;
  }
}

void dtor(dGeomID) {}

}  // namespace

int init() {
  if (g_class < 0) {
    dGeomClass c;
    c.bytes = sizeof(GeomData);
    c.collider = &get_collider;
    c.aabb = &aabb;
    c.aabb_test = nullptr;
    c.dtor = &dtor;
    g_class = dCreateGeomClass(&c);
    if (dcol_shape_new_halfspace(1.0, &g_halfspace) != DCOL_OK) g_halfspace = nullptr;
  }
  return g_class;
}

int geom_class() { return g_class; }

dGeomID create_geom(dSpaceID space, const dcol_shape *shape, double radius) {
  dGeomID g = dCreateGeom(init());
  GeomData *d = data(g);
  d->shape = shape;
  d->radius = radius;
  if (space) dSpaceAdd(space, g);
  return g;
}

const dcol_shape *geom_shape(dGeomID geom) { return data(geom)->shape; }

unsigned long collider_calls() { return g_calls; }

}  // namespace dcol_ode
