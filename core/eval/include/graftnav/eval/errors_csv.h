#pragma once
// errors.csv: the per-epoch errors of a navigation run against its reference, one row every
// min_interval_s (0: every epoch), columns with their units:
//   t_s,north_m,east_m,down_m,horizontal_m,vn_m_s,ve_m_s,vd_m_s,roll_deg,pitch_deg,heading_deg,
//   nees,outage
// A NEES without a solution sigma is an empty cell (as in errors.json), outage is the window's
// index or -1. Written as the epochs come (ErrorsCsvWriter, a StreamedEvaluation sink) or from an
// in-memory Evaluation (writeErrorsCsv, evaluation_files.h, through the same writer).

#include <memory>
#include <string>

#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/streamed_evaluation.h"

namespace graftnav {

class AtomicFile;

class ErrorsCsvWriter final : public EpochErrorSink {
 public:
  // Throws std::runtime_error like AtomicFile when the file cannot be created.
  ErrorsCsvWriter(const std::string& path, double min_interval_s);
  ~ErrorsCsvWriter() override;
  void add(const EpochError& e) override;
  // Writes the file. Throws std::runtime_error naming the file and the epoch when a written
  // epoch's error was not finite (the file is then not written).
  void commit() override;

 private:
  std::unique_ptr<AtomicFile> file_;
  std::string buffer_, failure_;
  double min_interval_s_;
  double last_t_s_ = -1e300;
};

}  // namespace graftnav
