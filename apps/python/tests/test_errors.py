"""Errors: a bad option raises ValueError with the CLI's validation text; a missing file raises
FileNotFoundError naming the path."""
import os
import tempfile
import unittest

import graftnav
from support import NAVIGATE_CONFIG, SAMPLES, run_cli


def cli_error(case_dir, run_config_text):
    """The CLI's message for a run config holding run_config_text (after its 'file:line: ')."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "bad.yaml")
        with open(path, "w") as f:
            f.write(run_config_text)
        code, _, err = run_cli("navigate", case_dir, "--out", os.path.join(tmp, "out"),
                               "--run-config", path, "--no-plots")
    assert code != 0, "the CLI accepted a bad run config"
    line = next(l for l in err.splitlines() if "error: " in l).split("error: ", 1)[1]
    if path in line:  # a value read from the file: the message after 'path:line: '
        line = line.split(path, 1)[1].split(": ", 1)[1]
    return line


class BadOptions(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.case = graftnav.load_case(SAMPLES["mems"])

    def check_same_message(self, options, yaml_text):
        with self.assertRaises(ValueError) as raised:
            graftnav.navigate(self.case, "ekf", imu="tested", options=options)
        expected = cli_error(SAMPLES["mems"], yaml_text)
        self.assertIn(expected, str(raised.exception))

    def test_invalid_value_gives_the_validate_text(self):
        self.check_same_message({"ekf": {"gnss_std_scale": -1.0}}, "ekf:\n  gnss_std_scale: -1.0\n")
        with self.assertRaises(ValueError) as raised:
            graftnav.navigate(self.case, "ekf", options={"ekf": {"gnss_std_scale": -1.0}})
        self.assertTrue(str(raised.exception).startswith("options: "), str(raised.exception))

    def test_invalid_value_dotted(self):
        self.check_same_message({"outages.length_s": -5}, "outages:\n  length_s: -5\n")

    def test_wrong_type(self):
        self.check_same_message({"ekf": {"gate_probability": "high"}},
                                "ekf:\n  gate_probability: high\n")

    def test_unknown_key_is_an_error(self):
        with self.assertRaises(ValueError) as raised:
            graftnav.navigate(self.case, "ekf", imu="tested", options={"ekf": {"gnss_floor": 1}})
        self.assertIn("ekf.gnss_floor", str(raised.exception))

    def test_unknown_estimator(self):
        with self.assertRaises(ValueError) as raised:
            graftnav.navigate(self.case, "ukf")
        self.assertIn("ukf", str(raised.exception))
        self.assertIn("ekf", str(raised.exception))  # names the known ones

    def test_bad_output_rate_and_imu(self):
        with self.assertRaises(ValueError):
            graftnav.navigate(self.case, "ekf", output_rate_hz=0)
        with self.assertRaises(ValueError):
            graftnav.navigate(self.case, "ekf", imu="lab")


class TimeRangeNotApplied(unittest.TestCase):
    """evaluate and diagnose do not apply a time range: one in the run config or the options is
    refused before they start, naming the key, the call and where it was set."""

    def test_evaluate_and_diagnose_refuse_a_time_range(self):
        case = graftnav.load_case(SAMPLES["mems"])
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "ranged.yaml")
            with open(path, "w") as f:
                f.write("time_range: {start_s: 456400, end_s: 456600}\n")
            calls = {"graftnav.evaluate": lambda: graftnav.evaluate(case, "ekf", run_config=path),
                     "graftnav.diagnose": lambda: graftnav.diagnose(case, run_config=path)}
            for name, call in calls.items():
                with self.assertRaises(ValueError) as raised:
                    call()
                self.assertIn(f"time_range is not applied by {name}: the run config '{path}' sets "
                              "time_range (start_s 456400, end_s 456600)", str(raised.exception))
        with self.assertRaises(ValueError) as raised:
            graftnav.evaluate(case, "ekf", options={"time_range.end_s": 456600})
        self.assertIn("time_range is not applied by graftnav.evaluate: the run config 'options' "
                      "sets time_range (end_s 456600)", str(raised.exception))


class MissingFiles(unittest.TestCase):
    def test_missing_case_folder(self):
        path = os.path.join(tempfile.gettempdir(), "graftnav-no-such-case")
        with self.assertRaises(FileNotFoundError) as raised:
            graftnav.load_case(path)
        self.assertIn(path, str(raised.exception))
        self.assertEqual(raised.exception.filename, path)

    def test_missing_run_config(self):
        case = graftnav.load_case(SAMPLES["mems"])
        path = os.path.join(tempfile.gettempdir(), "graftnav-no-such-run.yaml")
        with self.assertRaises(FileNotFoundError) as raised:
            graftnav.navigate(case, "ekf", run_config=path)
        self.assertEqual(raised.exception.filename, path)

    def test_case_without_its_gnss_file(self):
        with tempfile.TemporaryDirectory() as tmp:
            with open(os.path.join(SAMPLES["mems"], "case.yaml")) as f:
                text = f.read()
            with open(os.path.join(tmp, "case.yaml"), "w") as f:
                f.write(text)
            with self.assertRaises(FileNotFoundError) as raised:
                graftnav.load_case(tmp)
            self.assertEqual(raised.exception.filename, os.path.join(tmp, "field", "gnss.pos"))

    def test_missing_results_database(self):
        with self.assertRaises(FileNotFoundError):
            graftnav.results(os.path.join(tempfile.gettempdir(), "graftnav-no-such.sqlite"))


if __name__ == "__main__":
    unittest.main()
