// The job file of `prism batch` (docs/batch.md has the schema): JSON, versioned,
//   {"version": 1, "defaults": {...}, "jobs": [{"name": ..., "scene": ..., ...}, ...]}
// where a job's keys are `prism render`'s options spelled as its flags without the dashes
// ("spp", "max-depth", "target-error"), plus "name", "scene", "output" and "resolution" (the
// same as "res"). Each job is parsed by the very definition of `prism render`'s command line,
// so a job file accepts and refuses exactly what the command line does. Relative paths are
// resolved against the job file's folder; "camera", "integrator" and "spp" may be lists, and
// "camera" may be "all", each expanding into one render per value.
#pragma once

#include <string>
#include <vector>

#include "session/batch.h"

namespace prism {

struct JobFileError {
  int job = -1;  // its index in "jobs", or -1 for the file as a whole
  std::string name;
  std::string field;
  std::string message;
  // "jobs[3] 'name': spp: must be ..." (the file is named by the caller).
  std::string describe() const;
};

struct JobFile {
  std::vector<BatchJobSpec> specs;  // the valid jobs, lists expanded
  std::vector<JobFileError> errors;
  int jobs = 0;  // in the file
};

inline constexpr int kJobFileVersion = 1;

// Reads and checks `path`. A file that cannot be read or is not a job file at all gives one
// error with job -1 and no specs.
JobFile read_job_file(const std::string& path);

}  // namespace prism
