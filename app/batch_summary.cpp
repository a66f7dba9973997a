// Writes what a batch did, per job and in total, as JSON (for pipelines), Markdown (for people)
// and one self-contained HTML page with thumbnails (issue 23, "The batch report").
#include "batch_summary.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "batch_run.h"
#include "plot.h"
#include "untangle/version.h"

namespace untangle::app {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

constexpr int kSummarySchemaVersion = 1;

Json read_report(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Json();
  std::ostringstream s;
  s << in.rdbuf();
  Json j = Json::parse(s.str(), nullptr, false);
  return j.is_discarded() || !j.is_object() ? Json() : j;
}

Json counts_of(const Json& counts) {
  Json c;
  c["crossings"] = counts.value("crossings", 0);
  c["inside_vertices"] = counts.value("inside_vertices", 0);
  return c;
}

std::string md_escape(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string number(double x, const char* format = "%.3g") { return fmt(format, x); }

// "12 -> 0" for a job's before and after, "" when it did not finish.
std::string before_after(const Json& job, const char* key) {
  if (job["before"].is_null()) return "";
  return std::to_string(job["before"][key].get<long long>()) + " -> " +
         std::to_string(job["after"][key].get<long long>());
}

// The largest edge_change_max and the total flipped faces over the job's movable meshes.
std::pair<double, long long> quality_of(const Json& job) {
  double edge = 0.0;
  long long flipped = 0;
  for (const Json& q : job["quality"]) {
    edge = std::max(edge, q.value("edge_change_max", 0.0));
    flipped += q.value("flipped_faces", 0LL);
  }
  return {edge, flipped};
}

constexpr const char* kHtmlHead = R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>untangle batch</title>
<style>
body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse}
th,td{border:1px solid #ccc;padding:4px 8px;text-align:left;vertical-align:middle}
th{background:#eee;cursor:pointer}td.n{text-align:right}
.clean{color:#1a7f37}.distorted{color:#8250df}.unresolved{color:#b35900}.failed{color:#c00;font-weight:bold}
img{display:block;max-width:600px}
</style></head><body>
)";

// Sorting: a click on a header sorts by that column (data-key when present, else the text), again
// the other way round; status sorts failed, unresolved, distorted, clean.
constexpr const char* kHtmlScript = R"(<script>
document.querySelectorAll('th').forEach(function(th, col){
  th.addEventListener('click', function(){
    var body = th.closest('table').tBodies[0];
    var rows = Array.prototype.slice.call(body.rows);
    var down = th.getAttribute('data-down') !== '1';
    th.setAttribute('data-down', down ? '1' : '0');
    function key(row){ var c = row.cells[col]; var k = c.getAttribute('data-key');
      return k !== null ? k : c.textContent; }
    rows.sort(function(a, b){
      var x = key(a), y = key(b), nx = parseFloat(x), ny = parseFloat(y);
      var r = (!isNaN(nx) && !isNaN(ny)) ? nx - ny : (x < y ? -1 : x > y ? 1 : 0);
      return down ? r : -r; });
    rows.forEach(function(r){ body.appendChild(r); });
  });
});
</script>
)";

}  // namespace

BatchSummary make_summary(const BatchOptions& o, const BatchPlan& plan,
                          const std::vector<JobRecord>& records) {
  BatchSummary summary;
  summary.exit_code = worst_exit_code(records);
  Json jobs = Json::array();
  std::size_t clean = 0, distorted = 0, unresolved = 0, failed = 0, resumed = 0;
  double total_ms = 0.0;
  for (std::size_t k = 0; k < plan.jobs.size(); ++k) {
    const JobRecord& r = records[k];
    const JobFiles files = job_files(plan.jobs[k]);
    Json j = Json::parse(job_record_json(r));
    j["resumed"] = r.resumed;
    const bool finished = r.status != "failed";
    const Json report = finished ? read_report((fs::path(o.output_dir) / files.report).string()) : Json();
    j["report"] = report.is_null() ? Json() : Json(files.report);
    j["preview"] = finished && fs::exists(fs::path(o.output_dir) / files.preview) ? Json(files.preview) : Json();
    j["log"] = files.log;
    j["before"] = report.is_null() ? Json() : counts_of(report["before"]);
    j["after"] = report.is_null() ? Json() : counts_of(report["after"]);
    j["iterations"] = report.is_null() ? Json() : report["iterations"];
    j["quality"] = report.is_null() ? Json::array() : report["quality"];
    j.erase("time_ms");
    j["time_ms"] = r.time_ms;  // last: the only value that differs between two runs
    clean += r.status == "clean";
    distorted += r.status == "distorted";
    unresolved += r.status == "unresolved";
    failed += r.status == "failed";
    resumed += r.resumed;
    total_ms += r.time_ms;
    jobs.push_back(j);
  }
  const char* status = failed > 0       ? "failed"
                       : unresolved > 0 ? "unresolved"
                       : distorted > 0  ? "distorted"
                                        : "clean";
  Json top;
  top["schema_version"] = kSummarySchemaVersion;
  top["untangle_version"] = untangle_version();
  top["command"] = "batch";
  top["source"] = o.source;
  top["layout"] = plan.layout;
  top["status"] = status;
  top["exit_code"] = summary.exit_code;
  top["totals"] = {{"jobs", plan.jobs.size()}, {"clean", clean}, {"distorted", distorted},
                   {"unresolved", unresolved},
                   {"failed", failed}, {"resumed", resumed}, {"time_ms", total_ms}};
  top["jobs"] = jobs;
  summary.json = top.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";

  const std::string totals = std::to_string(plan.jobs.size()) + " jobs: " + std::to_string(clean) +
                             " clean, " + std::to_string(distorted) + " distorted, " +
                             std::to_string(unresolved) + " unresolved, " +
                             std::to_string(failed) + " failed (" + std::to_string(resumed) +
                             " kept from an earlier run)";
  std::ostringstream md;
  md << "# untangle batch: " << md_escape(o.source) << "\n\n"
     << "Status **" << status << "** (exit " << summary.exit_code << "); " << totals << ".\n\n"
     << "| job | status | crossings | inside vertices | max edge change | flipped faces | time (s) | outputs |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  std::ostringstream rows;
  for (const Json& j : jobs) {
    const std::string st = j["status"].get<std::string>();
    const std::string why = j["reason"].get<std::string>();
    const auto [edge, flipped] = quality_of(j);
    const bool numbers = !j["before"].is_null();
    std::string outputs;
    for (const Json& p : j["outputs"]) outputs += (outputs.empty() ? "" : ", ") + p.get<std::string>();
    md << "| " << md_escape(j["id"].get<std::string>()) << " | " << st
       << (why.empty() ? "" : ": " + md_escape(why)) << " | " << before_after(j, "crossings") << " | "
       << before_after(j, "inside_vertices") << " | " << (numbers ? number(edge) : "") << " | "
       << (numbers ? std::to_string(flipped) : "") << " | " << number(j["time_ms"].get<double>() / 1000.0, "%.2f")
       << " | " << md_escape(outputs) << " |\n";
    const int rank = st == "failed" ? 0 : st == "unresolved" ? 1 : st == "distorted" ? 2 : 3;
    rows << "<tr><td>" << xml_escaped(j["id"].get<std::string>()) << "</td><td class=\"" << st
         << "\" data-key=\"" << rank << "\">" << st << (why.empty() ? "" : ": " + xml_escaped(why))
         << "</td><td class=\"n\">" << xml_escaped(before_after(j, "crossings")) << "</td><td class=\"n\">"
         << xml_escaped(before_after(j, "inside_vertices")) << "</td><td class=\"n\">"
         << (numbers ? number(edge) : "") << "</td><td class=\"n\">"
         << (numbers ? std::to_string(flipped) : "") << "</td><td class=\"n\">"
         << number(j["time_ms"].get<double>() / 1000.0, "%.2f") << "</td><td>";
    if (j["preview"].is_string()) {
      const std::string src = xml_escaped(j["preview"].get<std::string>());
      rows << "<a href=\"" << src << "\"><img src=\"" << src << "\" alt=\"before, after, displacement\" loading=\"lazy\"></a>";
    }
    rows << "</td><td>";
    for (const Json& p : j["outputs"]) {
      const std::string href = xml_escaped(p.get<std::string>());
      rows << "<a href=\"" << href << "\">" << xml_escaped(fs::path(p.get<std::string>()).filename().string()) << "</a> ";
    }
    rows << "<a href=\"" << xml_escaped(j["log"].get<std::string>()) << "\">log</a></td></tr>\n";
  }
  md << "\nTimes are wall-clock per job; they are the only numbers that differ between two runs.\n";
  summary.markdown = md.str();

  std::ostringstream html;
  html << kHtmlHead << "<h1>untangle batch: " << xml_escaped(o.source) << "</h1>\n<p>Status <b class=\""
       << status << "\">" << status << "</b> (exit " << summary.exit_code << "); " << xml_escaped(totals)
       << ". Click a column header to sort.</p>\n"
       << "<table><thead><tr><th>job</th><th>status</th><th>crossings before -&gt; after</th>"
          "<th>inside vertices before -&gt; after</th><th>max edge change</th><th>flipped faces</th>"
          "<th>time (s)</th><th>before | after | displacement</th><th>files</th></tr></thead>\n<tbody>\n"
       << rows.str() << "</tbody></table>\n" << kHtmlScript << "</body></html>\n";
  summary.html = html.str();
  return summary;
}

}  // namespace untangle::app
