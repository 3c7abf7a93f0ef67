// Wakes this process's event streams when any process changes a job in the PostgreSQL store: a
// thread that LISTENs on the store's channel (every job change NOTIFYs at its commit), so that
// progress, Server-Sent Events and previews follow passes merged on any machine. It reconnects
// after a lost connection, and wakes the streams then too (a change may have been missed).
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <thread>

namespace caustic::server {

class PostgresListener {
public:
    PostgresListener(std::string conninfo, std::function<void()> changed);
    ~PostgresListener();
    PostgresListener(const PostgresListener&) = delete;
    PostgresListener& operator=(const PostgresListener&) = delete;

private:
    void run();

    std::string conninfo_;
    std::function<void()> changed_;
    std::atomic<bool> stopping_{false};
    std::thread thread_;
};

}  // namespace caustic::server
