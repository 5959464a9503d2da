#pragma once
// The IMU samples a streamed factor graph still needs: a run of consecutive samples addressed by
// their index in the recording. Samples are appended as a pass reads them and dropped from the
// front once no interval that may be (re-)preintegrated or output needs them, so the memory is
// that of the sliding window, not of the recording.

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "graftnav/nav/types.h"

namespace graftnav {

class ImuSampleBuffer {
 public:
  // Appends the next sample. When the storage is full and at least an eighth of it holds
  // dropped samples, those are removed instead of growing it: an outage, whose samples are all
  // held until GNSS returns, would otherwise double it for the dropped ones it still carries.
  void push(const ImuSample& s) {
    if (samples_.size() == samples_.capacity() && head_ > 0 && 8 * head_ >= samples_.size())
      compact();
    samples_.push_back(s);
  }
  // Index (in the recording) of the first sample held and one past the last one read.
  size_t begin() const { return base_ + head_; }
  size_t end() const { return base_ + samples_.size(); }
  // Sample `i` of the recording; throws std::out_of_range when it is not held.
  const ImuSample& at(size_t i) const {
    if (i < begin() || i >= end()) {
      throw std::out_of_range("ImuSampleBuffer: sample " + std::to_string(i) + " not held (held [" +
                              std::to_string(begin()) + ", " + std::to_string(end()) + "))");
    }
    return samples_[i - base_];
  }
  // Forgets the samples before index `i`. The storage moves only when the dropped part is at
  // least half of it (amortized constant time per sample, no per-sample allocation).
  void dropBefore(size_t i) {
    if (i <= begin()) return;
    head_ = std::min(i, end()) - base_;
    if (head_ >= kMinCompact && 2 * head_ >= samples_.size()) compact();
  }

 private:
  void compact() {
    samples_.erase(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(head_));
    base_ += head_;
    head_ = 0;
  }

  static constexpr size_t kMinCompact = 4096;
  std::vector<ImuSample> samples_;
  size_t base_ = 0;  // recording index of samples_[0]
  size_t head_ = 0;  // samples_[0, head_) are dropped
};

}  // namespace graftnav
