// The jobs of `untangle batch`: a JSON manifest, or a folder read by one of its layouts.
#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "batch.h"
#include "scenes/scenes.h"
#include "untangle/error.h"
#include "untangle/formats.h"

namespace untangle::app {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

[[noreturn]] void bad_key(const std::string& file, const std::string& key, const std::string& why) {
  throw Error(ExitCode::kUnreadableInput, file, "'" + key + "': " + why);
}

bool valid_id(const std::string& id) {
  if (id.empty() || id[0] == '.' || id.size() > 200) return false;
  for (char c : id)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      return false;
  return true;
}

// Manifest "options" (top level or per job) over `options`.
void read_options(const std::string& file, const std::string& at, const Json& j,
                  JobOptions& options) {
  if (!j.is_object()) bad_key(file, at, "must be an object");
  for (const auto& [key, value] : j.items()) {
    const std::string name = at + "." + key;
    if (key == "method") {
      if (!value.is_string() || (value != "region" && value != "paper"))
        bad_key(file, name, "must be \"region\" or \"paper\"");
      options.method = value.get<std::string>();
    } else if (key == "clearance") {
      if (!value.is_number() || !(value.get<double>() >= 0.0) || !std::isfinite(value.get<double>()))
        bad_key(file, name, "must be a number >= 0");
      options.clearance = value.get<double>();
    } else if (key == "max_iterations") {
      if (!value.is_number_integer() || value.get<long long>() < 0 || value.get<long long>() > 1000000000)
        bad_key(file, name, "must be an integer >= 0");
      options.max_iterations = value.get<int>();
    } else if (key == "outside_closed_obstacles") {
      if (!value.is_boolean()) bad_key(file, name, "must be true or false");
      options.outside_closed_obstacles = value.get<bool>();
    } else {
      bad_key(file, name, "unknown key (method, clearance, max_iterations, outside_closed_obstacles)");
    }
  }
}

std::vector<std::string> read_paths(const std::string& file, const std::string& at, const Json& j,
                                    const fs::path& base) {
  if (!j.is_array()) bad_key(file, at, "must be an array of file names");
  std::vector<std::string> paths;
  for (const Json& p : j) {
    if (!p.is_string() || p.get<std::string>().empty()) bad_key(file, at, "must be an array of file names");
    const fs::path path(p.get<std::string>());
    paths.push_back(path.is_absolute() ? path.string() : (base / path).string());
  }
  return paths;
}

BatchPlan read_manifest(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(ExitCode::kUnreadableInput, file, "no such file");
  std::ostringstream text;
  text << in.rdbuf();
  Json j;
  try {
    j = Json::parse(text.str());
  } catch (const Json::exception& e) {
    throw Error(ExitCode::kUnreadableInput, file, std::string("not a JSON manifest: ") + e.what());
  }
  if (!j.is_object()) throw Error(ExitCode::kUnreadableInput, file, "a manifest is a JSON object");
  for (const auto& [key, value] : j.items())
    if (key != "jobs" && key != "options") bad_key(file, key, "unknown key (jobs, options)");
  JobOptions defaults;
  if (j.contains("options")) read_options(file, "options", j["options"], defaults);
  if (!j.contains("jobs")) bad_key(file, "jobs", "missing (an array of jobs)");
  if (!j["jobs"].is_array() || j["jobs"].empty()) bad_key(file, "jobs", "must be a non-empty array");
  const fs::path base = fs::path(file).parent_path();
  BatchPlan plan;
  plan.layout = "manifest";
  for (std::size_t k = 0; k < j["jobs"].size(); ++k) {
    const Json& job = j["jobs"][k];
    const std::string at = "jobs[" + std::to_string(k) + "]";
    if (!job.is_object()) bad_key(file, at, "a job is an object");
    for (const auto& [key, value] : job.items()) {
      if (key != "id" && key != "inputs" && key != "obstacles" && key != "options")
        bad_key(file, at + "." + key, "unknown key (id, inputs, obstacles, options)");
    }
    BatchJob b;
    b.options = defaults;
    if (!job.contains("inputs")) bad_key(file, at + ".inputs", "missing (the movable meshes)");
    b.inputs = read_paths(file, at + ".inputs", job["inputs"], base);
    if (b.inputs.empty()) bad_key(file, at + ".inputs", "must name at least one mesh");
    if (job.contains("obstacles")) b.obstacles = read_paths(file, at + ".obstacles", job["obstacles"], base);
    if (job.contains("options")) read_options(file, at + ".options", job["options"], b.options);
    if (job.contains("id")) {
      if (!job["id"].is_string() || !valid_id(job["id"].get<std::string>()))
        bad_key(file, at + ".id", "must be a string of letters, digits, '_', '-' and '.', not starting with '.'");
      b.id = job["id"].get<std::string>();
    } else {
      b.id = fs::path(b.inputs[0]).stem().string();
      if (!valid_id(b.id))
        bad_key(file, at + ".id", "missing, and the first input's name '" + b.id + "' is no valid id");
    }
    for (const BatchJob& other : plan.jobs)
      if (other.id == b.id) bad_key(file, at + ".id", "'" + b.id + "' names two jobs");
    plan.jobs.push_back(std::move(b));
  }
  return plan;
}

bool is_mesh_file(const fs::directory_entry& entry) {
  if (!entry.is_regular_file()) return false;
  std::string ext = entry.path().extension().string();
  if (ext.size() < 2) return false;
  ext = ext.substr(1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  // Our own readers' formats first: a folder of OBJ files never loads the assimp module.
  if (ext == "obj" || ext == "off") return true;
  static const std::vector<FileFormat> formats = readable_formats();
  for (const FileFormat& f : formats)
    if (f.extension == ext) return true;
  return false;
}

std::vector<fs::path> sorted_entries(const fs::path& dir) {
  std::vector<fs::path> entries;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) entries.push_back(e.path());
  std::sort(entries.begin(), entries.end());
  return entries;
}

BatchPlan makehuman_plan(const std::string& dir, const std::string& garments,
                         const std::string& bodies) {
  std::vector<std::string> notes;
  BatchPlan plan;
  plan.layout = "makehuman";
  for (const auto& [garment, body] : scenes::garment_body_pairs_in(garments, bodies, notes)) {
    BatchJob job;
    job.id = fs::path(garment).stem().string();
    if (!valid_id(job.id)) throw Error(ExitCode::kUnreadableInput, garment, "its name is no valid job id");
    job.inputs = {garment};
    job.obstacles = {body};
    plan.jobs.push_back(std::move(job));
  }
  if (plan.jobs.empty()) {
    throw Error(ExitCode::kUnreadableInput, dir,
                "no garment <prefix>_*.obj with a matching body <prefix>_generic.obj");
  }
  return plan;
}

BatchPlan subfolder_plan(const std::string& dir, const std::string& pattern) {
  BatchPlan plan;
  plan.layout = "subfolders";
  for (const fs::path& sub : sorted_entries(dir)) {
    std::error_code ec;
    if (!fs::is_directory(sub, ec)) continue;
    BatchJob job;
    job.id = sub.filename().string();
    for (const fs::path& file : sorted_entries(sub)) {
      if (!is_mesh_file(fs::directory_entry(file))) continue;
      const bool obstacle = ::fnmatch(pattern.c_str(), file.filename().c_str(), 0) == 0;
      (obstacle ? job.obstacles : job.inputs).push_back(file.string());
    }
    if (job.inputs.empty() && job.obstacles.empty()) continue;
    if (!valid_id(job.id)) throw Error(ExitCode::kUnreadableInput, sub.string(), "its name is no valid job id");
    if (job.inputs.empty()) {
      throw Error(ExitCode::kUnreadableInput, sub.string(),
                  "every mesh file matches the obstacle pattern '" + pattern + "'; nothing to move");
    }
    plan.jobs.push_back(std::move(job));
  }
  if (plan.jobs.empty()) {
    throw Error(ExitCode::kUnreadableInput, dir,
                "no jobs: neither garments/ and bodies/, nor <prefix>_generic.obj bodies, nor "
                "subfolders with mesh files");
  }
  return plan;
}

}  // namespace

