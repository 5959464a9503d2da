"""diagnose: the finder's report equals `graftnav diagnose`'s diagnosis.json."""
import json
import os
import tempfile
import unittest

import graftnav
from support import SAMPLES, numbers_differ, run_cli


class DiagnoseMatchesCli(unittest.TestCase):
    def test_same_report(self):
        case = graftnav.load_case(SAMPLES["tactical"])
        py = graftnav.diagnose(case)
        with tempfile.TemporaryDirectory() as out:
            code, _, err = run_cli("diagnose", SAMPLES["tactical"], "--out", out, "--no-plots")
            self.assertEqual(code, 0, err)
            with open(os.path.join(out, "diagnosis.json")) as f:
                cli = json.load(f)
        for key in ("located", "effects", "unexplained", "fit"):
            self.assertIn(key, py)
        self.assertIsInstance(py["warnings"], list)
        del py["warnings"]
        self.assertIsNone(numbers_differ(py, cli, 1e-12))

    def test_arrays_case_is_refused(self):
        case = graftnav.load_case(SAMPLES["tactical"])
        built = graftnav.Case.from_arrays(imu=case.imu("ref"), gnss=case.gnss(),
                                          tested_imu=case.imu("tested"))
        with self.assertRaises(ValueError):
            graftnav.diagnose(built)


if __name__ == "__main__":
    unittest.main()
