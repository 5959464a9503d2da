#include "sg_evaluate.h"

#include "graftnav/sg/sg_report_files.h"
#include "script_locator.h"

namespace graftnav::app {

void writeSgOutputs(const std::string& out_dir, const SgEvaluationReport& rep, bool plots,
                    const LogFn& log, bool errors_csv) {
  writeSgEvaluationFiles(out_dir, rep, errors_csv);
  if (plots) {
    const std::string w = runPythonScript("plot_sg.py", {out_dir});
    if (!w.empty()) log("warning: " + w);
  }
}

}  // namespace graftnav::app
