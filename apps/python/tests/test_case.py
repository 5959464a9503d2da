"""load_case and Case.from_arrays: the arrays of a loaded case, and a case built from the same
data navigates to the same statistics."""
import os
import unittest

import numpy as np

import graftnav
from support import NAVIGATE_CONFIG, SAMPLES, numbers_differ


def field(sample, name):
    return os.path.join(SAMPLES[sample], "field", name)


class LoadCase(unittest.TestCase):
    def test_arrays_equal_the_files(self):
        case = graftnav.load_case(SAMPLES["mems"])
        self.assertEqual(case.name, "sample_mems")
        self.assertEqual(case.dir, SAMPLES["mems"])
        text = np.loadtxt(field("mems", "tested_imu.txt"))
        imu = case.imu("tested")
        self.assertEqual(len(imu), len(text))
        np.testing.assert_array_equal(imu["t_s"], text[:, 0])
        np.testing.assert_array_equal(imu["dvel_z_m_s"], text[:, 6])
        np.testing.assert_allclose(imu["dt_s"][1:], np.diff(text[:, 0]), rtol=0, atol=0)
        self.assertEqual(imu["dt_s"][0], 1.0 / case.imu_rate_hz)
        gnss = case.gnss()
        np.testing.assert_allclose(gnss["lat_deg"], np.loadtxt(field("mems", "gnss.pos"))[:, 1],
                                   rtol=0, atol=1e-12)
        truth = case.reference()
        self.assertEqual(truth["gnss_week"][0], 2100)
        self.assertTrue(case.has_imu("ref") and case.has_imu("tested"))


