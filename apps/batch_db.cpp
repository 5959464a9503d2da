#include "batch_db.h"

#include <fmt/core.h>
#include <sqlite3.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace graftnav::app {
namespace fs = std::filesystem;
namespace {

constexpr int kSchemaVersion = 1;

// One schema for the task files and the collected database (docs/batch.md describes it).
constexpr const char* kSchema = R"sql(
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE tasks (
  task_index INTEGER PRIMARY KEY, task_id TEXT NOT NULL UNIQUE, name TEXT NOT NULL,
  case_name TEXT NOT NULL, case_path TEXT NOT NULL, estimator TEXT NOT NULL,
  schedule TEXT NOT NULL, outage_length_s REAL, outage_period_s REAL, outage_start_s REAL,
  seed INTEGER NOT NULL);
CREATE TABLE runs (
  task_id TEXT PRIMARY KEY, status TEXT NOT NULL CHECK (status IN ('ok', 'failed')),
  error TEXT NOT NULL, outage_count INTEGER, reference TEXT NOT NULL, seconds REAL NOT NULL,
  graftnav_version TEXT NOT NULL, realizations INTEGER);
CREATE TABLE run_statistics (
  task_id TEXT NOT NULL, solution TEXT NOT NULL, statistic TEXT NOT NULL,
  outage_rms REAL, outage_max_rms REAL, overall_rms REAL, diff REAL,
  PRIMARY KEY (task_id, solution, statistic));
CREATE TABLE outages (
  task_id TEXT NOT NULL, solution TEXT NOT NULL, outage_index INTEGER NOT NULL,
  start_s REAL NOT NULL, end_s REAL NOT NULL, epochs INTEGER NOT NULL,
  horizontal_m REAL, vertical_m REAL, roll_deg REAL, pitch_deg REAL, heading_deg REAL,
  PRIMARY KEY (task_id, solution, outage_index));
CREATE TABLE predictive_intervals (
  task_id TEXT NOT NULL, solution TEXT NOT NULL, statistic TEXT NOT NULL,
  p05 REAL, p50 REAL, p95 REAL, mean REAL, sd REAL, real_percentile REAL, verdict TEXT,
  PRIMARY KEY (task_id, solution, statistic));
)sql";

// The tables copied from a task file into the collected database (tasks come from the manifest).
constexpr const char* kResultTables[] = {"runs", "run_statistics", "outages",
                                         "predictive_intervals"};

class Statement;

