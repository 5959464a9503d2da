// graftnav batch MANIFEST.yaml: cases x estimators x outage schedules, in parallel, one summary.
#include <fmt/core.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <cctype>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "batch_manifest.h"
#include "commands.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"
#include "sg_evaluate.h"

namespace graftnav::app {
namespace {
namespace fs = std::filesystem;

struct BatchRun {
  std::string case_dir, estimator, schedule_label, out_dir;
  std::optional<OutageScheduleSpec> schedule;
  bool ok = false;
  std::string error;
  double seconds = 0.0;
  SgEvaluationReport report;
};

std::string cell(double v, int digits) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : ""; }

// ERR or DIFF row values in report units (m, deg, fraction) for one run and label.
std::array<double, 5> values(const BatchRun& r, const std::string& label, bool diff) {
  std::array<double, 5> nan;
  nan.fill(std::numeric_limits<double>::quiet_NaN());
  if (!r.ok) return nan;
  if (diff) {
    const auto d = r.report.diff(label);
    return d ? asArray(*d) : nan;
  }
  const auto* s = r.report.find(label);
  if (!s) return nan;
  auto a = asArray(s->err_rms);
  for (int i = 2; i < 5; ++i) a[i] *= units::kRadToDeg;
  return a;
}

void writeSummaries(const std::string& out_dir, const std::vector<BatchRun>& runs) {
  const std::vector<std::pair<std::string, bool>> cols{
      {"SG1", false}, {"SG2", false}, {"REAL", false}, {"SG1", true}, {"SG2", true}};
  std::string csv = "case,estimator,outages,outage_count,status,seconds";
  for (const auto& [l, d] : cols)
    for (const auto& n : driftStatNames()) csv += fmt::format(",{}_{}_{}", d ? "DIFF" : "ERR", l, d ? n.substr(0, n.rfind('_')) + "_frac" : n);
  csv += ",error\n";
  std::string md = "# graftnav batch summary\n\nERR: RMS over outage epochs (m, deg); DIFF: |ERR_x - ERR_REAL| / ERR_REAL.\n\n";
  md += "| case | estimator | outages | n | ERR_SG1 h/v/hdg | ERR_SG2 h/v/hdg | ERR_REAL h/v/hdg | DIFF_1 h/v/hdg | DIFF_2 h/v/hdg | status |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : runs) {
    const std::string name = fs::path(r.case_dir).filename().string();
    csv += fmt::format("{},{},{},{},{},{:.2f}", name, r.estimator, r.schedule_label,
                       r.ok ? std::to_string(r.report.outages.size()) : "", r.ok ? "ok" : "failed", r.seconds);
    for (const auto& [l, d] : cols)
      for (double v : values(r, l, d)) csv += "," + cell(v, 6);
    std::string err = r.error;
    for (char& ch : err)
      if (ch == ',' || ch == '\n') ch = ';';
    csv += "," + err + "\n";
    md += fmt::format("| {} | {} | {} | {} |", name, r.estimator, r.schedule_label,
                      r.ok ? std::to_string(r.report.outages.size()) : "-");
    for (const auto& [l, d] : cols) {
      const auto v = values(r, l, d);
      if (!std::isfinite(v[0])) {
        md += " - |";
      } else if (d) {
        md += fmt::format(" {:.1f}% / {:.1f}% / {:.1f}% |", 100 * v[0], 100 * v[1], 100 * v[4]);
      } else {
        md += fmt::format(" {:.3f} / {:.3f} / {:.4f} |", v[0], v[1], v[4]);
      }
    }
    md += r.ok ? " ok |\n" : " failed: " + r.error + " |\n";
  }
  writeFileAtomically((fs::path(out_dir) / "summary.csv").string(), csv);
  writeFileAtomically((fs::path(out_dir) / "summary.md").string(), md);
}

// Monte-Carlo groups: runs whose case names differ only by a trailing "_seed<N>" (same
// estimator and schedule) are realizations of one experiment. For each group: the mean of each
// ERR statistic over the seeds, its standard deviation, and DIFF computed on the means, which
// separates what grafting gets wrong from the spread of single realizations.
std::string groupName(const std::string& case_name) {
  const auto pos = case_name.rfind("_seed");
  if (pos == std::string::npos || pos + 5 >= case_name.size()) return case_name;
  for (std::size_t i = pos + 5; i < case_name.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(case_name[i]))) return case_name;
  return case_name.substr(0, pos);
}

