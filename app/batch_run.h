// The job runner of `untangle batch` and the per-job records it writes (OUT/jobs/<id>/job.json).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "batch.h"

namespace untangle::app {

// The command line of one job: `EXE fix INPUTS --obstacle ... --output-dir OUT/jobs/<id> --report
// ... --preview ... --preview-size ... --threads ... <the job's options> --overwrite`.
std::vector<std::string> job_command(const std::string& exe, const BatchJob& job,
                                     const std::string& out, const BatchOptions& o);

// A job's exit code in batch terms: clean 0, unresolved 5, failed with fix's exit code 2, 3 or 4
// as it was, any other failure (crash, time limit, internal error) 1.
int job_exit_code(const std::string& status, int fix_exit);

// The batch's exit code: the worst job's, from best to worst 0, 5, 4, 3, 2, 1.
int worst_exit_code(const std::vector<JobRecord>& records);

std::string job_record_json(const JobRecord& r);
// Reads a job.json; false when it is missing or not one.
bool read_job_record(const std::string& path, JobRecord& r);

// Called in the order jobs finish.
using JobDone = std::function<void(const JobRecord&)>;

// Runs `jobs` (prepared[k] holds job k's id, hashes and options), `parallel` at once, each its own
// process with stdout and stderr in OUT/jobs/<id>/log.txt, killed (SIGKILL) at
// o.time_limit seconds; writes each job's job.json when it ends and returns the records in the
// order of `jobs`. The test hook UNTANGLE_BATCH_TEST_FAULT=crash:ID,hang:ID makes the process of
// job ID crash (SIGSEGV) or hang instead of running fix.
std::vector<JobRecord> run_jobs(const std::vector<const BatchJob*>& jobs,
                                const std::vector<JobRecord>& prepared, const std::string& exe,
                                const BatchOptions& o, int parallel, const JobDone& done);

}  // namespace untangle::app
