#include "graftnav/navigate/real_run.h"

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>

#include "graftnav/case/file_streams.h"
#include "graftnav/case/latency_study.h"
#include "graftnav/eval/gnss_latency.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/navigate/streamed_checkpoints.h"
#include "graftnav/navigate/streamed_imu_file.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

void requireFinite(const NavState& st) {
  if (!st.v_n.allFinite() || !std::isfinite(st.pos.lat_rad))
    throw std::runtime_error("non-finite state at t=" + std::to_string(st.t_s));
}

std::string evaluationFailure(const std::exception& e) {
  return fmt::format("warning: evaluation against the reference failed: {}", e.what());
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A streamed run's epochs, as they come: checked, written to solution.nav, evaluated at the
// check points and against the reference. An evaluation that fails is set aside (its message
// kept) and the run goes on, as the evaluation of a held solution fails alone.
class RealEpochSink final : public SolutionSink {
 public:
  RealEpochSink(const std::string& nav_path, StreamedCheckpoints* checkpoints,
                StreamedEvaluation* evaluation)
      : nav_(nav_path), checkpoints_(checkpoints), evaluation_(evaluation) {}
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate&) override {
    requireFinite(state);
    nav_.add(state);
    checkpoints_->add(state);
    if (!evaluation_) return;
    try {
      evaluation_->add(state, sigma);
    } catch (const std::exception& e) {
      evaluation_failure_ = evaluationFailure(e);
      evaluation_ = nullptr;
    }
  }
  void commit() { nav_.commit(); }
  const std::string& evaluationFailureText() const { return evaluation_failure_; }

 private:
  NavWriter nav_;
  StreamedCheckpoints* checkpoints_;
  StreamedEvaluation* evaluation_;
  std::string evaluation_failure_;
};

// An IMU pass over the samples of the file the range keeps, those before `start_s` skipped (see
// RealInputs::imu_start_s).
ImuPassFn realImuPass(const RealInputs& in) {
  const ImuPassFn file = imuRangeStream(in.imu, in.time_range);
  if (!std::isfinite(in.imu_start_s)) return file;
  const double start_s = in.imu_start_s;
  return [file, start_s](const ImuBlockFn& block) {
    bool started = false;
    ImuSeries kept;
    file([&](const ImuSeries& b) {
      if (started) return block(b);
      kept.clear();
      for (const ImuSample& s : b) {
        started = started || !(s.t_s - s.dt_s < start_s);
        if (started) kept.push_back(s);
      }
      if (!kept.empty()) block(kept);
    });
  };
}

// One estimator streamed into its folder; throws when the run fails (the folder then holds no
// solution.nav).
EstimatorRun runStreamed(const RealInputs& in, const std::string& name,
                         const EstimatorRegistry& registry, const fs::path& dir,
                         const RunMessages& messages) {
  EstimatorRun r;
  r.label = name;
  StreamedCheckpoints checkpoints(in.checkpoints, in.pr.outages, in.pr.lever_arm_b_m);
  std::unique_ptr<StreamedEvaluation> evaluation;
  std::string failure;
  if (in.hasReference()) {
    try {
      evaluation = std::make_unique<StreamedEvaluation>(
          navFileSource(in.reference.path, in.reference.policy)(), in.pr.outages,
          in.rc.evaluation.options, name, in.expected_rates);
    } catch (const std::exception& e) {
      failure = evaluationFailure(e);
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  RealEpochSink sink((dir / "solution.nav").string(), &checkpoints, evaluation.get());
  r.sol = registry.runStreaming(name, in.pr, realImuPass(in), in.rc, sink);
  r.seconds = secondsSince(t0);
  sink.commit();
  r.cp = checkpoints.finish();
  writeCheckpointCsv((dir / "checkpoints.csv").string(), r.cp);
  if (!sink.evaluationFailureText().empty()) failure = sink.evaluationFailureText();
  if (evaluation && failure.empty()) {
    try {
      r.ref = evaluation->finish();
    } catch (const std::exception& e) {
      failure = evaluationFailure(e);
    }
  }
  if (!failure.empty()) messages.note(failure);
  return r;
}

// One estimator in memory: the solution held, checked, written and evaluated whole.
EstimatorRun runHeld(const RealInputs& in, const std::string& name,
                     const EstimatorRegistry& registry, const fs::path& dir,
                     const RunMessages& messages) {
  EstimatorRun r;
  r.label = name;
  const auto t0 = std::chrono::steady_clock::now();
  r.sol = registry.run(name, in.pr, in.rc);
  for (const auto& st : r.sol.states) requireFinite(st);
  r.seconds = secondsSince(t0);
  fs::create_directories(dir);
  writeNav((dir / "solution.nav").string(), r.sol.states);
  r.cp = evaluateAtCheckpoints(r.sol.states, in.checkpoints, in.pr.outages, in.pr.lever_arm_b_m);
  writeCheckpointCsv((dir / "checkpoints.csv").string(), r.cp);
  r.ref = evaluateAgainstReference(r.sol, in.c.reference, in.pr.outages, in.rc,
                                   [&](const std::string& line) { messages.note(line); });
  return r;
}

}  // namespace

std::vector<EstimatorRun> runRealEstimators(const RealInputs& in,
                                            const std::vector<std::string>& estimators,
                                            const EstimatorRegistry& registry,
                                            const std::string& out_dir, const RunMessages& messages,
                                            std::vector<std::string>* failed) {
  std::vector<EstimatorRun> rows;
  for (const auto& name : estimators) {
    const fs::path dir = fs::path(out_dir) / name;
    const bool dir_existed = fs::exists(dir);
    EstimatorRun r;
    try {
      if (in.stream) {
        fs::create_directories(dir);
        r = runStreamed(in, name, registry, dir, messages);
      } else {
        r = runHeld(in, name, registry, dir, messages);
      }
    } catch (const std::exception& e) {
      messages.note(fmt::format("  {}: FAILED: {}", name, e.what()));
      failed->push_back(name + ": " + e.what());
      std::error_code ec;
      if (!dir_existed) fs::remove(dir, ec);  // only when empty: nothing of the run is left
      continue;
    }
    messages.note(fmt::format("  {}: {:.1f} s, GNSS used {}, rejected by the gate {}, withheld {}",
                              name, r.seconds, r.sol.gnss_used, r.sol.gnss_rejected,
                              r.sol.gnss_withheld));
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace graftnav
