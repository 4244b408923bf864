// dcol from C++ through the header-only wrapper include/dcol.hpp. This program is built from two
// translation units (this file and cpp_example_scene.cpp) that both include dcol.hpp, which
// checks that the header links cleanly when included more than once.
#include <dcol.hpp>

#include <cstdio>

#include "cpp_example_scene.hpp"

int main() {
  try {
    const Scene scene = make_scene();
    for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
      const dcol_proximity_result r =
          dcol::proximity(scene.robot, scene.robot_pose, scene.obstacles[i], scene.poses[i]);
      std::printf("obstacle %zu: alpha = %.9f (%s)\n", i, r.alpha,
                  r.alpha > 1.0 ? "clear" : "collision");
    }
    print_gradient(scene);

    // Every pair of bodies with alpha <= 1.5 at once, with a scene (it copies the shapes).
    dcol::Scene world;
    world.add(scene.robot, scene.robot_pose);
    for (std::size_t i = 0; i < scene.obstacles.size(); ++i) world.add(scene.obstacles[i], scene.poses[i]);
    for (const dcol_scene_pair &p : world.pairs_within(1.5))
      std::printf("bodies %zu and %zu: alpha = %.6f\n", p.body1, p.body2, p.proximity.alpha);

    // Errors become exceptions that carry the status and the message.
    try {
      dcol::Shape::sphere(-1.0);
      std::printf("a negative radius was accepted\n");
      return 1;
    } catch (const dcol::Error &e) {
      std::printf("expected error (status %d): %s\n", static_cast<int>(e.status()), e.what());
    }
    return 0;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
