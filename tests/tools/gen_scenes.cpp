// untangle_gen_scenes OUTDIR: writes every named test scene (except the cow) as OBJ files into
// OUTDIR/<scene>/movable_<i>.obj and OUTDIR/<scene>/obstacle_<i>.obj.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "scenes/scenes.h"

int main(int argc, char** argv) {
  // An option is never taken for OUTDIR (`--help` once wrote every scene into a folder "--help").
  if (argc == 2 && (std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help")) {
    std::printf("usage: untangle_gen_scenes OUTDIR\n");
    return 0;
  }
  if (argc != 2 || argv[1][0] == '-') {
    std::fprintf(stderr, "usage: untangle_gen_scenes OUTDIR\n");
    return 2;
  }
  const std::filesystem::path out = argv[1];
  try {
    for (const untangle::scenes::Scene& scene : untangle::scenes::named_scenes()) {
      const std::filesystem::path dir = out / scene.name;
      std::filesystem::create_directories(dir);
      for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        // Stale meshes of an earlier layout would be read by the tests as part of the scene.
        const std::string file = entry.path().filename().string();
        if (entry.path().extension() == ".obj" &&
            (file.rfind("movable_", 0) == 0 || file.rfind("obstacle_", 0) == 0)) {
          std::filesystem::remove(entry.path());
        }
      }
      untangle::scenes::write_scene_files(scene, dir.string());
      std::size_t triangles = 0;
      for (const untangle::Mesh& m : scene.movable) triangles += m.triangles.size();
      for (const untangle::Mesh& m : scene.obstacles) triangles += m.triangles.size();
      std::fprintf(stderr, "%s: %zu movable, %zu obstacles, %zu triangles\n", scene.name.c_str(),
                   scene.movable.size(), scene.obstacles.size(), triangles);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 4;
  }
  return 0;
}
