// The C++ wrapper of an installed dcol.
#include <dcol.hpp>

#include <cmath>
#include <cstdio>

int main() {
  try {
    const dcol::Shape box = dcol::Shape::box(0.5, 0.5, 0.5);
    const dcol::Shape ball = dcol::Shape::sphere(0.5);
    const dcol_proximity_result r =
        dcol::proximity(box, dcol::pose({0, 0, 0}), ball, dcol::pose({2, 0, 0}));
    std::printf("consumer_cpp (dcol %s): alpha = %.12f\n", dcol::version(), r.alpha);
    return std::fabs(r.alpha - 2.0) < 1e-8 ? 0 : 1;
  } catch (const dcol::Error &e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
