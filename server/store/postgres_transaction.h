// Transactions of the PostgreSQL store (store/postgres_job_store.cpp, postgres_asset_store.cpp):
// one connection behind the store's mutex, each operation one transaction, retried when PostgreSQL
// aborts it for a deadlock or a serialization failure, or when the connection broke before the
// commit (reconnecting first), and a full disk reported as StorageFull, a store still out of reach
// after the retries as StoreUnavailable.
#pragma once

#include <pqxx/pqxx>

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "store/job.h"
#include "store/storage_full.h"
#include "store/store_unavailable.h"

namespace caustic::server::postgres {

/// The store's connection: a connection string, and the connection made from it, remade when it
/// broke (the server restarted, a network cut). Not thread-safe: the store's mutex guards it.
struct Connection {
    std::string conninfo;
    std::unique_ptr<pqxx::connection> link;

    pqxx::connection& get() {
        if (!link || !link->is_open()) link = std::make_unique<pqxx::connection>(conninfo);
        return *link;
    }
};

/// The channel every change of a job is announced on (NOTIFY, delivered at commit), so that API
/// processes anywhere wake their event streams (farm/store_listener.h).
inline constexpr const char* kJobsChannel = "caustic_jobs";
void notifyJobs(pqxx::work& tx);
/// A job with its assets; with `lock`, its row locked until the transaction ends.
std::optional<Job> getJob(pqxx::work& tx, const std::string& id, bool lock = false);

/// Runs f(pqxx::work&) in a transaction under `mutex` and commits it; returns what f returns. An
/// exception from f (other than the retried ones) rolls the transaction back and propagates. A
/// transaction whose commit may or may not have happened (pqxx::in_doubt_error) is not retried.
template <class F>
auto transact(Connection& connection, std::mutex& mutex, F&& f) {
    constexpr int kTries = 5;
    std::lock_guard lock(mutex);
    for (int attempt = 1;; ++attempt) {
        try {
            pqxx::work tx(connection.get());
            auto result = f(tx);
            tx.commit();
            return result;
        } catch (const pqxx::transaction_rollback&) {
            // Deadlock or serialization failure: nothing was written; try again.
            if (attempt >= kTries) throw;
        } catch (const pqxx::in_doubt_error&) {
            throw;
        } catch (const pqxx::broken_connection& e) {
            // The server restarting, or a network cut: try again for about three seconds.
            connection.link.reset();
            if (attempt >= kTries)
                throw StoreUnavailable(
                    std::string("the job store (PostgreSQL) cannot be reached: ") + e.what());
            std::this_thread::sleep_for(std::chrono::milliseconds(100 << attempt));
        } catch (const pqxx::disk_full& e) {
            throw StorageFull(
                std::string("PostgreSQL's disk is full: the job store cannot write (") + e.what() +
                ")");
        }
    }
}

}  // namespace caustic::server::postgres
