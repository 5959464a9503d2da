#include "graftnav/graph/node_layout.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "graftnav/estimation/usable_gnss.h"

namespace graftnav {
namespace {

constexpr size_t kNone = std::numeric_limits<size_t>::max();
// Fewest IMU samples between two nodes: one sample makes a preintegration whose covariance is
// singular (its position and velocity errors both come from the one increment, dp = dv dt / 2).
constexpr size_t kMinIntervalSamples = 2;

struct SampleTime {
  size_t index = 0;
  double t_s = 0.0;
  double dt_s = 0.0;
};

}  // namespace

double nodeSpacing(const EstimationProblem& problem, const FgoOptions& options) {
  if (!problem.aiding.any()) return options.max_node_spacing_s;
  return std::min(options.max_node_spacing_s, 1.0 / problem.aiding.rateHz());
}

// Streams the samples once. A GNSS fix is placed on the sample whose end is nearest its time
// (searched from the first sample after the initial state), as soon as the first sample at or
// after the fix arrives; fixes are taken in time order. A node's sample (an "anchor") is final
// when a later fix lands on a later sample; then the nodes filling the gap before it every
// max_node_spacing_s are placed on the sample times held since the previous node.
class NodeLayoutBuilder::Impl {
 public:
  Impl(const EstimationProblem& problem, const LocalFrame& frame, const FgoOptions& options,
       NodeLayout* layout)
      : gnss_(problem),
        frame_(frame),
        options_(options),
        t0_(problem.initial.t_s),
        spacing_s_(nodeSpacing(problem, options)),
        layout_(*layout) {
    layout_ = NodeLayout{};
    layout_.first_sample = kNone;
  }

  void add(const ImuSample& s) {
    const size_t i = count_++;
    const SampleTime cur{i, s.t_s, s.dt_s};
    if (layout_.first_sample == kNone) {
      if (!(s.t_s > t0_ + 1e-6)) return;
      layout_.first_sample = i;
      GraphNode n0;
      n0.t_s = t0_;
      n0.sample_end = i;
      layout_.nodes.push_back(n0);
    }
    times_.push_back(cur);
    for (const GnssFix* f; (f = nextFix()) && f->t_s <= s.t_s; gnss_.pop()) {
      if (!placeFix(*f, times_.size() - 1)) break;  // its node needs a later sample
    }
  }

  void finish() {
    if (count_ < 2) throw std::invalid_argument("FgoGraph: fewer than 2 IMU samples");
    if (layout_.first_sample == kNone) {
      throw std::invalid_argument("FgoGraph: initial state at t=" + std::to_string(t0_) +
                                  " is after the last IMU sample");
    }
    if (count_ < layout_.first_sample + kMinIntervalSamples) {
      throw std::invalid_argument(
          "FgoGraph: fewer than " + std::to_string(kMinIntervalSamples) +
          " IMU samples after the initial state at t=" + std::to_string(t0_));
    }
    const SampleTime last = times_.back();
    for (const GnssFix* f; (f = nextFix()); gnss_.pop()) {  // fixes after the last sample's end
      if (f->t_s <= last.t_s + 0.5 * last.dt_s) placeFix(*f, times_.size() - 1);
    }
    layout_.gnss_withheld = gnss_.withheld();
    if (open_anchor_ != kNone) closeAnchor();
    // A last node where the recording goes on after the last fix; a one-sample tail has none
    // (the output integrates it from the last node).
    if (count_ >= layout_.nodes.back().sample_end + kMinIntervalSamples) {
      open_anchor_ = times_.size() - 1;
      closeAnchor();
    }
    layout_.sample_count = count_;
    layout_.complete = true;
  }

 private:
  // The next usable fix after the initial state (those at or before it are skipped).
  const GnssFix* nextFix() {
    const GnssFix* f = gnss_.peek();
    for (; f && !(f->t_s > t0_ + 1e-6); f = gnss_.peek()) gnss_.pop();
    return f;
  }

  // `fix` on the sample times_[pos] or the one before it, whichever ends nearer; dropped when
  // that sample does not cover it (an IMU gap at the fix). No interval may hold fewer than
  // kMinIntervalSamples samples, so a fix that would put its node closer than that to the open
  // anchor shares the anchor's node, and one that would put it that close to the last node
  // (the initial state's, before the first fix) goes on the first sample far enough from it,
  // with its own time offset either way. Returns false, placing nothing, when that sample has
  // not come yet.
  bool placeFix(const GnssFix& fix, size_t pos) {
    const double t = fix.t_s;
    if (times_[pos].index > layout_.first_sample &&
        std::abs(times_[pos - 1].t_s - t) < std::abs(times_[pos].t_s - t)) {
      --pos;
    }
    if (std::abs(times_[pos].t_s - t) > times_[pos].dt_s) return true;
    if (open_anchor_ != kNone) {
      if (times_[pos].index < times_[open_anchor_].index + kMinIntervalSamples) {
        pos = open_anchor_;
      } else {
        const size_t index = times_[pos].index;
        closeAnchor();
        pos = positionOf(index);
      }
    } else {
      const size_t earliest = layout_.nodes.back().sample_end + kMinIntervalSamples - 1;
      if (times_[pos].index < earliest) {
        if (times_.back().index < earliest) return false;
        pos = positionOf(earliest);
      }
    }
    open_anchor_ = pos;
    anchor_fixes_.push_back(layout_.fixCount());
    layout_.fixes.push_back(observe(fix, t - times_[pos].t_s));
    return true;
  }

