#pragma once
// The diagnose options file (configs/diagnose.yaml): every key optional, defaults those of
// DiagnoseOptions. Errors name the file, line and key; unknown keys are warnings.
#include <string>
#include <vector>

#include "graftnav/mismatch/diagnosis.h"

namespace graftnav {

// Throws std::runtime_error naming path:line and the key on a bad value or invalid options.
DiagnoseOptions loadDiagnoseConfig(const std::string& path, std::vector<std::string>* warnings);

}  // namespace graftnav
