// The scene of cpp_example.cpp, built in a second translation unit.
#ifndef DCOL_CPP_EXAMPLE_SCENE_HPP
#define DCOL_CPP_EXAMPLE_SCENE_HPP

#include <dcol.hpp>

#include <vector>

struct Scene {
  dcol::Shape robot;
  dcol_pose robot_pose;
  std::vector<dcol::Shape> obstacles;
  std::vector<dcol_pose> poses;
};

Scene make_scene();
void print_gradient(const Scene &scene);

#endif
