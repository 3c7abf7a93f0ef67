#include "http/connection_gate.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string_view>

#include "http/problem.h"
#include "http/tcp_received.h"

namespace caustic::server {
namespace {

using Clock = std::chrono::steady_clock;

// A head longer than this is handed over as it is: cpp-httplib answers it (414 or 400).
constexpr size_t kHeadLimit = 16 * 1024;
// A body's first bytes, up to this many, wait in the gate with its head (they fit a socket's
// receive buffer), for at most kBodyWait: a job's JSON comes whole to its thread. A client may
// send its head alone and wait for the answer (Expect: 100-continue, or to learn that its body is
// too large): after kBodyWait it gets a thread anyway, where --min-body-rate holds it.
constexpr uint64_t kGatedBodyBytes = 16 * 1024;
constexpr auto kBodyWait = std::chrono::milliseconds(500);
// What cpp-httplib may have read into its own buffer beyond the head (SocketStream's 4 KiB).
constexpr uint64_t kReadAhead = 4096;
// A head that grows by less than this is looked at again on the next sweep, not at once: a client
// sending a byte at a time costs one FIONREAD per byte, not a copy of its head.
constexpr size_t kPeekStep = 512;
constexpr auto kSweep = std::chrono::milliseconds(50);
// A refused connection's answer is sent, then its input drained until the client closes, so that
// closing with unread input does not reset the connection before the client reads the answer.
constexpr auto kLinger = std::chrono::seconds(1);
constexpr size_t kMaxLingering = 256;

// cpp-httplib serves a connection in Server::process_and_close_socket, a private virtual member,
// and Debian builds it as a library (libcpp-httplib0.11), so its internals cannot be called any
// other way. A member pointer named in an explicit instantiation is exempt from access checks
// ([temp.spec.general]/6): this takes it once, here, and calls it on the request handler, where
// it dispatches to Server's or SSLServer's own.
using ProcessMember = bool (httplib::Server::*)(socket_t);
struct ProcessTag {};
ProcessMember processMember(ProcessTag);
template <ProcessMember member>
struct ExposeProcess {
    friend ProcessMember processMember(ProcessTag) { return member; }
};
template struct ExposeProcess<&httplib::Server::process_and_close_socket>;

// The request handler's serving loop runs while its listening socket is valid (it checks
// Server::svr_sock_, protected): the gate sets it to its own and clears it to stop.
struct Listening {
    virtual ~Listening() = default;
    virtual void setListening(socket_t sock) = 0;
};
template <class Base>
class Gated final : public Base, public Listening {
public:
    using Base::Base;
    void setListening(socket_t sock) override { this->svr_sock_ = sock; }
};

std::string clientOf(const sockaddr_storage& addr) {
    char text[INET6_ADDRSTRLEN] = "?";
    if (addr.ss_family == AF_INET)
        ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in&>(addr).sin_addr, text,
                    sizeof text);
    else if (addr.ss_family == AF_INET6)
        ::inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6&>(addr).sin6_addr, text,
                    sizeof text);
    return text;
}

int64_t ticks(Clock::time_point t) {
    return t.time_since_epoch().count();
}

// Where a request's head ends in `bytes` (after its blank line), or 0 when it has not yet.
// cpp-httplib, like most servers, takes a bare LF for CRLF (RFC 9112, section 2.2).
size_t headEnd(std::string_view bytes) {
    for (size_t i = bytes.find('\n'); i != std::string_view::npos; i = bytes.find('\n', i + 1)) {
        if (i + 1 < bytes.size() && bytes[i + 1] == '\n') return i + 2;
        if (i + 2 < bytes.size() && bytes[i + 1] == '\r' && bytes[i + 2] == '\n') return i + 3;
    }
    return 0;
}

// The value of the header `name` (lowercase, with its colon) in a request's head, empty without it.
std::string_view headerValue(std::string_view head, std::string_view name) {
    for (size_t line = head.find('\n'); line != std::string_view::npos;
         line = head.find('\n', line + 1)) {
        std::string_view rest = head.substr(line + 1);
        if (rest.size() < name.size() ||
            !std::equal(name.begin(), name.end(), rest.begin(),
                        [](char a, char b) { return a == std::tolower((unsigned char)b); }))
            continue;
        rest = rest.substr(name.size());
        rest = rest.substr(0, std::min(rest.find('\r'), rest.find('\n')));
        while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t'))
            rest.remove_prefix(1);
        return rest;
    }
    return {};
}

