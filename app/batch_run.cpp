// Runs the jobs of `untangle batch`: one child process per job (this binary's `fix`), at most N at
// once, each killed at its time limit; the verdict from its exit status and its fix report.
#include "batch_run.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "untangle/error.h"
#include "untangle/report.h"

namespace untangle::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string format_number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

// The fault UNTANGLE_BATCH_TEST_FAULT asks for job `id`: "crash" or "hang", else "".
// The variable lists "crash:ID" and "hang:ID" items separated by commas; a test hook only.
std::string test_fault(const std::string& id) {
  const char* value = std::getenv("UNTANGLE_BATCH_TEST_FAULT");
  if (value == nullptr) return "";
  std::istringstream items(value);
  for (std::string item; std::getline(items, item, ',');) {
    for (const char* kind : {"crash", "hang"}) {
      if (item == std::string(kind) + ":" + id) return kind;
    }
  }
  return "";
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The last "error: ..." line of a job's log, without the prefix; "" when there is none.
std::string last_error(const std::string& log) {
  std::istringstream lines(log);
  std::string found;
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("error: ", 0) == 0) found = line.substr(7);
  return found;
}

struct Running {
  std::size_t index = 0;  // into the jobs
  pid_t pid = -1;
  Clock::time_point start;
  std::string log_tmp;
};

}  // namespace

std::vector<std::string> job_command(const std::string& exe, const BatchJob& job,
                                     const std::string& out, const BatchOptions& o) {
  const JobFiles files = job_files(job);
  const fs::path dir = fs::path(out) / files.folder;
  std::vector<std::string> argv = {exe, "fix"};
  for (const std::string& in : job.inputs) argv.push_back(in);
  for (const std::string& ob : job.obstacles) {
    argv.push_back("--obstacle");
    argv.push_back(ob);
  }
  const JobOptions& j = job.options;
  for (const std::string& a :
       {std::string("--output-dir"), dir.string(), std::string("--report"),
        (fs::path(out) / files.report).string(), std::string("--preview"), dir.string(),
        std::string("--preview-size"), o.thumbnail_size, std::string("--threads"),
        std::to_string(o.threads), std::string("--method"), j.method, std::string("--clearance"),
        format_number(j.clearance), std::string("--max-iterations"),
        std::to_string(j.max_iterations),
        std::string(j.outside_closed_obstacles ? "--outside-closed-obstacles" : "--orientation-free"),
        // run_batch checked every file the job writes before any job started.
        std::string("--overwrite")})
    argv.push_back(a);
  return argv;
}

int job_exit_code(const std::string& status, int fix_exit) {
  if (status == "clean") return 0;
  if (status == "distorted") return static_cast<int>(ExitCode::kDistorted);
  if (status == "unresolved") return static_cast<int>(ExitCode::kIntersecting);
  if (fix_exit == 2 || fix_exit == 3 || fix_exit == 4) return fix_exit;
  return static_cast<int>(ExitCode::kInternal);
}

int worst_exit_code(const std::vector<JobRecord>& records) {
  // From best to worst: clean, distorted, unresolved, output not written, unreadable input,
  // usage, crash / time limit / internal error.
  auto rank = [](int code) {
    switch (code) {
      case 0: return 0;
      case 6: return 1;
      case 5: return 2;
      case 4: return 3;
      case 3: return 4;
      case 2: return 5;
      default: return 6;
    }
  };
  int worst = 0;
  for (const JobRecord& r : records)
    if (rank(r.exit_code) > rank(worst)) worst = r.exit_code;
  return worst;
}

std::string job_record_json(const JobRecord& r) {
  nlohmann::ordered_json j;
  j["id"] = r.id;
  j["status"] = r.status;
  j["reason"] = r.reason;
  j["exit_code"] = r.exit_code;
  for (const auto* list : {&r.inputs, &r.obstacles}) {
    nlohmann::ordered_json files = nlohmann::ordered_json::array();
    for (const HashedFile& f : *list) files.push_back({{"path", f.path}, {"sha256", f.sha256}});
    j[list == &r.inputs ? "inputs" : "obstacles"] = files;
  }
  j["options"] = {{"method", r.options.method},
                  {"clearance", r.options.clearance},
                  {"max_iterations", r.options.max_iterations},
                  {"outside_closed_obstacles", r.options.outside_closed_obstacles}};
  j["outputs"] = r.outputs;
  j["time_ms"] = r.time_ms;
  return j.dump(2) + "\n";
}

