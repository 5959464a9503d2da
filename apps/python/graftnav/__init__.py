"""graftnav from Python: load or build a case, navigate it with any estimator, run the SG
evaluation and the mismatch finder, simulate a case, read a batch results database.

numpy arrays come in and go out (structured arrays, units in the field names, angles in
degrees); no file round trip is needed. Calls that run C++ release the GIL, so calls from
several threads run in parallel. docs/python.md shows a whole study.
"""
import json as _json
from dataclasses import dataclass, field
from typing import Optional

import numpy as _np

from . import _graftnav as _c
from ._arrays import canonical as _canonical, structured as _structured
from .results import results  # noqa: F401  (re-exported)

__all__ = ["Case", "NavigationResult", "EvaluationResult", "load_case", "navigate", "evaluate",
           "diagnose", "simulate", "results"]


class Case:
    """A case: case.yaml's content, GNSS, truth or reference solution, and its IMUs.

    Made by load_case(path), Case.from_arrays(...) or simulate(...)."""

    def __init__(self, impl):
        self._impl = impl

    @classmethod
    def from_arrays(cls, imu, gnss, truth=None, tested_imu=None, odometer=None, config=None):
        """A case from arrays, without a folder.

        imu, tested_imu: structured arrays with fields t_s, dtheta_{x,y,z}_rad, dvel_{x,y,z}_m_s
            and optionally dt_s and temperature_degC, or 2-D arrays in the IMU file's 7 or 8
            columns (the 8th: temperature). `imu` is the reference IMU (the case's one IMU).
        gnss: fields t_s, lat_deg, lon_deg, height_m, std_{n,e,d}_m [, fix_type, num_sv], or
            gnss.pos's 7 columns.
        truth: fields [gnss_week,] t_s, lat_deg, lon_deg, height_m, v_{n,e,d}_m_s, roll_deg,
            pitch_deg, heading_deg, or a .nav file's 11 columns.
        odometer: fields t_s, speed_m_s (forward speed at the odometer), or field/odometer.txt's
            2 columns; used when the run config turns the odometer on (odometer.enabled).
        config: case.yaml's content: a path, a dict of its keys, or None (then the IMU has no
            noise parameters and only free-inertial navigation runs).
        """
        to = lambda a, kind, name: None if a is None else _canonical(a, kind, name)
        return cls(_c.from_arrays(to(imu, "imu", "imu"), to(gnss, "gnss", "gnss"),
                                  to(truth, "nav", "truth"), to(tested_imu, "imu", "tested_imu"),
                                  to(odometer, "odometer", "odometer"), config))

    name = property(lambda self: self._impl.name, doc="case.yaml's name")
    dir = property(lambda self: self._impl.dir, doc="the case folder (None: built from arrays)")
    imu_rate_hz = property(lambda self: self._impl.imu_rate_hz)
    warnings = property(lambda self: list(self._impl.warnings), doc="from reading the case")
    default_imu = property(lambda self: self._impl.default_imu,
                           doc="the IMU navigate uses by default: the case's one IMU, else 'ref'")

    def has_imu(self, which):
        """Whether the case has the 'ref' or 'tested' IMU."""
        return self._impl.has_imu(which)

    def imu(self, which="ref"):
        """The 'ref' or 'tested' IMU samples (structured array, IMU_COLUMNS)."""
        return _structured(self._impl.imu(which), _c.IMU_COLUMNS)

    def gnss(self):
        """The GNSS fixes (structured array, GNSS_COLUMNS)."""
        return _structured(self._impl.gnss(), _c.GNSS_COLUMNS)

    def reference(self):
        """The truth or reference solution (NAV_COLUMNS), None when the case has none."""
        r = self._impl.reference()
        return None if r is None else _structured(r, _c.NAV_COLUMNS)

    def __repr__(self):
        where = self.dir if self.dir is not None else "arrays"
        return f"<graftnav.Case {self.name!r} ({where})>"


def load_case(path) -> Case:
    """Reads a case folder (case.yaml, field/, lab/). FileNotFoundError when it is missing."""
    return Case(_c.load_case(str(path)))


@dataclass
class NavigationResult:
    """What navigate returns.

    solution: time, position, velocity, attitude (and the 1-sigma columns *_std_* when the
        estimator gives them), decimated to output_rate_hz when given.
    imu_errors: estimated gyro and accelerometer biases and scale factors at the same epochs
        (None when the estimator estimates none).
    statistics: errors.json's content (same names; None when the case has no truth or
        reference solution; a statistic that could not be computed is None).
    """
    estimator: str
    imu: str
    solution: _np.ndarray
    imu_errors: Optional[_np.ndarray]
    statistics: Optional[dict]
    reference: str
    gnss: dict
    outage_windows_s: list
    notes: list = field(default_factory=list)
    warnings: list = field(default_factory=list)