// The head's Content-Length (0 without one or a bad one: the guards answer that).
uint64_t contentLength(std::string_view head) {
    uint64_t n = 0;
    for (char c : headerValue(head, "content-length:")) {
        if (c < '0' || c > '9') break;
        n = std::min<uint64_t>(n * 10 + uint64_t(c - '0'), uint64_t(1) << 62);
    }
    return n;
}

size_t available(int fd) {
    int n = 0;
    return ::ioctl(fd, FIONREAD, &n) == 0 && n > 0 ? size_t(n) : 0;
}

}  // namespace

struct ConnectionGate::Waiting {
    int fd = -1;
    std::string client;
    Clock::time_point deadline;
    Clock::time_point lastPeek;
    size_t scanned = 0;        ///< Bytes looked at for the end of the head.
    size_t need = 0;           ///< Head and gated body, once the head's end is known.
    Clock::time_point headAt;  ///< When the head's end was seen.
    bool lingering = false;
};

// A connection on a request thread. `watchFd` is a duplicate of its socket, kept open until the
// thread is done with it, so that the loop never shuts down a descriptor number reused since.
struct ConnectionGate::Serving {
    enum Phase { Head, Body, Handling, Idle };
    int watchFd = -1;
    std::string client;
    std::atomic<int> phase{Head};
    std::atomic<int64_t> deadline{0};  ///< Clock ticks; 0 for none.
    // A body being read: its length, when its head was read, and the bytes received by then
    // (the kernel's count) and waiting unread in the socket then.
    std::atomic<uint64_t> bodyLength{0}, receivedAtHead{0}, bufferedAtHead{0};
    std::atomic<int64_t> headTicks{0};
    bool cut = false;
    double headSeconds = 10;
    double minBodyRate = 8192;
};

namespace {

Clock::time_point after(Clock::time_point t, double seconds) {
    return t + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

}  // namespace

thread_local ConnectionGate::Serving* ConnectionGate::current = nullptr;

void ConnectionGate::headRead(uint64_t length) {
    if (!current) return;
    if (length == 0) {
        current->deadline = 0;
        current->phase = Serving::Handling;
        return;
    }
    // The body must come at --min-body-rate on average, after the head's own allowance: the
    // sweep moves the deadline on as its bytes arrive. Without the kernel's count, it is fixed
    // by the declared length.
    const Clock::time_point now = Clock::now();
    std::optional<uint64_t> received = tcpBytesReceived(current->watchFd);
    current->bodyLength = received ? length : 0;
    current->receivedAtHead = received.value_or(0);
    current->bufferedAtHead = available(current->watchFd);
    current->headTicks = ticks(now);
    current->deadline = ticks(after(
        now, current->headSeconds + (received ? 0.0 : double(length)) / current->minBodyRate));
    current->phase = Serving::Body;
}

void ConnectionGate::responded() {
    if (!current) return;
    // The next request on a kept-alive connection must be in within a head's allowance.
    current->deadline = ticks(after(Clock::now(), current->headSeconds));
    current->phase = Serving::Idle;
}

ConnectionGate::ConnectionGate(httplib::Server& http, const ServiceLimits& limits, int threads,
                               bool tls, int keepAliveSeconds, ConnectionCounters& counters)
    : http_(http),
      limits_(limits),
      tls_(tls),
      keepAliveSeconds_(keepAliveSeconds),
      counters_(counters) {
    if (!dynamic_cast<Listening*>(&http_))
        throw std::logic_error("the gate's request handler must come from makeGatedServer()");
    threads_.reserve(size_t(threads));
    for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { serveConnections(); });
}

ConnectionGate::~ConnectionGate() {
    stop();
    ready_.notify_all();
    for (std::thread& t : threads_)
        if (t.joinable()) t.join();
    for (auto& [fd, w] : waiting_) ::close(fd);
    for (const Queued& q : queue_) ::close(q.fd);
    for (int fd : {listenFd_, epollFd_, wakeFd_})
        if (fd >= 0) ::close(fd);
}

