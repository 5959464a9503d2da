#pragma once
// Finds the plot scripts the commands run (scripts/runtime/ in the source tree) next to the
// binary, and runs one with the python3 that has matplotlib. A missing script, python or
// matplotlib is a warning returned as text, never a failure of the command.
#include <string>
#include <vector>

namespace graftnav::app {

// Where the scripts are, relative to the binary: PREFIX/share/graftnav/scripts for PREFIX/bin/graftnav
// (installed, `cmake --install` or the .deb), BUILD/share/graftnav/scripts for BUILD/graftnav (the
// build stages them there, scripts/runtime/CMakeLists.txt).
inline constexpr const char* kInstalledScriptsDir = "share/graftnav/scripts";

// The folders searched, in order: $GRAFTNAV_SCRIPTS_DIR alone when set, else the two above.
std::vector<std::string> scriptDirs();
// The script's path in the first folder that holds it; "" when none does.
std::string findScript(const std::string& name);

// Runs `python3 DIR/<name> args...`; returns "" on success or a warning text.
std::string runPythonScript(const std::string& name, const std::vector<std::string>& args);

}  // namespace graftnav::app
