// Small RAII helpers over SQLite's C API, shared by the job store's files
// (store/sqlite/job_store.cpp, store/sqlite/asset_store.cpp): prepared statements, exec and
// transactions. Not thread-safe by themselves: the store's mutex serializes their use.
#pragma once

#include <sqlite3.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "store/job_store.h"
#include "store/storage_full.h"

namespace caustic::server::sqlite {

/// Throws StorageFull for a full disk, which SQLite reports as SQLITE_FULL (a write of the
/// database or its WAL) or as an I/O error whose errno is ENOSPC (growing the WAL index, for one;
/// https://www.sqlite.org/rescode.html#full), else runtime_error. The statement or transaction
/// that failed was rolled back, so the store stays as it was.
[[noreturn]] inline void fail(sqlite3* db, int rc, const std::string& context = {}) {
    const std::string m = std::string("sqlite: ") + sqlite3_errmsg(db) + context;
    if ((rc & 0xff) == SQLITE_FULL ||
        ((rc & 0xff) == SQLITE_IOERR && isNoSpaceError(sqlite3_system_errno(db))))
        throw StorageFull("the data folder's disk is full: the job store cannot write (" + m + ")");
    throw std::runtime_error(m);
}

// A prepared statement, finalized on scope exit. Binds by 1-based position.
class Statement {
public:
    Statement(sqlite3* db, const std::string& sql) : db_(db) {
        if (int rc = sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr); rc != SQLITE_OK)
            fail(db, rc, " in " + sql);
    }
    ~Statement() { sqlite3_finalize(stmt_); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;

    Statement& bind(int i, const std::string& v) {
        check(sqlite3_bind_text(stmt_, i, v.c_str(), int(v.size()), SQLITE_TRANSIENT));
        return *this;
    }
    Statement& bind(int i, const char* v) { return bind(i, std::string(v)); }
    Statement& bind(int i, double v) {
        check(std::isnan(v) ? sqlite3_bind_null(stmt_, i) : sqlite3_bind_double(stmt_, i, v));
        return *this;
    }
    Statement& bind(int i, int64_t v) {
        check(sqlite3_bind_int64(stmt_, i, v));
        return *this;
    }
    Statement& bind(int i, int v) { return bind(i, int64_t(v)); }
    /// Binds bytes as a BLOB (not text: they need not be UTF-8).
    Statement& bindBlob(int i, std::string_view v) {
        check(sqlite3_bind_blob64(stmt_, i, v.data(), v.size(), SQLITE_TRANSIENT));
        return *this;
    }

    /// Steps once: true while there is a row.
    bool step() {
        int rc = sqlite3_step(stmt_);
        if (rc == SQLITE_ROW) return true;
        if (rc == SQLITE_DONE) return false;
        fail(db_, rc);
    }
    /// Runs to completion; returns the rows changed.
    int run() {
        while (step()) {
        }
        return sqlite3_changes(db_);
    }

    std::string text(int col) const {
        const unsigned char* t = sqlite3_column_text(stmt_, col);
        return t ? std::string(reinterpret_cast<const char*>(t),
                               size_t(sqlite3_column_bytes(stmt_, col)))
                 : std::string();
    }
    int64_t integer(int col) const { return sqlite3_column_int64(stmt_, col); }
    /// A BLOB (or text) column's bytes.
    std::string blob(int col) const {
        const void* p = sqlite3_column_blob(stmt_, col);
        return p ? std::string(static_cast<const char*>(p),
                               size_t(sqlite3_column_bytes(stmt_, col)))
                 : std::string();
    }
    double real(int col) const {
        return sqlite3_column_type(stmt_, col) == SQLITE_NULL ? std::nan("")
                                                              : sqlite3_column_double(stmt_, col);
    }

private:
    void check(int rc) const {
        if (rc != SQLITE_OK) fail(db_, rc);
    }
    sqlite3* db_;
    sqlite3_stmt* stmt_ = nullptr;
};

inline void exec(sqlite3* db, const char* sql) {
    if (int rc = sqlite3_exec(db, sql, nullptr, nullptr, nullptr); rc != SQLITE_OK) fail(db, rc);
}

// BEGIN IMMEDIATE ... COMMIT, rolled back if the scope is left by an exception.
class Transaction {
public:
    explicit Transaction(sqlite3* db) : db_(db) { exec(db_, "BEGIN IMMEDIATE"); }
    ~Transaction() {
        if (!done_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    }
    void commit() {
        exec(db_, "COMMIT");
        done_ = true;
    }

private:
    sqlite3* db_;
    bool done_ = false;
};

}  // namespace caustic::server::sqlite
