#include "graftnav/io/nav_spool.h"

#include <algorithm>
#include <array>
#include <vector>

#include "graftnav/io/record_spool.h"

namespace graftnav {
namespace {

constexpr std::size_t kNavDoubles = 12;  // t, lat, lon, h, v_n (3), q_nb (w, x, y, z), week
constexpr std::size_t kBlock = 2048;

std::array<double, kNavDoubles> toRecord(const NavState& s) {
  return {s.t_s,      s.pos.lat_rad, s.pos.lon_rad, s.pos.h_m,
          s.v_n.x(),  s.v_n.y(),     s.v_n.z(),     s.q_nb.w(),
          s.q_nb.x(), s.q_nb.y(),    s.q_nb.z(),    static_cast<double>(s.gnss_week)};
}

NavState fromRecord(const double* r) {
  NavState s;
  s.t_s = r[0];
  s.pos.lat_rad = r[1];
  s.pos.lon_rad = r[2];
  s.pos.h_m = r[3];
  s.v_n = {r[4], r[5], r[6]};
  s.q_nb = Eigen::Quaterniond(r[7], r[8], r[9], r[10]);
  s.gnss_week = static_cast<int>(r[11]);
  return s;
}

// One pass over the spool, read in blocks.
class SpoolNavSource final : public NavSource {
 public:
  explicit SpoolNavSource(std::shared_ptr<const RecordSpool> spool)
      : pass_(std::move(spool), kBlock) {}
  bool next(NavState* state) override {
    const double* r = pass_.next();
    if (r == nullptr) return false;
    *state = fromRecord(r);
    return true;
  }

 private:
  RecordPass pass_;
};

}  // namespace

NavSpool::NavSpool(const std::string& directory)
    : spool_(std::make_shared<RecordSpool>(kNavDoubles, directory)) {}

void NavSpool::add(const NavState& state) {
  if (spool_->size() == 0) first_ = state;
  last_ = state;
  spool_->append(toRecord(state).data());
}

void NavSpool::finish() { spool_->finish(); }

std::size_t NavSpool::size() const { return spool_->size(); }

double NavSpool::rateHz() const {
  const double span = last_.t_s - first_.t_s;
  return size() > 1 && span > 0.0 ? static_cast<double>(size() - 1) / span : 0.0;
}

NavOpenFn NavSpool::opener() const {
  std::shared_ptr<const RecordSpool> spool = spool_;
  return
      [spool]() -> std::unique_ptr<NavSource> { return std::make_unique<SpoolNavSource>(spool); };
}

NavSpool spoolNav(NavSource& source) {
  NavSpool spool;
  NavState s;
  while (source.next(&s)) spool.add(s);
  spool.finish();
  return spool;
}

}  // namespace graftnav
