#pragma once
// What the finder (diagnosis.h) is given besides the records: the simulation of the tested IMU
// and what is known about it beforehand. With lab data the simulation is SG#2 (the lab
// calibration grafted onto the reference, graft_case.h) and the lab's figures become the
// finder's priors; without, it is the reference plus the tested IMU's bias measured in a static
// span of the field record (or the reference alone when there is none).

#include <functional>
#include <string>
#include <vector>

#include "graftnav/calibration/calibration_result.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/sensor.h"

namespace graftnav {

// A sensor triad's lab figures as the finder's priors: M and its 1-sigma, the Allan bias
// instability and rate random walk (when the lab measured them), the fitting polynomial's
// quadratic (when the lab fitted one). reference_scale_sigma is left unset.
SensorPriors labPriors(const SensorCalibration& cal);

// Sets in->simulated to SG#2 from the case's lab data (calibrated, then grafted onto
// in->reference with the graft starting start_offset_s into the tiled lab record), its
// temperature column from the tiled lab temperature, the graft's tiling, and the priors of both
// sensors. reference_scale_std: the reference IMU's 1-sigma scale uncertainty per sensor
// (fraction; 0 = not stated). With reload_lab (the same lab data read again), also
// in->remake_simulated, which calibrates and grafts again rather than holding the lab record.
// With spooled, SG#2 is in->simulated_recording instead of in->simulated: grafted block by block
// into an unlinked spool (TMPDIR, 72 bytes a sample) that the finder's passes read back.
// `lab` is consumed: its static record goes once the calibration has read it (the graft holds
// its error signal, and its temperature when it has one). Throws what calibrateLab and
// graftCase throw.
void simulateFromLab(LabData lab, double start_offset_s,
                     const PerSensor<double>& reference_scale_std, DiagnosisInputs* in,
                     std::function<LabData()> reload_lab = {}, bool spooled = false);

// Sets in->simulated without lab data: the reference plus the tested IMU's static bias
// (simulateFromReferenceAndStaticBias), or the reference alone when the field record has no
// static span. Adds the notes the report needs; the one about a missing static span goes to
// `warnings` too.
void simulateWithoutLab(DiagnosisInputs* in, std::vector<std::string>* notes,
                        std::vector<std::string>* warnings);

// SG#2's basic error signal is the lab static record tiled over the field test, so it carries
// the lab record's temperature history; the same tiling of the lab temperature gives each SG#2
// sample the temperature behind its bias (left NaN when the lab file has no temperature).
void attachLabTemperature(const ImuSeries& lab_static, double start_offset_s, ImuSeries* sg2);

}  // namespace graftnav
