#!/usr/bin/env python3
"""Table of the vehicle-aiding study (scripts/experiments/aiding_table.sh) from its runs.

Usage: scripts/experiments/aiding_table.py OUT_DIR [--out FILE.md] [--inject DOC.md] [--command CMD]

Reads OUT_DIR/runs/<estimator>_{free,aided}/errors.json (outage.horizontal_m: the RMS horizontal
error over the outage epochs), the last line of the aided runs' odometer_scale.txt (estimated
scale and 1-sigma, ppm) and the injected scale of OUT_DIR/case/simulation.yaml. The done-when
ratios: aided / free at most 1/5 for ekf and fgo-window, 1/2 for rts and fgo (whose outages are
already bridged from both sides). --inject replaces the block between "<!-- aiding_table:begin -->"
and "<!-- aiding_table:end -->" of DOC.md, so the page cannot drift from the runs.
"""
import argparse, json, math, os, re, sys

ESTIMATORS = ["ekf", "rts", "fgo", "fgo-window"]
REQUIRED = {"ekf": 0.2, "fgo-window": 0.2, "rts": 0.5, "fgo": 0.5}


def outage_rms(run):
    with open(os.path.join(run, "errors.json")) as f:
        return json.load(f)["outage"]["horizontal_m"]


def last_scale(run):
    """(scale_ppm, std_ppm or None) from the last line of odometer_scale.txt, or None."""
    path = os.path.join(run, "odometer_scale.txt")
    if not os.path.exists(path):
        return None
    last = None
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                last = line.split()
    if last is None:
        return None
    std = float(last[2]) if len(last) > 2 else None
    return float(last[1]), std


def injected_scale_ppm(case_dir):
    with open(os.path.join(case_dir, "simulation.yaml")) as f:
        m = re.search(r"scale_error_ppm:\s*(-?[0-9.eE+-]+)", f.read())
    return float(m.group(1)) if m else None


def noise_limited_scale_ppm(case_dir):
    """(scale_ppm, sigma_ppm): the least-squares scale of the odometer readings against the truth's
    forward speed at the same epochs, and its 1-sigma from the white noise alone
    (noise_std_m_s / sqrt(sum v^2)). No estimator can do better with this noise realization.
    The land drive's odometer sits at the IMU with zero mounting angles, so the truth's forward
    speed is C_bn v_n's first component; None when the case has no such files."""
    truth_path = os.path.join(case_dir, "field", "truth.nav")
    odo_path = os.path.join(case_dir, "field", "odometer.txt")
    with open(os.path.join(case_dir, "simulation.yaml")) as f:
        m = re.search(r"noise_std_m_s:\s*([0-9.eE+-]+)", f.read())
    if not (os.path.exists(truth_path) and os.path.exists(odo_path) and m):
        return None
    forward = {}
    with open(truth_path) as f:
        for line in f:
            c = line.split()
            if len(c) < 11:
                continue
            pitch, yaw = math.radians(float(c[9])), math.radians(float(c[10]))
            vn, ve, vd = float(c[5]), float(c[6]), float(c[7])
            forward[round(float(c[1]) * 1000)] = (math.cos(pitch) * (math.cos(yaw) * vn + math.sin(yaw) * ve)
                                                  - math.sin(pitch) * vd)
    sv = vv = 0.0
    with open(odo_path) as f:
        for line in f:
            c = line.split()
            if len(c) < 2 or line.startswith("#"):
                continue
            v = forward.get(round(float(c[0]) * 1000))
            if v is None or abs(v) < 1e-3:  # no reading noise at standstill
                continue
            sv += float(c[1]) * v
            vv += v * v
    if vv <= 0.0:
        return None
    return (sv / vv - 1.0) * 1e6, float(m.group(1)) / math.sqrt(vv) * 1e6


def wall_time(run):
    try:
        with open(run + ".time") as f:
            return f.read().split()[0]
    except OSError:
        return "-"


def rows(out_dir):
    truth = injected_scale_ppm(os.path.join(out_dir, "case"))
    table = []
    for est in ESTIMATORS:
        free = os.path.join(out_dir, "runs", est + "_free")
        aided = os.path.join(out_dir, "runs", est + "_aided")
        e_free, e_aided = outage_rms(free), outage_rms(aided)
        ratio = e_aided / e_free
        scale = last_scale(aided)
        table.append(dict(est=est, free=e_free, aided=e_aided, ratio=ratio,
                          required=REQUIRED[est], met=ratio <= REQUIRED[est], scale=scale,
                          truth=truth, t_free=wall_time(free), t_aided=wall_time(aided)))
    return table


def scale_cell(r):
    if r["scale"] is None:
        return "-", "-"
    k, sd = r["scale"]
    if sd is None or sd != sd:
        return "%.0f" % k, "- (no sigma)"
    z = abs(k - r["truth"]) / sd if r["truth"] is not None else float("nan")
    return "%.0f +- %.0f" % (k, sd), "%.1f" % z


def markdown(table, command, full, limit=None):
    lines = ["Written by scripts/experiments/aiding_table.py from `%s`." % command, "",
             "| estimator | outage horizontal RMS without aiding (m) | with odometer + NHC (m) | "
             "ratio | required | met | odometer scale (ppm, injected %s) | abs(error) / sigma |"
             % ("%.0f" % table[0]["truth"] if table[0]["truth"] is not None else "?"),
             "|---|---|---|---|---|---|---|---|"]
    for r in table:
        sc, z = scale_cell(r)
        lines.append("| %s | %.3f | %.3f | %.4f | <= %.1f | %s | %s | %s |" % (
            r["est"], r["free"], r["aided"], r["ratio"], r["required"],
            "yes" if r["met"] else "**no**", sc, z))
    if limit is not None:
        lines += ["", "The odometer's readings fitted against the truth's forward speed (what its white noise "
                  "alone allows, the bound on every estimator): %.0f +- %.0f ppm." % limit]
    if full:
        lines += ["", "Wall times on a shared 2-core machine (other jobs running: compare, not benchmark).", "",
                  "| estimator | wall time without aiding (s) | with aiding (s) |", "|---|---|---|"]
        for r in table:
            lines.append("| %s | %s | %s |" % (r["est"], r["t_free"], r["t_aided"]))
    return "\n".join(lines) + "\n"


def inject(doc, text):
    with open(doc) as f:
        s = f.read()
    begin, end = "<!-- aiding_table:begin -->", "<!-- aiding_table:end -->"
    if begin not in s or end not in s:
        sys.exit("aiding_table: %s has no %s ... %s block" % (doc, begin, end))
    s = s[:s.index(begin) + len(begin)] + "\n" + text + s[s.index(end):]
    with open(doc, "w") as f:
        f.write(s)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out_dir")
    ap.add_argument("--out")
    ap.add_argument("--inject")
    ap.add_argument("--command", default="scripts/experiments/aiding_table.sh OUT")
    a = ap.parse_args()
    table = rows(a.out_dir)
    limit = noise_limited_scale_ppm(os.path.join(a.out_dir, "case"))
    text = markdown(table, a.command, full=False, limit=limit)
    sys.stdout.write(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write("# Vehicle aiding on the 25-minute land drive\n\n" +
                    markdown(table, a.command, full=True, limit=limit))
    if a.inject:
        inject(a.inject, text)


if __name__ == "__main__":
    main()
