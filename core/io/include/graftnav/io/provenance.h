#pragma once
// What a result file needs to be traced back to its run: the graftnav version and git commit, the
// full command line, and a hash of every configuration file the run read. Written into every
// run_info.json and printed by `graftnav --version`.
#include <nlohmann/json.hpp>
#include <string>

namespace graftnav {

// From the one generated header, graftnav/version.h (cmake/graftnav_version.cmake: the project
// VERSION of CMakeLists.txt and the git commit of the source tree at build time).
const char* graftnavVersion();    // "0.1.0"
const char* graftnavGitCommit();  // short commit, "-dirty" with local changes, or "unknown"
std::string versionLine();        // "graftnav 0.1.0 (commit abc123...)"

void setCommandLine(int argc, const char* const* argv);
// Records a configuration file read by this run, with its FNV-1a 64-bit content hash. Repeated
// paths are recorded once. Throws std::runtime_error naming the path when it cannot be read.
void recordConfigFile(const std::string& path);
// 64-bit FNV-1a of the bytes, as 16 hex digits (stable across builds and machines).
std::string fnv1a64Hex(const std::string& bytes);

// {"version", "git_commit", "command_line", "configs": [{"path", "fnv1a64"}]}
nlohmann::json provenanceJson();

}  // namespace graftnav
