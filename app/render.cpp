// `untangle render` and `untangle fix --preview DIR`: checks the output, renders, writes the PNG.
#include "render.h"

#include <CLI/CLI.hpp>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "output_plan.h"
#include "untangle/error.h"
#include "untangle/read_meshes.h"
#include "untangle/report.h"

namespace untangle::app {

namespace {

namespace fs = std::filesystem;

constexpr int kMinSize = 16, kMaxSize = 8192;

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw Error(ExitCode::kOutputNotWritten, path, why);
}

// A render output must be named *.png (the format it writes).
void check_png_name(const std::string& out) {
  std::string ext = fs::path(out).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".png") refuse(out, "render writes PNG only; name the output *.png");
}

RenderView parse_view(const std::string& text) {
  for (RenderView v : {RenderView::kFront, RenderView::kBack, RenderView::kLeft, RenderView::kRight,
                       RenderView::kTop, RenderView::kAuto})
    if (text == to_string(v)) return v;
  throw Error(ExitCode::kUsage, "",
              "--view " + text + ": expected front, back, left, right, top or auto");
}

}  // namespace

void parse_size(const std::string& option, const std::string& text, int& width, int& height) {
  const std::size_t x = text.find('x');
  auto number = [&](const std::string& part, int& value) {
    if (part.empty() || part.size() > 5) return false;
    for (char c : part)
      if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    value = std::stoi(part);
    return value >= kMinSize && value <= kMaxSize;
  };
  if (x == std::string::npos || !number(text.substr(0, x), width) ||
      !number(text.substr(x + 1), height)) {
    throw Error(ExitCode::kUsage, "",
                option + " " + text + ": expected WxH, each from " + std::to_string(kMinSize) +
                    " to " + std::to_string(kMaxSize) + " pixels (e.g. 800x800)");
  }
}

CLI::App* add_render_command(CLI::App& app, RenderCliOptions& o, const std::string& footer,
                             bool with_options) {
  CLI::App* cmd = app.add_subcommand(
      "render", "Draw the meshes to a PNG: shaded surfaces, contours in red, a legend");
  cmd->footer(footer);
  if (!with_options) return cmd;
  cmd->add_option("meshes", o.inputs,
                  "Mesh files (every format assimp reads), each in its own colour")
      ->required();
  cmd->add_option("--obstacle", o.obstacles, "A mesh drawn in a neutral grey (repeatable)")
      ->allow_extra_args(false)
      ->option_text("MESH");
  cmd->add_option("-o,--output", o.output, "The PNG file to write")
      ->required()
      ->option_text("OUT.png");
  cmd->add_option("--view", o.view,
                  "Seen from: front (+z), back, left (-x), right, top (+y), or auto: the one that "
                  "shows the most contour length" +
                      std::string(" (default ") + o.view + ")")
      ->check(CLI::IsMember({"front", "back", "left", "right", "top", "auto"}))
      ->option_text("front|back|left|right|top|auto");
  cmd->add_option("--size", o.size, "Picture size in pixels (default " + o.size + ")")
      ->option_text("WxH");
  cmd->add_flag("--contours", o.contours, "Draw the contours in red, over the surfaces");
  cmd->add_flag("--inside", o.inside, "Tint the illegal regions (amber) and the faces that cross (magenta)");
  cmd->add_flag("--overwrite", o.overwrite, "Replace an existing output file (never an input)");
  cmd->add_option("--threads", o.threads,
                  "Worker threads, 0 = all cores; the same bytes for every N (default " +
                      std::to_string(o.threads) + ")")
      ->check(CLI::NonNegativeNumber)
      ->option_text("N");
  cmd->add_flag("-q,--quiet", o.quiet, "Print nothing but errors");
  return cmd;
}

int run_render(const RenderCliOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  RenderOptions options;
  options.view = parse_view(o.view);
  parse_size("--size", o.size, options.width, options.height);
  options.contours = o.contours;
  options.inside = o.inside;
  options.threads = o.threads;
  // Checked before any work, like every file untangle writes (output_plan.h).
  check_png_name(o.output);
  std::vector<PlannedFile> read;
  for (const std::string& p : o.inputs) add_read(p, "the input", read);
  for (const std::string& p : o.obstacles) add_read(p, "the obstacle", read);
  check_planned(read, {{o.output, "-o " + o.output}}, o.overwrite);

  CommonOptions load;
  load.inputs = o.inputs;
  load.obstacles = o.obstacles;
  const std::vector<Mesh> meshes = load_all(load);
  RenderSummary summary;
  const RgbImage image = render_scene(meshes, options, &summary);
  write_text_file_atomically(o.output, encode_png(image));
  if (!o.quiet) {
    // Counts only when detection ran (contours, inside or the auto view asked for it).
    const bool detected = options.contours || options.inside || options.view == RenderView::kAuto;
    std::printf("view %s, %dx%d", to_string(summary.view), image.width, image.height);
    if (detected)
      std::printf(", %zu crossings, %zu contours", summary.counts.crossings,
                  summary.counts.contours);
    std::printf(", %.0f ms\n", ms_since(start));
    std::printf("wrote %s\n", o.output.c_str());
  }
  return 0;
}

void add_preview_option(CLI::App& fix, std::string& dir, CommonOptions& o) {
  fix.add_option("--preview", dir,
                 "Also write DIR/<first input's stem>_before_after.png: before, after and the "
                 "displacement, contours in red")
      ->option_text("DIR");
  o.preview_size =
      std::to_string(RenderOptions{}.width) + "x" + std::to_string(RenderOptions{}.height);
  fix.add_option("--preview-size", o.preview_size,
                 "Size of each of the preview's three panels in pixels (default " + o.preview_size +
                     ")")
      ->option_text("WxH");
}

std::string plan_preview(const std::string& dir, const CommonOptions& o) {
  if (!o.preview_size.empty()) {
    int width = 0, height = 0;
    parse_size("--preview-size", o.preview_size, width, height);  // a bad size is a usage error before any work
  }
  if (dir.empty()) return "";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) refuse(dir, "--preview: folder does not exist");
  // The rest (never a file read, nor another file written, nor existing without --overwrite) is
  // checked with fix's outputs, before any work (CommonOptions::preview_png).
  return (fs::path(dir) / (fs::path(o.inputs[0]).stem().string() + "_before_after.png")).string();
}

void write_preview(const std::string& path, const PipelineRun& run, const CommonOptions& o) {
  if (path.empty()) return;
  std::vector<Mesh> before = run.meshes;
  for (std::size_t m = 0; m < before.size() && m < run.input.size(); ++m)
    before[m].positions = run.input[m];
  // Detected like fix's own verdict: obstacle pairs left out, since fix cannot change them.
  DetectOptions detect;
  detect.threads = o.threads;
  detect.skip_obstacle_pairs = true;
  const Intersections found_before = find_intersections(before, detect);
  RenderOptions options;
  options.threads = o.threads;
  if (!o.preview_size.empty()) parse_size("--preview-size", o.preview_size, options.width, options.height);
  const RgbImage image =
      render_before_after(before, run.meshes, found_before, run.verified, options);
  write_text_file_atomically(path, encode_png(image));
}

}  // namespace untangle::app
