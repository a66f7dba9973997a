// Pictures from the command line: `untangle render` and `untangle fix --preview DIR`.
#pragma once

#include <string>
#include <vector>

#include "pipeline.h"
#include "untangle/render.h"

namespace CLI {
class App;  // by name only, as in batch.h
}

namespace untangle::app {

struct RenderCliOptions {
  std::vector<std::string> inputs;
  std::vector<std::string> obstacles;
  std::string output;
  std::string view = to_string(RenderOptions{}.view);
  std::string size = std::to_string(RenderOptions{}.width) + "x" +
                     std::to_string(RenderOptions{}.height);
  bool contours = false;
  bool inside = false;
  bool overwrite = false;
  bool quiet = false;
  int threads = RenderOptions{}.threads;
};

// Parses "WxH" (each 16 to 8192 pixels) of `option`; throws Error(kUsage) naming the option.
void parse_size(const std::string& option, const std::string& text, int& width, int& height);

// Adds the `render` subcommand to `app`, options parsed into `o` (none without `with_options`:
// main gives options only to the subcommands the command line names).
CLI::App* add_render_command(CLI::App& app, RenderCliOptions& o, const std::string& footer,
                             bool with_options);
int run_render(const RenderCliOptions& o);

// Adds `--preview DIR` and `--preview-size WxH` (into o.preview_size) to `fix`.
void add_preview_option(CLI::App& fix, std::string& dir, CommonOptions& o);
// The picture `fix --preview DIR` writes (DIR/<first input's stem>_before_after.png); throws
// Error(kOutputNotWritten) when DIR is no folder. The caller puts it in CommonOptions::preview_png
// so that it is checked with fix's other outputs before any work.
std::string plan_preview(const std::string& dir, const CommonOptions& o);
// Renders and writes the preview of a finished run to `path` (from plan_preview).
void write_preview(const std::string& path, const PipelineRun& run, const CommonOptions& o);

}  // namespace untangle::app
