// The store's schema as an ordered list of migrations (see migrations.cpp).
#pragma once

#include <cstddef>

#include "server/store/sqlite.h"

namespace granulab::server {

/// Number of migrations this build knows: the schema version of an up-to-date database.
std::size_t schema_version_latest();

/// Brings the database to the latest schema: applies each missing migration in its own transaction and
/// records it in PRAGMA user_version. Idempotent; safe when several processes open the file at once.
/// Throws if the database was written by a newer build (user_version above the latest).
void migrate(sqlite::Database& db);

}  // namespace granulab::server
