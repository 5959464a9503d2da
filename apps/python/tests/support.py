"""Paths and helpers shared by the Python module's tests (run by CTest from the build tree)."""
import json
import math
import os
import subprocess
import tempfile

SOURCE_DIR = os.environ.get("GRAFTNAV_SOURCE_DIR",
                            os.path.abspath(os.path.join(os.path.dirname(__file__), "../../..")))
BINARY = os.environ.get("GRAFTNAV_BINARY", os.path.join(SOURCE_DIR, "build", "graftnav"))
SAMPLES = {name: os.path.join(SOURCE_DIR, "data", "sample_" + name) for name in ("mems", "tactical")}
NAVIGATE_CONFIG = os.path.join(SOURCE_DIR, "configs", "navigate.yaml")


def run_cli(*args):
    """Runs the graftnav binary; returns (exit code, stdout, stderr)."""
    p = subprocess.run([BINARY, *args], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def cli_navigate(case_dir, estimator, imu, run_config=NAVIGATE_CONFIG):
    """errors.json of `graftnav navigate` for one estimator and IMU."""
    with tempfile.TemporaryDirectory() as out:
        args = ["navigate", case_dir, "--out", out, "--estimator", estimator, "--imu", imu,
                "--no-plots"]
        if run_config:
            args += ["--run-config", run_config]
        code, _, err = run_cli(*args)
        if code != 0:
            raise AssertionError(f"graftnav {' '.join(args)} failed ({code}): {err}")
        with open(os.path.join(out, "errors.json")) as f:
            return json.load(f)


def numbers_differ(a, b, tol, path=""):
    """The first place where two JSON-like values differ by more than tol (absolute), or None."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return f"{path}: keys {sorted(a)} != {sorted(b)}"
        for k in a:
            d = numbers_differ(a[k], b[k], tol, f"{path}/{k}")
            if d:
                return d
        return None
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if math.isfinite(a) and math.isfinite(b) and abs(a - b) <= tol:
            return None
        return f"{path}: {a!r} != {b!r} (tolerance {tol})"
    return None if a == b else f"{path}: {a!r} != {b!r}"
