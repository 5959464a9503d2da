"""simulate: the same files as `graftnav simulate`; a case in a temporary folder lives as long as
the Case object."""
import filecmp
import gc
import os
import tempfile
import unittest

import graftnav
from support import SOURCE_DIR, run_cli

SIM_CONFIG = os.path.join(SOURCE_DIR, "configs", "sim", "sample_tactical.yaml")


class Simulate(unittest.TestCase):
    def test_same_files_as_the_cli(self):
        with tempfile.TemporaryDirectory() as tmp:
            py_dir, cli_dir = os.path.join(tmp, "py"), os.path.join(tmp, "cli")
            case = graftnav.simulate(SIM_CONFIG, seed=5, out=py_dir)
            code, _, err = run_cli("simulate", "--sim-config", SIM_CONFIG, "--out", cli_dir,
                                   "--seed", "5")
            self.assertEqual(code, 0, err)
            self.assertEqual(case.dir, py_dir)
            for f in ("case.yaml", "field/ref_imu.txt", "field/tested_imu.txt", "field/gnss.pos",
                      "field/truth.nav", "lab/static.txt"):
                self.assertTrue(filecmp.cmp(os.path.join(py_dir, f), os.path.join(cli_dir, f),
                                            shallow=False), f)

    def test_in_memory_case_and_seed(self):
        a = graftnav.simulate(SIM_CONFIG, seed=5)
        b = graftnav.simulate(SIM_CONFIG, seed=6)
        folder = a.dir
        self.assertTrue(os.path.isdir(folder))
        self.assertFalse((a.imu("tested")["dtheta_x_rad"] == b.imu("tested")["dtheta_x_rad"]).all())
        r = graftnav.navigate(a, "ekf", imu="tested", output_rate_hz=1)
        self.assertIsNotNone(r.statistics["overall"]["horizontal_rms_m"])
        del a, r
        gc.collect()
        self.assertFalse(os.path.exists(folder))  # the temporary folder went with the case

    def test_missing_sim_config(self):
        with self.assertRaises(FileNotFoundError):
            graftnav.simulate(os.path.join(tempfile.gettempdir(), "graftnav-no-such-sim.yaml"))


if __name__ == "__main__":
    unittest.main()
