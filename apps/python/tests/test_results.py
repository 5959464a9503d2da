"""results: a batch results database (schema version 2) as DataFrames or sqlite3 rows."""
import os
import sqlite3
import tempfile
import unittest

import graftnav
from support import NAVIGATE_CONFIG, SAMPLES, run_cli


def has_pandas():
    try:
        import pandas  # noqa: F401
        return True
    except ImportError:
        return False


class Results(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        manifest = os.path.join(cls.tmp.name, "m.yaml")
        with open(manifest, "w") as f:
            f.write(f"out: out\njobs: 1\ngroups:\n  - command: navigate\n"
                    f"    cases: [{SAMPLES['tactical']}]\n    estimators: [ekf]\n"
                    f"    run_config: {NAVIGATE_CONFIG}\n    flags: {{imu: tested}}\n")
        code, _, err = run_cli("batch", manifest)
        if code != 0:
            raise AssertionError(f"graftnav batch failed ({code}): {err}")
        cls.db = os.path.join(cls.tmp.name, "out", "results.sqlite")

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def expected_overall(self):
        case = graftnav.load_case(SAMPLES["tactical"])
        return graftnav.navigate(case, "ekf", run_config=NAVIGATE_CONFIG, imu="tested").statistics

    @unittest.skipUnless(has_pandas(), "python3-pandas not installed")
    def test_dataframes(self):
        r = graftnav.results(self.db)
        for t in ("meta", "tasks", "runs", "statistics", "outages"):
            self.assertIn(t, r.tables)
        self.assertEqual(list(r.runs["status"]), ["ok"])
        s = r.statistics
        row = s[(s.scope == "overall") & (s.statistic == "horizontal_m") & (s.measure == "rms")]
        self.assertEqual(len(row), 1)
        expected = self.expected_overall()["overall"]["horizontal_rms_m"]
        self.assertAlmostEqual(float(row.value.iloc[0]), expected, delta=1e-9 * expected)
        self.assertEqual(len(r.outages), self.expected_overall()["outages"]["count"])

    def test_rows_without_pandas(self):
        r = graftnav.results(self.db, use_pandas=False)
        self.assertIsInstance(r.statistics, list)
        self.assertIsInstance(r.statistics[0], sqlite3.Row)
        names = {(x["scope"], x["statistic"], x["measure"]) for x in r.statistics}
        self.assertIn(("outage", "horizontal_m", "rms"), names)
        self.assertEqual(r.table("tasks")[0]["estimator"], "ekf")
        with self.assertRaises(KeyError):
            r.table("no_such_table")

    def test_other_schema_version_is_refused(self):
        old = os.path.join(self.tmp.name, "v1.sqlite")
        con = sqlite3.connect(old)
        con.execute("CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL)")
        con.execute("INSERT INTO meta VALUES ('schema_version', '1')")
        con.commit()
        con.close()
        with self.assertRaises(ValueError) as raised:
            graftnav.results(old)
        self.assertIn("schema version 1", str(raised.exception))


if __name__ == "__main__":
    unittest.main()
