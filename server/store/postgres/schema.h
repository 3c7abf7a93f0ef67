// The PostgreSQL store's schema as numbered migrations, and the code that applies them: at start-up
// every process brings the database up to its version, one at a time (an advisory lock), each
// migration in the transaction that records it in schema_migrations(version).
#pragma once

#include <pqxx/pqxx>

namespace caustic::server::postgres {

/// The highest migration this program knows.
int latestSchemaVersion();

/// Applies the migrations the database lacks, in order. Throws std::runtime_error when the
/// database's version is newer than latestSchemaVersion() (written by a newer program).
void migrate(pqxx::connection& connection);

}  // namespace caustic::server::postgres
