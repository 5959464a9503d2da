#include "graftnav/estimation/gnss_source.h"

#include <stdexcept>
#include <string>

#include "graftnav/estimation/usable_gnss.h"

namespace graftnav {
namespace {

class SeriesGnssSource final : public GnssSource {
 public:
  explicit SeriesGnssSource(const GnssSeries& fixes) : fixes_(fixes) {}
  bool next(GnssFix* fix) override {
    if (i_ >= fixes_.size()) return false;
    *fix = fixes_[i_++];
    return true;
  }

 private:
  const GnssSeries& fixes_;
  std::size_t i_ = 0;
};

}  // namespace

std::unique_ptr<GnssSource> seriesGnssSource(const GnssSeries& fixes) {
  return std::make_unique<SeriesGnssSource>(fixes);
}

UsableGnss::UsableGnss(const EstimationProblem& problem)
    : problem_(problem),
      source_(problem.gnss_stream ? problem.gnss_stream() : seriesGnssSource(problem.gnss)) {
  if (!source_) throw std::invalid_argument("UsableGnss: the problem's GNSS stream opened nothing");
}

const GnssFix* UsableGnss::peek() {
  while (!has_ && !ended_) {
    if (!source_->next(&fix_)) {
      ended_ = true;
      break;
    }
    if (any_ && fix_.t_s < t_prev_) {
      throw std::invalid_argument("GNSS fixes out of time order: t=" + std::to_string(fix_.t_s) +
                                  " after t=" + std::to_string(t_prev_));
    }
    any_ = true;
    t_prev_ = fix_.t_s;
    bool inside = false;
    for (const TimeWindow& w : problem_.outages) {
      if (w.contains(fix_.t_s)) {
        inside = true;
        break;
      }
    }
    if (inside) {
      ++withheld_;
    } else {
      has_ = true;
    }
  }
  return has_ ? &fix_ : nullptr;
}

void UsableGnss::skipRest() {
  while (peek()) pop();
}

}  // namespace graftnav
