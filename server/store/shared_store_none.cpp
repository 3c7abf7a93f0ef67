// A build without the PostgreSQL store (CAUSTIC_POSTGRES=OFF).
#include <stdexcept>

#include "store/shared_store.h"

namespace caustic::server {

SharedStore openSharedStore(const ServerConfig&, RenderCounters&, std::function<void()>) {
    throw std::runtime_error("this build has no PostgreSQL store (CAUSTIC_POSTGRES=OFF)");
}

}  // namespace caustic::server
