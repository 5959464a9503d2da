#include "sqlite_db.h"

#include <fmt/core.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <stdexcept>

namespace graftnav::sqlite {
namespace fs = std::filesystem;

Database::Database(const std::string& path, int flags) : path_(path) {
  if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
    const std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw std::runtime_error(fmt::format("SQLite database '{}': {}", path, msg));
  }
  sqlite3_busy_timeout(db_, 10000);
}

void Database::exec(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string msg = err ? err : "unknown error";
    sqlite3_free(err);
    throw std::runtime_error(
        fmt::format("SQLite database '{}': {} (in: {})", path_, msg, sql.substr(0, 80)));
  }
}

Statement::Statement(Database& db, const std::string& sql) : db_(db) {
  if (sqlite3_prepare_v2(db.handle(), sql.c_str(), -1, &st_, nullptr) != SQLITE_OK) fail(sql);
}

Statement& Statement::bind(int i, const std::string& v) {
  check(sqlite3_bind_text(st_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
  return *this;
}

Statement& Statement::bind(int i, double v) {
  check(std::isfinite(v) ? sqlite3_bind_double(st_, i, v) : sqlite3_bind_null(st_, i));
  return *this;
}

Statement& Statement::bind(int i, long long v) {
  check(sqlite3_bind_int64(st_, i, v));
  return *this;
}

Statement& Statement::bindNull(int i) {
  check(sqlite3_bind_null(st_, i));
  return *this;
}

bool Statement::step() {
  const int rc = sqlite3_step(st_);
  if (rc == SQLITE_ROW) return true;
  if (rc != SQLITE_DONE) fail("step");
  return false;
}

void Statement::run() {
  step();
  sqlite3_reset(st_);
  sqlite3_clear_bindings(st_);
}

std::string Statement::text(int c) const {
  const auto* p = sqlite3_column_text(st_, c);
  return p ? reinterpret_cast<const char*>(p) : "";
}

void Statement::check(int rc) {
  if (rc != SQLITE_OK) fail("bind");
}

void Statement::fail(const std::string& what) {
  throw std::runtime_error(fmt::format("SQLite database '{}': {} ({})", db_.path(),
                                       sqlite3_errmsg(db_.handle()), what.substr(0, 80)));
}

AtomicDatabase::AtomicDatabase(const std::string& path) : path_(path) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(path);
  tmp_ =
      (p.parent_path() / fmt::format(".{}.tmp.{}.{}", p.filename().string(), ::getpid(), counter++))
          .string();
  fs::remove(tmp_);
  db_.emplace(tmp_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db_->exec("PRAGMA journal_mode = OFF; PRAGMA synchronous = NORMAL;");
}

AtomicDatabase::~AtomicDatabase() {
  db_.reset();
  if (!committed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void AtomicDatabase::commit() {
  db_.reset();
  fs::rename(tmp_, path_);
  committed_ = true;
}

}  // namespace graftnav::sqlite
