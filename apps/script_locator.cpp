#include "script_locator.h"

#include <cstdlib>
#include <filesystem>

namespace graftnav::app {
namespace fs = std::filesystem;

std::vector<std::string> scriptDirs() {
  if (const char* env = std::getenv("GRAFTNAV_SCRIPTS_DIR")) return {env};
  std::error_code ec;
  const fs::path bin = fs::read_symlink("/proc/self/exe", ec).parent_path();
  return {(bin / ".." / kInstalledScriptsDir).lexically_normal().string(),
          (bin / kInstalledScriptsDir).lexically_normal().string()};
}

std::string findScript(const std::string& name) {
  const std::vector<std::string> dirs = scriptDirs();
  for (const std::string& d : dirs)
    if (fs::exists(fs::path(d) / name)) return (fs::path(d) / name).string();
  return {};
}

namespace {
std::string quote(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

// Debian's python3-matplotlib belongs to /usr/bin/python3; a pyenv python3 earlier on PATH may
// lack it. GRAFTNAV_PYTHON overrides.
const std::string& pythonWithMatplotlib() {
  static const std::string python = [] {
    if (const char* env = std::getenv("GRAFTNAV_PYTHON")) return std::string(env);
    for (const char* cand : {"/usr/bin/python3", "python3"}) {
      const std::string probe = std::string(cand) + " -c 'import matplotlib' >/dev/null 2>&1";
      if (std::system(probe.c_str()) == 0) return std::string(cand);
    }
    return std::string();
  }();
  return python;
}
}  // namespace

std::string runPythonScript(const std::string& name, const std::vector<std::string>& args) {
  const std::string script = findScript(name);
  if (script.empty()) {
    std::string tried;
    for (const auto& d : scriptDirs()) tried += (tried.empty() ? "" : ", ") + d;
    return "plot script " + name + " not found in " + tried +
           " (set GRAFTNAV_SCRIPTS_DIR to the folder holding it)";
  }
  const std::string& py = pythonWithMatplotlib();
  if (py.empty())
    return "python3 with matplotlib not available (apt-get install python3-matplotlib): no plots";
  std::string cmd = py + " " + quote(script);
  for (const auto& a : args) cmd += " " + quote(a);
  cmd += " >/dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) return "plot script failed: " + cmd;
  return {};
}

}  // namespace graftnav::app
