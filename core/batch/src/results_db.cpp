#include "graftnav/batch/results_db.h"

#include <fmt/core.h>

#include <filesystem>
#include <map>
#include <stdexcept>

#include "sqlite_db.h"

namespace graftnav {
namespace fs = std::filesystem;
using sqlite::AtomicDatabase;
using sqlite::Database;
using sqlite::Statement;

namespace {

// One schema for the task files and the collected database (docs/batch.md describes it).
constexpr const char* kSchema = R"sql(
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE tasks (
  task_index INTEGER PRIMARY KEY, task_id TEXT NOT NULL UNIQUE, name TEXT NOT NULL,
  case_name TEXT NOT NULL, case_path TEXT NOT NULL, estimator TEXT NOT NULL,
  schedule TEXT NOT NULL, outage_length_s REAL, outage_period_s REAL, outage_start_s REAL,
  seed INTEGER, grp TEXT NOT NULL, command TEXT NOT NULL, options_json TEXT NOT NULL,
  peak_rss_mb REAL, seconds REAL);
CREATE TABLE runs (
  task_id TEXT PRIMARY KEY, status TEXT NOT NULL CHECK (status IN ('ok', 'failed')),
  error TEXT NOT NULL, outage_count INTEGER, reference TEXT NOT NULL, seconds REAL NOT NULL,
  graftnav_version TEXT NOT NULL, realizations INTEGER, exit_code INTEGER);
CREATE TABLE statistics (
  task_id TEXT NOT NULL, estimator TEXT NOT NULL, solution TEXT NOT NULL, schedule TEXT NOT NULL,
  scope TEXT NOT NULL CHECK (scope IN ('overall', 'outage', 'checkpoint', 'reference')),
  statistic TEXT NOT NULL, measure TEXT NOT NULL, value REAL, unit TEXT NOT NULL,
  PRIMARY KEY (task_id, estimator, solution, scope, statistic, measure));
CREATE TABLE outages (
  task_id TEXT NOT NULL, solution TEXT NOT NULL, outage_index INTEGER NOT NULL,
  start_s REAL NOT NULL, end_s REAL NOT NULL, epochs INTEGER NOT NULL,
  horizontal_m REAL, vertical_m REAL, roll_deg REAL, pitch_deg REAL, heading_deg REAL,
  PRIMARY KEY (task_id, solution, outage_index));
CREATE TABLE predictive_intervals (
  task_id TEXT NOT NULL, solution TEXT NOT NULL, statistic TEXT NOT NULL,
  p05 REAL, p50 REAL, p95 REAL, mean REAL, sd REAL, real_percentile REAL, verdict TEXT,
  PRIMARY KEY (task_id, solution, statistic));
CREATE TABLE effects (
  task_id TEXT NOT NULL, kind TEXT NOT NULL, name TEXT NOT NULL, sensor TEXT NOT NULL,
  parameter TEXT NOT NULL, value REAL, sigma REAL, text TEXT NOT NULL);
CREATE TABLE cross_checks (
  task_id TEXT NOT NULL, a TEXT NOT NULL, b TEXT NOT NULL, sigma_form TEXT NOT NULL,
  statistic TEXT NOT NULL, rms_difference REAL, rms_sigma REAL, rms_normalized REAL,
  max_normalized REAL, epochs INTEGER NOT NULL, PRIMARY KEY (task_id, a, b, statistic));
)sql";

// The tables copied from a task file into the collected database (tasks come from the manifest).
constexpr const char* kResultTables[] = {
    "runs", "statistics", "outages", "predictive_intervals", "effects", "cross_checks"};

void createSchema(Database& db) {
  db.exec(kSchema);
  db.exec(
      fmt::format("INSERT INTO meta VALUES ('schema_version', '{}'), ('graftnav_version', '{}');",
                  kBatchSchemaVersion, batchSoftwareVersion()));
}

void insertTask(Database& db, const BatchTask& t, const BatchRunRecord* r) {
  Statement st(db,
               "INSERT INTO tasks VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, "
               "?14, ?15, ?16)");
  st.bind(1, t.index).bind(2, t.id).bind(3, t.folder()).bind(4, t.case_name).bind(5, t.case_dir);
  st.bind(6, t.estimator).bind(7, t.schedule_label);
  if (t.schedule)
    st.bind(8, t.schedule->length_s).bind(9, t.schedule->period_s).bind(10, t.schedule->start_s);
  else
    st.bindNull(8).bindNull(9).bindNull(10);
  if (t.seed)
    st.bind(11, static_cast<long long>(*t.seed));
  else
    st.bindNull(11);
  st.bind(12, t.grp).bind(13, batchCommandName(t.command)).bind(14, t.options_json);
  if (r)
    st.bind(15, r->peak_rss_mb).bind(16, r->cpu_seconds);
  else
    st.bindNull(15).bindNull(16);
  st.run();
}

void insertStatistics(Database& db, const BatchTask& t, const BatchRunRecord& r) {
  Statement st(db, "INSERT INTO statistics VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
  for (const auto& s : r.statistics) {
    st.bind(1, t.id).bind(2, s.estimator).bind(3, s.solution).bind(4, t.schedule_label);
    st.bind(5, s.scope).bind(6, s.statistic).bind(7, s.measure).bind(8, s.value).bind(9, s.unit);
    st.run();
  }
}

void insertOutages(Database& db, const std::string& id, const BatchRunRecord& r) {
  Statement st(db, "INSERT INTO outages VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)");
  for (const auto& o : r.outages) {
    st.bind(1, id).bind(2, o.solution).bind(3, o.outage_index).bind(4, o.start_s);
    st.bind(5, o.end_s).bind(6, o.epochs).bind(7, o.horizontal_m).bind(8, o.vertical_m);
    st.bind(9, o.roll_deg).bind(10, o.pitch_deg).bind(11, o.heading_deg).run();
  }
}

void insertPredictive(Database& db, const std::string& id, const BatchRunRecord& r) {
  Statement st(db,
               "INSERT INTO predictive_intervals VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)");
  for (const auto& p : r.predictive) {
    st.bind(1, id).bind(2, p.solution).bind(3, p.statistic).bind(4, p.p05).bind(5, p.p50);
    st.bind(6, p.p95).bind(7, p.mean).bind(8, p.sd).bind(9, p.real_percentile);
    st.bind(10, p.verdict).run();
  }
}

void insertEffectsAndCrossChecks(Database& db, const std::string& id, const BatchRunRecord& r) {
  Statement e(db, "INSERT INTO effects VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)");
  for (const auto& x : r.effects) {
    e.bind(1, id).bind(2, x.kind).bind(3, x.name).bind(4, x.sensor).bind(5, x.parameter);
    e.bind(6, x.value).bind(7, x.sigma).bind(8, x.text).run();
  }
  Statement c(db, "INSERT INTO cross_checks VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)");
  for (const auto& x : r.cross_checks) {
    c.bind(1, id).bind(2, x.a).bind(3, x.b).bind(4, x.sigma_form).bind(5, x.statistic);
    c.bind(6, x.rms_difference).bind(7, x.rms_sigma).bind(8, x.rms_normalized);
    c.bind(9, x.max_normalized).bind(10, x.epochs).run();
  }
}

void insertResults(Database& db, const BatchTask& t, const BatchRunRecord& r) {
  Statement run(db, "INSERT INTO runs VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
  run.bind(1, t.id).bind(2, statusName(r.ok ? TaskStatus::kOk : TaskStatus::kFailed));
  run.bind(3, r.error).bind(4, r.outage_count).bind(5, r.reference).bind(6, r.seconds);
  run.bind(7, batchSoftwareVersion()).bind(8, r.realizations).bind(9, r.exit_code).run();
  insertStatistics(db, t, r);
  insertOutages(db, t.id, r);
  insertPredictive(db, t.id, r);
  insertEffectsAndCrossChecks(db, t.id, r);
}

TaskStatus parseStatus(const std::string& word, const std::string& db_path) {
  for (TaskStatus s : {TaskStatus::kOk, TaskStatus::kFailed, TaskStatus::kMissing})
    if (word == statusName(s)) return s;
  throw std::runtime_error(
      fmt::format("SQLite database '{}': unknown run status '{}'", db_path, word));
}

BatchCommand parseCommandColumn(const std::string& word, const std::string& db_path) {
  if (const auto c = parseBatchCommand(word)) return *c;
  throw std::runtime_error(
      fmt::format("SQLite database '{}': unknown command '{}' (expected one of {})", db_path, word,
                  batchCommandList()));
}

int schemaVersion(Database& db) {
  try {
    Statement st(db, "SELECT value FROM meta WHERE key = 'schema_version'");
    return st.step() ? std::stoi(st.text(0)) : 0;
  } catch (const std::exception&) {
    return 0;  // no meta table: not a batch database
  }
}

std::string versionError(const std::string& path, int version) {
  return fmt::format(
      "'{}' is a batch results database of schema version {}; this graftnav reads version {} "
      "({})",
      path, version, kBatchSchemaVersion,
      version < kBatchSchemaVersion
          ? "written by an older graftnav: rerun its tasks (graftnav batch MANIFEST --force) "
            "and collect again"
          : "written by a newer graftnav");
}

// The status a task file records for task_id, or kMissing (no record of this id and schema).
TaskStatus recordedStatus(Database& db, const std::string& task_id) {
  if (schemaVersion(db) != kBatchSchemaVersion) return TaskStatus::kMissing;
  Statement st(db, "SELECT status FROM runs WHERE task_id = ?1");
  st.bind(1, task_id);
  return st.step() ? parseStatus(st.text(0), db.path()) : TaskStatus::kMissing;
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

void writeTaskDatabase(const std::string& path, const BatchTask& task,
                       const BatchRunRecord& record) {
  AtomicDatabase out(path);
  createSchema(out.db());
  out.db().exec("BEGIN");
  insertTask(out.db(), task, &record);
  insertResults(out.db(), task, record);
  out.db().exec("COMMIT");
  out.commit();
}

TaskStatus taskDatabaseStatus(const std::string& path, const std::string& task_id) {
  if (!fs::is_regular_file(path)) return TaskStatus::kMissing;
  try {
    Database db(path, SQLITE_OPEN_READONLY);
    return recordedStatus(db, task_id);
  } catch (const std::runtime_error&) {
    return TaskStatus::kMissing;  // an unreadable or foreign file is no record: the task reruns
  }
}

std::optional<double> taskPeakRssMb(const std::string& path) {
  if (!fs::is_regular_file(path)) return std::nullopt;
  try {
    Database db(path, SQLITE_OPEN_READONLY);
    if (schemaVersion(db) != kBatchSchemaVersion) return std::nullopt;
    Statement st(db,
                 "SELECT max(t.peak_rss_mb) FROM tasks t JOIN runs r USING (task_id) WHERE "
                 "r.status = 'ok'");
    return st.step() ? st.optReal(0) : std::nullopt;
  } catch (const std::runtime_error&) {
    return std::nullopt;
  }
}

int databaseSchemaVersion(const std::string& db_path) {
  Database db(db_path, SQLITE_OPEN_READONLY);
  return schemaVersion(db);
}

CollectCounts collectTaskDatabases(const std::string& out_db_path,
                                   const std::vector<BatchTask>& tasks) {
  CollectCounts n;
  AtomicDatabase out(out_db_path);
  Database& db = out.db();
  createSchema(db);
  db.exec("BEGIN");
  for (const auto& t : tasks) insertTask(db, t, nullptr);
  db.exec("COMMIT");
  for (const auto& t : tasks) {
    const std::string file = (fs::path(t.out_dir) / "task.sqlite").string();
    if (fs::is_regular_file(file)) {
      const int version = databaseSchemaVersion(file);
      if (version != kBatchSchemaVersion) throw std::runtime_error(versionError(file, version));
    }
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
    Statement usage(db,
                    "UPDATE main.tasks SET (peak_rss_mb, seconds) = (SELECT peak_rss_mb, seconds "
                    "FROM task.tasks WHERE task_id = ?1) WHERE task_id = ?1");
    usage.bind(1, t.id).run();
    db.exec("COMMIT");
    db.exec("DETACH DATABASE task");
  }
  out.commit();
  return n;
}

namespace {

std::vector<BatchTaskResult> readTaskRows(Database& db, std::map<std::string, std::size_t>* by_id) {
  std::vector<BatchTaskResult> rows;
  Statement st(db,
               "SELECT t.task_index, t.task_id, t.name, t.grp, t.command, t.case_name, "
               "t.estimator, t.schedule, t.options_json, t.seed, coalesce(r.status, 'missing'), "
               "coalesce(r.error, ''), r.outage_count FROM tasks t LEFT JOIN runs r "
               "ON r.task_id = t.task_id ORDER BY t.task_index");
  while (st.step()) {
    BatchTaskResult r;
    r.task_index = static_cast<int>(st.integer(0));
    r.task_id = st.text(1);
    r.name = st.text(2);
    r.grp = st.text(3);
    r.command = parseCommandColumn(st.text(4), db.path());
    r.case_name = st.text(5);
    r.estimator = st.text(6);
    r.schedule = st.text(7);
    r.options_json = st.text(8);
    if (auto s = st.optInteger(9)) r.seed = static_cast<unsigned long long>(*s);
    r.status = parseStatus(st.text(10), db.path());
    r.error = st.text(11);
    if (auto c = st.optInteger(12)) r.outage_count = static_cast<int>(*c);
    (*by_id)[r.task_id] = rows.size();
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace

std::vector<BatchTaskResult> readBatchResults(const std::string& db_path) {
  if (!fs::is_regular_file(db_path))
    throw std::runtime_error("'" + db_path + "' not found: run the batch or --collect first");
  Database db(db_path, SQLITE_OPEN_READONLY);
  const int version = schemaVersion(db);
  if (version != kBatchSchemaVersion) throw std::runtime_error(versionError(db_path, version));
  std::map<std::string, std::size_t> by_id;
  std::vector<BatchTaskResult> rows = readTaskRows(db, &by_id);
  Statement stats(db,
                  "SELECT task_id, estimator, solution, scope, statistic, measure, value, unit "
                  "FROM statistics ORDER BY task_id, estimator, solution, scope, statistic, "
                  "measure");
  while (stats.step()) {
    BatchStatisticRow s{stats.text(1), stats.text(2), stats.text(3), stats.text(4),
                        stats.text(5), stats.real(6), stats.text(7)};
    rows.at(by_id.at(stats.text(0))).statistics.push_back(std::move(s));
  }
  Statement cc(db,
               "SELECT task_id, a, b, sigma_form, statistic, rms_difference, rms_sigma, "
               "rms_normalized, max_normalized, epochs FROM cross_checks ORDER BY task_id, a, b, "
               "statistic");
  while (cc.step()) {
    BatchCrossCheckRow c{cc.text(1),    cc.text(2),    cc.text(3),
                         cc.text(4),    cc.optReal(5), cc.optReal(6),
                         cc.optReal(7), cc.optReal(8), static_cast<int>(cc.integer(9))};
    rows.at(by_id.at(cc.text(0))).cross_checks.push_back(std::move(c));
  }
  Statement ef(db, "SELECT task_id, count(*) FROM effects GROUP BY task_id");
  while (ef.step()) rows.at(by_id.at(ef.text(0))).effects = static_cast<int>(ef.integer(1));
  return rows;
}

}  // namespace graftnav
