#include "logging.h"

#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace caustic::server {

void setUpLogging(const std::string& level, const std::string& accessLog) {
    // Both console sinks take spdlog's one console mutex, so lines of the two loggers never mix.
    auto messages = spdlog::stderr_color_mt("caustic");
    messages->set_pattern("%Y-%m-%d %H:%M:%S.%e caustic %^%l%$: %v");
    spdlog::set_default_logger(messages);
    std::shared_ptr<spdlog::logger> access;
    if (accessLog.empty())
        access = spdlog::stderr_color_mt("access");
    else if (accessLog == "-")
        access = spdlog::stdout_logger_mt("access");
    else
        access = spdlog::basic_logger_mt("access", accessLog);
    access->set_pattern("%Y-%m-%d %H:%M:%S.%e access %v");
    // A file sink buffers; someone following the log (tail -f, a test) sees each line at once.
    access->flush_on(spdlog::level::info);
    spdlog::set_level(spdlog::level::from_str(level));
}

}  // namespace caustic::server