class FromArrays(unittest.TestCase):
    def test_from_file_columns_equals_load_case(self):
        """np.loadtxt of the case's files -> the same doubles -> the same statistics, exactly."""
        for sample in ("mems", "tactical"):
            with self.subTest(sample=sample):
                loaded = graftnav.load_case(SAMPLES[sample])
                built = graftnav.Case.from_arrays(
                    imu=np.loadtxt(field(sample, "ref_imu.txt")),
                    tested_imu=np.loadtxt(field(sample, "tested_imu.txt")),
                    gnss=np.loadtxt(field(sample, "gnss.pos")),
                    truth=np.loadtxt(field(sample, "truth.nav")),
                    config=os.path.join(SAMPLES[sample], "case.yaml"))
                self.assertIsNone(built.dir)
                for imu in ("ref", "tested"):
                    a = graftnav.navigate(loaded, "ekf", run_config=NAVIGATE_CONFIG, imu=imu)
                    b = graftnav.navigate(built, "ekf", run_config=NAVIGATE_CONFIG, imu=imu)
                    self.assertIsNone(numbers_differ(a.statistics, b.statistics, 0.0))
                    np.testing.assert_array_equal(a.solution, b.solution)

    def test_from_structured_arrays_and_a_config_dict(self):
        """The loaded case's own arrays (degrees, round trip) and case.yaml as a dict."""
        import yaml  # Debian's python3-yaml
        loaded = graftnav.load_case(SAMPLES["tactical"])
        with open(os.path.join(SAMPLES["tactical"], "case.yaml")) as f:
            config = yaml.safe_load(f)
        imu = loaded.imu("tested")
        imu_no_dt = imu[[n for n in imu.dtype.names if n not in ("dt_s", "temperature_degC")]]
        built = graftnav.Case.from_arrays(imu=loaded.imu("ref"), tested_imu=imu_no_dt,
                                          gnss=loaded.gnss(), truth=loaded.reference(),
                                          config=config)
        np.testing.assert_array_equal(built.imu("tested")["dt_s"], imu["dt_s"])
        a = graftnav.navigate(loaded, "ekf", run_config=NAVIGATE_CONFIG, imu="tested")
        b = graftnav.navigate(built, "ekf", run_config=NAVIGATE_CONFIG, imu="tested")
        # Degrees -> radians -> degrees moves a coordinate by an ulp or so: millimetres at most.
        self.assertIsNone(numbers_differ(a.statistics, b.statistics, 1e-6))

    def test_one_imu_without_truth(self):
        loaded = graftnav.load_case(SAMPLES["mems"])
        built = graftnav.Case.from_arrays(imu=loaded.imu("tested"), gnss=loaded.gnss(),
                                          config={"name": "one", "imu_rate_hz": 50,
                                                  "reference_imu": {"grade": "mems",
                                                                    "arw_deg_rt_h": 0.15,
                                                                    "vrw_m_s_rt_h": 0.06,
                                                                    "gyro_bias_instability_deg_h": 10,
                                                                    "accel_bias_instability_mg": 1},
                                                  "lever_arm_m": [0.1, -0.2, -1.2],
                                                  "gnss": {"week": 2100}})
        self.assertEqual(built.default_imu, "ref")
        self.assertFalse(built.has_imu("tested"))
        with self.assertRaises(RuntimeError):  # no initial state: no truth, no case.yaml state
            graftnav.navigate(built, "ekf")
        # A MEMS gyro cannot gyrocompass (the library says so); in-motion alignment from GNSS.
        with self.assertRaises(RuntimeError):
            graftnav.navigate(built, "ekf", options={"ekf": {"alignment": "static"}})
        aligned = graftnav.navigate(built, "ekf", options={"ekf": {"alignment": "motion"}})
        self.assertIsNone(aligned.statistics)  # nothing to compare with
        self.assertGreater(len(aligned.solution), 0)

    def test_odometer_array_aids_the_outages(self):
        """An odometer built from the truth's speed narrows the outage drift of the MEMS IMU."""
        loaded = graftnav.load_case(SAMPLES["mems"])
        truth = loaded.reference()
        odometer = np.empty(len(truth), dtype=[("t_s", "f8"), ("speed_m_s", "f8")])
        odometer["t_s"] = truth["t_s"]
        odometer["speed_m_s"] = np.hypot(truth["v_n_m_s"], truth["v_e_m_s"])
        import yaml  # Debian's python3-yaml
        with open(os.path.join(SAMPLES["mems"], "case.yaml")) as f:
            config = yaml.safe_load(f)
        config["reference_imu"] = config["tested_imu"]  # the tested IMU is the case's one IMU
        built = graftnav.Case.from_arrays(imu=loaded.imu("tested"), gnss=loaded.gnss(),
                                          truth=truth, odometer=odometer, config=config)
        free = graftnav.navigate(loaded, "ekf", run_config=NAVIGATE_CONFIG, imu="tested")
        aided = graftnav.navigate(built, "ekf", run_config=NAVIGATE_CONFIG,
                                  options={"odometer": {"enabled": True}})
        self.assertTrue(any("odometer from the array" in n for n in aided.notes))
        self.assertLess(aided.statistics["outage"]["horizontal_m"],
                        0.5 * free.statistics["outage"]["horizontal_m"])
        no_odometer = graftnav.Case.from_arrays(imu=loaded.imu("tested"), gnss=loaded.gnss(),
                                                config=os.path.join(SAMPLES["mems"], "case.yaml"))
        with self.assertRaises(ValueError):
            graftnav.navigate(no_odometer, "ekf", options={"odometer": {"enabled": True}})
        # The file reader's speed rule holds for arrays: a reversing sample is refused while
        # the run config says forward only, and accepted when it allows reversing.
        reversing = odometer.copy()
        reversing["speed_m_s"][100] = -0.5
        backing = graftnav.Case.from_arrays(imu=loaded.imu("tested"), gnss=loaded.gnss(),
                                            truth=truth, odometer=reversing, config=config)
        with self.assertRaisesRegex(ValueError, "odometer row 100: speed -0.5 m/s is negative"):
            graftnav.navigate(backing, "ekf", run_config=NAVIGATE_CONFIG,
                              options={"odometer": {"enabled": True}})
        allowed = graftnav.navigate(backing, "ekf", run_config=NAVIGATE_CONFIG,
                                    options={"odometer": {"enabled": True, "forward_only": False}})
        self.assertLess(allowed.statistics["outage"]["horizontal_m"],
                        0.5 * free.statistics["outage"]["horizontal_m"])

    def test_bad_arrays(self):
        loaded = graftnav.load_case(SAMPLES["mems"])
        imu = loaded.imu("ref")
        with self.assertRaises(ValueError):
            graftnav.Case.from_arrays(imu=imu[::-1], gnss=loaded.gnss(),
                                      config=os.path.join(SAMPLES["mems"], "case.yaml"))
        with self.assertRaises(ValueError):
            graftnav.Case.from_arrays(imu=np.zeros((10, 5)), gnss=loaded.gnss())


if __name__ == "__main__":
    unittest.main()
