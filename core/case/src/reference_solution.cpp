#include "graftnav/case/reference_solution.h"

#include <stdexcept>

#include "graftnav/case/problem.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/io/nav_spool.h"

namespace graftnav {

namespace {

const char* kSmoothedDescription = "RTS-smoothed reference IMU with all GNSS (SOL_REF of the seed)";

std::string caseReferenceDescription(bool is_truth, const std::string& path) {
  return is_truth ? "truth (" + path + ")" : "external reference solution (" + path + ")";
}

void requireNoiseToSmooth(const CaseInputs& c, const ImuSelection& ref, bool has_reference) {
  if (!ref.profile_given)
    throw std::runtime_error(
        c.paths().caseYaml() + ": reference_imu needs noise parameters to smooth SOL_REF" +
        (has_reference ? "" : " (the case has no truth or reference solution)"));
}

// Appends the smoother's epochs to a spool.
class NavSpoolSink final : public SolutionSink {
 public:
  explicit NavSpoolSink(NavSpool* spool) : spool_(spool) {}
  void add(const NavState& state, const PvaSigma*, const ImuErrorEstimate&) override {
    spool_->add(state);
  }

 private:
  NavSpool* spool_;
};

}  // namespace

ReferenceSolution resolveReferenceSolution(const CaseInputs& c, const ReferenceImuFn& reference_imu,
                                           const RunConfig& rc, const EstimatorRegistry& estimators,
                                           const ReferenceSolutionOptions& o) {
  ReferenceSolution r;
  if (o.use_case_reference && !c.reference.empty()) {
    r.states = c.reference;
    r.description = caseReferenceDescription(c.reference_is_truth, c.reference_name);
    return r;
  }
  const ImuSelection ref = reference_imu();
  requireNoiseToSmooth(c, ref, !c.reference.empty());
  EstimationProblem pr = makeProblem(c, ref, rc, std::nullopt, &r.notes);
  if (o.start_at_initial_state) startAtInitialState(&pr, &r.notes);
  r.states = estimators.run(o.smoother, pr, rc).states;
  r.description = kSmoothedDescription;
  r.smoothed = true;
  return r;
}

StreamedReferenceSolution streamReferenceSolution(
    const CaseInputs& c, const CaseReferenceFile& file, const ImuSelection& ref,
    const ImuPassFn& reference_pass, const RunConfig& rc, const EstimatorRegistry& estimators,
    const ReferenceSolutionOptions& o) {
  StreamedReferenceSolution r;
  if (o.use_case_reference && !file.path.empty()) {
    NavStreamReader reader(file.path, file.policy);
    const NavSpool spool = spoolNav(reader);
    r.open = spool.opener();
    r.rate_hz = spool.rateHz();
    r.description = caseReferenceDescription(file.is_truth, file.path);
    return r;
  }
  requireNoiseToSmooth(c, ref, !file.path.empty());
  if (!estimators.canStream(o.smoother) || rc.alignment.mode != AlignmentMode::kGiven ||
      o.start_at_initial_state)
    throw std::invalid_argument("streamReferenceSolution: '" + o.smoother +
                                "' cannot smooth the reference IMU as a stream with this run "
                                "config (an alignment from the data, or a start at the initial "
                                "state, needs the samples)");
  EstimationProblem pr = makeProblem(c, ref, rc, std::nullopt, &r.notes);
  pr.imu = {};
  NavSpool spool;
  NavSpoolSink sink(&spool);
  estimators.runStreaming(o.smoother, pr, reference_pass, rc, sink);
  spool.finish();
  r.open = spool.opener();
  r.rate_hz = spool.rateHz();
  r.description = kSmoothedDescription;
  r.smoothed = true;
  return r;
}

}  // namespace graftnav
