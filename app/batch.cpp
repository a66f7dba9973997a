// `untangle batch`: plans every job and every file before any job starts, keeps what --resume may
// keep, runs the rest (or writes Slurm / GNU parallel scripts that do), and writes the summary.
#include "batch.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "batch_run.h"
#include "batch_summary.h"
#include "output_plan.h"
#include "pipeline.h"
#include "render.h"
#include "sha256.h"
#include "untangle/error.h"
#include "untangle/report.h"

namespace untangle::app {

namespace {

namespace fs = std::filesystem;

const char* const kSummaryFiles[] = {"summary.json", "summary.md", "summary.html"};

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string format_seconds(double s) {
  std::ostringstream text;
  text << s;
  return text.str();
}

std::string this_binary() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error(ExitCode::kInternal, "/proc/self/exe", "cannot find the untangle binary");
  return exe.string();
}

// The job's record before it runs: id, input hashes and options. A file that cannot be hashed gets
// no hash; its job then fails in fix, as unreadable input.
JobRecord prepare(const BatchJob& job) {
  JobRecord r;
  r.id = job.id;
  r.options = job.options;
  auto hashed = [](const std::string& path) {
    try {
      return HashedFile{path, sha256_of_file(path)};
    } catch (const Error&) {
      return HashedFile{path, ""};
    }
  };
  for (const std::string& p : job.inputs) r.inputs.push_back(hashed(p));
  for (const std::string& p : job.obstacles) r.obstacles.push_back(hashed(p));
  return r;
}

bool same_files(const std::vector<HashedFile>& a, const std::vector<HashedFile>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].path != b[k].path || a[k].sha256 != b[k].sha256 || a[k].sha256.empty()) return false;
  return true;
}

// --resume keeps an earlier record when the job finished (clean or unresolved) on the same input
// bytes with the same options and its outputs, report and record still exist.
bool keep_earlier(const BatchOptions& o, const BatchJob& job, const JobRecord& now, JobRecord& kept) {
  const JobFiles files = job_files(job);
  const fs::path out(o.output_dir);
  if (!read_job_record((out / files.record).string(), kept)) return false;
  if (kept.id != now.id || kept.status == "failed" || !(kept.options == now.options) ||
      !same_files(kept.inputs, now.inputs) || !same_files(kept.obstacles, now.obstacles))
    return false;
  std::error_code ec;
  for (const std::string& p : files.outputs)
    if (!fs::is_regular_file(out / p, ec)) return false;
  if (!fs::is_regular_file(out / files.report, ec)) return false;
  kept.resumed = true;
  return true;
}

// Every file a job writes, for check_planned.
void add_job_files(const BatchOptions& o, const BatchJob& job, std::vector<PlannedFile>& written) {
  const JobFiles files = job_files(job);
  const fs::path out(o.output_dir);
  CommonOptions fix;
  fix.inputs = job.inputs;
  fix.report = (out / files.report).string();
  fix.preview_png = (out / files.preview).string();
  std::vector<std::string> outputs;
  for (const std::string& p : files.outputs) outputs.push_back((out / p).string());
  for (PlannedFile& f : files_written(fix, outputs)) {
    f.label = "job " + job.id + ": " + f.label;
    written.push_back(f);
  }
  for (const std::string& p : {files.log, files.folder + "/.log.txt.tmp", files.record})
    written.push_back({(out / p).string(), "job " + job.id + ": " + (out / p).string()});
}

// The command line that reruns this batch with `extra` arguments (for the emitted scripts), with
// absolute paths so that it runs from any folder.
std::string batch_command(const BatchOptions& o, const std::string& exe, const std::string& extra) {
  std::string c = shell_quote(exe) + " batch " + shell_quote(fs::absolute(o.source).string()) +
                  " --output-dir " + shell_quote(fs::absolute(o.output_dir).string()) +
                  " --time-limit " + format_seconds(o.time_limit) + " --threads " +
                  std::to_string(o.threads) + " --thumbnail-size " + o.thumbnail_size +
                  " --obstacle-pattern " + shell_quote(o.obstacle_pattern);
  if (o.overwrite) c += " --overwrite";
  if (o.resume) c += " --resume";
  return c + " " + extra;
}

