// A batch's records as JSON: the rows of batch-report.json, and what ranks send rank 0 when
// a batch is spread over MPI (the same text, so what a rank reports is what the file says).
#pragma once

#include <nlohmann/json.hpp>

#include "session/batch.h"

namespace prism {

nlohmann::json record_json(const JobRecord& record);
// The record `json` describes (as record_json writes it); throws nlohmann::json::exception
// for anything else.
JobRecord record_from_json(const nlohmann::json& json);

}  // namespace prism
