// `prism batch JOBS.json`: many renders in one process (session/batch.h), from a job file
// (apps/batch_file.h); prints progress, a summary table and writes batch-report.json.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace prism {

struct BatchCommandOptions {
  std::string job_file;
  bool dry_run = false;
  bool force = false;
  bool keep_going = false;
  bool one_at_a_time = false;
  int threads = 0;
  double memory_budget_gib = 8.0;  // the scenes kept loaded
  double memory_limit_gib = 8.0;   // each load
  std::string shard;               // "K/N", empty = every job
  std::string report;              // empty: batch-report.json beside the outputs
  double checkpoint_interval = 300.0;
  bool quiet = false;
  bool verbose = false;
};

CLI::App* add_batch_command(CLI::App& app, BatchCommandOptions* options);
int run_batch(const BatchCommandOptions& options);

}  // namespace prism
