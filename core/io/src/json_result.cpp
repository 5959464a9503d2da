#include "graftnav/io/json_result.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"

namespace graftnav {
namespace {

using nlohmann::json;

// Depth-first walk: a non-finite number throws, a null is listed by its JSON pointer.
void scanJson(const json& j, const std::string& pointer, const std::string& path,
              std::vector<std::string>* nulls) {
  if (j.is_null()) {
    nulls->push_back(pointer.empty() ? "/" : pointer);
  } else if (j.is_number_float()) {
    if (!std::isfinite(j.get<double>()))
      throw std::runtime_error(path + ": result field " + pointer + " is not finite (" +
                               fmt::format("{}", j.get<double>()) + "); refusing to write it");
  } else if (j.is_object()) {
    const bool all_null =
        !j.empty() && std::all_of(j.begin(), j.end(), [](const json& v) { return v.is_null(); });
    if (all_null) {
      nulls->push_back(pointer + "/*");
      return;
    }
    for (const auto& [k, v] : j.items()) scanJson(v, pointer + "/" + k, path, nulls);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      scanJson(j[i], pointer + "/" + std::to_string(i), path, nulls);
  }
}

}  // namespace

std::vector<std::string> writeJsonResult(const std::string& path, const json& j,
                                         const std::string& why_null) {
  std::vector<std::string> nulls;
  scanJson(j, "", path, &nulls);
  writeFileAtomically(path, j.dump(2) + "\n");
  if (nulls.empty()) return {};
  std::string fields;
  for (const std::string& n : nulls) fields += (fields.empty() ? "" : ", ") + n;
  return {path + ": absent (null): " + fields + (why_null.empty() ? "" : " (" + why_null + ")")};
}

}  // namespace graftnav