bool read_job_record(const std::string& path, JobRecord& r) {
  const nlohmann::json j = nlohmann::json::parse(read_text(path), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return false;
  try {
    r.id = j.at("id").get<std::string>();
    r.status = j.at("status").get<std::string>();
    r.reason = j.at("reason").get<std::string>();
    r.exit_code = j.at("exit_code").get<int>();
    r.inputs.clear();
    r.obstacles.clear();
    for (const auto& f : j.at("inputs")) r.inputs.push_back({f.at("path"), f.at("sha256")});
    for (const auto& f : j.at("obstacles")) r.obstacles.push_back({f.at("path"), f.at("sha256")});
    const auto& opt = j.at("options");
    r.options.method = opt.at("method").get<std::string>();
    r.options.clearance = opt.at("clearance").get<double>();
    r.options.max_iterations = opt.at("max_iterations").get<int>();
    r.options.outside_closed_obstacles = opt.at("outside_closed_obstacles").get<bool>();
    r.outputs = j.at("outputs").get<std::vector<std::string>>();
    r.time_ms = j.at("time_ms").get<double>();
  } catch (const nlohmann::json::exception&) {
    return false;
  }
  return true;
}

std::vector<JobRecord> run_jobs(const std::vector<const BatchJob*>& jobs,
                                const std::vector<JobRecord>& prepared, const std::string& exe,
                                const BatchOptions& o, int parallel, const JobDone& done) {
  std::vector<JobRecord> records = prepared;
  std::vector<Running> running;
  std::size_t next = 0;
  const auto limit = std::chrono::duration<double>(o.time_limit);
  while (next < jobs.size() || !running.empty()) {
    while (next < jobs.size() && static_cast<int>(running.size()) < parallel) {
      const BatchJob& job = *jobs[next];
      const JobFiles files = job_files(job);
      const std::vector<std::string> args = job_command(exe, job, o.output_dir, o);
      Running r;
      r.index = next++;
      r.log_tmp = (fs::path(o.output_dir) / files.folder / ".log.txt.tmp").string();
      const std::string fault = test_fault(job.id);
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      const int log = ::open(r.log_tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
      if (log < 0) throw Error(ExitCode::kOutputNotWritten, r.log_tmp, std::strerror(errno));
      std::fflush(stdout);
      std::fflush(stderr);
      r.start = Clock::now();
      r.pid = ::fork();
      if (r.pid < 0) throw Error(ExitCode::kInternal, "", std::string("fork: ") + std::strerror(errno));
      if (r.pid == 0) {
        // The child: only async-signal-safe calls until exec. It stays in the batch's process
        // group, so that Ctrl-C on the batch stops its jobs too.
        const int null = ::open("/dev/null", O_RDONLY);
        if (null >= 0) ::dup2(null, 0);
        ::dup2(log, 1);
        ::dup2(log, 2);
        if (fault == "crash") {
          const struct rlimit no_core = {0, 0};
          ::setrlimit(RLIMIT_CORE, &no_core);
          // The default action, not a handler the process installed (AddressSanitizer's turns
          // the signal into exit 1): the job dies by the signal, as a real crash would.
          struct sigaction by_default {};
          by_default.sa_handler = SIG_DFL;
          ::sigaction(SIGSEGV, &by_default, nullptr);
          ::raise(SIGSEGV);
        }
        if (fault == "hang")
          for (;;) ::pause();
        ::execv(argv[0], argv.data());
        static const char kMessage[] = "error: cannot run the untangle binary\n";
        (void)!::write(2, kMessage, sizeof kMessage - 1);
        ::_exit(1);
      }
      ::close(log);
      running.push_back(r);
    }
    bool any = false;
    for (std::size_t k = 0; k < running.size();) {
      Running& r = running[k];
      int status = 0;
      const pid_t got = ::waitpid(r.pid, &status, WNOHANG);
      const bool timed_out = got == 0 && Clock::now() - r.start > limit;
      if (got == 0 && !timed_out) {
        ++k;
        continue;
      }
      if (timed_out) {
        ::kill(r.pid, SIGKILL);
        ::waitpid(r.pid, &status, 0);
      }
      any = true;
      const BatchJob& job = *jobs[r.index];
      const JobFiles files = job_files(job);
      JobRecord& rec = records[r.index];
      rec.time_ms = std::chrono::duration<double, std::milli>(Clock::now() - r.start).count();
      const std::string log = (fs::path(o.output_dir) / files.log).string();
      std::error_code ec;
      fs::rename(r.log_tmp, log, ec);
      const std::string error = last_error(read_text(log));
      int fix_exit = -1;
      rec.status = "failed";
      if (timed_out) {
        rec.reason = "time limit (" + format_number(o.time_limit) + " s)";
      } else if (WIFSIGNALED(status)) {
        rec.reason = "crash (signal " + std::to_string(WTERMSIG(status)) + ")";
      } else {
        fix_exit = WEXITSTATUS(status);
        const std::string report = (fs::path(o.output_dir) / files.report).string();
        const nlohmann::json j = nlohmann::json::parse(read_text(report), nullptr, false);
        const bool reported = fs::exists(report, ec) && j.is_object() && j.contains("status") &&
                              j["status"].is_string();
        const bool finished = fix_exit == 0 || fix_exit == 5 || fix_exit == 6;
        if (finished && reported) {
          rec.status = j["status"].get<std::string>();
        } else if (finished) {
          rec.reason = "no report written";
        } else {
          const char* kind = fix_exit == 3   ? "unreadable input"
                             : fix_exit == 4 ? "output not written"
                             : fix_exit == 2 ? "usage error"
                                             : "internal error";
          rec.reason = std::string(kind) + (error.empty() ? "" : ": " + error);
        }
      }
      rec.exit_code = job_exit_code(rec.status, fix_exit);
      if (rec.status != "failed") rec.outputs = files.outputs;
      write_text_file_atomically((fs::path(o.output_dir) / files.record).string(),
                                 job_record_json(rec));
      if (done) done(rec);
      running.erase(running.begin() + static_cast<std::ptrdiff_t>(k));
    }
    if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return records;
}

}  // namespace untangle::app
