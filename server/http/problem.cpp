#include "http/problem.h"

#include <nlohmann/json.hpp>

namespace caustic::server {
const char* statusTitle(int status) {
    switch (status) {
        case 400:
            return "Bad Request";
        case 401:
            return "Unauthorized";
        case 403:
            return "Forbidden";
        case 404:
            return "Not Found";
        case 405:
            return "Method Not Allowed";
        case 409:
            return "Conflict";
        case 411:
            return "Length Required";
        case 413:
            return "Content Too Large";
        case 414:
            return "URI Too Long";
        case 415:
            return "Unsupported Media Type";
        case 416:
            return "Range Not Satisfiable";
        case 422:
            return "Unprocessable Content";
        case 429:
            return "Too Many Requests";
        case 431:
            return "Request Header Fields Too Large";
        case 500:
            return "Internal Server Error";
        case 503:
            return "Service Unavailable";
        case 507:
            return "Insufficient Storage";
        default:
            return status < 500 ? "Client Error" : "Server Error";
    }
}

void sendProblem(httplib::Response& res, int status, const std::string& detail,
                 const std::string& pointer) {
    nlohmann::json body{{"type", "about:blank"},
                        {"title", statusTitle(status)},
                        {"status", status},
                        {"detail", detail}};
    if (!pointer.empty()) body["pointer"] = pointer;
    res.status = status;
    // A detail may quote the request (a malformed body, a header): bytes that are not UTF-8 become
    // U+FFFD instead of failing the error response itself, and anything not ASCII is escaped, so
    // that a client that guesses the charset (there is no charset parameter) still reads JSON.
    res.set_content(body.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace),
                    "application/problem+json");
}

}  // namespace caustic::server
