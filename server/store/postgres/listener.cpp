#include "store/postgres/listener.h"

#include <pqxx/pqxx>

#include <chrono>

#include <spdlog/spdlog.h>

#include "store/postgres/transaction.h"

namespace caustic::server {
namespace {

class Receiver final : public pqxx::notification_receiver {
public:
    Receiver(pqxx::connection& c, const std::function<void()>& changed)
        : pqxx::notification_receiver(c, postgres::kJobsChannel), changed_(changed) {}
    void operator()(const std::string&, int) override { changed_(); }

private:
    const std::function<void()>& changed_;
};

}  // namespace

PostgresListener::PostgresListener(std::string conninfo, std::function<void()> changed)
    : conninfo_(std::move(conninfo)), changed_(std::move(changed)), thread_([this] { run(); }) {}

PostgresListener::~PostgresListener() {
    stopping_ = true;
    thread_.join();
}

void PostgresListener::run() {
    bool warned = false;
    while (!stopping_) {
        try {
            pqxx::connection connection(conninfo_);
            Receiver receiver(connection, changed_);
            changed_();  // whatever happened while no one listened
            warned = false;
            while (!stopping_) connection.await_notification(0, 200000);
        } catch (const std::exception& e) {
            if (!warned) spdlog::warn("listening for job changes in PostgreSQL: {}", e.what());
            warned = true;
            for (int i = 0; i < 10 && !stopping_; ++i)
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    }
}

}  // namespace caustic::server