  // The fix in the local frame, whitened.
  GnssObservation observe(const GnssFix& f, double dt_s) const {
    GnssObservation obs;
    obs.fix = f;
    obs.z_w = frame_.toLocal(f.pos);
    const Eigen::Vector3d std_ned = f.std_ned_m.cwiseMax(options_.gnss_min_std_m);
    const Eigen::Matrix3d C_wn = frame_.C_nw(f.pos).transpose();
    const Eigen::Matrix3d cov_w = C_wn * std_ned.cwiseAbs2().asDiagonal() * C_wn.transpose();
    obs.sqrt_info_w =
        Eigen::LLT<Eigen::Matrix3d>(cov_w).matrixL().solve(Eigen::Matrix3d::Identity());
    obs.dt_s = dt_s;
    return obs;
  }

  size_t positionOf(size_t index) const { return index - times_.front().index; }

  // Nodes every max_node_spacing_s between the last node and the open anchor, then the anchor
  // with its fixes; keeps the sample times from the sample before the anchor on.
  void closeAnchor() {
    std::deque<GraphNode>& nodes = layout_.nodes;
    const SampleTime a = times_[open_anchor_];
    const double t_prev = nodes.back().t_s;
    const int n_sub = static_cast<int>(std::ceil((a.t_s - t_prev) / spacing_s_ - 0.25));
    for (int m = 1; m < n_sub; ++m) {
      const SampleTime s = nearest(t_prev + (a.t_s - t_prev) * m / n_sub);
      if (s.index + 1 >= nodes.back().sample_end + kMinIntervalSamples &&
          s.index + kMinIntervalSamples <= a.index) {
        GraphNode n;
        n.t_s = s.t_s;
        n.sample_end = s.index + 1;
        nodes.push_back(n);
      }
    }
    if (a.index + 1 < nodes.back().sample_end + kMinIntervalSamples) {
      throw std::logic_error("LayoutBuilder: anchor at t=" + std::to_string(a.t_s) +
                             " too close to the node before it");
    }
    GraphNode n;
    n.t_s = a.t_s;
    n.sample_end = a.index + 1;
    n.gnss = anchor_fixes_;
    nodes.push_back(n);
    anchor_fixes_.clear();
    const size_t keep = open_anchor_ > 0 ? open_anchor_ - 1 : 0;
    times_.erase(times_.begin(), times_.begin() + static_cast<std::ptrdiff_t>(keep));
    open_anchor_ = kNone;
  }

  // The held sample whose end is nearest t (the first at or after t, or the one before it).
  SampleTime nearest(double t) const {
    auto it = std::lower_bound(times_.begin(), times_.end(), t,
                               [](const SampleTime& s, double tt) { return s.t_s < tt; });
    if (it == times_.end()) --it;
    if (it->index > layout_.first_sample) {
      if (it == times_.begin())
        throw std::logic_error("LayoutBuilder: sample before the held times");
      if (std::abs((it - 1)->t_s - t) < std::abs(it->t_s - t)) --it;
    }
    return *it;
  }

  UsableGnss gnss_;  // the problem's fixes in time order, outages withheld
  const LocalFrame& frame_;
  const FgoOptions& options_;
  const double t0_;
  const double spacing_s_;  // largest interval between nodes (nodeSpacing)
  NodeLayout& layout_;
  size_t count_ = 0;                  // samples seen
  std::vector<SampleTime> times_;     // from the sample before the last node on
  size_t open_anchor_ = kNone;        // position in times_ of the newest fixes' sample
  std::vector<size_t> anchor_fixes_;  // their fix numbers
};

const GraphNode& NodeLayout::node(std::size_t k) const {
  if (k < nodes_base || k >= nodeCount()) {
    throw std::out_of_range("NodeLayout: node " + std::to_string(k) + " not held (held [" +
                            std::to_string(nodes_base) + ", " + std::to_string(nodeCount()) + "))");
  }
  return nodes[k - nodes_base];
}

const GnssObservation& NodeLayout::fix(std::size_t i) const {
  if (i < fixes_base || i >= fixCount()) {
    throw std::out_of_range("NodeLayout: fix " + std::to_string(i) + " not held (held [" +
                            std::to_string(fixes_base) + ", " + std::to_string(fixCount()) + "))");
  }
  return fixes[i - fixes_base];
}

void NodeLayout::forgetBefore(std::size_t k) {
  k = std::min(k, nodeCount() > 0 ? nodeCount() - 1 : 0);
  std::size_t fixes_end = fixes_base;  // one past the last fix on a forgotten node
  for (; nodes_base < k; ++nodes_base) {
    if (!nodes.front().gnss.empty()) fixes_end = std::max(fixes_end, nodes.front().gnss.back() + 1);
    nodes.pop_front();
  }
  for (; fixes_base < fixes_end && !fixes.empty(); ++fixes_base) fixes.pop_front();
}

NodeLayoutBuilder::NodeLayoutBuilder(const EstimationProblem& problem, const LocalFrame& frame,
                                     const FgoOptions& options, NodeLayout* layout)
    : impl_(std::make_unique<Impl>(problem, frame, options, layout)) {}

NodeLayoutBuilder::~NodeLayoutBuilder() = default;

void NodeLayoutBuilder::add(const ImuSample& s) { impl_->add(s); }

void NodeLayoutBuilder::finish() { impl_->finish(); }

NodeLayout buildNodeLayout(const EstimationProblem& problem, const LocalFrame& frame,
                           const FgoOptions& options, const ImuPassFn& imu) {
  NodeLayout layout;
  NodeLayoutBuilder builder(problem, frame, options, &layout);
  imu([&](const ImuSeries& block) {
    for (const ImuSample& s : block) builder.add(s);
  });
  builder.finish();
  return layout;
}

}  // namespace graftnav