// Slurm's --time, D-HH:MM:SS: the job's limit and a minute for starting and writing the record.
std::string slurm_time(double seconds) {
  long long s = static_cast<long long>(seconds + 0.999) + 60;
  char text[64];
  std::snprintf(text, sizeof text, "%lld-%02lld:%02lld:%02lld", s / 86400, s / 3600 % 24, s / 60 % 60,
                s % 60);
  return text;
}

struct Emitted {
  std::string name, text;
};

std::vector<Emitted> emitted_scripts(const BatchOptions& o, const BatchPlan& plan, int parallel) {
  const std::string exe = this_binary();
  const std::string out = fs::absolute(o.output_dir).string();
  std::string gather = batch_command(o, exe, "--gather -q");
  if (!o.report.empty() && o.report != "-")
    gather += " --report " + shell_quote(fs::absolute(o.report).string());
  std::vector<Emitted> files;
  if (o.emit == "slurm") {
    std::ostringstream array;
    array << "#!/bin/bash\n"
          << "# untangle batch: one array task per job (index in job-id order); submit with submit.sh,\n"
          << "# which runs gather.sbatch after every task ended.\n"
          << "#SBATCH --job-name=untangle-batch\n"
          << "#SBATCH --array=0-" << plan.jobs.size() - 1 << "%" << parallel << "\n"
          << "#SBATCH --time=" << slurm_time(o.time_limit) << "\n"
          << "#SBATCH --ntasks=1\n"
          << "#SBATCH --cpus-per-task=" << std::max(1, o.threads) << "\n"
          << "#SBATCH --output=" << out << "/slurm-%A_%a.out\n";
    if (!o.partition.empty()) array << "#SBATCH --partition=" << o.partition << "\n";
    array << "exec " << batch_command(o, exe, "--only-job \"$SLURM_ARRAY_TASK_ID\"") << "\n";
    std::ostringstream merge;
    merge << "#!/bin/bash\n"
          << "# untangle batch: merges the jobs' records into summary.json, .md and .html.\n"
          << "#SBATCH --job-name=untangle-batch-gather\n"
          << "#SBATCH --time=0-00:30:00\n"
          << "#SBATCH --ntasks=1\n"
          << "#SBATCH --output=" << out << "/slurm-gather-%j.out\n";
    if (!o.partition.empty()) merge << "#SBATCH --partition=" << o.partition << "\n";
    merge << "exec " << gather << "\n";
    std::ostringstream submit;
    submit << "#!/bin/sh\n"
           << "# Submits the job array, then the gather step to run after every task ended.\n"
           << "set -e\n"
           << "array=$(sbatch --parsable " << shell_quote(out + "/batch.sbatch") << ")\n"
           << "sbatch --dependency=afterany:\"${array%%;*}\" " << shell_quote(out + "/gather.sbatch") << "\n";
    files = {{"batch.sbatch", array.str()}, {"gather.sbatch", merge.str()}, {"submit.sh", submit.str()}};
  } else {
    std::ostringstream lines;
    for (std::size_t k = 0; k < plan.jobs.size(); ++k)
      lines << batch_command(o, exe, "--only-job " + std::to_string(k) + " -q") << "\n";
    std::ostringstream run;
    run << "#!/bin/sh\n"
        << "# untangle batch: the jobs with GNU parallel (one line of parallel_jobs.txt each), then\n"
        << "# the summary. parallel.joblog lists each job's exit status and time.\n"
        << "parallel --jobs " << parallel << " --joblog " << shell_quote(out + "/parallel.joblog")
        << " < " << shell_quote(out + "/parallel_jobs.txt") << "\n"
        << "exec " << gather << "\n";
    files = {{"parallel_jobs.txt", lines.str()}, {"parallel.sh", run.str()}};
  }
  return files;
}

