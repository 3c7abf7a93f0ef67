#include <libpq-fe.h>

#include <cctype>

#include "store/postgres/transaction.h"

namespace caustic::server::postgres {
namespace {

// Client side (libpq): how long a connection may take, and how soon a peer that stopped
// answering is noticed (keepalive probes after 10 s idle, 5 s apart, 3 unanswered; data
// unacknowledged for 30 s).
constexpr const char* kClientDefaults[][2] = {
    {"connect_timeout", "10"},    {"keepalives", "1"},       {"keepalives_idle", "10"},
    {"keepalives_interval", "5"}, {"keepalives_count", "3"}, {"tcp_user_timeout", "30000"},
};

// Server side (the session's settings): no statement runs longer than a minute, no lock is waited
// for longer than 10 s, and a transaction its client left open (the client's machine or network
// gone between statements) is ended after 30 s, releasing its locks. A connection string that
// sets one (options=-c name=value) keeps its own.
constexpr const char* kSessionSettings[][2] = {
    {"statement_timeout", "60s"},
    {"lock_timeout", "10s"},
    {"idle_in_transaction_session_timeout", "30s"},
};

bool isUri(const std::string& conninfo) {
    return conninfo.rfind("postgresql://", 0) == 0 || conninfo.rfind("postgres://", 0) == 0;
}

void addParameter(std::string& conninfo, const std::string& key, const std::string& value) {
    if (conninfo.find(key + "=") != std::string::npos) return;  // the user's own
    if (isUri(conninfo))
        conninfo += (conninfo.find('?') == std::string::npos ? "?" : "&") + key + "=" + value;
    else
        conninfo += (conninfo.empty() ? "" : " ") + key + "=" + value;
}

// `conninfo` with each client default it does not set itself, and the application name (letters,
// digits, '-' and '_' only: nothing to quote in either syntax).
std::string withClientDefaults(std::string conninfo, std::string name) {
    for (const auto& [key, value] : kClientDefaults) addParameter(conninfo, key, value);
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '-';
    if (!name.empty()) addParameter(conninfo, "fallback_application_name", name);
    return conninfo;
}

}  // namespace

struct Pool::RawConnections {
    std::mutex mutex;
    std::vector<PGconn*> idle;

    ~RawConnections() {
        for (PGconn* c : idle) PQfinish(c);
    }
};

Pool::Pool(std::string conninfo, const std::string& name)
    : conninfo_(withClientDefaults(conninfo, name)), raw_(std::make_unique<RawConnections>()) {
    for (const auto& [key, value] : kSessionSettings)
        if (conninfo.find(key) == std::string::npos)
            sessionSettings_ += std::string("SET ") + key + " = '" + value + "'; ";
}

Pool::~Pool() = default;

std::optional<std::string> Pool::readBytes(const char* sql,
                                           const std::vector<std::string>& params) {
    PGconn* c = nullptr;
    {
        std::lock_guard lock(raw_->mutex);
        if (!raw_->idle.empty()) {
            c = raw_->idle.back();
            raw_->idle.pop_back();
        }
    }
    if (!c || PQstatus(c) != CONNECTION_OK) {
        if (c) PQfinish(c);
        c = PQconnectdb(conninfo_.c_str());
        if (PQstatus(c) != CONNECTION_OK) {
            const std::string why = PQerrorMessage(c);
            PQfinish(c);
            throw pqxx::broken_connection(why);
        }
        if (!sessionSettings_.empty()) PQclear(PQexec(c, sessionSettings_.c_str()));
    }
    std::vector<const char*> values;
    for (const std::string& p : params) values.push_back(p.c_str());
    PGresult* r = PQexecParams(c, sql, int(values.size()), nullptr, values.data(), nullptr, nullptr,
                               /*resultFormat=*/1);
    const ExecStatusType status = PQresultStatus(r);
    std::optional<std::string> bytes;
    std::string error;
    if (status == PGRES_TUPLES_OK) {
        if (PQntuples(r) > 0 && !PQgetisnull(r, 0, 0))
            bytes.emplace(PQgetvalue(r, 0, 0), size_t(PQgetlength(r, 0, 0)));
    } else {
        error = PQresultErrorMessage(r);
    }
    PQclear(r);
    const bool broken = PQstatus(c) != CONNECTION_OK;
    if (broken) {
        PQfinish(c);
    } else {
        std::lock_guard lock(raw_->mutex);
        raw_->idle.push_back(c);
    }
    if (broken) throw pqxx::broken_connection(error);
    if (!error.empty()) throw std::runtime_error("reading from the job store: " + error);
    return bytes;
}

std::unique_ptr<pqxx::connection> Pool::connect() const {
    auto link = std::make_unique<pqxx::connection>(conninfo_);
    if (!sessionSettings_.empty()) pqxx::nontransaction(*link).exec(sessionSettings_);
    return link;
}

pqxx::connection& Pool::Lease::get() {
    if (!link_ || !link_->is_open()) link_ = pool_.connect();
    return *link_;
}

Pool::Lease Pool::acquire() {
    std::lock_guard lock(mutex_);
    if (idle_.empty()) return Lease(*this, nullptr);
    std::unique_ptr<pqxx::connection> link = std::move(idle_.back());
    idle_.pop_back();
    return Lease(*this, std::move(link));
}

void Pool::giveBack(std::unique_ptr<pqxx::connection> link) {
    if (!link || !link->is_open()) return;
    // A connection left inside a transaction (it cannot be: pqxx::work rolls back) is dropped.
    std::lock_guard lock(mutex_);
    idle_.push_back(std::move(link));
}

bool isLockTimeout(const pqxx::sql_error& e) {
    return e.sqlstate() == "55P03";
}

}  // namespace caustic::server::postgres