BatchPlan read_batch_source(const BatchOptions& o) {
  std::error_code ec;
  BatchPlan plan;
  if (!fs::exists(o.source, ec)) throw Error(ExitCode::kUnreadableInput, o.source, "no such file or folder");
  if (!fs::is_directory(o.source, ec)) {
    plan = read_manifest(o.source);
  } else if (fs::is_directory(fs::path(o.source) / "garments", ec) &&
             fs::is_directory(fs::path(o.source) / "bodies", ec)) {
    plan = makehuman_plan(o.source, (fs::path(o.source) / "garments").string(),
                          (fs::path(o.source) / "bodies").string());
  } else {
    bool bodies = false;
    for (const fs::path& file : sorted_entries(o.source)) {
      const std::string name = file.filename().string();
      bodies = bodies || (name.size() > 12 && name.compare(name.size() - 12, 12, "_generic.obj") == 0 &&
                          fs::is_regular_file(file, ec));
    }
    plan = bodies ? makehuman_plan(o.source, o.source, o.source) : subfolder_plan(o.source, o.obstacle_pattern);
  }
  std::sort(plan.jobs.begin(), plan.jobs.end(),
            [](const BatchJob& a, const BatchJob& b) { return a.id < b.id; });
  return plan;
}

JobFiles job_files(const BatchJob& job) {
  JobFiles f;
  f.folder = "jobs/" + job.id;
  for (const std::string& in : job.inputs) f.outputs.push_back(f.folder + "/" + fs::path(in).filename().string());
  f.report = f.folder + "/report.json";
  f.preview = f.folder + "/" + fs::path(job.inputs[0]).stem().string() + "_before_after.png";
  f.log = f.folder + "/log.txt";
  f.record = f.folder + "/job.json";
  return f;
}

}  // namespace untangle::app
