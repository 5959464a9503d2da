#pragma once
// One place that turns a case directory into estimator inputs: case.yaml, GNSS, the truth or
// reference solution, and which IMU of the case is navigated with which profile. Used by every
// command that navigates a case, by the batch and by the Python module.
#include <stdexcept>
#include <string>
#include <vector>

#include "graftnav/case/run_config.h"
#include "graftnav/io/case_config.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/nav_io.h"

namespace graftnav {

struct CaseInputs {
  std::string dir;
  CaseConfig config;
  GnssSeries gnss;             // empty when not loaded
  NavSeries reference;         // truth.nav, else the case's reference solution (may be empty)
  std::string reference_name;  // its path
  bool reference_is_truth = false;
  std::vector<std::string> warnings;  // from the readers and case.yaml (print them)
  CasePaths paths() const { return CasePaths(dir); }
};

struct CaseLoadOptions {
  bool load_gnss = true;
  bool lenient = false;  // the "real" read policies (repair/warn) instead of strict
  // Read the reference solution (truth.nav, else case.yaml's reference solution) now; false:
  // later, with loadCaseReference (a caller that holds other records first).
  bool load_reference = true;
};

// Throws std::runtime_error naming the directory or file when the case is not usable.
CaseInputs loadCaseInputs(const std::string& case_dir, const CaseLoadOptions& options = {});
// The case's reference file, not read: truth.nav (strict), else case.yaml's reference solution
// (the real-data policy when lenient); path empty when the case has none.
struct CaseReferenceFile {
  std::string path;
  bool is_truth = false;
  NavReadPolicy policy;
};
CaseReferenceFile caseReferenceFile(const CaseInputs& c, bool lenient);
// Of the reference file, the first epoch, the last one at or before t_s and the two after it
// (all when fewer): what makeProblem reads of CaseInputs::reference (the week, the initial state
// interpolated at the IMU's start: the same bracket as in the whole series), so that a run
// reading the reference as a stream need not hold it, even when t_s lies hours into it.
NavSeries readReferenceHead(const CaseReferenceFile& f, double t_s);
// Reads the case's reference solution into c (reference, reference_name, reference_is_truth);
// nothing when it has none.
void loadCaseReference(CaseInputs* c, bool lenient);

// Which IMU of a case: "ref", "tested", or a file path (navigated with the tested IMU's rate and
// profile unless a profile file is given).
struct ImuSelection {
  ImuSeries imu;
  ImuProfile profile;
  bool profile_given = false;  // noise parameters known (case.yaml or a profile file)
  std::string path;
  std::string label;
  std::string read_summary;     // the reader's conditions met (repairs/warnings); empty when clean
  ImuReadOptions read_options;  // how the file is (or is to be) read
};
// A grafted series to navigate as the tested IMU: its samples with the tested IMU's profile.
ImuSelection graftedSelection(ImuSeries imu, const ImuProfile& tested_profile,
                              const ImuReadOptions& read_options = {});
// The IMU navigated when none is asked for: "ref" when the case holds field/ref_imu.txt, else
// "tested" when it holds only field/tested_imu.txt (a real recording of one IMU); "ref" when it
// holds neither (selectImu then names the missing file).
std::string defaultImuOf(const CasePaths& paths);
// `requested` when given (non-empty), else defaultImuOf(paths) with a printable line saying which
// IMU that is and why in *note (left empty when the case's reference IMU is chosen).
std::string chooseImu(const std::string& requested, const CasePaths& paths, std::string* note);

// read_samples = false leaves `imu` empty (for a run that streams the file with read_options).
ImuSelection selectImu(const CaseInputs& c, const std::string& which,
                       const std::string& profile_file = "", bool lenient = false,
                       bool read_samples = true);

// Keeps the IMU samples whose interval lies in the range (TimeRangeConfig::keepsImuSample) and
// the GNSS epochs inside it. Throws std::runtime_error naming the range when no IMU sample is left.
void restrictToTimeRange(const TimeRangeConfig& range, CaseInputs* c, ImuSelection* imu,
                         std::vector<std::string>* notes);
// The error when a time range keeps no sample of the IMU file `path` (first and last: its span).
std::runtime_error timeRangeWithoutSamples(const TimeRangeConfig& range, const std::string& path,
                                           const ImuSample& first, const ImuSample& last);
// The note of a time range: the span kept (its first and last samples) and the counts.
std::string timeRangeNote(const ImuSeries& kept_span, long imu_kept, long imu_total, long gnss_kept,
                          long gnss_total);

}  // namespace graftnav