void writeMonteCarloSummary(const std::string& out_dir, const std::vector<BatchRun>& runs) {
  std::map<std::string, std::vector<const BatchRun*>> groups;
  std::vector<std::string> order;
  for (const auto& r : runs) {
    if (!r.ok) continue;
    const std::string key = groupName(fs::path(r.case_dir).filename().string()) + "|" + r.estimator + "|" +
                            r.schedule_label;
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&r);
  }
  bool any = false;
  for (const auto& k : order) any = any || groups[k].size() > 1;
  if (!any) return;
  std::string md = "# graftnav batch: Monte-Carlo summary over seeds\n\n"
                   "Mean (and standard deviation over seeds) of the seed's outage statistic; DIFF on the means.\n\n"
                   "| experiment | estimator | outages | seeds | row | horizontal_m | vertical_m | roll_deg | pitch_deg | heading_deg |\n"
                   "|---|---|---|---|---|---|---|---|---|---|\n";
  std::string csv = "experiment,estimator,outages,seeds,row,horizontal_m,vertical_m,roll_deg,pitch_deg,heading_deg\n";
  for (const auto& k : order) {
    const auto& g = groups[k];
    if (g.size() < 2) continue;
    const std::string exp = k.substr(0, k.find('|'));
    std::map<std::string, std::array<double, 5>> mean;
    for (const std::string label : {"SG1", "SG2", "REAL"}) {
      std::array<double, 5> m{}, sq{};
      int n = 0;
      for (const BatchRun* r : g) {
        const auto v = values(*r, label, false);
        if (!std::isfinite(v[0])) continue;
        ++n;
        for (int i = 0; i < 5; ++i) {
          m[i] += v[i];
          sq[i] += v[i] * v[i];
        }
      }
      if (n == 0) continue;
      std::array<double, 5> sd{};
      for (int i = 0; i < 5; ++i) {
        m[i] /= n;
        sd[i] = n > 1 ? std::sqrt(std::max(0.0, (sq[i] - n * m[i] * m[i]) / (n - 1))) : 0.0;
      }
      mean[label] = m;
      md += fmt::format("| {} | {} | {} | {} | ERR_{} |", exp, g.front()->estimator, g.front()->schedule_label, n, label);
      csv += fmt::format("{},{},{},{},ERR_{}_mean", exp, g.front()->estimator, g.front()->schedule_label, n, label);
      for (int i = 0; i < 5; ++i) {
        md += fmt::format(" {:.4f} ({:.4f}) |", m[i], sd[i]);
        csv += fmt::format(",{:.6f}", m[i]);
      }
      md += "\n";
      csv += "\n";
    }
    if (!mean.count("REAL")) continue;
    for (const std::string label : {"SG1", "SG2"}) {
      if (!mean.count(label)) continue;
      md += fmt::format("| {} | {} | {} | {} | DIFF_{} (of means) |", exp, g.front()->estimator, g.front()->schedule_label,
                        g.size(), label.substr(2));
      csv += fmt::format("{},{},{},{},DIFF_{}_of_means", exp, g.front()->estimator, g.front()->schedule_label, g.size(),
                         label.substr(2));
      for (int i = 0; i < 5; ++i) {
        const double d = std::abs(mean[label][i] - mean["REAL"][i]) / mean["REAL"][i];
        md += fmt::format(" {:.1f}% |", 100.0 * d);
        csv += fmt::format(",{:.6f}", d);
      }
      md += "\n";
      csv += "\n";
    }
  }
  writeFileAtomically((fs::path(out_dir) / "summary_monte_carlo.md").string(), md);
  writeFileAtomically((fs::path(out_dir) / "summary_monte_carlo.csv").string(), csv);
}

}  // namespace

