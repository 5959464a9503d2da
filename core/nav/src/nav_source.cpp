#include "graftnav/nav/nav_source.h"

namespace graftnav {

namespace {
class SeriesNavSource final : public NavSource {
 public:
  explicit SeriesNavSource(const NavSeries& series) : series_(series) {}
  bool next(NavState* state) override {
    if (i_ >= series_.size()) return false;
    *state = series_[i_++];
    return true;
  }

 private:
  const NavSeries& series_;
  std::size_t i_ = 0;
};
}  // namespace

std::unique_ptr<NavSource> seriesNavSource(const NavSeries& series) {
  return std::make_unique<SeriesNavSource>(series);
}

}  // namespace graftnav
