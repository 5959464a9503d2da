#include "graftnav/eval/gnss_selection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

namespace graftnav {

namespace {

double latencyOf(const GnssSelectionOptions& o, int fix_type) {
  const auto it = o.latency_s_by_fix_type.find(fix_type);
  return it != o.latency_s_by_fix_type.end() ? it->second : o.latency_s;
}

bool finiteFix(const GnssFix& f) {
  return std::isfinite(f.t_s) && std::isfinite(f.pos.lat_rad) && std::isfinite(f.pos.lon_rad) &&
         std::isfinite(f.pos.h_m) && f.std_ned_m.allFinite();
}

std::string countsByType(const std::map<int, int>& m) {
  std::string s;
  for (const auto& [k, v] : m) s += fmt::format("{}fix {}: {}", s.empty() ? "" : ", ", k, v);
  return s;
}

}  // namespace

void GnssSelectionOptions::validate() const {
  if (!(max_horizontal_std_m > 0.0)) {
    throw std::invalid_argument("GnssSelectionOptions.max_horizontal_std_m must be > 0");
  }
  if (!(max_vertical_std_m > 0.0)) {
    throw std::invalid_argument("GnssSelectionOptions.max_vertical_std_m must be > 0");
  }
  auto check_latency = [](double l, const std::string& what) {
    if (!std::isfinite(l) || std::abs(l) > 10.0) {
      throw std::invalid_argument("GnssSelectionOptions." + what + " = " + std::to_string(l) +
                                  " s: must be finite and within +-10 s");
    }
  };
  check_latency(latency_s, "latency_s");
  if (!(min_spacing_s >= 0.0) || min_spacing_s > 10.0) {
    throw std::invalid_argument("GnssSelectionOptions.min_spacing_s must be in [0, 10] s");
  }
  for (const auto& [k, v] : latency_s_by_fix_type) {
    check_latency(v, "latency_s_by_fix_type[" + std::to_string(k) + "]");
  }
}

bool GnssSelectionOptions::isIdentity() const {
  if (!accepted_fix_types.empty() || max_horizontal_std_m < 1e9 || max_vertical_std_m < 1e9)
    return false;
  if (latency_s != 0.0 || min_spacing_s > 0.0) return false;
  for (const auto& kv : latency_s_by_fix_type)
    if (kv.second != 0.0) return false;
  return true;
}

std::string GnssSelectionCounts::summary() const {
  return fmt::format(
      "GNSS selection: {} epochs in ({}), used {} ({}), rejected {} (fix type {}, std {}, "
      "non-finite {}, duplicate time {}, spacing {}), reordered by the time-tag correction {}",
      input, countsByType(input_by_fix_type), used, countsByType(used_by_fix_type), rejected(),
      rejected_fix_type, rejected_std, rejected_non_finite, rejected_duplicate_time,
      rejected_spacing, reordered);
}

GnssSelection selectGnss(const GnssSeries& gnss, const GnssSelectionOptions& o) {
  o.validate();
  GnssSelection out;
  GnssSelectionCounts& c = out.counts;
  c.input = static_cast<int>(gnss.size());
  out.kept.reserve(gnss.size());
  for (const GnssFix& f : gnss) {
    ++c.input_by_fix_type[f.fix_type];
    if (!finiteFix(f)) {
      ++c.rejected_non_finite;
      continue;
    }
    if (!o.accepted_fix_types.empty() &&
        std::find(o.accepted_fix_types.begin(), o.accepted_fix_types.end(), f.fix_type) ==
            o.accepted_fix_types.end()) {
      ++c.rejected_fix_type;
      continue;
    }
    if (std::max(f.std_ned_m.x(), f.std_ned_m.y()) > o.max_horizontal_std_m ||
        f.std_ned_m.z() > o.max_vertical_std_m) {
      ++c.rejected_std;
      continue;
    }
    GnssFix g = f;
    g.t_s -= latencyOf(o, f.fix_type);
    out.kept.push_back(g);
  }
  // Re-sort after the per-type correction; count the epochs that moved.
  std::vector<std::size_t> order(out.kept.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return out.kept[a].t_s < out.kept[b].t_s; });
  GnssSeries sorted;
  sorted.reserve(out.kept.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (order[i] != i) ++c.reordered;
    const GnssFix& g = out.kept[order[i]];
    if (!sorted.empty() && g.t_s <= sorted.back().t_s) {
      ++c.rejected_duplicate_time;
      continue;
    }
    if (o.min_spacing_s > 0.0 && !sorted.empty() && g.t_s - sorted.back().t_s < o.min_spacing_s) {
      ++c.rejected_spacing;
      const auto h = [](const GnssFix& f) { return std::max(f.std_ned_m.x(), f.std_ned_m.y()); };
      if (h(g) < h(sorted.back())) sorted.back() = g;
      continue;
    }
    sorted.push_back(g);
  }
  out.kept = std::move(sorted);
  for (const GnssFix& g : out.kept) ++c.used_by_fix_type[g.fix_type];
  c.used = static_cast<int>(out.kept.size());
  return out;
}

GnssSeries gnssOfFixTypes(const GnssSeries& gnss, const std::vector<int>& fix_types,
                          const GnssSelectionOptions& latency_rule) {
  GnssSelectionOptions o;
  o.accepted_fix_types = fix_types;
  o.latency_s = latency_rule.latency_s;
  o.latency_s_by_fix_type = latency_rule.latency_s_by_fix_type;
  return selectGnss(gnss, o).kept;
}

}  // namespace graftnav
