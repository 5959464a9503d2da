#include "navigate.h"

#include <fmt/format.h>

#include <optional>
#include <stdexcept>

#include "graftnav/case/input_checks.h"
#include "graftnav/case/problem.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/eval/evaluation_files.h"
#include "graftnav/io/odometer_io.h"

namespace graftnav::python {
namespace {

constexpr const char* kFreeInertial = "free-inertial";

// The case and IMU restricted to the run config's time range; the case's own when none.
struct RunInputs {
  const CaseInputs* c = nullptr;
  const ImuSelection* imu = nullptr;
  CaseInputs c_restricted;
  ImuSelection imu_restricted;
};

void restrictInputs(const PyCase& pc, const NavigateRequest& r, RunInputs* in,
                    std::vector<std::string>* notes) {
  in->c = &pc.inputs();
  in->imu = &pc.imu(r.imu);
  if (r.rc.time_range.empty()) return;
  in->c_restricted = pc.inputs();
  in->imu_restricted = *in->imu;
  restrictToTimeRange(r.rc.time_range, &in->c_restricted, &in->imu_restricted, notes);
  in->c = &in->c_restricted;
  in->imu = &in->imu_restricted;
}

// makeProblem; a case from arrays hands its odometer array to the estimator (makeProblem reads
// a folder's field/odometer.txt).
EstimationProblem problemOf(const PyCase& pc, const CaseInputs& c, const ImuSelection& imu,
                            const RunConfig& rc, const std::optional<OutageScheduleConfig>& outages,
                            std::vector<std::string>* notes) {
  if (pc.hasFolder() || !rc.aiding.options.odometer.enabled)
    return makeProblem(c, imu, rc, outages, notes);
  if (pc.odometer().empty())
    throw std::invalid_argument(
        "odometer.enabled is true but the case built from arrays has no odometer array");
  const OdometerSeries& samples = pc.odometer();
  for (std::size_t k = 0; k < samples.size(); ++k) {  // the file reader's speed rule, per row
    const std::string problem = odometerSpeedProblem(
        samples[k].speed_m_s, fmt::format("{:g}", samples[k].speed_m_s), rc.aiding.odometer_read);
    if (!problem.empty())
      throw std::invalid_argument("odometer row " + std::to_string(k) + ": " + problem);
  }
  RunConfig without = rc;
  without.aiding.options.odometer.enabled = false;
  EstimationProblem pr = makeProblem(c, imu, without, outages, notes);
  pr.aiding = rc.aiding.options;
  const OdometerSeries* odometer = &pc.odometer();  // the case outlives the run
  pr.odometer_stream = [odometer] { return seriesOdometerSource(*odometer); };
  notes->push_back("vehicle aiding: odometer from the array (" + std::to_string(odometer->size()) +
                   " samples)");
  return pr;
}

}  // namespace

NavigateOutcome navigateCase(const PyCase& pc, const NavigateRequest& r) {
  const bool free_inertial = r.estimator == kFreeInertial;
  estimatorTable().find(r.estimator);  // std::invalid_argument naming the known ones
  NavigateOutcome out;
  RunConfig rc = r.rc;
  if (free_inertial) rc.alignment.mode = AlignmentMode::kGiven;
  RunInputs in;
  restrictInputs(pc, r, &in, &out.notes);
  const CaseInputs& c = *in.c;
  const ImuSelection& imu = *in.imu;
  if (!free_inertial && !imu.profile_given)
    throw std::runtime_error("no noise parameters for IMU '" + r.imu +
                             "' in case.yaml: give the case an IMU profile");
  auto warn = [&out](const std::vector<std::string>& w) {
    out.warnings.insert(out.warnings.end(), w.begin(), w.end());
  };
  if (!imu.read_summary.empty()) warn({imu.read_summary});
  if (!free_inertial) warn(checkGnssCoverage(c.gnss, c.paths().gnssPos(), imu.imu, false));

  std::optional<OutageScheduleConfig> outages;
  if (rc.outages_given && !free_inertial) outages = rc.outages;
  const EstimationProblem pr = problemOf(pc, c, imu, rc, outages, &out.notes);
  if (outages) {
    const double t0 = pr.imu.front().t_s - pr.imu.front().dt_s;
    requireOutagesInsideData(*outages, pr.outages, t0, pr.imu.back().t_s);
  }
  warn(checkReferenceCoverage(c.reference, c.reference_name, pr.imu, pr.outages));

  out.solution = estimatorTable().run(r.estimator, pr, rc);
  warn(checkGnssUsed(out.solution.gnss_used, free_inertial));
  out.outages = pr.outages;
  if (c.reference.empty()) return out;

  const Evaluation ev =
      evaluateSolution(out.solution, c.reference, pr.outages, rc.evaluation.options);
  ReportMeta meta;
  meta.estimator = r.estimator;
  meta.imu = imu.label;
  meta.outage_count = static_cast<int>(pr.outages.size());
  meta.outage_length_s = pr.outages.empty()                    ? 0.0
                         : rc.outages.explicit_windows.empty() ? rc.outages.length_s
                                                               : pr.outages.front().length_s();
  out.evaluated = true;
  out.statistics_json = errorsJson(meta, ev).dump();
  out.reference = c.reference_name;
  const std::string why = missingStatisticsReason(ev);
  if (!why.empty()) warn({"statistics absent (None): " + why});
  return out;
}

}  // namespace graftnav::python
