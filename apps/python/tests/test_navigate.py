"""navigate: the statistics equal `graftnav navigate`'s errors.json, the arrays are complete,
decimation, options, threads."""
import threading
import unittest

import numpy as np

import graftnav
from support import NAVIGATE_CONFIG, SAMPLES, cli_navigate, numbers_differ


class NavigateMatchesCli(unittest.TestCase):
    """Same case, IMU, estimator and run config: statistics to 1e-12."""

    def check(self, sample, estimator, imu):
        case = graftnav.load_case(SAMPLES[sample])
        py = graftnav.navigate(case, estimator, run_config=NAVIGATE_CONFIG, imu=imu)
        cli = cli_navigate(SAMPLES[sample], estimator, imu)
        self.assertIsNone(numbers_differ(py.statistics, cli, 1e-12))
        # The outage statistics exist (the run config has outages), so the comparison means something.
        self.assertGreater(py.statistics["outages"]["count"], 0)
        self.assertIsNotNone(py.statistics["outage"]["horizontal_m"])
        return py

    def test_ekf_tested_mems(self):
        self.check("mems", "ekf", "tested")

    def test_ekf_tested_tactical(self):
        self.check("tactical", "ekf", "tested")

    def test_rts_reference_mems(self):
        self.check("mems", "rts", "ref")

    def test_fgo_tested_mems(self):
        self.check("mems", "fgo", "tested")


class NavigateArrays(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.case = graftnav.load_case(SAMPLES["tactical"])

    def test_solution_and_imu_errors(self):
        r = graftnav.navigate(self.case, "ekf", run_config=NAVIGATE_CONFIG, imu="tested")
        imu = self.case.imu("tested")
        self.assertEqual(len(r.solution), len(imu))  # one state per IMU epoch
        for name in ("t_s", "lat_deg", "lon_deg", "height_m", "v_n_m_s", "roll_deg",
                     "heading_deg", "pos_std_n_m", "att_std_d_deg"):
            self.assertIn(name, r.solution.dtype.names)
        self.assertTrue(np.all(np.isfinite(r.solution["pos_std_n_m"])))
        self.assertTrue(np.all((r.solution["heading_deg"] >= 0) & (r.solution["heading_deg"] < 360)))
        self.assertEqual(len(r.imu_errors), len(r.solution))
        # The tactical tested IMU's gyro bias is deg/h-level: the EKF's estimate is finite and small.
        self.assertLess(np.max(np.abs(r.imu_errors["gyro_bias_x_deg_h"])), 100.0)
        self.assertGreater(r.gnss["used"], 0)
        self.assertEqual(len(r.outage_windows_s), r.statistics["outages"]["count"])

    def test_output_rate_decimates_arrays_not_statistics(self):
        full = graftnav.navigate(self.case, "ekf", run_config=NAVIGATE_CONFIG, imu="tested")
        one_hz = graftnav.navigate(self.case, "ekf", run_config=NAVIGATE_CONFIG, imu="tested",
                                   output_rate_hz=1.0)
        span = full.solution["t_s"][-1] - full.solution["t_s"][0]
        self.assertLessEqual(abs(len(one_hz.solution) - (span + 1)), 1)
        self.assertTrue(np.all(np.diff(one_hz.solution["t_s"]) > 0.999))
        self.assertEqual(one_hz.statistics, full.statistics)
        self.assertEqual(len(one_hz.imu_errors), len(one_hz.solution))

    def test_options_change_the_run(self):
        base = graftnav.navigate(self.case, "ekf", run_config=NAVIGATE_CONFIG, imu="tested")
        nested = graftnav.navigate(self.case, "ekf", run_config=NAVIGATE_CONFIG, imu="tested",
                                   options={"ekf": {"gnss_std_floor_m": 0.5}})
        dotted = graftnav.navigate(self.case, "ekf", run_config=NAVIGATE_CONFIG, imu="tested",
                                   options={"ekf.gnss_std_floor_m": 0.5})
        self.assertEqual(nested.statistics, dotted.statistics)
        self.assertNotEqual(nested.statistics["overall"], base.statistics["overall"])
        # Outages from options alone, without a run-config file.
        no_file = graftnav.navigate(self.case, "ekf", imu="tested",
                                    options={"outages": {"length_s": 30, "period_s": 120}})
        self.assertGreater(no_file.statistics["outages"]["count"], 0)
        self.assertEqual(no_file.statistics["outages"]["length_s"], 30)

    def test_default_imu_is_the_reference(self):
        r = graftnav.navigate(self.case, "ekf", run_config=NAVIGATE_CONFIG)
        self.assertEqual(r.imu, "ref")
        self.assertEqual(self.case.default_imu, "ref")


class NavigateThreads(unittest.TestCase):
    def test_two_threads_give_the_sequential_results(self):
        """The GIL is released while C++ runs; concurrent runs must not share state."""
        case = graftnav.load_case(SAMPLES["mems"])
        runs = [("ekf", "tested"), ("rts", "ref")]
        sequential = [graftnav.navigate(case, e, run_config=NAVIGATE_CONFIG, imu=i).statistics
                      for e, i in runs]
        parallel = [None, None]

        def work(k):
            e, i = runs[k]
            parallel[k] = graftnav.navigate(case, e, run_config=NAVIGATE_CONFIG, imu=i).statistics

        threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        self.assertEqual(parallel, sequential)


if __name__ == "__main__":
    unittest.main()
