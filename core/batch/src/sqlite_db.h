#pragma once
// A small RAII layer over SQLite's C API for the batch database (results_db.cpp): a connection,
// prepared statements with typed binds and columns, and a database built under a temporary name
// and renamed into place. Errors throw std::runtime_error naming the file.

#include <sqlite3.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace graftnav::sqlite {

class Database {
 public:
  Database(const std::string& path, int flags);
  ~Database() { sqlite3_close(db_); }
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  void exec(const std::string& sql);
  sqlite3* handle() const { return db_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

class Statement {
 public:
  Statement(Database& db, const std::string& sql);
  ~Statement() { sqlite3_finalize(st_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, const std::string& v);
  Statement& bind(int i, const char* v) { return bind(i, std::string(v)); }
  Statement& bind(int i, double v);  // NaN and inf as NULL
  Statement& bind(int i, long long v);
  Statement& bind(int i, int v) { return bind(i, static_cast<long long>(v)); }
  Statement& bindNull(int i);
  template <typename T>
  Statement& bind(int i, const std::optional<T>& v) {
    return v ? bind(i, *v) : bindNull(i);
  }
  // True while a row is available.
  bool step();
  // Runs the statement once and resets it for the next binds.
  void run();
  bool isNull(int c) const { return sqlite3_column_type(st_, c) == SQLITE_NULL; }
  std::string text(int c) const;
  double real(int c) const {
    return isNull(c) ? std::numeric_limits<double>::quiet_NaN() : sqlite3_column_double(st_, c);
  }
  long long integer(int c) const { return sqlite3_column_int64(st_, c); }
  std::optional<double> optReal(int c) const {
    return isNull(c) ? std::nullopt : std::optional<double>(real(c));
  }
  std::optional<long long> optInteger(int c) const {
    return isNull(c) ? std::nullopt : std::optional<long long>(integer(c));
  }

 private:
  void check(int rc);
  [[noreturn]] void fail(const std::string& what);
  Database& db_;
  sqlite3_stmt* st_ = nullptr;
};

// A database built under a temporary name next to `path` and renamed onto it by commit(); the
// destructor removes the temporary file unless committed.
class AtomicDatabase {
 public:
  explicit AtomicDatabase(const std::string& path);
  ~AtomicDatabase();
  Database& db() { return *db_; }
  void commit();

 private:
  std::string path_, tmp_;
  std::optional<Database> db_;
  bool committed_ = false;
};

}  // namespace graftnav::sqlite
