#pragma once
// Every JSON result file goes through writeJsonResult: a NaN or inf never reaches a result (it
// throws naming the file and the field), a statistic that could not be computed is written as
// null and said so, and the file appears atomically (atomic_file.h).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace graftnav {

// Throws std::runtime_error naming the file and the field (JSON pointer) when a number is NaN or
// inf, then writes `j` atomically (2-space indent, trailing newline). Returns one warning listing
// the fields written as null ("path: absent (null): /outage/*, /nees (why)"), `why_null` saying
// why such a statistic could not be computed; the caller prints it.
std::vector<std::string> writeJsonResult(const std::string& path, const nlohmann::json& j,
                                         const std::string& why_null = "");

}  // namespace graftnav