void registerBatch(CLI::App& app) {
  auto manifest = std::make_shared<std::string>();
  auto jobs_cli = std::make_shared<int>(-1);
  CLI::App* cmd = app.add_subcommand(
      "batch", "Run evaluate over cases x estimators x outage schedules in parallel, one summary table");
  cmd->add_option("manifest", *manifest, "batch manifest YAML")->required()->check(CLI::ExistingFile);
  cmd->add_option("--jobs", *jobs_cli, "runs in parallel (overrides the manifest; 0 = all cores)");
  cmd->callback([manifest, jobs_cli]() {
    const BatchManifest m = loadBatchManifest(*manifest);
    std::vector<BatchRun> runs;
    for (const auto& c : m.cases) {
      for (const auto& e : m.estimators) {
        std::vector<std::optional<OutageScheduleSpec>> sch(m.schedules.begin(), m.schedules.end());
        if (sch.empty()) sch.push_back(std::nullopt);
        for (const auto& s : sch) {
          BatchRun r;
          r.case_dir = c;
          r.estimator = e;
          r.schedule = s;
          r.schedule_label = s ? s->label() : "config";
          r.out_dir = (fs::path(m.out_dir) / fmt::format("{}__{}__{}", fs::path(c).filename().string(), e,
                                                         r.schedule_label))
                          .string();
          runs.push_back(std::move(r));
        }
      }
    }
    fs::create_directories(m.out_dir);
    const int jobs = *jobs_cli >= 0 ? *jobs_cli : m.jobs;
    const int n_threads = std::max(1, std::min<int>(static_cast<int>(runs.size()),
                                                    jobs > 0 ? jobs : static_cast<int>(std::thread::hardware_concurrency())));
    fmt::print(stderr, "batch: {} runs ({} cases x {} estimators x {} schedules) on {} threads -> {}\n",
               runs.size(), m.cases.size(), m.estimators.size(), std::max<size_t>(1, m.schedules.size()),
               n_threads, m.out_dir);
    std::atomic<size_t> next{0};
    std::atomic<int> done{0}, failed{0};
    std::mutex print_mutex;
    const auto t0 = std::chrono::steady_clock::now();
    auto progress = [&](const BatchRun& r) {
      std::lock_guard<std::mutex> lock(print_mutex);
      const int d = done.load();
      const int width = 30;
      const int fill = static_cast<int>(width * d / static_cast<double>(runs.size()));
      const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      fmt::print(stderr, "[{}{}] {}/{} done, {} failed, {:.0f} s  {} {} {}: {}\n", std::string(fill, '#'),
                 std::string(width - fill, '.'), d, runs.size(), failed.load(), el,
                 fs::path(r.case_dir).filename().string(), r.estimator, r.schedule_label,
                 r.ok ? "ok" : "FAILED (" + r.error + ")");
    };
    auto worker = [&]() {
      for (size_t i = next++; i < runs.size(); i = next++) {
        BatchRun& r = runs[i];
        const auto ts = std::chrono::steady_clock::now();
        try {
          SgEvaluateOptions o;
          o.case_dir = r.case_dir;
          o.out_dir = r.out_dir;
          o.estimator = r.estimator;
          o.config_path = m.config;
          o.seed = m.seed;
          o.plots = m.plots;
          o.write_grafted_imu = false;
          o.jobs = 1;
          if (r.schedule) {
            o.outage_length_s = r.schedule->length_s;
            o.outage_period_s = r.schedule->period_s;
            o.outage_start_s = r.schedule->start_s;
          }
          fs::create_directories(r.out_dir);
          std::ofstream log((fs::path(r.out_dir) / "log.txt").string());
          r.report = runSgEvaluation(o, [&](const std::string& s) { log << s << "\n"; });
          r.ok = true;
        } catch (const std::exception& e) {
          r.error = e.what();
          ++failed;
        }
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
        ++done;
        progress(r);
      }
    };
    std::vector<std::thread> pool;
    for (int k = 0; k < n_threads; ++k) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    writeSummaries(m.out_dir, runs);
    writeMonteCarloSummary(m.out_dir, runs);
    fmt::print("batch: {} runs, {} ok, {} failed; summary: {}/summary.md and summary.csv\n", runs.size(),
               runs.size() - failed.load(), failed.load(), m.out_dir);
    if (failed.load() > 0) throw std::runtime_error(fmt::format("{} of {} batch runs failed (see the summary)",
                                                                failed.load(), runs.size()));
  });
}

}  // namespace graftnav::app
