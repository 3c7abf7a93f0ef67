// The service's front door: accepts connections, holds each until its request's head (and a small
// body) has arrived, and only then gives it one of cpp-httplib's request threads; it caps the
// connections of one client address and of the whole service, and cuts a request whose head or body
// comes too slowly.
//
// cpp-httplib serves a connection on one thread from accept to close, and its read timeout holds
// per read: a client that sends a byte of its head every few seconds keeps a thread for as long as
// it likes, and some dozens of them stop the API (Slowloris). The gate waits for heads with epoll
// on one thread instead, as FreeBSD's accf_http(9) does in the kernel: a slow head costs a file
// descriptor, not a thread. On a thread, the deadlines are kept by the same loop, which shuts the
// read side of a connection whose head or body is late (its response, if any, still goes out).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>

#include "server_config.h"

namespace caustic::server {

/// What the gate refused and cut, for /metrics.
struct ConnectionCounters {
    std::atomic<int64_t> accepted{0};
    std::atomic<int64_t> refusedPerClient{0};  ///< Over --max-connections-per-client.
    std::atomic<int64_t> refusedFull{0};       ///< Over --max-connections.
    std::atomic<int64_t> cutHead{0};           ///< A head not in within --request-head-seconds.
    std::atomic<int64_t> cutBody{0};           ///< A body slower than --min-body-rate.
    std::atomic<int64_t> cutIdle{0};  ///< Kept-alive and idle while others waited for a thread.
    std::atomic<int> open{0};         ///< Connections open, waiting or on a thread.
    std::atomic<int> busyThreads{0};
};

class ConnectionGate {
public:
    /// `http` serves the requests (its routes, timeouts and, for an httplib::SSLServer, TLS); it
    /// must be made by makeGatedServer(). `threads` request threads serve at once.
    ConnectionGate(httplib::Server& http, const ServiceLimits& limits, int threads, bool tls,
                   int keepAliveSeconds, ConnectionCounters& counters);
    ~ConnectionGate();

    /// Listens on host:port (0 for any free port); returns the port. Throws when it cannot.
    int bind(const std::string& host, int port);
    /// Accepts and serves until stop(). Blocks.
    void run();
    /// Stops accepting, closes waiting connections and ends kept-alive ones (any thread).
    void stop();

    /// Request threads call these from cpp-httplib's hooks: the head of a request with a body of
    /// `contentLength` bytes was read (pre-routing), and a response was written (the logger).
    static void headRead(uint64_t contentLength);
    static void responded();

private:
    struct Waiting;
    struct Serving;
    struct Queued {
        int fd = -1;
        std::string client;
    };
    using Clock = std::chrono::steady_clock;

    /// The connection this request thread serves, for headRead() and responded().
    static thread_local Serving* current;

    void accept();
    void refuse(int fd, int status, const std::string& detail);
    void check(Waiting& w, Clock::time_point now, bool event);
    void handOver(int fd);
    void closeWaiting(int fd);
    void release(const std::string& client);
    void sweep(Clock::time_point now);
    static void extendBodyDeadline(Serving& s);
    void serveConnections();

    httplib::Server& http_;
    const ServiceLimits limits_;
    const bool tls_;
    const int keepAliveSeconds_;
    ConnectionCounters& counters_;
    int listenFd_ = -1;
    int epollFd_ = -1;
    int wakeFd_ = -1;
    std::atomic<bool> stopping_{false};

    std::map<int, Waiting> waiting_;  ///< By file descriptor; the loop's thread only.

    std::mutex mutex_;  ///< Guards what follows.
    std::condition_variable ready_;
    std::deque<Queued> queue_;  ///< Connections whose heads are in, for a thread.
    std::list<std::shared_ptr<Serving>> serving_;
    std::map<std::string, int> perClient_;  ///< Open connections by client address.
    std::vector<std::thread> threads_;
};

/// The request handler the gate hands connections to: a plain server, or with a certificate and
/// key an HTTPS one (throws when they cannot be used).
std::unique_ptr<httplib::Server> makeGatedServer(const std::string& tlsCert,
                                                 const std::string& tlsKey);

}  // namespace caustic::server