def navigate(case, estimator="ekf", run_config=None, imu=None, options=None,
             output_rate_hz=None) -> NavigationResult:
    """Navigates one IMU of the case with one estimator, as `graftnav navigate` does.

    estimator: ekf, rts, fgo, fgo-window, free-inertial.
    run_config: a run-config file (configs/navigate.yaml); None: the case's run.yaml if any.
    imu: 'ref' or 'tested'; None: the case's one IMU, else the reference.
    options: run-config sections over the run config, nested ({"ekf": {"gnss_std_floor_m":
        0.02}}) or dotted ({"ekf.gnss_std_floor_m": 0.02}). A bad value or an unknown key raises
        ValueError with the message the CLI prints.
    output_rate_hz: decimates the returned arrays (statistics always use every epoch).
    """
    if output_rate_hz is not None and not output_rate_hz > 0:
        raise ValueError(f"output_rate_hz must be > 0, got {output_rate_hz}")
    d = _c.navigate(case._impl, estimator, imu or "", "" if run_config is None else str(run_config),
                    options, 0.0 if output_rate_hz is None else float(output_rate_hz))
    solution_columns = list(_c.NAV_COLUMNS)
    if d["solution"].shape[1] > len(solution_columns):
        solution_columns += list(_c.SIGMA_COLUMNS)
    errors = d["imu_errors"]
    return NavigationResult(
        estimator=d["estimator"], imu=d["imu"],
        solution=_structured(d["solution"], solution_columns),
        imu_errors=_structured(errors, _c.IMU_ERROR_COLUMNS) if errors.shape[0] else None,
        statistics=None if d["statistics_json"] is None else _json.loads(d["statistics_json"]),
        reference=d["reference"], gnss=dict(d["gnss"]),
        outage_windows_s=[tuple(w) for w in d["outage_windows_s"]],
        notes=list(d["notes"]), warnings=list(d["warnings"]))


@dataclass
class EvaluationResult:
    """What evaluate returns.

    evaluation: evaluation.json's content (err, diff, predictive intervals, outages, notes).
    per_realization: per SG solution ('SG1', 'SG2') a structured array with one row per grafted
        realization: its ERR (horizontal_m, vertical_m, roll_deg, pitch_deg, heading_deg; RMS
        over the outage epochs, mean over the outage schedules).
    """
    evaluation: dict
    per_realization: dict
    warnings: list = field(default_factory=list)


def evaluate(case, estimator="ekf", realizations=None, seed=1, options=None, run_config=None,
             jobs=0) -> EvaluationResult:
    """The SG evaluation of a case folder, as `graftnav evaluate` (same seed: same numbers).

    realizations: K grafted realizations per strategy; None: the run config's
        grafting.realizations (20). seed: the grafting seed. jobs: navigations in parallel
        (0: all cores). options, run_config: as for navigate.
    """
    d = _c.evaluate(case._impl, estimator, realizations, int(seed),
                    "" if run_config is None else str(run_config), options, int(jobs))
    draws = {label: _structured(a, _c.DRAW_COLUMNS) for label, a in d["draws"].items()}
    return EvaluationResult(evaluation=_json.loads(d["evaluation_json"]), per_realization=draws,
                            warnings=list(d["warnings"]))


def diagnose(case, diagnose_config=None, run_config=None, options=None) -> dict:
    """The mismatch finder on a case folder (`graftnav diagnose` without --estimator): where the
    simulation of the tested IMU and its real recording differ, which physics explains it.

    Returns diagnosis.json's content (located spans, effects with parameters and evidence,
    unexplained spans, fit), plus "warnings". diagnose_config: configs/diagnose.yaml-style file;
    run_config/options: the run config (its grafting section makes SG#2).
    """
    d = _c.diagnose(case._impl, "" if diagnose_config is None else str(diagnose_config),
                    "" if run_config is None else str(run_config), options)
    report = _json.loads(d["diagnosis_json"])
    report["warnings"] = list(d["warnings"])
    return report


def simulate(sim_config, seed=None, out=None, ideal=False) -> Case:
    """A simulated case from a sim config (configs/sim/*.yaml), as `graftnav simulate`.

    seed: None keeps the config's seed. out: the case folder to write; None: a temporary folder
    that is removed when the returned case is garbage-collected.
    """
    c, _warnings = _c.simulate(str(sim_config), seed, "" if out is None else str(out), bool(ideal))
    return Case(c)
