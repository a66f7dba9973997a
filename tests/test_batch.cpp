// `untangle batch` end to end: jobs in their own processes (a crash and a hang do not stop the
// others), --resume, the folder layouts, manifest errors, output safety, the summary checked against
// `check` and `sha256sum` run on the files, and the emitted Slurm / GNU parallel scripts.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "scenes/scenes.h"
#include "test_support.h"

namespace untangle {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;
using testing::write_text;

// A generous limit for the jobs that finish (each takes a fraction of a second), so that a slow or
// sanitized build never reaches it; the hanging job waits for it.
#if defined(__SANITIZE_ADDRESS__)
constexpr const char* kTimeLimit = "30";
#else
constexpr const char* kTimeLimit = "5";
#endif

// Job folders job-00 ... job-<n-1> under `dir` (the subfolder layout): the sheet through the
// sphere, the whole scene moved by 0.25 * k along x so that every job's files are different (a
// sheet moved against the sphere may end unresolved, which is fix's business, not this test's).
// How such a job finishes: intersection-free, but the sheet's disc inside the sphere moves 0.23
// of the sheet's diagonal, beyond fix's default --max-move, so distorted (exit 6).
constexpr const char* kFinished = "distorted";

void write_jobs(const fs::path& dir, int n) {
  for (int k = 0; k < n; ++k) {
    scenes::Scene scene = scenes::sheet_through_sphere();
    for (auto* meshes : {&scene.movable, &scene.obstacles})
      for (Mesh& m : *meshes)
        for (Vec3& p : m.positions) p[0] += 0.25 * k;
    char id[16];
    std::snprintf(id, sizeof id, "job-%02d", k);
    scenes::write_scene_files(scene, (dir / id).string());
  }
}

std::string sha256sum(const std::string& path) {
  TempDir dir;
  const std::string out = dir.file("sum.txt");
  const int rc = std::system(("sha256sum " + quote(path) + " >" + quote(out)).c_str());
  EXPECT_EQ(rc, 0);
  return read_text(out).substr(0, 64);
}

nlohmann::json check_report(const std::string& mesh, const std::string& obstacle) {
  const auto r = run_cli("check " + quote(mesh) + " --obstacle " + quote(obstacle) + " --report -");
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 5) << r.err;
  return nlohmann::json::parse(r.out);
}

nlohmann::json summary_of(const fs::path& out) {
  return nlohmann::json::parse(read_text((out / "summary.json").string()));
}

