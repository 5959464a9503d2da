#pragma once
// A case's IMU and GNSS files as the one-pass sources of a streamed run (the registry's streamed
// estimators, EstimationProblem::gnss_stream): each pass reads the file again, so memory does
// not grow with the recording.
#include <string>

#include "graftnav/estimation/gnss_source.h"
#include "graftnav/estimation/nav_solution.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"

namespace graftnav {

// An IMU file read in blocks (ImuBlockReader; options.nominal_rate_hz > 0). *report (when given)
// receives the last pass's reader report.
ImuPassFn imuFileStream(const std::string& path, const ImuReadOptions& options,
                        ReadReport* report = nullptr);

// GNSS files read one epoch at a time (GnssStreamReader). fixtype_path empty: no fix-type file.
GnssOpenFn gnssFileStream(const std::string& pos_path, const std::string& fixtype_path,
                          const GnssReadPolicy& policy);

}  // namespace graftnav