// A line per finished job (no terminal) or a progress bar (terminal) on stdout.
class Progress {
 public:
  Progress(std::size_t total, bool show) : total_(total), show_(show), tty_(::isatty(1) != 0) {}
  void done(const JobRecord& r) {
    ++done_;
    failed_ += r.status == "failed";
    if (!show_) return;
    if (tty_) {
      const int width = 30;
      const int filled = total_ == 0 ? width : static_cast<int>(width * done_ / total_);
      std::printf("\r[%s%s] %zu/%zu jobs, %zu failed", std::string(filled, '#').c_str(),
                  std::string(width - filled, ' ').c_str(), done_, total_, failed_);
      if (done_ == total_) std::printf("\n");
    } else {
      std::printf("[%zu/%zu] %s: %s%s%s, %.2f s\n", done_, total_, r.id.c_str(), r.status.c_str(),
                  r.reason.empty() ? "" : ": ", r.reason.c_str(), r.time_ms / 1000.0);
    }
    std::fflush(stdout);
  }

 private:
  std::size_t total_, done_ = 0, failed_ = 0;
  bool show_, tty_;
};

}  // namespace

CLI::App* add_batch_command(CLI::App& app, BatchOptions& o, const std::string& footer,
                            bool with_options) {
  const BatchOptions d;
  CLI::App* cmd = app.add_subcommand(
      "batch", "Run fix on many jobs (a manifest or a folder), each in its own process; summarise");
  cmd->footer(footer);
  if (!with_options) return cmd;
  cmd->add_option("source", o.source,
                  "MANIFEST.json, or a folder: garments/ and bodies/, <prefix>_generic.obj bodies, or one subfolder per job")
      ->required();
  cmd->add_option("--output-dir", o.output_dir,
                  "Write OUT/jobs/<id>/ per job and OUT/summary.json, .md, .html (the folder must exist)")
      ->required()
      ->option_text("OUT");
  cmd->add_option("--jobs", o.jobs, "Jobs at once, 0 = cores (default " + std::to_string(d.jobs) + ")")
      ->check(CLI::NonNegativeNumber)
      ->option_text("N");
  cmd->add_option("--time-limit", o.time_limit,
                  "Seconds of wall time per job, then it is killed (default " +
                      format_seconds(d.time_limit) + ")")
      ->check(CLI::PositiveNumber)
      ->option_text("S");
  cmd->add_option("--threads", o.threads,
                  "Worker threads of each job, 0 = all cores; the same result for every N (default " +
                      std::to_string(d.threads) + ")")
      ->check(CLI::NonNegativeNumber)
      ->option_text("N");
  cmd->add_option("--obstacle-pattern", o.obstacle_pattern,
                  "Subfolder layout: mesh files whose name matches this glob are obstacles (default " +
                      d.obstacle_pattern + ")")
      ->option_text("GLOB");
  cmd->add_option("--thumbnail-size", o.thumbnail_size,
                  "Each panel of a job's before/after picture, in pixels (default " + d.thumbnail_size + ")")
      ->option_text("WxH");
  cmd->add_option("--report", o.report,
                  "Also write summary.json to FILE ('-' = stdout, which then carries nothing else)")
      ->option_text("FILE");
  cmd->add_flag("--resume", o.resume,
                "Keep jobs that finished on the same input bytes and options and whose outputs exist; rerun the others");
  cmd->add_flag("--overwrite", o.overwrite, "Replace files an earlier batch left in OUT (never an input)");
  cmd->add_option("--emit", o.emit,
                  "Run nothing: write OUT/batch.sbatch, gather.sbatch and submit.sh (slurm) or OUT/parallel_jobs.txt and parallel.sh (parallel)")
      ->check(CLI::IsMember({"slurm", "parallel"}))
      ->option_text("slurm|parallel");
  cmd->add_option("--partition", o.partition, "--emit slurm: the partition to submit to (none: the cluster's default)")
      ->option_text("NAME");
  cmd->add_option("--only-job", o.only_job,
                  "Run only this job (its index in id order, from 0, or its id) and write its record, not the summary; exit 0 unless the job failed")
      ->option_text("K|ID");
  cmd->add_flag("--gather", o.gather, "Run nothing: merge the jobs' records into the summary");
  cmd->add_flag("-q,--quiet", o.quiet, "Print nothing but errors");
  return cmd;
}

