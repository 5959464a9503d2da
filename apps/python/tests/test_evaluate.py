"""evaluate: the same seed gives `graftnav evaluate`'s evaluation.json; the per-realization
statistics are the ones the ERR is the mean of."""
import json
import os
import tempfile
import unittest

import numpy as np

import graftnav
from support import NAVIGATE_CONFIG, SAMPLES, numbers_differ, run_cli

K = 3  # realizations: enough for a mean and an interval, small for the suite's time
SEED = 7


def cli_evaluation(case_dir):
    with tempfile.TemporaryDirectory() as out:
        code, _, err = run_cli("evaluate", case_dir, "--out", out, "--run-config", NAVIGATE_CONFIG,
                               "--realizations", str(K), "--seed", str(SEED), "--no-plots")
        if code != 0:
            raise AssertionError(f"graftnav evaluate failed ({code}): {err}")
        with open(os.path.join(out, "evaluation.json")) as f:
            return json.load(f)


class EvaluateMatchesCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.case = graftnav.load_case(SAMPLES["mems"])
        cls.py = graftnav.evaluate(cls.case, "ekf", realizations=K, seed=SEED,
                                   run_config=NAVIGATE_CONFIG)
        cls.cli = cli_evaluation(SAMPLES["mems"])

    def test_same_statistics_for_the_same_seed(self):
        for key in ("err", "diff", "err_outage_max", "outages", "outage_windows_s", "reference",
                    "estimator", "case"):
            with self.subTest(key=key):
                self.assertIsNone(numbers_differ(self.py.evaluation[key], self.cli[key], 1e-12))
        # The predictive intervals too (every key the CLI writes besides the notes).
        for key in set(self.cli) - {"notes"}:
            with self.subTest(key=key):
                self.assertIsNone(numbers_differ(self.py.evaluation[key], self.cli[key], 1e-12))

    def test_per_realization_statistics(self):
        for label in ("SG1", "SG2"):
            draws = self.py.per_realization[label]
            self.assertEqual(len(draws), K)
            # ERR_SGx is the mean over the realizations (one outage schedule).
            self.assertAlmostEqual(float(np.mean(draws["horizontal_m"])),
                                   self.py.evaluation["err"][label]["horizontal_m"], delta=1e-12)
            self.assertGreater(np.std(draws["horizontal_m"]), 0.0)  # realizations differ
        self.assertNotIn("REAL", self.py.per_realization)

    def test_another_seed_changes_the_draws(self):
        other = graftnav.evaluate(self.case, "ekf", realizations=K, seed=SEED + 1,
                                  run_config=NAVIGATE_CONFIG)
        self.assertFalse(np.array_equal(other.per_realization["SG1"],
                                        self.py.per_realization["SG1"]))
        self.assertEqual(other.evaluation["err"]["REAL"], self.py.evaluation["err"]["REAL"])

    def test_bad_realizations_and_arrays_case(self):
        with self.assertRaises(ValueError):
            graftnav.evaluate(self.case, realizations=0)
        built = graftnav.Case.from_arrays(imu=self.case.imu("ref"), gnss=self.case.gnss(),
                                          config=os.path.join(SAMPLES["mems"], "case.yaml"))
        with self.assertRaises(ValueError):
            graftnav.evaluate(built)


if __name__ == "__main__":
    unittest.main()
