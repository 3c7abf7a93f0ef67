// The JSON resource of a job, as the API returns it.
#pragma once

#include <optional>

#include "jobs/job_events.h"
#include "store/job.h"

namespace caustic::server {

/// The job with its links; `live` overrides the stored progress of a running job.
Json jobJson(const Job& job, const std::optional<LiveProgress>& live);

/// An RFC 3339 UTC time for Unix seconds, or null for 0.
Json timeJson(double unixSeconds);

}  // namespace caustic::server
