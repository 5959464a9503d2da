#include "py_case.h"

#include <stdexcept>

#include "graftnav/io/case_config.h"
#include "graftnav/io/file_errors.h"

namespace graftnav::python {

std::shared_ptr<PyCase> PyCase::load(const std::string& dir) {
  auto c = std::make_shared<PyCase>();
  c->inputs_ = loadCaseInputs(dir);
  if (c->hasImu("ref")) c->imu("ref");
  return c;
}

std::shared_ptr<PyCase> PyCase::fromInputs(CaseInputs inputs,
                                           std::map<std::string, ImuSelection> imus,
                                           OdometerSeries odometer) {
  auto c = std::make_shared<PyCase>();
  c->inputs_ = std::move(inputs);
  c->imus_ = std::move(imus);
  c->odometer_ = std::move(odometer);
  return c;
}

bool PyCase::hasImu(const std::string& which) const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (imus_.count(which)) return true;
  }
  if (!hasFolder()) return false;
  const CasePaths p = inputs_.paths();
  if (which == "ref") return CasePaths::exists(p.refImu());
  if (which == "tested") return CasePaths::exists(p.testedImu());
  return false;
}

std::string PyCase::defaultImu() const {
  if (hasFolder()) return defaultImuOf(inputs_.paths());  // the command's rule
  return hasImu("ref") ? "ref" : "tested";
}

const ImuSelection& PyCase::imu(const std::string& which) const {
  if (which != "ref" && which != "tested")
    throw std::invalid_argument("imu '" + which + "': expected 'ref' or 'tested'");
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = imus_.find(which);
  if (it != imus_.end()) return it->second;
  if (!hasFolder())
    throw std::invalid_argument("imu '" + which + "': the case built from arrays has no " +
                                (which == "ref" ? "reference" : "tested") + " IMU");
  return imus_.emplace(which, selectImu(inputs_, which)).first->second;
}

}  // namespace graftnav::python
