// `untangle batch`: many `fix` jobs from a manifest or a folder layout, each in its own process,
// with a per-job time limit, summarised in OUT/summary.json, .md and .html (issue 22 §4-5, 23).
#pragma once

#include <string>
#include <vector>

#include "untangle/fix.h"

// CLI::App only by name: every file that includes CLI11 constructs its own copies of CLI11's
// global validators (strings and std::functions) before main, so only the files that build the
// command line include it.
namespace CLI {
class App;
}

namespace untangle::app {

// Every default of the batch command, written once here; --help and the man page state them.
struct BatchOptions {
  std::string source;      // MANIFEST.json or a folder
  std::string output_dir;  // OUT (must exist)
  int jobs = 0;            // jobs at once, 0 = cores
  double time_limit = 600.0;  // seconds of wall time per job, then SIGKILL
  int threads = 1;            // fix --threads of each job (the result is the same for every N)
  std::string obstacle_pattern = "obstacle*";  // subfolder layout: file names of the obstacles
  std::string thumbnail_size = "200x200";      // fix --preview-size of each job
  std::string report;  // a copy of summary.json ('-' = stdout)
  bool resume = false;
  bool overwrite = false;
  bool quiet = false;
  std::string emit;      // "", "slurm" or "parallel": write scripts into OUT, run nothing
  std::string partition;  // --emit slurm: #SBATCH --partition (none when empty)
  std::string only_job;  // run only this job (index in id order, or id), write its record only
  bool gather = false;   // run nothing, merge the job records into the summary
};

// The fix options one job may set (manifest "options"); defaults from FixOptions.
struct JobOptions {
  std::string method = to_string(FixOptions{}.method);
  double clearance = FixOptions{}.clearance;
  int max_iterations = FixOptions{}.max_iterations;
  bool outside_closed_obstacles = FixOptions{}.outside_closed_obstacles;
  bool operator==(const JobOptions& o) const {
    return method == o.method && clearance == o.clearance && max_iterations == o.max_iterations &&
           outside_closed_obstacles == o.outside_closed_obstacles;
  }
};

// One job: `untangle fix INPUTS --obstacle OBSTACLES` with its options.
struct BatchJob {
  std::string id;  // [A-Za-z0-9_.-], not starting with '.'; its files go to OUT/jobs/<id>/
  std::vector<std::string> inputs;
  std::vector<std::string> obstacles;
  JobOptions options;
};

// The jobs of a manifest or folder, sorted by id (ids unique).
struct BatchPlan {
  std::string layout;  // manifest | makehuman | subfolders
  std::vector<BatchJob> jobs;
};

// Reads a manifest (a file) or a folder by its layout (man page, BATCH). Throws
// Error(kUnreadableInput) with one line naming the file and the key.
BatchPlan read_batch_source(const BatchOptions& o);

// A file read by a job, with its SHA-256.
struct HashedFile {
  std::string path;
  std::string sha256;
};

// What became of one job: written by the runner to OUT/jobs/<id>/job.json, read back by --resume
// and --gather.
struct JobRecord {
  std::string id;
  std::string status;  // clean | unresolved (fix's report) | failed
  std::string reason;  // why failed: "unreadable input: ...", "crash (signal 11)", "time limit (600 s)"
  int exit_code = 0;   // the job's exit code in batch terms (job_exit_code)
  std::vector<HashedFile> inputs;
  std::vector<HashedFile> obstacles;
  JobOptions options;
  std::vector<std::string> outputs;  // relative to OUT
  double time_ms = 0.0;
  bool resumed = false;  // not in job.json: set when --resume kept an earlier record
};

// The files of job `job` relative to OUT.
struct JobFiles {
  std::string folder;  // jobs/<id>
  std::vector<std::string> outputs;
  std::string report, preview, log, record;
};
JobFiles job_files(const BatchJob& job);

// Adds the `batch` subcommand, its options (parsed into `o`) only `with_options` (as render.h's).
CLI::App* add_batch_command(CLI::App& app, BatchOptions& o, const std::string& footer,
                            bool with_options);
int run_batch(const BatchOptions& o);

}  // namespace untangle::app
