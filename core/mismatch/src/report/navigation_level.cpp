#include "graftnav/mismatch/navigation_level.h"

#include <fmt/core.h>

#include <array>
#include <cmath>

#include "graftnav/case/problem.h"
#include "graftnav/case/reference_solution.h"
#include "graftnav/io/atomic_file.h"
#include "graftnav/sg/sg_statistics.h"

namespace graftnav {

NavigationComparison compareNavigation(const CaseInputs& c, const ImuSelection& tested,
                                       const std::string& estimator, const RunConfig& rc,
                                       const OutageOverrides& outages, const ImuSeries& sg2,
                                       const ImuSeries& sg3, const EstimatorRegistry& estimators,
                                       std::vector<std::string>* notes) {
  if (c.gnss.empty()) throw std::runtime_error(c.paths().gnssPos() + " not found or empty");
  const OutageScheduleConfig oc = outages.appliedTo(rc.outages);
  const NavSeries sol_ref = resolveReferenceSolution(
                                c, [&c] { return selectImu(c, "ref", "", true); }, rc, estimators)
                                .states;
  if (c.reference.empty()) notes->push_back("SOL_REF: RTS-smoothed reference IMU with all GNSS");
  if (!tested.profile_given)
    notes->push_back(
        "tested_imu has no noise parameters in case.yaml: the estimator's defaults are used");
  NavigationComparison nav;
  nav.estimator = estimator;
  std::array<Evaluation, 3> ev;
  const std::array<const ImuSeries*, 3> series = {&sg2, &sg3, &tested.imu};
  for (int k = 0; k < 3; ++k) {
    ImuSelection s = tested;
    s.imu = *series[k];
    std::vector<std::string> n;
    const EstimationProblem p = makeProblem(c, s, rc, oc, &n);
    const NavSolution sol = estimators.run(estimator, p, rc);
    ev[k] = evaluateSolution(sol, sol_ref, p.outages, rc.evaluation.options);
    if (k == 2) {
      nav.outage_count = static_cast<int>(p.outages.size());
      nav.outage_length_s = p.outages.empty() ? 0.0 : p.outages.front().length_s();
      for (const auto& m : n) notes->push_back(m);
    }
  }
  nav.err_sg2 = ev[0].outage_rms;
  nav.err_sg3 = ev[1].outage_rms;
  nav.err_real = ev[2].outage_rms;
  nav.diff_before = relativeDifference(nav.err_sg2, nav.err_real);
  nav.diff_after = relativeDifference(nav.err_sg3, nav.err_real);
  // Which outages carry |ERR_SG2 - ERR_REAL| (per-outage maximum horizontal drift).
  double total = 0.0;
  for (std::size_t i = 0; i < ev[2].outages.size(); ++i) {
    NavigationComparison::OutageShare o;
    o.window = ev[2].outages[i].window;
    o.real_horizontal_m = ev[2].outages[i].max.horizontal_m;
    for (const auto& od : ev[0].outages)
      if (std::abs(od.window.start_s - o.window.start_s) < 1e-6)
        o.sg2_horizontal_m = od.max.horizontal_m;
    for (const auto& od : ev[1].outages)
      if (std::abs(od.window.start_s - o.window.start_s) < 1e-6)
        o.sg3_horizontal_m = od.max.horizontal_m;
    o.share = std::abs(o.sg2_horizontal_m - o.real_horizontal_m);
    total += o.share;
    nav.outages.push_back(o);
  }
  for (auto& o : nav.outages) o.share = total > 0.0 ? o.share / total : 0.0;
  return nav;
}

void writeNavigationOutagesCsv(const std::string& out, const NavigationComparison& nav) {
  std::string csv = "t_start,t_end,sg2_horizontal_m,sg3_horizontal_m,real_horizontal_m,share\n";
  for (const auto& o : nav.outages)
    csv +=
        fmt::format("{:.3f},{:.3f},{:.4f},{:.4f},{:.4f},{:.4f}\n", o.window.start_s, o.window.end_s,
                    o.sg2_horizontal_m, o.sg3_horizontal_m, o.real_horizontal_m, o.share);
  writeFileAtomically(out + "/outages.csv", csv);
}

}  // namespace graftnav
