#include "graftnav/eval/real_report.h"

#include <fmt/core.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "graftnav/io/atomic_file.h"
#include "graftnav/io/provenance.h"

namespace graftnav {
namespace {

constexpr double kR2D = 57.29577951308232;

nlohmann::json numOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace

std::string formatOrDash(double v, const char* f) {
  return std::isfinite(v) ? fmt::format(fmt::runtime(f), v) : std::string("-");
}

void writeCheckpointCsv(const std::string& path, const CheckpointEvaluation& cp) {
  std::string o = "start_s,end_s,n,rms_h_m,max_h_m,rms_v_m,max_v_m,last_h_m\n";
  for (const auto& w : cp.windows) {
    o += fmt::format("{:.3f},{:.3f},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}\n", w.window.start_s,
                     w.window.end_s, w.n, w.rms_h_m, w.max_h_m, w.rms_v_m, w.max_v_m, w.last_h_m);
  }
  writeFileAtomically(path, o);
}

void writeRealSummaryJson(const std::string& path, const std::vector<EstimatorRun>& rows,
                          const std::vector<TimeWindow>& outages, int checkpoints_in_outages,
                          const std::vector<std::string>& failed) {
  nlohmann::json est = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json e = {
        {"estimator", r.label},
        {"gnss",
         {{"used", r.sol.gnss_used},
          {"rejected", r.sol.gnss_rejected},
          {"withheld", r.sol.gnss_withheld}}},
        {"checkpoints",
         {{"n", r.cp.n},
          {"rms_h_m", numOrNull(r.cp.n ? r.cp.rms_h_m : std::nan(""))},
          {"rms_of_max_h_m", numOrNull(r.cp.n ? r.cp.rms_of_max_h_m : std::nan(""))},
          {"rms_v_m", numOrNull(r.cp.n ? r.cp.rms_v_m : std::nan(""))}}},
        {"run_time_s", r.seconds}};
    if (r.ref) {
      e["reference"] = {{"outage_rms_h_m", numOrNull(r.ref->outage_rms.horizontal_m)},
                        {"outage_max_rms_h_m", numOrNull(r.ref->outage_max_rms.horizontal_m)},
                        {"heading_rms_deg", numOrNull(r.ref->overall_rms.heading_rad * kR2D)}};
    }
    est.push_back(e);
  }
  nlohmann::json w = nlohmann::json::array();
  for (const auto& t : outages) w.push_back({t.start_s, t.end_s});
  const nlohmann::json j = {{"outage_windows_s", w},
                            {"checkpoints_in_outages", checkpoints_in_outages},
                            {"estimators", est},
                            {"failed", failed},
                            {"provenance", provenanceJson()}};
  writeFileAtomically(path, j.dump(2) + "\n");
}

std::string realOutageTablesMd(const std::vector<EstimatorRun>& rows,
                               const std::vector<std::string>& failed,
                               const std::vector<TimeWindow>& outages,
                               const std::vector<int>& checkpoint_fix_types, double t_first_s) {
  std::string md;
  md += fmt::format(
      "Outage errors, {} outages of {:.1f} s; check points = withheld GNSS epochs of fix types",
      outages.size(), outages.empty() ? 0.0 : outages.front().length_s());
  for (int t : checkpoint_fix_types) md += fmt::format(" {}", t);
  md += " inside the outages.\n\n";
  md +=
      "| estimator | GNSS used / gated / withheld | check points | RMS h (m) | RMS of per-outage max h (m) | RMS v (m) | vs reference.nav: outage RMS h (m) | RMS of max h (m) | heading RMS (deg) | run (s) |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    const double nan = std::nan("");
    md += fmt::format("| {} | {} / {} / {} | {} | {} | {} | {} | {} | {} | {} | {:.1f} |\n",
                      r.label, r.sol.gnss_used, r.sol.gnss_rejected, r.sol.gnss_withheld, r.cp.n,
                      formatOrDash(r.cp.n ? r.cp.rms_h_m : nan),
                      formatOrDash(r.cp.n ? r.cp.rms_of_max_h_m : nan),
                      formatOrDash(r.cp.n ? r.cp.rms_v_m : nan),
                      formatOrDash(r.ref ? r.ref->outage_rms.horizontal_m : nan),
                      formatOrDash(r.ref ? r.ref->outage_max_rms.horizontal_m : nan),
                      formatOrDash(r.ref ? r.ref->overall_rms.heading_rad * kR2D : nan), r.seconds);
  }
  for (const auto& f : failed) md += "\nFAILED " + f + "\n";
  // Per outage, per estimator: max horizontal error at the check points.
  if (!rows.empty() && !rows.front().cp.windows.empty()) {
    md +=
        "\nPer outage: maximum horizontal error at the check points (m), number of check points\n\n| outage (s after start) | n |";
    for (const auto& r : rows) md += " " + r.label + " |";
    md += "\n|---|---|";
    for (std::size_t i = 0; i < rows.size(); ++i) md += "---|";
    md += "\n";
    const double t_first = t_first_s;
    for (std::size_t w = 0; w < rows.front().cp.windows.size(); ++w) {
      const auto& win = rows.front().cp.windows[w];
      md += fmt::format("| {:.0f}-{:.0f} | {} |", win.window.start_s - t_first,
                        win.window.end_s - t_first, win.n);
      for (const auto& r : rows)
        md += w < r.cp.windows.size() ? fmt::format(" {:.2f} |", r.cp.windows[w].max_h_m) : " - |";
      md += "\n";
    }
  }
  return md;
}

}  // namespace graftnav
