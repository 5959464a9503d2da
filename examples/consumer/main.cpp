// Links the installed graftnav libraries: writes a two-sample IMU file with the io module, reads
// it back, and checks a rotation round trip of the nav module. Exit 0 when both agree.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "graftnav/io/imu_io.h"
#include "graftnav/nav/rotation.h"

int main() {
  graftnav::ImuSeries imu(2);
  for (int k = 0; k < 2; ++k) {
    imu[k].t_s = 100.0 + 0.01 * (k + 1);
    imu[k].dt_s = 0.01;
    imu[k].dvel_m_s.z() = -0.0981;
  }
  const std::string path =
      (std::filesystem::temp_directory_path() / "graftnav_consumer_imu.txt").string();
  graftnav::writeImu(path, imu);
  const graftnav::ImuSeries back = graftnav::readImu(path);
  const Eigen::Vector3d euler(0.1, -0.2, 2.0);
  const Eigen::Vector3d again = graftnav::eulerFromQuat(graftnav::quatFromEuler(euler));
  const bool ok = back.size() == 2 && std::abs(back[1].dvel_m_s.z() + 0.0981) < 1e-12 &&
                  (again - euler).norm() < 1e-12;
  std::printf("graftnav consumer: %zu IMU samples read back, rotation round trip %s\n", back.size(),
              ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
