// The one error type for bad input: it carries the JSON path (RFC 6901 pointer) of what is wrong.
#pragma once

#include <stdexcept>
#include <string>

namespace caustic {

/// Bad input (a scene, settings, a mesh file). `path()` is the JSON pointer of the offending value
/// ("/shapes/3/radius"), empty for the document itself; `message()` says what was expected.
class InputError : public std::runtime_error {
public:
    InputError(std::string path, std::string message)
        : std::runtime_error((path.empty() ? std::string("/") : path) + ": " + message),
          path_(std::move(path)),
          message_(std::move(message)) {}

    const std::string& path() const { return path_; }
    const std::string& message() const { return message_; }

private:
    std::string path_;
    std::string message_;
};

}  // namespace caustic
