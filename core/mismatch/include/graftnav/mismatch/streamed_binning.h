#pragma once
// Binning of an IMU record read in blocks: the samples are added in time order, as a file or a
// spool hands them out, and the bin means come out as soon as the samples after each bin edge
// are known. It gives binImu's numbers bit for bit (binImu is this class fed the whole series)
// while holding a window of about 70 samples (the 64 nodes of CumulativeImu's band-limited
// interpolation and the samples of the bins not yet closed), not the record's cumulative
// integral (68 bytes a sample).
#include <cstddef>
#include <deque>
#include <vector>

#include "graftnav/mismatch/common_grid.h"

namespace graftnav {

// What a binning keeps: every column of BinnedImu, or only the mean angular rates (the others
// left empty; 24 bytes a bin instead of 76 while binning, e.g. for a cross-correlation).
enum class BinnedColumns { all, rates_only };

class StreamedBinning {
 public:
  // The same grid, shift and map as binImu (common_grid.h).
  explicit StreamedBinning(const GridSpec& grid, double time_shift_s = 0.0, ImuSampleMap map = {},
                           BinnedColumns columns = BinnedColumns::all);

  // The next sample (after every sample added before). Throws std::invalid_argument, as
  // CumulativeImu does, when dt_s <= 0 or the tag is not after the previous one (naming the
  // sample's index in the record).
  void add(const ImuSample& sample);
  void add(const ImuSeries& block) {
    for (const ImuSample& s : block) add(s);
  }
  std::size_t samplesAdded() const { return added_; }
  // The bins, after the last sample. Throws std::invalid_argument when no sample was added.
  BinnedImu finish();

 private:
  // A node of the cumulative integral (CumulativeImu's t_, cum_, cum_temp_, irregular_).
  struct Node {
    double t_s = 0.0;
    Vector6d cum = Vector6d::Zero();
    double cum_temp = 0.0;
    int irregular = 0;
  };
  struct PendingSample {  // a sample whose bin is not closed yet (within-bin vibration)
    int bin = 0;
    Eigen::Vector3d f_m_s2 = Eigen::Vector3d::Zero();
  };
  struct NodeView;                          // the window as cumulative_nodes.h reads it
  const Node& nodeAt(std::size_t k) const;  // node k of the record (held, or one of the first two)
  std::size_t nodeCount() const { return base_ + nodes_.size(); }
  std::size_t upperBound(double t_s) const;  // first node after t_s (absolute index)
  // The integral at t_s; false when the nodes it needs are not all read yet.
  bool integralAt(double t_s, Vector6d* value, double* temp) const;
  // Closes every bin whose end edge can be evaluated, then drops the nodes no later edge needs.
  void closeBins();
  void closeBin(int i, const Vector6d& next, double next_temp);
  void dropPendingUpTo(int bin);

  GridSpec grid_;
  double shift_s_ = 0.0;
  ImuSampleMap map_;
  bool rates_only_ = false;
  BinnedImu out_;
  std::deque<Node> nodes_;
  Node first_[2];         // nodes 0 and 1: the extrapolation before the record reads them
  std::size_t base_ = 0;  // absolute index of nodes_.front()
  std::size_t added_ = 0;
  bool all_temperature_ = true;
  bool finished_ = false;
  int next_bin_ = -1;  // -1: the first edge is not evaluated yet
  Vector6d prev_ = Vector6d::Zero();
  double prev_temp_ = 0.0;
  std::deque<PendingSample> pending_;
  Eigen::VectorXd sum_sq_;
  Eigen::VectorXi count_;
};

}  // namespace graftnav
