// The bytes a TCP connection has received, whoever read them: the kernel's count (tcp_info's
// tcpi_bytes_received, RFC 4898's ThruOctetsReceived, Linux 4.1 on), which glibc's <netinet/tcp.h>
// does not declare. A file of its own: <linux/tcp.h> cannot be included beside <netinet/tcp.h>.
#pragma once

#include <cstdint>
#include <optional>

namespace caustic::server {

/// The bytes received on the socket `fd`, or nothing when the kernel does not say.
std::optional<uint64_t> tcpBytesReceived(int fd);

}  // namespace caustic::server
