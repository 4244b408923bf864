#include "cpp_example_scene.hpp"

#include <cstdio>
#include <utility>

Scene make_scene() {
  std::vector<dcol::Shape> obstacles;
  obstacles.push_back(dcol::Shape::box(0.5, 0.5, 0.5));
  obstacles.push_back(dcol::Shape::cylinder(0.3, 1.0));
  obstacles.push_back(dcol::Shape::cone(1.0, 0.4));
  obstacles.push_back(dcol::Shape::ellipsoid({{4, 0, 0, 0, 1, 0, 0, 0, 1}}));
  obstacles.push_back(dcol::Shape::polygon({{{1, 0}}, {{0, 1}}, {{-1, 0}}, {{0, -1}}},
                                           {0.5, 0.5, 0.5, 0.5}, 0.05));
  std::vector<dcol_pose> poses = {dcol::pose({2, 0, 0}), dcol::pose({0, 1.2, 0}),
                                  dcol::pose({0, 0, -1.5}, {0.7071, 0, 0.7071, 0}),
                                  dcol::pose({-1, -1, 0}), dcol::pose({0.5, 0.5, 0.5})};
  return Scene{dcol::Shape::capsule(0.3, 1.0), dcol::pose({0, 0, 0}), std::move(obstacles),
               std::move(poses)};
}

void print_gradient(const Scene &scene) {
  try {
    const dcol::Gradient g =
        dcol::gradient(scene.robot, scene.robot_pose, scene.obstacles[0], scene.poses[0]);
    std::printf("d alpha / d r2 = [%.6f, %.6f, %.6f]\n", g.gradient[7], g.gradient[8],
                g.gradient[9]);
  } catch (const dcol::Error &e) {
    std::printf("no gradient: %s\n", e.what());
  }
}
