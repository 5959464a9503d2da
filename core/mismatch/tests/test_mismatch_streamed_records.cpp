// The finder reading the real record and the simulation as passes (DiagnosisInputs::
// real_recording and simulated_recording, e.g. a file or a graft spooled) gives the held
// records' diagnosis number for number: the same report, the same SG#3.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "graftnav/io/imu_recording.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/diagnosis_report.h"
#include "mismatch_diagnosis_fixture.h"

namespace graftnav {
namespace {

using namespace diagnosis_test;

// The real record with 1.5 s of samples lost (the sample after the gap stretched over it, as
// the reader does) and its tags moved late by tag_delay_s.
ImuSeries gappedAndDelayed(const ImuSeries& real, double tag_delay_s) {
  ImuSeries out;
  for (const ImuSample& s : real) {
    if (s.t_s > 5060.0 && s.t_s <= 5061.5) continue;
    out.push_back(s);
    if (out.size() > 1) out.back().dt_s = out.back().t_s - out[out.size() - 2].t_s;
  }
  for (ImuSample& s : out) s.t_s += tag_delay_s;
  return out;
}

// Diagnoses `p` with its real record and simulation read back in blocks of 37 and 41 samples
// from spools (the 120-Hz record has 6 samples a bin, the 100-Hz simulation 5: block boundaries
// fall inside bins); `held` is its diagnosis with the records held, which must agree exactly.
void expectStreamedEqualsHeld(const Pair& p, const DiagnosisResult& held) {
  DiagnosisInputs streamed = p.in;
  streamed.real_recording = spooledRecording(viewedRecording(p.in.real).pass, 37);
  streamed.real.clear();
  streamed.simulated_recording = spooledRecording(viewedRecording(p.in.simulated).pass, 41);
  streamed.simulated.clear();
  const DiagnosisResult read = diagnose(std::move(streamed));
  EXPECT_EQ(diagnosisJson(held), diagnosisJson(read));
  EXPECT_EQ(held.masked_bins, read.masked_bins);
  ASSERT_TRUE(read.sg3_recording);
  EXPECT_TRUE(read.sg3.empty());
  const ImuSeries sg3 = collectRecording(*read.sg3_recording);
  ASSERT_EQ(held.sg3.size(), sg3.size());
  for (std::size_t i = 0; i < sg3.size(); ++i) {
    ASSERT_EQ(held.sg3[i].t_s, sg3[i].t_s) << "sample " << i;
    ASSERT_EQ(held.sg3[i].dtheta_rad, sg3[i].dtheta_rad) << "sample " << i;
    ASSERT_EQ(held.sg3[i].dvel_m_s, sg3[i].dvel_m_s) << "sample " << i;
  }
}

TEST(MismatchStreamedRecords, AGappedRecordReadInBlocksGivesTheHeldDiagnosis) {
  ImuErrorModel extra;
  extra.time_offset.tau_s = 0.018;
  extra.lever_arm.r_m << 0.5, -0.3, 0.2;
  Pair p = makePair(extra, 3);
  p.in.real = gappedAndDelayed(p.in.real, 0.0);
  const DiagnosisResult held = diagnose(p.in);
  ASSERT_EQ(held.masked_spans.size(), 1u);  // the gap is masked
  ASSERT_FALSE(held.effects.empty());       // and something is claimed, to compare
  expectStreamedEqualsHeld(p, held);
}

// Tags 0.4 s late: the finder moves them back before binning (a realignment), reading the
// record once more as tagged for the raw residual.
TEST(MismatchStreamedRecords, ARealignedRecordReadInBlocksGivesTheHeldDiagnosis) {
  ImuErrorModel extra;
  extra.lever_arm.r_m << 0.5, -0.3, 0.2;
  Pair p = makePair(extra, 4);
  p.in.real = gappedAndDelayed(p.in.real, 0.4);
  const DiagnosisResult held = diagnose(p.in);
  ASSERT_NE(diagnosisMarkdown(held).find("were moved by it before binning"), std::string::npos)
      << diagnosisMarkdown(held);
  expectStreamedEqualsHeld(p, held);
}

}  // namespace
}  // namespace graftnav
