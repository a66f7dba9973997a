// `untangle simulate` (simulate.h): the example scenes, the frame files, the report.
#include "simulate.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "output_plan.h"
#include "scenes/random_tangles.h"
#include "scenes/scenes.h"
#include "scenes/sim_examples.h"
#include "untangle/error.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"
#include "untangle/render.h"
#include "untangle/report.h"
#include "untangle/write_meshes.h"

namespace untangle::app {
namespace {

namespace fs = std::filesystem;

// A frame with an edge longer than this many times its rest length is not clean.
constexpr double kMaxStretch = 2.0;

std::string frame_path(const fs::path& dir, const std::string& stem, int frame) {
  char digits[16];
  std::snprintf(digits, sizeof digits, "%04d", frame);
  return (dir / (stem + "_" + digits + ".obj")).string();
}

// DIR/frame_<frame>.png, the picture of a saved frame (--preview).
std::string frame_png(const std::string& dir, int frame) {
  std::string path = frame_path(dir, "frame", frame);
  return path.replace(path.size() - 4, 4, ".png");
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ExitCode::kUnreadableInput, path, "cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// One input file of the scene: its meshes (indices into the scene) are written together.
struct SceneInput {
  std::string path;
  std::string stem;  // the frames' name: DIR/<stem>_<frame>.obj
  Role role = Role::kMovable;
  std::vector<std::size_t> meshes;
};

// The numbers and counts of ClothOptions a scene file's `cloth` object names (gravity and the
// contact switches aside): read by load_scene_file, written by example_scene_file, in this order.
const std::pair<const char*, double ClothOptions::*> kClothNumbers[] = {
    {"time_step", &ClothOptions::time_step},     {"stretch", &ClothOptions::stretch},
    {"bend", &ClothOptions::bend},               {"damping", &ClothOptions::damping},
    {"density", &ClothOptions::density},         {"friction", &ClothOptions::friction},
    {"restitution", &ClothOptions::restitution}, {"max_speed", &ClothOptions::max_speed},
    {"contact_reach", &ClothOptions::contact_reach}, {"thickness", &ClothOptions::thickness}};
const std::pair<const char*, int ClothOptions::*> kClothCounts[] = {
    {"substeps", &ClothOptions::substeps}, {"solver_iterations", &ClothOptions::solver_iterations}};

// The scene file of an example (SCENE FILES OF SIMULATE), its meshes at `inputs` (one file each,
// beside it): every key load_scene_file reads, with the example's values, so that running it
// gives the example's frames byte for byte and a user has every parameter in front of them.
nlohmann::ordered_json example_scene_file(const SimulationScene& scene,
                                          const std::vector<SceneInput>& inputs, int frames) {
  const ClothOptions& c = scene.options;
  nlohmann::ordered_json meshes = nlohmann::ordered_json::array();
  for (const SceneInput& input : inputs) {
    nlohmann::ordered_json m;
    m["path"] = fs::path(input.path).filename().string();
    m["role"] = input.role == Role::kObstacle ? "obstacle" : "cloth";
    const std::size_t index = input.meshes[0];
    if (index < scene.pins.size()) {
      nlohmann::ordered_json pins = nlohmann::ordered_json::array();
      for (std::size_t v = 0; v < scene.pins[index].size(); ++v)
        if (scene.pins[index][v]) pins.push_back(v);
      if (!pins.empty()) m["pins"] = pins;
    }
    for (const ObstacleSchedule& s : scene.schedules)
      if (s.mesh == index)
        m["schedule"] = {{"from", s.from},
                         {"frames", s.frames},
                         {"centre", {s.centre[0], s.centre[1], s.centre[2]}}};
    meshes.push_back(m);
  }
  nlohmann::ordered_json j;
  j["meshes"] = meshes;
  j["frames"] = frames;
  j["clearance"] = c.fix.clearance;
  j["relax_sweeps"] = c.fix.relax_sweeps;
  nlohmann::ordered_json cloth;
  cloth["gravity"] = {c.gravity[0], c.gravity[1], c.gravity[2]};
  cloth["contacts"] = c.contacts;
  cloth["self_contacts"] = c.self_contacts;
  for (const auto& [name, member] : kClothCounts) cloth[name] = c.*member;
  for (const auto& [name, member] : kClothNumbers) cloth[name] = c.*member;
  j["cloth"] = cloth;
  return j;
}

[[noreturn]] void bad_key(const std::string& file, const std::string& key, const std::string& why) {
  throw Error(ExitCode::kUnreadableInput, file, "'" + key + "': " + why);
}

// Reads SCENE.json (docs: man page, SIMULATE SCENE FILES). Paths are relative to its folder.
SimulationScene load_scene_file(const std::string& file, std::vector<SceneInput>& inputs,
                                int& frames) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(read_text_file(file));
  } catch (const nlohmann::json::exception& e) {
    throw Error(ExitCode::kUnreadableInput, file, std::string("not a JSON scene: ") + e.what());
  }
  if (!j.is_object()) throw Error(ExitCode::kUnreadableInput, file, "a scene is a JSON object");
  auto number = [&](const nlohmann::json& v, const std::string& key) {
    if (!v.is_number()) bad_key(file, key, "must be a number");
    return v.get<double>();
  };
  auto vec3 = [&](const nlohmann::json& v, const std::string& key) {
    if (!v.is_array() || v.size() != 3) bad_key(file, key, "must be an array of 3 numbers");
    return Vec3{number(v[0], key), number(v[1], key), number(v[2], key)};
  };
  SimulationScene scene;
  const fs::path base = fs::path(file).parent_path();
  for (const auto& [key, value] : j.items()) {
    if (key == "meshes" || key == "frames" || key == "cloth" || key == "clearance" ||
        key == "relax_sweeps")
      continue;
    bad_key(file, key, "unknown key (meshes, frames, cloth, clearance, relax_sweeps)");
  }
  if (j.contains("frames")) {
    const double f = number(j["frames"], "frames");
    if (!(f >= 1.0) || f != std::floor(f) || f > 1e7)
      bad_key(file, "frames", "must be a positive integer");
    frames = static_cast<int>(f);
  }
  if (j.contains("clearance")) scene.options.fix.clearance = number(j["clearance"], "clearance");
  if (j.contains("relax_sweeps")) {
    const double n = number(j["relax_sweeps"], "relax_sweeps");
    if (!(n >= 0.0) || n != std::floor(n) || n > 1000.0)  // fix --relax-sweeps's range
      bad_key(file, "relax_sweeps", "must be an integer from 0 to 1000");
    scene.options.fix.relax_sweeps = static_cast<int>(n);
  }
  if (j.contains("cloth")) {
    const nlohmann::json& c = j["cloth"];
    if (!c.is_object()) bad_key(file, "cloth", "must be an object");
    ClothOptions& o = scene.options;
    // Every number of ClothOptions by its name; substeps and solver_iterations are counts.
    std::map<std::string, double*> numbers;
    std::map<std::string, int*> counts;
    for (const auto& [name, member] : kClothNumbers) numbers[name] = &(o.*member);
    for (const auto& [name, member] : kClothCounts) counts[name] = &(o.*member);
    for (const auto& [key, value] : c.items()) {
      const std::string name = "cloth." + key;
      if (key == "gravity") {
        o.gravity = vec3(value, name);
      } else if (key == "contacts") {
        if (!value.is_boolean()) bad_key(file, name, "must be true or false");
        o.contacts = value.get<bool>();
      } else if (key == "self_contacts") {
        if (!value.is_boolean()) bad_key(file, name, "must be true or false");
        o.self_contacts = value.get<bool>();
      } else if (const auto n = numbers.find(key); n != numbers.end()) {
        *n->second = number(value, name);
      } else if (const auto k = counts.find(key); k != counts.end()) {
        const double count = number(value, name);
        if (!(count >= 1.0 && count <= 1000.0) || count != std::floor(count))
          bad_key(file, name, "must be an integer from 1 to 1000");
        *k->second = static_cast<int>(count);
      } else {
        bad_key(file, name, "unknown key");
      }
    }
  }
  if (!j.contains("meshes") || !j["meshes"].is_array() || j["meshes"].empty())
    bad_key(file, "meshes", "must be a non-empty array");
  for (std::size_t k = 0; k < j["meshes"].size(); ++k) {
    const nlohmann::json& m = j["meshes"][k];
    const std::string at = "meshes[" + std::to_string(k) + "]";
    if (!m.is_object() || !m.contains("path") || !m["path"].is_string())
      bad_key(file, at + ".path", "every mesh needs a path");
    SceneInput input;
    const fs::path path = base / m["path"].get<std::string>();
    input.path = path.string();
    input.stem = path.stem().string();
    const std::string role = m.value("role", std::string("cloth"));
    if (role == "cloth")
      input.role = Role::kMovable;
    else if (role == "obstacle")
      input.role = Role::kObstacle;
    else
      bad_key(file, at + ".role", "must be cloth or obstacle");
    for (const auto& [key, value] : m.items())
      if (key != "path" && key != "role" && key != "pins" && key != "schedule")
        bad_key(file, at + "." + key, "unknown key (path, role, pins, schedule)");
    std::vector<Mesh> read = read_meshes(input.path, input.role);
    for (Mesh& mesh : read) {
      input.meshes.push_back(scene.meshes.size());
      scene.meshes.push_back(std::move(mesh));
    }
    if (m.contains("pins")) {
      if (input.role != Role::kMovable) bad_key(file, at + ".pins", "only cloth is pinned");
      if (!m["pins"].is_array()) bad_key(file, at + ".pins", "must be an array of vertex indices");
      // Vertex indices count through the file's meshes in order (as --pin does).
      scene.pins.resize(scene.meshes.size());
      for (const nlohmann::json& v : m["pins"]) {
        const double index = number(v, at + ".pins");
        std::size_t rest = static_cast<std::size_t>(index);
        bool placed = false;
        for (std::size_t mi : input.meshes) {
          const std::size_t n = scene.meshes[mi].positions.size();
          if (rest < n) {
            scene.pins[mi].resize(n, 0);
            scene.pins[mi][rest] = 1;
            placed = true;
            break;
          }
          rest -= n;
        }
        if (!(index >= 0.0) || index != std::floor(index) || !placed)
          bad_key(file, at + ".pins", "vertex index out of range");
      }
    }
    if (m.contains("schedule")) {
      const nlohmann::json& sc = m["schedule"];
      if (input.role != Role::kObstacle)
        bad_key(file, at + ".schedule", "only obstacles follow a schedule");
      if (!sc.is_object()) bad_key(file, at + ".schedule", "must be an object");
      for (const auto& [key, value] : sc.items())
        if (key != "from" && key != "frames" && key != "centre")
          bad_key(file, at + ".schedule." + key, "unknown key (from, frames, centre)");
      for (std::size_t mi : input.meshes) {
        ObstacleSchedule schedule;
        schedule.mesh = mi;
        schedule.from = number(sc.value("from", nlohmann::json(1.0)), at + ".schedule.from");
        schedule.frames = static_cast<int>(
            number(sc.value("frames", nlohmann::json(0)), at + ".schedule.frames"));
        if (!(schedule.from > 0.0)) bad_key(file, at + ".schedule.from", "must be positive");
        if (sc.contains("centre")) {
          schedule.centre = vec3(sc["centre"], at + ".schedule.centre");
        } else {  // the centre of the file's bounding box
          Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
          for (std::size_t mj : input.meshes)
            for (const Vec3& p : scene.meshes[mj].positions)
              for (int c = 0; c < 3; ++c) {
                lo[c] = std::min(lo[c], p[c]);
                hi[c] = std::max(hi[c], p[c]);
              }
          for (int c = 0; c < 3; ++c) schedule.centre[c] = 0.5 * (lo[c] + hi[c]);
        }
        scene.schedules.push_back(schedule);
      }
    }
    inputs.push_back(std::move(input));
  }
  return scene;
}

}  // namespace

