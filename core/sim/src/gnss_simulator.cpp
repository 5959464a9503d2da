#include "graftnav/sim/gnss_simulator.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/imu/gauss_markov.h"
#include "graftnav/sim/sampling_grid.h"

namespace graftnav {

void GnssSimOptions::validate() const {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) {
    throw std::invalid_argument("GnssSimOptions: rate_hz must be > 0, got " +
                                std::to_string(rate_hz));
  }
  if (!lever_arm_b_m.allFinite()) throw std::invalid_argument("GnssSimOptions: lever_arm_b_m");
  if (!(noise_std_neu_m.minCoeff() > 0.0) || !noise_std_neu_m.allFinite()) {
    throw std::invalid_argument(
        "GnssSimOptions: noise_std_neu_m must be > 0 (it is written as "
        "the std columns of the .pos file)");
  }
}

Geodetic antennaPosition(const Geodetic& pos, const Eigen::Matrix3d& C_nb,
                         const Eigen::Vector3d& lever_arm_b_m) {
  return earth::geodeticFromNed(pos, C_nb * lever_arm_b_m);
}

GnssSeries simulateGnss(const Trajectory& trj, double t_begin_s, double t_end_s,
                        const GnssSimOptions& opt, uint64_t seed) {
  opt.validate();
  StandardNormalSampler rng(deriveStreamSeed(seed, 101));
  GnssSeries out;
  for (const double t : uniformEpochs_s(t_begin_s, t_end_s, opt.rate_hz)) {
    const TrajectoryPoint p = trj.at(t);
    Eigen::Vector3d offset_n = p.C_nb * opt.lever_arm_b_m;
    if (opt.add_noise) {
      const Eigen::Vector3d z = rng.next3();
      offset_n += Eigen::Vector3d(opt.noise_std_neu_m.x() * z.x(), opt.noise_std_neu_m.y() * z.y(),
                                  -opt.noise_std_neu_m.z() * z.z());
    }
    GnssFix f;
    f.t_s = t;
    f.pos = earth::geodeticFromNed(p.pos, offset_n);
    f.std_ned_m = opt.noise_std_neu_m;
    f.fix_type = opt.fix_type;
    f.num_sv = 0;
    out.push_back(f);
  }
  return out;
}

}  // namespace graftnav
