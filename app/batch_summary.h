// The batch's summary: OUT/summary.json, summary.md and summary.html from the job records and the
// jobs' fix reports.
#pragma once

#include <string>
#include <vector>

#include "batch.h"

namespace untangle::app {

struct BatchSummary {
  std::string json, markdown, html;
  int exit_code = 0;
};

// `records[k]` is the record of plan.jobs[k]; the numbers are read from each job's report under
// `out`. Deterministic but for the time_ms fields (jobs in id order, stable keys).
BatchSummary make_summary(const BatchOptions& o, const BatchPlan& plan,
                          const std::vector<JobRecord>& records);

}  // namespace untangle::app
