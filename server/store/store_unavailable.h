// The shared job store (PostgreSQL) cannot be reached: it is restarting, down, or the network to
// it is cut, and reconnecting for a few seconds did not help. Nothing was written. The HTTP
// boundary answers it with 503 Service Unavailable and a Retry-After (RFC 9110, section 15.6.4):
// the request may succeed once the store is back; it is not a fault of the server.
#pragma once

#include <stdexcept>

namespace caustic::server {

class StoreUnavailable : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace caustic::server
