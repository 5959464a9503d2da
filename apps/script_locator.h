#pragma once
// Finds the project's plot scripts (scripts/<name>) from the installed binary's location, and
// runs one with the python3 that has matplotlib. A missing python or matplotlib is a warning
// returned as text, never a failure of the command.
#include <string>
#include <vector>

namespace graftnav::app {

// GRAFTNAV_SCRIPTS_DIR overrides; else <binary>/../scripts, <binary>/../../scripts, ./scripts.
std::string findScript(const std::string& name);

// Runs `python3 scripts/<name> args...`; returns "" on success or a warning text.
std::string runPythonScript(const std::string& name, const std::vector<std::string>& args);

}  // namespace graftnav::app