int ConnectionGate::bind(const std::string& host, int port) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    addrinfo* found = nullptr;
    const std::string service = std::to_string(port);
    const std::string where = host + ":" + service;
    if (::getaddrinfo(host.c_str(), service.c_str(), &hints, &found) != 0 || !found)
        throw std::runtime_error("cannot listen on " + where + ": unknown host");
    std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> list(found, ::freeaddrinfo);
    for (addrinfo* a = found; a && listenFd_ < 0; a = a->ai_next) {
        int fd =
            ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, a->ai_protocol);
        if (fd < 0) continue;
        // SO_REUSEADDR only: with SO_REUSEPORT a second server on a port in use would start
        // without an error and take a share of its connections.
        int yes = 1;
        ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        if (::bind(fd, a->ai_addr, a->ai_addrlen) == 0 && ::listen(fd, SOMAXCONN) == 0)
            listenFd_ = fd;
        else
            ::close(fd);
    }
    if (listenFd_ < 0) throw std::runtime_error("cannot listen on " + where);
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    ::getsockname(listenFd_, reinterpret_cast<sockaddr*>(&addr), &len);
    epollFd_ = ::epoll_create1(EPOLL_CLOEXEC);
    wakeFd_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    for (int fd : {listenFd_, wakeFd_}) {
        epoll_event ev{};
        ev.events = EPOLLIN;
        ev.data.fd = fd;
        ::epoll_ctl(epollFd_, EPOLL_CTL_ADD, fd, &ev);
    }
    dynamic_cast<Listening&>(http_).setListening(listenFd_);
    return addr.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6&>(addr).sin6_port)
                                      : ntohs(reinterpret_cast<sockaddr_in&>(addr).sin_port);
}

void ConnectionGate::run() {
    epoll_event events[64];
    Clock::time_point lastSweep = Clock::now();
    while (!stopping_) {
        int n = ::epoll_wait(epollFd_, events, 64, int(kSweep.count()));
        const Clock::time_point now = Clock::now();
        for (int i = 0; i < n; ++i) {
            const int fd = events[i].data.fd;
            if (fd == listenFd_) {
                accept();
            } else if (auto it = waiting_.find(fd); it != waiting_.end()) {
                check(it->second, now, true);
            }
        }
        if (now - lastSweep >= kSweep) {
            sweep(now);
            lastSweep = now;
        }
    }
    // Requests being served finish (an event stream ends when the service stops); kept-alive
    // connections end with the listening socket cleared.
    dynamic_cast<Listening&>(http_).setListening(INVALID_SOCKET);
    {
        std::lock_guard lock(mutex_);
        for (const std::shared_ptr<Serving>& s : serving_)
            if (s->phase != Serving::Handling) ::shutdown(s->watchFd, SHUT_RD);
    }
    ready_.notify_all();
    for (std::thread& t : threads_) t.join();
    threads_.clear();
}

void ConnectionGate::stop() {
    {
        std::lock_guard lock(mutex_);  // No request thread misses the change while it waits.
        stopping_ = true;
    }
    ready_.notify_all();
    if (wakeFd_ >= 0) {
        uint64_t one = 1;
        (void)!::write(wakeFd_, &one, sizeof one);
    }
}

void ConnectionGate::accept() {
    for (;;) {
        sockaddr_storage addr{};
        socklen_t len = sizeof addr;
        int fd = ::accept4(listenFd_, reinterpret_cast<sockaddr*>(&addr), &len,
                           SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) return;  // EAGAIN, or out of descriptors: the next wake-up tries again.
        int yes = 1;
        // No Nagle delay: a response goes out in more than one write (headers, body), and on a
        // kept-alive connection the second would wait for the client's delayed ACK.
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
        std::string client = clientOf(addr);
        ++counters_.accepted;
        {
            std::lock_guard lock(mutex_);
            if (counters_.open.load() >= limits_.maxConnections) {
                ++counters_.refusedFull;
                refuse(fd, 503,
                       "the server has " + std::to_string(limits_.maxConnections) +
                           " connections open (--max-connections); try again shortly");
                continue;
            }
            int& mine = perClient_[client];
            if (limits_.maxConnectionsPerClient > 0 && mine >= limits_.maxConnectionsPerClient) {
                ++counters_.refusedPerClient;
                refuse(fd, 429,
                       "your address " + client + " has " + std::to_string(mine) +
                           " connections open, the most one client may "
                           "(--max-connections-per-client)");
                continue;
            }
            ++mine;
            ++counters_.open;
        }
        epoll_event ev{};
        ev.events = EPOLLIN | EPOLLRDHUP | EPOLLET;
        ev.data.fd = fd;
        ::epoll_ctl(epollFd_, EPOLL_CTL_ADD, fd, &ev);
        const Clock::time_point now = Clock::now();
        Waiting& w = waiting_[fd];
        w.fd = fd;
        w.client = std::move(client);
        w.deadline = after(now, limits_.requestHeadSeconds);
        // Data that came with the connection raises no edge of its own.
        check(w, now, true);
    }
}