int run_batch(const BatchOptions& o) {
  if ((!o.emit.empty()) + (!o.only_job.empty()) + o.gather > 1)
    throw Error(ExitCode::kUsage, "", "--emit, --only-job and --gather exclude each other");
  int width = 0, height = 0;
  parse_size("--thumbnail-size", o.thumbnail_size, width, height);
  std::error_code ec;
  if (!fs::is_directory(o.output_dir, ec))
    throw Error(ExitCode::kOutputNotWritten, o.output_dir, "--output-dir: folder does not exist");
  const BatchPlan plan = read_batch_source(o);
  const int parallel = o.jobs > 0 ? o.jobs : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));

  std::vector<std::size_t> selected;
  if (!o.only_job.empty()) {
    const bool index = o.only_job.find_first_not_of("0123456789") == std::string::npos;
    for (std::size_t k = 0; k < plan.jobs.size(); ++k)
      if (index ? std::to_string(k) == o.only_job : plan.jobs[k].id == o.only_job) selected.push_back(k);
    if (selected.empty()) {
      throw Error(ExitCode::kUsage, "",
                  "--only-job " + o.only_job + ": no such job (" + std::to_string(plan.jobs.size()) +
                      " jobs, 0 to " + std::to_string(plan.jobs.size() - 1) + ")");
    }
  } else if (!o.gather) {
    for (std::size_t k = 0; k < plan.jobs.size(); ++k) selected.push_back(k);
  }

  std::vector<JobRecord> records(plan.jobs.size());
  std::vector<bool> run(plan.jobs.size(), false);
  for (std::size_t k : selected) {
    records[k] = prepare(plan.jobs[k]);
    JobRecord kept;
    if (o.resume && o.emit.empty() && keep_earlier(o, plan.jobs[k], records[k], kept)) {
      records[k] = kept;
    } else {
      run[k] = true;
    }
  }

  // Every file written, checked before any job starts (output_plan.h).
  std::vector<PlannedFile> read, written;
  if (!fs::is_directory(o.source, ec)) add_read(o.source, "the manifest", read);
  for (const BatchJob& job : plan.jobs) {
    for (const std::string& p : job.inputs) add_read(p, "job " + job.id + ": the input", read);
    for (const std::string& p : job.obstacles) add_read(p, "job " + job.id + ": the obstacle", read);
  }
  const fs::path out(o.output_dir);
  std::vector<fs::path> created;
  for (std::size_t k = 0; k < plan.jobs.size(); ++k) {
    if (!run[k] && o.emit.empty()) continue;
    add_job_files(o, plan.jobs[k], written);
    const fs::path folder = out / job_files(plan.jobs[k]).folder;
    for (const fs::path& f : {out / "jobs", folder}) {
      if (fs::is_directory(f, ec)) continue;
      fs::create_directory(f, ec);
      if (ec) throw Error(ExitCode::kOutputNotWritten, f.string(), "cannot create the folder: " + ec.message());
      created.push_back(f);
    }
  }
  const bool summary = o.only_job.empty();
  if (summary) {
    for (const char* name : kSummaryFiles)
      written.push_back({(out / name).string(), (out / name).string()});
    if (!o.report.empty() && o.report != "-") written.push_back({o.report, "--report " + o.report});
  }
  const std::vector<Emitted> scripts = o.emit.empty() ? std::vector<Emitted>() : emitted_scripts(o, plan, parallel);
  for (const Emitted& e : scripts) written.push_back({(out / e.name).string(), "--emit " + o.emit + ": " + (out / e.name).string()});
  try {
    check_planned(read, written, o.overwrite || o.resume);
  } catch (const Error&) {
    for (auto it = created.rbegin(); it != created.rend(); ++it) fs::remove(*it, ec);  // only if empty
    throw;
  }
  const bool show = !o.quiet && o.report != "-";

  if (!scripts.empty()) {
    for (const Emitted& e : scripts) {
      const fs::path path = out / e.name;
      write_text_file_atomically(path.string(), e.text);
      if (e.name.size() > 3 && e.name.compare(e.name.size() - 3, 3, ".sh") == 0)
        fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                        fs::perm_options::add, ec);
      if (show) std::printf("wrote %s\n", path.string().c_str());
    }
    return 0;
  }

  if (o.gather) {
    for (std::size_t k = 0; k < plan.jobs.size(); ++k) {
      JobRecord& r = records[k];
      if (!read_job_record((out / job_files(plan.jobs[k]).record).string(), r) || r.id != plan.jobs[k].id) {
        r = prepare(plan.jobs[k]);
        r.status = "failed";
        r.reason = "no record (the job did not run or did not finish)";
        r.exit_code = static_cast<int>(ExitCode::kInternal);
      }
    }
  } else {
    std::vector<const BatchJob*> jobs;
    std::vector<JobRecord> prepared;
    std::vector<std::size_t> slot;
    for (std::size_t k = 0; k < plan.jobs.size(); ++k) {
      if (!run[k]) continue;
      jobs.push_back(&plan.jobs[k]);
      prepared.push_back(records[k]);
      slot.push_back(k);
    }
    Progress progress(jobs.size(), show);
    if (show && jobs.size() < selected.size())
      std::printf("kept %zu jobs from an earlier run (--resume)\n", selected.size() - jobs.size());
    const std::vector<JobRecord> done = run_jobs(jobs, prepared, this_binary(), o, parallel,
                                                 [&](const JobRecord& r) { progress.done(r); });
    for (std::size_t i = 0; i < done.size(); ++i) records[slot[i]] = done[i];
    // A task of an emitted script (Slurm's array, GNU parallel) that ran its job and wrote its
    // record succeeded, whatever the job's verdict: sacct and the joblog list as failed exactly
    // the jobs the summary lists as failed (crash, time limit, unreadable input, ...), and the
    // gathered summary's exit code carries the verdicts (man page, BATCH, Scale-out).
    if (!o.only_job.empty()) {
      const JobRecord& r = records[selected[0]];
      return r.status == "failed" ? r.exit_code : 0;
    }
  }

  const BatchSummary s = make_summary(o, plan, records);
  write_text_file_atomically((out / "summary.json").string(), s.json);
  write_text_file_atomically((out / "summary.md").string(), s.markdown);
  write_text_file_atomically((out / "summary.html").string(), s.html);
  if (o.report == "-") {
    std::fwrite(s.json.data(), 1, s.json.size(), stdout);
  } else if (!o.report.empty()) {
    write_text_file_atomically(o.report, s.json);
  }
  if (show) {
    std::size_t failed = 0, unresolved = 0, distorted = 0;
    for (const JobRecord& r : records) {
      failed += r.status == "failed";
      unresolved += r.status == "unresolved";
      distorted += r.status == "distorted";
    }
    std::printf("%zu jobs: %zu clean, %zu distorted, %zu unresolved, %zu failed\n", records.size(),
                records.size() - failed - unresolved - distorted, distorted, unresolved, failed);
    for (const char* name : kSummaryFiles) std::printf("wrote %s\n", (out / name).string().c_str());
    std::printf("status: %s\n", failed > 0       ? "failed"
                                 : unresolved > 0 ? "unresolved"
                                 : distorted > 0  ? "distorted"
                                                  : "clean");
  }
  return s.exit_code;
}

}  // namespace untangle::app
