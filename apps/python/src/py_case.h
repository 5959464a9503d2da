#pragma once
// A case as the Python module holds it: the case inputs (case.yaml, GNSS, truth or reference
// solution) and its IMUs with their profiles. A case loaded from a folder reads an IMU file on
// first use; a case built from arrays (Case.from_arrays) is given its IMUs. Read from several
// Python threads at once (navigate releases the GIL): the IMUs are filled under a lock and never
// changed afterwards.
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "graftnav/case/case_inputs.h"
#include "graftnav/estimation/vehicle_aiding.h"

namespace graftnav::python {

class PyCase {
 public:
  // loadCaseInputs(dir) with the reference IMU read now (navigate's input, so that a run
  // excludes loading).
  static std::shared_ptr<PyCase> load(const std::string& dir);
  // A case without a folder: no lab data, so evaluate and diagnose need a folder.
  static std::shared_ptr<PyCase> fromInputs(CaseInputs inputs,
                                            std::map<std::string, ImuSelection> imus,
                                            OdometerSeries odometer = {});

  const CaseInputs& inputs() const { return inputs_; }
  bool hasFolder() const { return !inputs_.dir.empty(); }
  // "ref" or "tested": whether the case has it (its file, or the array given).
  bool hasImu(const std::string& which) const;
  // The case's one IMU, else the reference (navigate's imu=None).
  std::string defaultImu() const;
  // Throws std::invalid_argument for another name, MissingFileError when its file is missing.
  const ImuSelection& imu(const std::string& which) const;

  // The odometer given as an array (a case from arrays); empty otherwise (a folder's
  // field/odometer.txt is read by makeProblem).
  const OdometerSeries& odometer() const { return odometer_; }

  // simulate(out=None) keeps its temporary folder alive as long as the case.
  void keepAlive(std::shared_ptr<void> owner) { owner_ = std::move(owner); }

 private:
  CaseInputs inputs_;
  mutable std::mutex mutex_;
  mutable std::map<std::string, ImuSelection> imus_;
  OdometerSeries odometer_;
  std::shared_ptr<void> owner_;
};

}  // namespace graftnav::python
