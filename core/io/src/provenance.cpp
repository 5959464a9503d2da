#include "graftnav/io/provenance.h"

#include <fmt/core.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "graftnav/version.h"  // generated

namespace graftnav {
namespace {

struct Registry {
  std::mutex mutex;
  std::vector<std::string> argv;
  std::vector<std::pair<std::string, std::string>> configs;  // absolute path, hash
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

const char* graftnavVersion() { return GRAFTNAV_VERSION; }
const char* graftnavGitCommit() { return GRAFTNAV_GIT_COMMIT; }

std::string versionLine() {
  return fmt::format("graftnav {} (commit {})", graftnavVersion(), graftnavGitCommit());
}

void setCommandLine(int argc, const char* const* argv) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  registry().argv.assign(argv, argv + argc);
}

std::string fnv1a64Hex(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

void recordConfigFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read the config to hash it");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string abs = std::filesystem::absolute(path).lexically_normal().string();
  const std::string hash = fnv1a64Hex(ss.str());
  std::lock_guard<std::mutex> lock(registry().mutex);
  for (const auto& c : registry().configs)
    if (c.first == abs) return;
  registry().configs.emplace_back(abs, hash);
}

nlohmann::json provenanceJson() {
  std::lock_guard<std::mutex> lock(registry().mutex);
  nlohmann::json configs = nlohmann::json::array();
  for (const auto& c : registry().configs)
    configs.push_back({{"path", c.first}, {"fnv1a64", c.second}});
  return {{"version", graftnavVersion()},
          {"git_commit", graftnavGitCommit()},
          {"command_line", registry().argv},
          {"configs", configs}};
}

}  // namespace graftnav
