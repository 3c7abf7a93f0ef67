// The data folder's disk is full: a write of the store or of a job's files failed for lack of
// space (ENOSPC, EDQUOT, SQLITE_FULL). The HTTP boundary answers it with 507 Insufficient Storage
// (RFC 4918, section 11.5); a worker fails the job it was rendering with its message. Whatever
// failed was not written: files go through a temporary name and a rename, and SQLite rolls the
// transaction back, so nothing is left half-written.
#pragma once

#include <cerrno>
#include <stdexcept>

namespace caustic::server {

class StorageFull : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// True for the errno values of a full disk or an exhausted quota.
inline bool isNoSpaceError(int error) {
    return error == ENOSPC || error == EDQUOT;
}

}  // namespace caustic::server