class Database {
 public:
  Database(const std::string& path, int flags) : path_(path) {
    if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
      const std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw std::runtime_error(fmt::format("SQLite database '{}': {}", path, msg));
    }
    sqlite3_busy_timeout(db_, 10000);
  }
  ~Database() { sqlite3_close(db_); }
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  void exec(const std::string& sql) {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string msg = err ? err : "unknown error";
      sqlite3_free(err);
      throw std::runtime_error(
          fmt::format("SQLite database '{}': {} (in: {})", path_, msg, sql.substr(0, 80)));
    }
  }
  sqlite3* handle() const { return db_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

class Statement {
 public:
  Statement(Database& db, const std::string& sql) : db_(db) {
    if (sqlite3_prepare_v2(db.handle(), sql.c_str(), -1, &st_, nullptr) != SQLITE_OK) fail(sql);
  }
  ~Statement() { sqlite3_finalize(st_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, const std::string& v) {
    check(sqlite3_bind_text(st_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
    return *this;
  }
  Statement& bind(int i, const char* v) { return bind(i, std::string(v)); }
  Statement& bind(int i, double v) {
    check(std::isfinite(v) ? sqlite3_bind_double(st_, i, v) : sqlite3_bind_null(st_, i));
    return *this;
  }
  Statement& bind(int i, long long v) {
    check(sqlite3_bind_int64(st_, i, v));
    return *this;
  }
  Statement& bind(int i, int v) { return bind(i, static_cast<long long>(v)); }
  template <typename T>
  Statement& bind(int i, const std::optional<T>& v) {
    if (v) return bind(i, *v);
    check(sqlite3_bind_null(st_, i));
    return *this;
  }
  // True while a row is available.
  bool step() {
    const int rc = sqlite3_step(st_);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) fail("step");
    return false;
  }
  void run() {
    step();
    sqlite3_reset(st_);
    sqlite3_clear_bindings(st_);
  }
  bool isNull(int c) const { return sqlite3_column_type(st_, c) == SQLITE_NULL; }
  std::string text(int c) const {
    const auto* p = sqlite3_column_text(st_, c);
    return p ? reinterpret_cast<const char*>(p) : "";
  }
  double real(int c) const {
    return isNull(c) ? std::numeric_limits<double>::quiet_NaN() : sqlite3_column_double(st_, c);
  }
  long long integer(int c) const { return sqlite3_column_int64(st_, c); }
  std::optional<double> optReal(int c) const {
    return isNull(c) ? std::nullopt : std::optional<double>(real(c));
  }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK) fail("bind");
  }
  [[noreturn]] void fail(const std::string& what) {
    throw std::runtime_error(fmt::format("SQLite database '{}': {} ({})", db_.path(),
                                         sqlite3_errmsg(db_.handle()), what.substr(0, 80)));
  }
  Database& db_;
  sqlite3_stmt* st_ = nullptr;
};

// A database built under a temporary name and renamed onto `path` by commit().
class AtomicDatabase {
 public:
  explicit AtomicDatabase(const std::string& path) : path_(path) {
    static std::atomic<unsigned> counter{0};
    const fs::path p(path);
    tmp_ = (p.parent_path() /
            fmt::format(".{}.tmp.{}.{}", p.filename().string(), ::getpid(), counter++))
               .string();
    fs::remove(tmp_);
    db_.emplace(tmp_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    db_->exec("PRAGMA journal_mode = OFF; PRAGMA synchronous = NORMAL;");
    db_->exec(kSchema);
    db_->exec(
        fmt::format("INSERT INTO meta VALUES ('schema_version', '{}'), ('graftnav_version', '{}');",
                    kSchemaVersion, batchSoftwareVersion()));
  }
  ~AtomicDatabase() {
    db_.reset();
    if (!committed_) fs::remove(tmp_);
  }
  Database& db() { return *db_; }
  void commit() {
    db_.reset();
    fs::rename(tmp_, path_);
    committed_ = true;
  }

 private:
  std::string path_, tmp_;
  std::optional<Database> db_;
  bool committed_ = false;
};

void insertTask(Database& db, const BatchTask& t) {
  Statement st(db, "INSERT INTO tasks VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)");
  st.bind(1, t.index)
      .bind(2, t.id)
      .bind(3, t.name)
      .bind(4, t.case_name)
      .bind(5, t.case_dir)
      .bind(6, t.estimator);
  st.bind(7, t.schedule_label);
  if (t.schedule)
    st.bind(8, t.schedule->length_s).bind(9, t.schedule->period_s).bind(10, t.schedule->start_s);
  else
    st.bind(8, std::optional<double>())
        .bind(9, std::optional<double>())
        .bind(10, std::optional<double>());
  st.bind(11, static_cast<long long>(t.seed));
  st.run();
}

void insertResults(Database& db, const std::string& id, const BatchRunRecord& r) {
  Statement run(db, "INSERT INTO runs VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)");
  run.bind(1, id)
      .bind(2, statusName(r.ok ? TaskStatus::kOk : TaskStatus::kFailed))
      .bind(3, r.error)
      .bind(4, r.outage_count)
      .bind(5, r.reference);
  run.bind(6, r.seconds).bind(7, batchSoftwareVersion()).bind(8, r.realizations).run();
  Statement stat(db, "INSERT INTO run_statistics VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)");
  for (const auto& s : r.statistics) {
    stat.bind(1, id)
        .bind(2, s.solution)
        .bind(3, s.statistic)
        .bind(4, s.outage_rms)
        .bind(5, s.outage_max_rms);
    stat.bind(6, s.overall_rms).bind(7, s.diff).run();
  }
  Statement out(db, "INSERT INTO outages VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)");
  for (const auto& o : r.outages) {
    out.bind(1, id)
        .bind(2, o.solution)
        .bind(3, o.outage_index)
        .bind(4, o.start_s)
        .bind(5, o.end_s)
        .bind(6, o.epochs);
    out.bind(7, o.horizontal_m).bind(8, o.vertical_m).bind(9, o.roll_deg).bind(10, o.pitch_deg);
    out.bind(11, o.heading_deg).run();
  }
  Statement pred(
      db, "INSERT INTO predictive_intervals VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)");
  for (const auto& p : r.predictive) {
    pred.bind(1, id)
        .bind(2, p.solution)
        .bind(3, p.statistic)
        .bind(4, p.p05)
        .bind(5, p.p50)
        .bind(6, p.p95);
    pred.bind(7, p.mean).bind(8, p.sd).bind(9, p.real_percentile).bind(10, p.verdict).run();
  }
}

TaskStatus parseStatus(const std::string& word, const std::string& db_path) {
  for (TaskStatus s : {TaskStatus::kOk, TaskStatus::kFailed, TaskStatus::kMissing})
    if (word == statusName(s)) return s;
  throw std::runtime_error(
      fmt::format("SQLite database '{}': unknown run status '{}'", db_path, word));
}

std::optional<double> jsonNumber(const nlohmann::json& o, const char* key) {
  const auto it = o.find(key);
  if (it == o.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

}  // namespace

const char* statusName(TaskStatus s) {
  switch (s) {
    case TaskStatus::kOk:
      return "ok";
    case TaskStatus::kFailed:
      return "failed";
    case TaskStatus::kMissing:
      return "missing";
  }
  return "missing";
}

BatchPredictive readPredictive(const std::string& path) {
  BatchPredictive out;
  std::ifstream in(path);
  if (!in) return out;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format("'{}' is not valid JSON: {}", path, e.what()));
  }
  if (const auto k = j.find("realizations"); k != j.end() && k->is_number_integer())
    out.realizations = k->get<int>();
  const auto it = j.find("predictive");
  if (it == j.end() || !it->is_object()) return out;
  for (const auto& [solution, stats] : it->items()) {
    if (!stats.is_object()) continue;
    for (const auto& [statistic, v] : stats.items()) {
      if (!v.is_object()) continue;
      BatchPredictiveRow r;
      r.solution = solution;
      r.statistic = statistic;
      r.p05 = jsonNumber(v, "p05");
      r.p50 = jsonNumber(v, "p50");
      r.p95 = jsonNumber(v, "p95");
      r.mean = jsonNumber(v, "mean");
      r.sd = jsonNumber(v, "sd");
      // REAL's place sits beside "predictive", under the same solution and statistic keys.
      const nlohmann::json pct = j.value("real_percentile", nlohmann::json::object());
      if (pct.contains(solution) && pct[solution].contains(statistic) &&
          pct[solution][statistic].is_number())
        r.real_percentile = pct[solution][statistic].get<double>();
      const nlohmann::json ver = j.value("verdict", nlohmann::json::object());
      if (ver.contains(solution) && ver[solution].contains(statistic) &&
          ver[solution][statistic].is_string())
        r.verdict = ver[solution][statistic].get<std::string>();
      out.rows.push_back(std::move(r));
    }
  }
  return out;
}

void writeTaskDatabase(const std::string& path, const BatchTask& task,
                       const BatchRunRecord& record) {
  AtomicDatabase out(path);
  out.db().exec("BEGIN");
  insertTask(out.db(), task);
  insertResults(out.db(), task.id, record);
  out.db().exec("COMMIT");
  out.commit();
}

TaskStatus taskDatabaseStatus(const std::string& path, const std::string& task_id) {
  if (!fs::is_regular_file(path)) return TaskStatus::kMissing;
  try {
    Database db(path, SQLITE_OPEN_READONLY);
    Statement st(db, "SELECT status FROM runs WHERE task_id = ?1");
    st.bind(1, task_id);
    if (st.step()) return parseStatus(st.text(0), path);
  } catch (const std::runtime_error&) {
    // An unreadable or foreign file is not a record of this task: the task runs again.
  }
  return TaskStatus::kMissing;
}

CollectCounts collectTaskDatabases(const std::string& out_db_path,
                                   const std::vector<BatchTask>& tasks) {
  CollectCounts n;
  AtomicDatabase out(out_db_path);
  Database& db = out.db();
  db.exec("BEGIN");
  for (const auto& t : tasks) insertTask(db, t);
  db.exec("COMMIT");
  for (const auto& t : tasks) {
    const std::string file = (fs::path(t.out_dir) / "task.sqlite").string();
    const TaskStatus status = taskDatabaseStatus(file, t.id);
    if (status == TaskStatus::kMissing) {
      ++n.missing;
      continue;
    }
    (status == TaskStatus::kOk ? n.ok : n.failed)++;
    Statement attach(db, "ATTACH DATABASE ?1 AS task");
    attach.bind(1, file).run();
    db.exec("BEGIN");
    for (const char* table : kResultTables) {
      Statement copy(
          db, fmt::format("INSERT INTO main.{0} SELECT * FROM task.{0} WHERE task_id = ?1", table));
      copy.bind(1, t.id).run();
    }
    db.exec("COMMIT");
    db.exec("DETACH DATABASE task");
  }
  out.commit();
  return n;
}

std::vector<BatchSummaryRow> readSummaryRows(const std::string& db_path) {
  Database db(db_path, SQLITE_OPEN_READONLY);
  std::vector<BatchSummaryRow> rows;
  std::map<std::string, std::size_t> by_id;
  Statement st(db,
               "SELECT t.task_index, t.task_id, t.case_name, t.estimator, t.schedule, t.seed, "
               "coalesce(r.status, 'missing'), coalesce(r.error, ''), r.outage_count "
               "FROM tasks t LEFT JOIN runs r ON r.task_id = t.task_id ORDER BY t.task_index");
  while (st.step()) {
    BatchSummaryRow r;
    r.task_index = static_cast<int>(st.integer(0));
    r.case_name = st.text(2);
    r.estimator = st.text(3);
    r.schedule = st.text(4);
    r.seed = static_cast<unsigned long long>(st.integer(5));
    r.status = parseStatus(st.text(6), db_path);
    r.error = st.text(7);
    if (!st.isNull(8)) r.outage_count = static_cast<int>(st.integer(8));
    by_id[st.text(1)] = rows.size();
    rows.push_back(std::move(r));
  }
  Statement stats(
      db,
      "SELECT task_id, solution, statistic, outage_rms, outage_max_rms, overall_rms, diff "
      "FROM run_statistics ORDER BY task_id, solution, statistic");
  while (stats.step()) {
    BatchStatisticRow s{stats.text(1), stats.text(2), stats.real(3),
                        stats.real(4), stats.real(5), stats.optReal(6)};
    rows.at(by_id.at(stats.text(0))).statistics.push_back(std::move(s));
  }
  return rows;
}

}  // namespace graftnav::app
