// Errors as RFC 9457 problem details (application/problem+json): a title for the status, a detail
// for people, and `pointer`, the JSON path of the offending input when there is one.
#pragma once

#include <string>

#include <httplib.h>

namespace caustic::server {

/// The reason phrase of an HTTP status (RFC 9110).
const char* statusTitle(int status);

void sendProblem(httplib::Response& res, int status, const std::string& detail,
                 const std::string& pointer = {});

/// A request refused before it is routed (http/guards.h): the status and the problem's detail.
struct Refusal {
    int status;
    std::string detail;
};

}  // namespace caustic::server