// The summary without what may differ between two runs of the same jobs: times, and whether a
// record was kept by --resume.
nlohmann::json without_times(nlohmann::json j) {
  j["totals"].erase("time_ms");
  j["totals"].erase("resumed");
  for (auto& job : j["jobs"]) {
    job.erase("time_ms");
    job.erase("resumed");
  }
  return j;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Issue 22 §4: twenty jobs, one crashing its worker and one hanging (the test hook): the others
// finish, the two are reported with their cause, the exit code says failure, and --resume reruns
// only those two.
TEST(Batch, CrashAndHangStopNoOtherJobAndResumeRerunsOnlyThem) {
  TempDir dir;
  const fs::path in = dir.path() / "in", out = dir.path() / "out";
  write_jobs(in, 20);
  fs::create_directories(out);
  const std::string command = "batch " + quote(in.string()) + " --output-dir " + quote(out.string()) +
                              " --jobs 2 --time-limit " + kTimeLimit;
  const std::string env_command = "UNTANGLE_BATCH_TEST_FAULT=hang:job-01,crash:job-07 " +
                                  quote(UNTANGLE_BINARY) + " " + command;
  TempDir logs;
  const int status = std::system((env_command + " >" + quote(logs.file("out.txt")) + " 2>" +
                                  quote(logs.file("err.txt")))
                                     .c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << read_text(logs.file("err.txt"));  // a crash: exit 1
  // Not a terminal: one line per job.
  EXPECT_EQ(count(read_text(logs.file("out.txt")), "] job-"), 20u) << read_text(logs.file("out.txt"));

  const nlohmann::json s = summary_of(out);
  EXPECT_EQ(s["command"], "batch");
  EXPECT_EQ(s["layout"], "subfolders");
  EXPECT_EQ(s["status"], "failed");
  EXPECT_EQ(s["exit_code"], 1);
  EXPECT_EQ(s["totals"]["jobs"], 20);
  EXPECT_EQ(s["totals"]["distorted"], 18);
  EXPECT_EQ(s["totals"]["failed"], 2);
  ASSERT_EQ(s["jobs"].size(), 20u);
  for (std::size_t k = 0; k < 20; ++k) {
    const nlohmann::json& job = s["jobs"][k];
    char id[16];
    std::snprintf(id, sizeof id, "job-%02zu", k);
    EXPECT_EQ(job["id"], id);  // sorted by id
    const std::string movable = (in / id / "movable_0.obj").string();
    const std::string obstacle = (in / id / "obstacle_0.obj").string();
    // The recorded hashes are those of the files, computed by another program.
    EXPECT_EQ(job["inputs"][0]["path"], movable);
    EXPECT_EQ(job["inputs"][0]["sha256"], sha256sum(movable));
    EXPECT_EQ(job["obstacles"][0]["sha256"], sha256sum(obstacle));
    if (k == 1 || k == 7) {
      EXPECT_EQ(job["status"], "failed") << id;
      EXPECT_EQ(job["reason"], k == 1 ? std::string("time limit (") + kTimeLimit + " s)"
                                      : std::string("crash (signal 11)"))
          << id;
      EXPECT_EQ(job["exit_code"], 1);
      EXPECT_TRUE(job["outputs"].empty());
      EXPECT_TRUE(job["before"].is_null());
      continue;
    }
    EXPECT_EQ(job["status"], kFinished) << id << ": " << job["reason"];
    EXPECT_EQ(job["reason"], "");
    ASSERT_EQ(job["outputs"].size(), 1u);
    // The numbers agree with `check` run on the input and on the written output.
    const std::string written = (out / job["outputs"][0].get<std::string>()).string();
    EXPECT_EQ(written, (out / "jobs" / id / "movable_0.obj").string());
    const nlohmann::json before = check_report(movable, obstacle);
    const nlohmann::json after = check_report(written, obstacle);
    EXPECT_GT(job["before"]["crossings"].get<int>(), 0);
    EXPECT_EQ(job["before"]["crossings"], before["before"]["crossings"]) << id;
    EXPECT_EQ(job["before"]["inside_vertices"], before["before"]["inside_vertices"]) << id;
    EXPECT_EQ(job["after"]["crossings"], after["before"]["crossings"]) << id;
    EXPECT_EQ(job["after"]["inside_vertices"], after["before"]["inside_vertices"]) << id;
    EXPECT_EQ(after["status"], "clean") << id;
    EXPECT_EQ(job["quality"].size(), 1u);
    EXPECT_TRUE(fs::is_regular_file(out / job["preview"].get<std::string>())) << id;
    EXPECT_TRUE(fs::is_regular_file(out / job["log"].get<std::string>())) << id;
  }
  // The page: one row per job, thumbnails by relative links that exist, no external resource.
  const std::string html = read_text((out / "summary.html").string());
  EXPECT_EQ(count(html, "<tr><td>"), 20u);
  EXPECT_EQ(count(html, "<img src=\"jobs/"), 18u);
  EXPECT_EQ(count(html, "http"), 0u);
  EXPECT_EQ(count(html, "data-key=\"0\">failed"), 2u);
  const std::string md = read_text((out / "summary.md").string());
  EXPECT_NE(md.find("| job-07 | failed: crash (signal 11) |"), std::string::npos) << md;

  // --resume without the hook: only the two failed jobs run again, and now all finish.
  const auto again = run_cli(command + " --resume");
  EXPECT_EQ(again.exit_code, 6) << again.err << again.out;
  EXPECT_NE(again.out.find("kept 18 jobs"), std::string::npos) << again.out;
  EXPECT_EQ(count(again.out, "] job-"), 2u) << again.out;
  EXPECT_NE(again.out.find("job-01: distorted"), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("job-07: distorted"), std::string::npos) << again.out;
  const nlohmann::json r = summary_of(out);
  EXPECT_EQ(r["totals"]["distorted"], 20);
  EXPECT_EQ(r["totals"]["resumed"], 18);
  for (const auto& job : r["jobs"])
    EXPECT_EQ(job["resumed"], job["id"] != "job-01" && job["id"] != "job-07") << job["id"];
  // The kept jobs' entries are as before, times included (they were not run again).
  for (std::size_t k = 0; k < 20; ++k) {
    if (k == 1 || k == 7) continue;
    nlohmann::json was = s["jobs"][k], now = r["jobs"][k];
    was.erase("resumed");
    now.erase("resumed");
    EXPECT_EQ(was, now) << k;
  }

  // A changed input byte is run again; the others are kept.
  write_text((in / "job-03" / "movable_0.obj").string(),
             read_text((in / "job-03" / "movable_0.obj").string()) + "# changed\n");
  const auto third = run_cli(command + " --resume");
  EXPECT_EQ(third.exit_code, 6) << third.err;
  EXPECT_EQ(count(third.out, "] job-"), 1u) << third.out;
  EXPECT_NE(third.out.find("job-03: distorted"), std::string::npos) << third.out;
}

// The MakeHuman layout: testdata/makehuman as shipped (bodies *_generic.obj beside the garments),
// and the garments/ + bodies/ folders.
TEST(Batch, MakeHumanLayouts) {
  TempDir dir;
  const std::string data = std::string(UNTANGLE_SOURCE_DIR) + "/testdata/makehuman";
  const auto r = run_cli("batch " + quote(data) + " --output-dir " + quote(dir.path().string()) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  const nlohmann::json s = summary_of(dir.path());
  EXPECT_EQ(s["layout"], "makehuman");
  ASSERT_EQ(s["jobs"].size(), 1u);
  const nlohmann::json& job = s["jobs"][0];
  EXPECT_EQ(job["id"], "male_casualsuit04");
  EXPECT_EQ(job["status"], "clean");
  EXPECT_EQ(job["obstacles"][0]["path"], data + "/male_generic.obj");
  const std::string written = (dir.path() / job["outputs"][0].get<std::string>()).string();
  const nlohmann::json after = check_report(written, data + "/male_generic.obj");
  EXPECT_EQ(after["status"], "clean");
  EXPECT_EQ(job["before"]["crossings"],
            check_report(data + "/male_casualsuit04.obj", data + "/male_generic.obj")["before"]["crossings"]);

  // garments/ and bodies/: planned only (--emit runs nothing): one job line per garment with a
  // body, the garment without one left out.
  const fs::path folder = dir.path() / "mh";
  fs::create_directories(folder / "garments");
  fs::create_directories(folder / "bodies");
  fs::copy_file(data + "/male_casualsuit04.obj", folder / "garments" / "male_casualsuit04.obj");
  fs::copy_file(data + "/male_casualsuit04.obj", folder / "garments" / "female_dress.obj");
  fs::copy_file(data + "/male_generic.obj", folder / "bodies" / "male_generic.obj");
  const fs::path out = dir.path() / "mh_out";
  fs::create_directories(out);
  const auto e = run_cli("batch " + quote(folder.string()) + " --output-dir " + quote(out.string()) +
                         " --emit parallel -q");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const std::string lines = read_text((out / "parallel_jobs.txt").string());
  EXPECT_EQ(count(lines, "--only-job "), 1u) << lines;
  EXPECT_TRUE(fs::is_directory(out / "jobs" / "male_casualsuit04"));
  EXPECT_FALSE(fs::exists(out / "jobs" / "female_dress"));
}

// A bad manifest: exit 3, one line naming the file and the key, nothing written.
TEST(Batch, ManifestErrorsNameTheKey) {
  TempDir dir;
  write_text(dir.file("a.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string manifest = dir.file("m.json");
  struct Case {
    const char* json;
    const char* key;
  };
  const Case cases[] = {
      {R"({"jobs": [{"inputs": ["a.obj"], "inptus": []}]})", "'jobs[0].inptus': unknown key"},
      {R"({"job": []})", "'job': unknown key"},
      {R"({"options": {}})", "'jobs': missing"},
      {R"({"jobs": []})", "'jobs': must be a non-empty array"},
      {R"({"jobs": [{"obstacles": ["a.obj"]}]})", "'jobs[0].inputs': missing"},
      {R"({"jobs": [{"inputs": "a.obj"}]})", "'jobs[0].inputs': must be an array"},
      {R"({"jobs": [{"inputs": ["a.obj"]}, {"inputs": ["a.obj"]}]})", "'jobs[1].id': 'a' names two jobs"},
      {R"({"jobs": [{"id": "../x", "inputs": ["a.obj"]}]})", "'jobs[0].id': must be a string"},
      {R"({"jobs": [{"inputs": ["a.obj"], "options": {"method": "fast"}}]})", "'jobs[0].options.method'"},
      {R"({"options": {"clearance": -1}, "jobs": [{"inputs": ["a.obj"]}]})", "'options.clearance'"},
      {R"({"jobs": [{"inputs": ["a.obj"], "options": {"max_iterations": 1.5}}]})", "'jobs[0].options.max_iterations'"},
      {R"({"jobs": [{"inputs": ["a.obj"], "options": {"step": 1}}]})", "'jobs[0].options.step': unknown key"},
      {R"({"jobs": [)", "not a JSON manifest"},
  };
  const fs::path out = dir.path() / "out";
  fs::create_directories(out);
  for (const Case& c : cases) {
    write_text(manifest, c.json);
    const auto r = run_cli("batch " + quote(manifest) + " --output-dir " + quote(out.string()));
    EXPECT_EQ(r.exit_code, 3) << c.json;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("error: " + manifest + ": "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.key), std::string::npos) << c.json << "\n" << r.err;
    EXPECT_TRUE(fs::is_empty(out)) << c.json;
  }
  // A usage error: --only-job names no job.
  write_text(manifest, R"({"jobs": [{"inputs": ["a.obj"]}]})");
  const auto u = run_cli("batch " + quote(manifest) + " --output-dir " + quote(out.string()) + " --only-job 1");
  EXPECT_EQ(u.exit_code, 2) << u.err;
  EXPECT_TRUE(fs::is_empty(out));
}

// Every file of every job is checked before any job starts: a clash is exit 4 naming both files,
// and nothing is written (not even the job folders).
TEST(Batch, OutputClashesRefusedBeforeAnyJob) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  write_jobs(dir.path() / "in", 1);
  fs::create_directories(out / "jobs" / "inside");
  // An input where its own output would go.
  fs::copy_file(dir.path() / "in" / "job-00" / "movable_0.obj", out / "jobs" / "inside" / "movable_0.obj");
  const std::string ob = (dir.path() / "in" / "job-00" / "obstacle_0.obj").string();
  write_text(dir.file("m.json"), "{\"jobs\": [{\"id\": \"inside\", \"inputs\": [" +
                                     nlohmann::json((out / "jobs" / "inside" / "movable_0.obj").string()).dump() +
                                     "], \"obstacles\": [" + nlohmann::json(ob).dump() +
                                     "]}, {\"id\": \"other\", \"inputs\": [\"in/job-00/movable_0.obj\"]}]}");
  const auto r = run_cli("batch " + quote(dir.file("m.json")) + " --output-dir " + quote(out.string()) + " --overwrite");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("job inside: output"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("never overwrites what it reads"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "jobs" / "other"));
  EXPECT_FALSE(fs::exists(out / "summary.json"));

  // A summary left by an earlier run is kept without --overwrite.
  const fs::path out2 = dir.path() / "out2";
  fs::create_directories(out2);
  write_text((out2 / "summary.json").string(), "{}");
  const auto s = run_cli("batch " + quote((dir.path() / "in").string()) + " --output-dir " + quote(out2.string()));
  EXPECT_EQ(s.exit_code, 4) << s.err;
  EXPECT_NE(s.err.find("summary.json exists; pass --overwrite"), std::string::npos) << s.err;
  EXPECT_EQ(read_text((out2 / "summary.json").string()), "{}");
  EXPECT_FALSE(fs::exists(out2 / "jobs"));
  // A missing output folder.
  const auto m = run_cli("batch " + quote((dir.path() / "in").string()) + " --output-dir " +
                         quote((dir.path() / "nowhere").string()));
  EXPECT_EQ(m.exit_code, 4) << m.err;
}

// A job whose input cannot be read fails with that reason; the others run; exit 3.
TEST(Batch, UnreadableInputFailsOnlyItsJob) {
  TempDir dir;
  write_jobs(dir.path() / "in", 2);
  write_text((dir.path() / "in" / "job-01" / "movable_0.obj").string(), "v 0 0 nan\n");
  const fs::path out = dir.path() / "out";
  fs::create_directories(out);
  const auto r = run_cli("batch " + quote((dir.path() / "in").string()) + " --output-dir " + quote(out.string()) +
                         " --report -");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  const nlohmann::json s = nlohmann::json::parse(r.out);  // stdout carries only the summary
  EXPECT_EQ(s, summary_of(out));
  EXPECT_EQ(s["jobs"][0]["status"], kFinished);
  EXPECT_EQ(s["jobs"][1]["status"], "failed");
  EXPECT_EQ(s["jobs"][1]["exit_code"], 3);
  EXPECT_EQ(s["jobs"][1]["reason"].get<std::string>().rfind("unreadable input: ", 0), 0u) << s["jobs"][1]["reason"];
}

// --emit writes scripts and runs nothing; running their command lines one by one and then the
// gather step gives the summary of a local run (times aside).
TEST(Batch, EmittedScriptsGiveTheSummaryOfALocalRun) {
  TempDir dir;
  const fs::path in = dir.path() / "in";
  write_jobs(in, 3);
  const fs::path local = dir.path() / "local", slurm = dir.path() / "slurm", par = dir.path() / "par";
  for (const fs::path& p : {local, slurm, par}) fs::create_directories(p);
  const auto l = run_cli("batch " + quote(in.string()) + " --output-dir " + quote(local.string()) + " -q");
  ASSERT_EQ(l.exit_code, 6) << l.err;

  const auto e = run_cli("batch " + quote(in.string()) + " --output-dir " + quote(slurm.string()) +
                         " --emit slurm --jobs 2 --time-limit 90 --partition debug");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_FALSE(fs::exists(slurm / "summary.json"));
  EXPECT_FALSE(fs::exists(slurm / "jobs" / "job-00" / "job.json"));
  const std::string script = read_text((slurm / "batch.sbatch").string());
  EXPECT_NE(script.find("#SBATCH --array=0-2%2\n"), std::string::npos) << script;
  EXPECT_NE(script.find("#SBATCH --time=0-00:02:30\n"), std::string::npos) << script;
  EXPECT_NE(script.find("#SBATCH --partition=debug\n"), std::string::npos) << script;
  EXPECT_NE(script.find("--only-job \"$SLURM_ARRAY_TASK_ID\""), std::string::npos) << script;
  EXPECT_NE(read_text((slurm / "submit.sh").string()).find("--dependency=afterany:"), std::string::npos);
  // Each array task as Slurm would start it, then the gather step.
  for (int k = 0; k < 3; ++k) {
    const std::string task = "SLURM_ARRAY_TASK_ID=" + std::to_string(k) + " bash " +
                             quote((slurm / "batch.sbatch").string()) + " >/dev/null 2>&1";
    // A task that ran its job to a verdict (distorted here) succeeded; the summary says how.
    const int status = std::system(task.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << k << ": " << status;
  }
  // The gather exits with the batch's code: 6, every job distorted.
  ASSERT_EQ(WEXITSTATUS(std::system(("bash " + quote((slurm / "gather.sbatch").string())).c_str())), 6);
  // The source and inputs are named by absolute paths in the scripts, as in the local run here.
  EXPECT_EQ(without_times(summary_of(slurm)), without_times(summary_of(local)));

  const auto p = run_cli("batch " + quote(in.string()) + " --output-dir " + quote(par.string()) +
                         " --emit parallel --jobs 2");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  const std::string run = read_text((par / "parallel.sh").string());
  EXPECT_NE(run.find("parallel --jobs 2 --joblog "), std::string::npos) << run;
  const std::string lines = read_text((par / "parallel_jobs.txt").string());
  EXPECT_EQ(count(lines, "\n"), 3u);
  std::size_t start = 0;
  for (std::size_t end = lines.find('\n'); end != std::string::npos; start = end + 1, end = lines.find('\n', start))
    EXPECT_EQ(WEXITSTATUS(std::system(lines.substr(start, end - start).c_str())), 0);
  const std::string gather = run.substr(run.find("exec ") + 5);
  ASSERT_EQ(WEXITSTATUS(std::system(gather.c_str())), 6);
  EXPECT_EQ(without_times(summary_of(par)), without_times(summary_of(local)));

  // A gather before the jobs ran reports them failed, with the reason.
  const fs::path early = dir.path() / "early";
  fs::create_directories(early);
  const auto g = run_cli("batch " + quote(in.string()) + " --output-dir " + quote(early.string()) + " --gather -q");
  EXPECT_EQ(g.exit_code, 1);
  EXPECT_EQ(summary_of(early)["totals"]["failed"], 3);
}

// Issue 22 §5: the emitted parallel.sh run by GNU parallel itself (Debian's `parallel`) gives the
// summary and meshes of a local batch (times aside); its joblog shows as failed exactly the job the
// summary lists as failed (an unreadable input, exit 3) and the others, which ran to a verdict
// (distorted), as exit 0; parallel.sh exits with the gathered batch's status, as the local run.
TEST(Batch, GnuParallelScriptGivesTheSummaryOfALocalRun) {
  if (std::system("command -v parallel >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "GNU parallel is not installed (Debian package parallel, scripts/setup.sh)";
  TempDir dir;
  const fs::path in = dir.path() / "in", local = dir.path() / "local", par = dir.path() / "par";
  write_jobs(in, 4);
  write_text((in / "job-02" / "movable_0.obj").string(), "v 0 0 nan\n");
  for (const fs::path& p : {local, par}) fs::create_directories(p);
  const auto l = run_cli("batch " + quote(in.string()) + " --output-dir " + quote(local.string()) +
                         " --jobs 2 -q");
  ASSERT_EQ(l.exit_code, 3) << l.err;
  const auto e = run_cli("batch " + quote(in.string()) + " --output-dir " + quote(par.string()) +
                         " --emit parallel --jobs 2 -q");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  TempDir logs;
  const int status = std::system(("sh " + quote((par / "parallel.sh").string()) + " >" +
                                  quote(logs.file("out.txt")) + " 2>" + quote(logs.file("err.txt")))
                                     .c_str());
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 3) << read_text(logs.file("err.txt"));
  const nlohmann::json a = without_times(summary_of(local)), b = without_times(summary_of(par));
  EXPECT_EQ(a["totals"]["jobs"], 4);
  EXPECT_EQ(a["totals"]["distorted"], 3);
  EXPECT_EQ(a["totals"]["failed"], 1);
  EXPECT_EQ(b, a);
  for (const auto& job : a["jobs"]) {
    for (const auto& p : job["outputs"]) {
      const std::string rel = p.get<std::string>();
      EXPECT_EQ(read_text((par / rel).string()), read_text((local / rel).string())) << rel;
    }
  }
  // The joblog: a header, then one line per job (Seq Host Starttime JobRuntime Send Receive
  // Exitval Signal Command, tab-separated), in the order the jobs ended.
  const std::string joblog = read_text((par / "parallel.joblog").string());
  std::istringstream lines(joblog);
  std::string line;
  ASSERT_TRUE(static_cast<bool>(std::getline(lines, line))) << joblog;
  EXPECT_EQ(line.rfind("Seq\tHost\tStarttime\tJobRuntime\tSend\tReceive\tExitval\tSignal\tCommand", 0), 0u) << line;
  std::set<int> seen;
  while (std::getline(lines, line)) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, '\t');) fields.push_back(cell);
    ASSERT_EQ(fields.size(), 9u) << line;
    const std::size_t at = fields[8].find("--only-job ");
    ASSERT_NE(at, std::string::npos) << line;
    const int k = std::stoi(fields[8].substr(at + 11));
    seen.insert(k);
    EXPECT_EQ(fields[6], k == 2 ? "3" : "0") << line;  // Exitval
    EXPECT_EQ(fields[7], "0") << line;                 // no signal
  }
  EXPECT_EQ(seen, (std::set<int>{0, 1, 2, 3})) << joblog;
}

// The thumbnails: fix --preview-size sets each of the preview's three panels; a bad size is a
// usage error before any work.
TEST(Batch, PreviewSizeSetsEachPanel) {
  TempDir dir;
  write_jobs(dir.path() / "in", 1);
  const std::string job = (dir.path() / "in" / "job-00").string();
  const std::string args = "fix " + quote(job + "/movable_0.obj") + " --obstacle " +
                           quote(job + "/obstacle_0.obj") + " --output-dir " + quote(dir.path().string()) +
                           " --preview " + quote(dir.path().string()) + " -q --preview-size ";
  const auto r = run_cli(args + "48x32");
  ASSERT_EQ(r.exit_code, 6) << r.err;
  const std::string png = read_text(dir.file("movable_0_before_after.png"));
  ASSERT_GE(png.size(), 24u);
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(be32(16), 3 * 48);  // before, after, displacement side by side
  EXPECT_EQ(be32(20), 32);
  const auto bad = run_cli(args + "48 --overwrite");
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("--preview-size 48: expected WxH"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace untangle