int run_simulate(const SimulateOptions& o) {
  if (o.scene_file.empty() == o.example.empty())
    throw Error(ExitCode::kUsage, "", "simulate takes a scene file or --example, one of them");
  std::vector<SceneInput> inputs;
  int frames = o.frames;
  int scene_frames = 0;
  SimulationScene scene = o.scene_file.empty()
                              ? scenes::simulation_example(o.example)
                              : load_scene_file(o.scene_file, inputs, scene_frames);
  if (!o.frames_given && scene_frames > 0) frames = scene_frames;
  scene.options.fix.threads = o.threads;
  const fs::path dir = o.output_dir;
  const bool example = o.scene_file.empty();
  // An example's start is written first, one file per mesh: the frames are rewritten from it.
  if (example)
    for (std::size_t m = 0; m < scene.meshes.size(); ++m)
      inputs.push_back({(dir / (scene.meshes[m].name + ".obj")).string(),
                        scene.meshes[m].name,
                        scene.meshes[m].role,
                        {m}});
  std::vector<int> saved;  // the frames written
  for (int f = 1; f <= frames; ++f)
    if (f % o.save_every == 0 || f == frames) saved.push_back(f);
  std::vector<int> sheet_frames;  // those on the contact sheet: up to six, spread evenly
  if (!o.preview.empty()) {
    const std::size_t count = std::min<std::size_t>(6, saved.size());
    for (std::size_t k = 0; k < count; ++k)
      sheet_frames.push_back(saved[(k + 1) * saved.size() / count - 1]);
  }
  // Every file the run reads and writes, checked before any work like every command's
  // (output_plan.h): frames and their side files, pictures, the report.
  std::vector<PlannedFile> read, written;
  if (!example) {
    read.push_back({o.scene_file, "the scene file " + o.scene_file});
    for (const SceneInput& input : inputs) add_read(input.path, "the scene's mesh", read);
  } else {
    for (const SceneInput& input : inputs)
      written.push_back({input.path, "the start " + input.path});
    written.push_back({(dir / "scene.json").string(), "the example's scene file"});
  }
  for (int f : saved)
    for (const SceneInput& input : inputs) {
      if (input.role != Role::kMovable) continue;
      const std::string path = frame_path(dir, input.stem, f);
      written.push_back({path, "frame " + path});
      for (const std::string& side : side_files_of_output(input.path, path))
        written.push_back({side, "side file " + side + " of frame " + path});
    }
  if (!o.preview.empty()) {
    for (int f : saved)
      written.push_back({frame_png(o.preview, f), "picture " + frame_png(o.preview, f)});
    const std::string sheet_path = (fs::path(o.preview) / "contact_sheet.png").string();
    written.push_back({sheet_path, "picture " + sheet_path});
  }
  if (!o.report.empty() && o.report != "-") written.push_back({o.report, "--report " + o.report});
  // The output folder is made for the check (its files must lie in a folder) and removed again
  // when the check refuses the run.
  std::error_code ec;
  const bool made = !fs::exists(dir, ec) && fs::create_directories(dir, ec);
  try {
    if (ec || !fs::is_directory(dir, ec))
      throw Error(ExitCode::kOutputNotWritten, o.output_dir, "cannot create the output folder");
    check_planned(read, written, o.overwrite);
  } catch (...) {
    if (made) fs::remove(dir, ec);
    throw;
  }

  if (example) {
    for (const SceneInput& input : inputs)
      scenes::write_obj(scene.meshes[input.meshes[0]], input.path);
    write_text_file_atomically((dir / "scene.json").string(),
                               example_scene_file(scene, inputs, frames).dump(2) + "\n");
  }

  nlohmann::ordered_json report;
  // 2: options.contacts and options.contact_reach replace hold_contacts and release_distance.
  // 3: options.relax_sweeps.
  // 4: options.self_contacts and each frame's self_planes.
  // 5: options.thickness.
  report["schema_version"] = 5;
  report["command"] = "simulate";
  report["untangle_version"] = UNTANGLE_VERSION;
  if (example)
    report["example"] = o.example;
  else
    report["scene"] = o.scene_file;
  const ClothOptions& c = scene.options;
  report["options"] = {{"frames", frames},
                       {"time_step", c.time_step},
                       {"substeps", c.substeps},
                       {"solver_iterations", c.solver_iterations},
                       {"stretch", c.stretch},
                       {"bend", c.bend},
                       {"damping", c.damping},
                       {"friction", c.friction},
                       {"max_speed", c.max_speed},
                       {"contacts", c.contacts},
                       {"self_contacts", c.self_contacts},
                       {"contact_reach", c.contact_reach},
                       {"thickness", c.thickness},
                       {"clearance", c.fix.clearance},
                       {"relax_sweeps", c.fix.relax_sweeps}};
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  const std::vector<Mesh> start_meshes = scene.meshes;
  RenderCamera camera;
  bool camera_set = false;
  RgbImage sheet;
  Simulation sim(std::move(scene));
  const bool progress = !o.quiet && isatty(STDERR_FILENO);
  std::size_t bad_frames = 0, overstretched = 0;
  double integrate_ms = 0.0, detect_ms = 0.0, correct_ms = 0.0;
  for (int f = 1; f <= frames; ++f) {
    const FrameRecord r = sim.advance();
    integrate_ms += r.integrate_ms;
    detect_ms += r.detect_ms;
    correct_ms += r.correct_ms;
    nlohmann::ordered_json row = {{"frame", r.frame},
                                  {"crossings_before", r.crossings_before},
                                  {"crossings_after", r.crossings_after},
                                  {"correction_iterations", r.correction_iterations},
                                  {"corrected_steps", r.corrected_steps},
                                  {"uncorrected_steps", r.uncorrected_steps},
                                  {"kinetic_energy", r.kinetic_energy},
                                  {"max_stretch", r.max_stretch},
                                  {"self_planes", r.self_planes}};
    if (std::binary_search(saved.begin(), saved.end(), f)) {
      // Written, then read back with the obstacles at this frame: the written file is the truth.
      std::vector<Mesh> written;
      for (const Mesh& mesh : sim.meshes())
        if (mesh.role == Role::kObstacle) written.push_back(mesh);
      for (const SceneInput& input : inputs) {
        if (input.role != Role::kMovable) continue;
        const std::string path = frame_path(dir, input.stem, f);
        std::vector<const Mesh*> of_file;
        for (std::size_t m : input.meshes) of_file.push_back(&sim.meshes()[m]);
        write_meshes(input.path, path, of_file);
        for (Mesh& back : read_meshes(path, Role::kMovable)) written.push_back(std::move(back));
      }
      DetectOptions detect;
      detect.threads = o.threads;
      detect.skip_obstacle_pairs = true;
      const IntersectionCounts found = find_intersections(written, detect).counts;
      const std::size_t crossings = found.crossings;
      row["written_crossings"] = crossings;
      row["written_inside_vertices"] = found.inside_vertices;
      if (crossings > 0 || found.inside_vertices > 0) ++bad_frames;
      if (!o.preview.empty()) {
        // One camera for the whole run, fitted to the start.
        if (!camera_set) {
          camera = fit_camera({&start_meshes}, RenderView::kFront, 400, 400);
          camera_set = true;
        }
        RenderMarks marks;
        marks.legend = {"frame " + std::to_string(f) + ": " + std::to_string(crossings) +
                        " crossings"};
        const RgbImage image = render_meshes(written, camera, marks, o.threads);
        write_text_file_atomically(frame_png(o.preview, f), encode_png(image));
        if (std::find(sheet_frames.begin(), sheet_frames.end(), f) != sheet_frames.end())
          sheet = sheet.width == 0 ? image : side_by_side(sheet, image);
      }
    }
    // Zero crossings is not enough: an edge beyond twice its rest length is cloth torn or flung.
    if (r.max_stretch > kMaxStretch) ++overstretched;
    row["timing_ms"] = {
        {"integrate", r.integrate_ms}, {"detect", r.detect_ms}, {"correct", r.correct_ms}};
    rows.push_back(row);
    if (progress)
      std::fprintf(stderr, "\rframe %d of %d, %.0f ms", f, frames,
                   r.integrate_ms + r.detect_ms + r.correct_ms);
  }
  if (progress) std::fprintf(stderr, "\n");
  if (!o.preview.empty() && sheet.width > 0)
    write_text_file_atomically((fs::path(o.preview) / "contact_sheet.png").string(),
                               encode_png(sheet));
  report["frames"] = rows;
  const bool clean = bad_frames == 0 && overstretched == 0;
  report["status"] = clean ? "clean" : bad_frames > 0 ? "unresolved" : "overstretched";
  report["frames_with_crossings"] = bad_frames;
  report["frames_overstretched"] = overstretched;
  report["timing_ms"] = {
      {"integrate", integrate_ms}, {"detect", detect_ms}, {"correct", correct_ms}};
  if (o.report == "-") {
    std::printf("%s\n", report.dump(2).c_str());
  } else {
    if (!o.report.empty()) write_text_file_atomically(o.report, report.dump(2) + "\n");
    if (!o.quiet)
      std::printf(
          "simulated %d frames of '%s': %s (%zu saved frames with crossings, %zu frames with "
          "an edge beyond %gx its rest length); wrote %s\n",
          frames, example ? o.example.c_str() : o.scene_file.c_str(),
          clean ? "every frame clean" : "not clean", bad_frames, overstretched, kMaxStretch,
          o.output_dir.c_str());
  }
  return static_cast<int>(clean ? ExitCode::kOk : ExitCode::kIntersecting);
}

}  // namespace untangle::app
