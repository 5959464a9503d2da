#pragma once
// The builders of the built-in terms (term_spec.h TermBuildFunction), one per TermSpec row of
// term_specs.cpp: triad_terms.cpp builds a term per sensor triad, pair_terms.cpp the terms of the
// pair of IMUs (motion, geometry, the simulation's own omissions).
#include "graftnav/mismatch/term_spec.h"

namespace graftnav::term_builders {

TermBuildFunction constantBias;
TermBuildFunction biasInstability;
TermBuildFunction scaleFactor;
TermBuildFunction nonOrthogonality;
TermBuildFunction scaleAsymmetry;
TermBuildFunction scaleNonlinearity;
TermBuildFunction temperatureBias;
TermBuildFunction temperatureScale;
TermBuildFunction vibrationRectification;
TermBuildFunction gSensitivity;
TermBuildFunction timeOffset;
TermBuildFunction leverArm;
TermBuildFunction mountingMisalignment;
TermBuildFunction earthRotationOmitted;
TermBuildFunction gravityModel;

}  // namespace graftnav::term_builders
