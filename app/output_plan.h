// Every file a run will write, checked before any work against every file it reads and against
// each other (issue 22 §1): a clash, an existing file without --overwrite or a folder that cannot
// be written is refused with one line naming both paths, and nothing is written.
#pragma once

#include <string>
#include <vector>

#include "pipeline.h"

namespace untangle::app {

// A file the run reads or writes, with how the user named it ("--report r.json", "the obstacle
// b.obj", "b.mtl, a side file of the input b.obj").
struct PlannedFile {
  std::string path;
  std::string label;
};

// The files a run reads: movable inputs, obstacles, pin files, and the side files the inputs
// name (an OBJ's `mtllib`, a glTF's buffer and image URIs).
std::vector<PlannedFile> files_read(const CommonOptions& o);

// The files a run writes: the `outputs` (one per movable input, as planned) and the side files
// their writer creates next to them (write_meshes' side_files_of_output), then --report and
// --contours unless they are '-' (stdout).
std::vector<PlannedFile> files_written(const CommonOptions& o,
                                       const std::vector<std::string>& outputs);

// Adds `path`, and the side files it names (an OBJ's `mtllib`, a glTF's buffer and image URIs),
// to `out` as files read; `label` says how the user named it ("the input").
void add_read(const std::string& path, const std::string& label, std::vector<PlannedFile>& out);

// Throws Error(kOutputNotWritten) when a written file is a read file or another written file
// (after resolving `..`, symlinks and hard links), exists without `overwrite`, is a folder, or lies
// in a folder that does not exist or cannot be written. Every command that writes files checks
// them here before any work. Reads directory entries only (the side files are found by add_read).
void check_planned(const std::vector<PlannedFile>& read, const std::vector<PlannedFile>& written,
                   bool overwrite);

// check_planned for a run of `check` or `fix` (CommonOptions: inputs, obstacles, pin files,
// outputs, report, contours, preview); also refuses --report and --contours both '-'.
void check_written_files(const CommonOptions& o, const std::vector<std::string>& outputs);

}  // namespace untangle::app
