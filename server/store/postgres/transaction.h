// Transactions of the PostgreSQL store (store/postgres/job_store.cpp, asset_store.cpp,
// tasks.cpp, consolidation.cpp): a pool of connections, each operation one transaction on a
// connection of its own (a heartbeat never waits behind another thread's merge or upload), retried
// when PostgreSQL aborts it for a deadlock, a serialization failure or a lock timeout, or when the
// connection broke before the commit (reconnecting first, holding no lock while it waits); a full
// disk is reported as StorageFull, a store still out of reach after the retries as
// StoreUnavailable.
//
// Every connection bounds what a stalled peer can hold (store/postgres/pool.cpp,
// docs/operations.md): statement_timeout, lock_timeout and idle_in_transaction_session_timeout on
// the server, and connect_timeout, TCP keepalives and tcp_user_timeout on the client, unless the
// connection string sets them.
#pragma once

#include <pqxx/pqxx>

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "store/job.h"
#include "store/storage_full.h"
#include "store/store_unavailable.h"

namespace caustic::server::postgres {

/// The store's connections, made from one connection string as they are needed and kept while
/// they work. Thread-safe.
class Pool {
public:
    /// `name`: the connections' application_name, as pg_stat_activity shows them.
    Pool(std::string conninfo, const std::string& name);
    ~Pool();

    /// A connection of the pool's, for one caller at a time.
    class Lease {
    public:
        Lease(Pool& pool, std::unique_ptr<pqxx::connection> link)
            : pool_(pool), link_(std::move(link)) {}
        ~Lease() { pool_.giveBack(std::move(link_)); }
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        /// The connection, made anew when it broke.
        pqxx::connection& get();
        /// Drops the connection (it broke): the next get() connects again.
        void reset() { link_.reset(); }

    private:
        Pool& pool_;
        std::unique_ptr<pqxx::connection> link_;
    };

    Lease acquire();
    /// The bytea of the first column of the first row `sql` returns with text parameters
    /// `params`, read in binary (pqxx reads bytea as hex text: twice the bytes, and decoding).
    /// Outside any transaction of the caller's: for rows that do not change while they are read.
    /// Nothing when there is no row or the value is NULL; throws pqxx::broken_connection when
    /// the server cannot be reached, std::runtime_error for any other failure.
    std::optional<std::string> readBytes(const char* sql, const std::vector<std::string>& params);
    /// The connection string with the client-side timeouts added.
    const std::string& conninfo() const { return conninfo_; }
    /// A new connection with the session's timeouts set.
    std::unique_ptr<pqxx::connection> connect() const;

private:
    void giveBack(std::unique_ptr<pqxx::connection> link);

    std::string conninfo_;
    std::string sessionSettings_;  ///< SET statements run on each new connection.
    std::mutex mutex_;
    std::vector<std::unique_ptr<pqxx::connection>> idle_;
    struct RawConnections;  // libpq connections for readBytes
    std::unique_ptr<RawConnections> raw_;
};

/// The database's clock in Unix seconds, for SQL: every lease, time limit and liveness is
/// reckoned by it, never by a worker's clock (machines' clocks differ).
inline constexpr const char* kNow = "EXTRACT(EPOCH FROM now())::DOUBLE PRECISION";

/// The channel every change of a job is announced on (NOTIFY, delivered at commit), so that API
/// processes anywhere wake their event streams (store/postgres/listener.h).
inline constexpr const char* kJobsChannel = "caustic_jobs";
void notifyJobs(pqxx::work& tx);
/// A job with its assets; with `lock`, its row locked until the transaction ends.
std::optional<Job> getJob(pqxx::work& tx, const std::string& id, bool lock = false);

/// The database's clock (kNow) at the transaction's start.
double dbNow(pqxx::work& tx);
/// Fails a split job that has not ended; false when it had.
bool failJobRow(pqxx::work& tx, const std::string& id, double now, const std::string& error);
/// Ends the cancelled split jobs that no task renders any more; whether any ended.
bool endCancelledJobs(pqxx::work& tx, double now);

/// Whether `e` is PostgreSQL's lock_timeout (SQLSTATE 55P03): nothing was written.
bool isLockTimeout(const pqxx::sql_error& e);

/// Runs f(pqxx::work&) in a transaction on a connection of `pool`'s and commits it; returns what f
/// returns. An exception from f (other than the retried ones) rolls the transaction back and
/// propagates. A transaction whose commit may or may not have happened (pqxx::in_doubt_error) is
/// not retried.
template <class F>
auto transact(Pool& pool, F&& f) {
    constexpr int kTries = 5;
    Pool::Lease connection = pool.acquire();
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
            connection.reset();
            if (attempt >= kTries)
                throw StoreUnavailable(
                    std::string("the job store (PostgreSQL) cannot be reached: ") + e.what());
            std::this_thread::sleep_for(std::chrono::milliseconds(100 << attempt));
        } catch (const pqxx::disk_full& e) {
            throw StorageFull(
                std::string("PostgreSQL's disk is full: the job store cannot write (") + e.what() +
                ")");
        } catch (const pqxx::sql_error& e) {
            // A row another transaction held past lock_timeout: nothing was written.
            if (!isLockTimeout(e) || attempt >= kTries) throw;
        }
    }
}

}  // namespace caustic::server::postgres