// An answer for a connection refused before it has a thread (status 429 or 503). Over TLS no
// answer can be sent without a handshake: the connection is closed.
void ConnectionGate::refuse(int fd, int status, const std::string& detail) {
    spdlog::get("access") ? spdlog::get("access")->info("- - - {} - - ms ({})", status, detail)
                          : spdlog::info("refused a connection: {}", detail);
    if (tls_ || waiting_.size() >= kMaxLingering + size_t(limits_.maxConnections)) {
        ::close(fd);
        return;
    }
    const std::string body = nlohmann::json{
        {"type", "about:blank"},
        {"title", statusTitle(status)},
        {"status", status},
        {"detail", detail}}.dump();
    const std::string answer = "HTTP/1.1 " + std::to_string(status) + " " + statusTitle(status) +
                               "\r\nContent-Type: application/problem+json\r\nRetry-After: "
                               "5\r\nConnection: close\r\nContent-Length: " +
                               std::to_string(body.size()) + "\r\n\r\n" + body;
    (void)!::send(fd, answer.data(), answer.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    ::shutdown(fd, SHUT_WR);
    epoll_event ev{};
    ev.events = EPOLLIN | EPOLLRDHUP | EPOLLET;
    ev.data.fd = fd;
    ::epoll_ctl(epollFd_, EPOLL_CTL_ADD, fd, &ev);
    Waiting& w = waiting_[fd];
    w.fd = fd;
    w.lingering = true;
    w.deadline = Clock::now() + kLinger;
}

// Looks at what a waiting connection has sent: hands it over once its head (and a small body) is
// in, or closes it when the client closed or its time is up. `event`: new bytes came (or the
// client closed), as opposed to the sweep looking again.
void ConnectionGate::check(Waiting& w, Clock::time_point now, bool event) {
    const int fd = w.fd;
    const size_t avail = available(fd);
    if (w.lingering) {
        char drain[4096];
        ssize_t got;
        while ((got = ::recv(fd, drain, sizeof drain, MSG_DONTWAIT)) > 0) {
        }
        if (got == 0 || now >= w.deadline) closeWaiting(fd);
        return;
    }
    // With nothing to read, a readable socket is one the client closed (or reset).
    if (avail == 0) {
        char byte;
        ssize_t got = ::recv(fd, &byte, 1, MSG_PEEK | MSG_DONTWAIT);
        if (got == 0 || (got < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) closeWaiting(fd);
        return;
    }
    // TLS: the handshake must happen on a thread; it and the head are held to the deadline there.
    if (tls_) return handOver(fd);
    if (w.need == 0 && avail > w.scanned) {
        if (event && w.scanned > 0 && avail < w.scanned + kPeekStep && now - w.lastPeek < kSweep)
            return;
        std::string bytes(std::min(avail, kHeadLimit), '\0');
        ssize_t got = ::recv(fd, bytes.data(), bytes.size(), MSG_PEEK | MSG_DONTWAIT);
        if (got <= 0) return;
        bytes.resize(size_t(got));
        w.scanned = bytes.size();
        w.lastPeek = now;
        if (size_t end = headEnd(bytes)) {
            const std::string_view head = std::string_view(bytes).substr(0, end);
            // A client that expects 100 Continue sends its body only when told to.
            const bool expects = !headerValue(head, "expect:").empty();
            w.need = end + size_t(expects ? 0 : std::min(contentLength(head), kGatedBodyBytes));
            w.headAt = now;
        } else if (bytes.size() >= kHeadLimit) {
            return handOver(fd);
        }
    }
    if (w.need > 0 && (avail >= w.need || now - w.headAt >= kBodyWait)) handOver(fd);
}

void ConnectionGate::closeWaiting(int fd) {
    auto it = waiting_.find(fd);
    if (it == waiting_.end()) return;
    if (!it->second.lingering) release(it->second.client);
    waiting_.erase(it);
    ::epoll_ctl(epollFd_, EPOLL_CTL_DEL, fd, nullptr);
    ::close(fd);
}

void ConnectionGate::handOver(int fd) {
    auto it = waiting_.find(fd);
    std::string client = std::move(it->second.client);
    waiting_.erase(it);
    ::epoll_ctl(epollFd_, EPOLL_CTL_DEL, fd, nullptr);
    // cpp-httplib reads and writes blocking sockets (after waiting for them with poll).
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    {
        std::lock_guard lock(mutex_);
        queue_.push_back({fd, std::move(client)});
    }
    ready_.notify_one();
}

void ConnectionGate::release(const std::string& client) {
    std::lock_guard lock(mutex_);
    if (auto it = perClient_.find(client); it != perClient_.end() && --it->second <= 0)
        perClient_.erase(it);
    --counters_.open;
}

// Deadlines: a waiting head that is late is closed; a connection on a thread whose head or body is
// late has its read side shut down (cpp-httplib then sees the request end and closes). While
// connections wait for a thread, kept-alive idle ones give theirs up.
void ConnectionGate::sweep(Clock::time_point now) {
    // check() and closeWaiting() change waiting_: what to do is gathered first.
    std::vector<int> late, grown;
    for (auto& [fd, w] : waiting_) {
        if (now >= w.deadline) {
            late.push_back(fd);
            if (!w.lingering) ++counters_.cutHead;
        } else if (!w.lingering &&
                   (w.need > 0 ? now - w.headAt >= kBodyWait : available(fd) > w.scanned)) {
            grown.push_back(fd);
        }
    }
    for (int fd : late) closeWaiting(fd);
    for (int fd : grown)
        if (auto it = waiting_.find(fd); it != waiting_.end()) check(it->second, now, false);
    std::lock_guard lock(mutex_);
    size_t waitingForThread = queue_.size();
    for (const std::shared_ptr<Serving>& s : serving_) {
        if (s->cut) continue;
        if (s->phase == Serving::Body && s->bodyLength > 0) extendBodyDeadline(*s);
        const int phase = s->phase.load();
        const int64_t deadline = s->deadline.load();
        const bool overdue = deadline != 0 && ticks(now) >= deadline;
        const bool yield = phase == Serving::Idle && waitingForThread > 0;
        if (!overdue && !yield) continue;
        ::shutdown(s->watchFd, SHUT_RD);
        s->cut = true;
        if (overdue)
            ++(phase == Serving::Body ? counters_.cutBody : counters_.cutHead);
        else {
            ++counters_.cutIdle;
            --waitingForThread;
        }
    }
}

// A body's deadline: the head's allowance, then a second for each --min-body-rate bytes arrived
// (as Apache's mod_reqtimeout does with MinRate). Once it is all in, the handler has no deadline.
void ConnectionGate::extendBodyDeadline(Serving& s) {
    std::optional<uint64_t> received = tcpBytesReceived(s.watchFd);
    if (!received) return;
    const uint64_t arrived = s.bufferedAtHead + (*received - s.receivedAtHead);
    if (arrived + kReadAhead >= s.bodyLength) {
        s.deadline = 0;
        s.phase = Serving::Handling;
        return;
    }
    const Clock::time_point head{Clock::duration(s.headTicks.load())};
    s.deadline = ticks(after(head, s.headSeconds + double(arrived) / s.minBodyRate));
}

void ConnectionGate::serveConnections() {
    const ProcessMember process = processMember(ProcessTag{});
    for (;;) {
        Queued next;
        {
            std::unique_lock lock(mutex_);
            ready_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
            if (queue_.empty()) return;
            next = std::move(queue_.front());
            queue_.pop_front();
            if (stopping_) {
                ::close(next.fd);
                --counters_.open;
                continue;
            }
        }
        auto s = std::make_shared<Serving>();
        s->watchFd = ::dup(next.fd);
        s->client = next.client;
        s->headSeconds = limits_.requestHeadSeconds;
        s->minBodyRate = double(limits_.minBodyBytesPerSecond);
        s->deadline = ticks(after(Clock::now(), s->headSeconds));
        {
            std::lock_guard lock(mutex_);
            serving_.push_back(s);
        }
        ++counters_.busyThreads;
        current = s.get();
        (http_.*process)(next.fd);  // Serves the connection's requests and closes it.
        current = nullptr;
        --counters_.busyThreads;
        {
            std::lock_guard lock(mutex_);
            serving_.remove(s);
        }
        if (s->watchFd >= 0) ::close(s->watchFd);
        release(next.client);
    }
}

std::unique_ptr<httplib::Server> makeGatedServer(const std::string& tlsCert,
                                                 const std::string& tlsKey) {
    if (tlsCert.empty()) return std::make_unique<Gated<httplib::Server>>();
    auto server = std::make_unique<Gated<httplib::SSLServer>>(tlsCert.c_str(), tlsKey.c_str());
    if (!server->is_valid())
        throw std::runtime_error("cannot use the TLS certificate " + tlsCert + " with the key " +
                                 tlsKey +
                                 ": each must be a readable PEM file, and the key the "
                                 "certificate's");
    return server;
}

}  // namespace caustic::server
