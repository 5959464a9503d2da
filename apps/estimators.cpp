#include "estimators.h"

#include <algorithm>
#include <stdexcept>

#include "graftnav/filters/free_inertial.h"
#include "graftnav/filters/rts_smoother.h"
#include "graftnav/graph/fgo_solver.h"

namespace graftnav::app {

namespace {
FgoEpochFn toSink(SolutionSink& sink) {
  return [&sink](const NavState& s, const PvaSigma* sigma, const Eigen::Vector3d& bg,
                 const Eigen::Vector3d& ba) {
    ImuErrorEstimate e;
    e.gyro_bias_rad_s = bg;
    e.accel_bias_m_s2 = ba;
    sink.add(s, sigma, e);
  };
}
}  // namespace

const std::vector<EstimatorEntry>& estimatorTable() {
  static const std::vector<EstimatorEntry> table = {
      {"ekf", "forward closed-loop 21-state GNSS/INS EKF",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn& f) {
         return runEkf(p, c.ekf, nullptr, f);
       },
       [](const EstimationProblem& p, const ImuStream& imu, const RunConfig& c,
          SolutionSink& sink) { return runEkfStreaming(p, c.ekf, imu.pass, sink); }},
      {"rts", "EKF + Rauch-Tung-Striebel smoother",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn& f) {
         return runRts(p, c.ekf, nullptr, nullptr, f);
       },
       [](const EstimationProblem& p, const ImuStream& imu, const RunConfig& c,
          SolutionSink& sink) { return runRtsStreaming(p, c.ekf, imu.pass, sink); }},
      {"fgo", "factor-graph batch smoother (Ceres, SuiteSparse), docs/fgo.md",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn&) {
         return solveBatchFgo(p, c.fgo);
       },
       [](const EstimationProblem& p, const ImuStream& imu, const RunConfig& c,
          SolutionSink& sink) { return solveBatchFgo(p, imu.pass, c.fgo, nullptr, toSink(sink)); }},
      {"fgo-window", "factor-graph sliding window with marginalization, causal output",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn&) {
         return solveWindowFgo(p, c.fgo);
       },
       [](const EstimationProblem& p, const ImuStream& imu, const RunConfig& c,
          SolutionSink& sink) {
         return solveWindowFgo(p, imu.pass, c.fgo, nullptr, toSink(sink));
       }},
      {"free-inertial",
       "mechanization from the initial state, no GNSS",
       [](const EstimationProblem& p, const RunConfig& c, const ProgressFn& f) {
         return runFreeInertial(p, c.ekf.output_decimation, f);
       },
       {}},
  };
  return table;
}

std::vector<std::string> estimatorNames() {
  std::vector<std::string> names;
  for (const auto& e : estimatorTable()) names.push_back(e.name);
  return names;
}

namespace {

const EstimatorEntry& findEstimator(const std::string& name) {
  for (const auto& e : estimatorTable()) {
    if (e.name == name) return e;
  }
  std::string known;
  for (const auto& n : estimatorNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown estimator '" + name + "' (known: " + known + ")");
}
}  // namespace

NavSolution runEstimator(const std::string& name, const EstimationProblem& problem,
                         const RunConfig& config, const ProgressFn& progress) {
  return findEstimator(name).run(problem, config, progress);
}

bool canStream(const std::string& name) { return static_cast<bool>(findEstimator(name).stream); }

ImuStream imuFileStream(const std::string& path, const ImuReadOptions& options,
                        ReadReport* report) {
  ImuStream s;
  s.pass = [path, options, report](const ImuBlockFn& block) {
    ImuBlockReader reader(path, options);
    ImuSeries samples;
    while (reader.next(&samples)) block(samples);
    if (report) *report = reader.report();
  };
  return s;
}

namespace {
class GnssFileSource final : public GnssSource {
 public:
  GnssFileSource(const std::string& pos, const std::string& fixtype, const GnssReadPolicy& policy)
      : reader_(pos, fixtype, policy) {}
  bool next(GnssFix* fix) override { return reader_.next(fix); }

 private:
  GnssStreamReader reader_;
};
}  // namespace

GnssOpenFn gnssFileStream(const std::string& pos_path, const std::string& fixtype_path,
                          const GnssReadPolicy& policy) {
  return [pos_path, fixtype_path, policy]() -> std::unique_ptr<GnssSource> {
    return std::make_unique<GnssFileSource>(pos_path, fixtype_path, policy);
  };
}

NavSolution runEstimatorStreaming(const std::string& name, const EstimationProblem& problem,
                                  const ImuStream& imu, const RunConfig& config,
                                  SolutionSink& sink) {
  const EstimatorEntry& e = findEstimator(name);
  if (!e.stream) throw std::invalid_argument("estimator '" + name + "' has no streamed form");
  return e.stream(problem, imu, config, sink);
}

}  // namespace graftnav::app
