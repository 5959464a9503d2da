"""numpy structured arrays <-> the 2-D float64 arrays of the compiled module.

The column names (units in the names, angles in degrees) come from the compiled module, so the
two sides cannot disagree on the layout.
"""
import numpy as np

from . import _graftnav as _c

# Columns stored as integers in the structured arrays.
_INTEGER_COLUMNS = {"gnss_week", "fix_type", "num_sv"}

# A plain 2-D array in a file's column layout (dataset.md): which columns it holds, in order.
_FILE_LAYOUTS = {
    "imu": {7: ["t_s", "dtheta_x_rad", "dtheta_y_rad", "dtheta_z_rad", "dvel_x_m_s", "dvel_y_m_s",
                "dvel_z_m_s"]},
    "gnss": {7: ["t_s", "lat_deg", "lon_deg", "height_m", "std_n_m", "std_e_m", "std_d_m"]},
    "nav": {11: list(_c.NAV_COLUMNS)},
    "odometer": {2: list(_c.ODOMETER_COLUMNS)},
}
_FILE_LAYOUTS["imu"][8] = _FILE_LAYOUTS["imu"][7] + ["temperature_degC"]

_COLUMNS = {"imu": _c.IMU_COLUMNS, "gnss": _c.GNSS_COLUMNS, "nav": _c.NAV_COLUMNS,
            "odometer": _c.ODOMETER_COLUMNS}


def structured(table, columns):
    """A 2-D float array whose columns are `columns` -> a structured array with those fields."""
    table = np.asarray(table, dtype=np.float64)
    dtype = [(n, np.int64 if n in _INTEGER_COLUMNS else np.float64) for n in columns]
    out = np.empty(table.shape[0], dtype=dtype)
    for k, name in enumerate(columns):
        out[name] = table[:, k]
    return out


def canonical(array, kind, name):
    """A structured array (fields by name) or a plain 2-D array in the file's column layout ->
    the compiled module's 2-D layout for `kind` ('imu', 'gnss', 'nav'), NaN where absent."""
    columns = _COLUMNS[kind]
    a = np.asarray(array)
    if a.dtype.names:
        fields = {n: a[n] for n in a.dtype.names}
        missing_required = [n for n in columns if n not in fields and not _optional(kind, n)]
        if missing_required:
            raise ValueError(f"{name}: missing field(s) {', '.join(missing_required)} "
                             f"(fields: {', '.join(columns)})")
        unknown = [n for n in a.dtype.names if n not in columns]
        if unknown:
            raise ValueError(f"{name}: unknown field(s) {', '.join(unknown)} "
                             f"(fields: {', '.join(columns)})")
    else:
        if a.ndim != 2 or a.shape[1] not in _FILE_LAYOUTS[kind]:
            raise ValueError(f"{name}: expected a structured array or a 2-D array with "
                             f"{' or '.join(str(n) for n in _FILE_LAYOUTS[kind])} columns "
                             f"(the file layout), got shape {a.shape}")
        layout = _FILE_LAYOUTS[kind][a.shape[1]]
        fields = {n: a[:, k] for k, n in enumerate(layout)}
    out = np.full((len(a), len(columns)), np.nan)
    for k, n in enumerate(columns):
        if n in fields:
            out[:, k] = np.asarray(fields[n], dtype=np.float64)
    return out


def _optional(kind, column):
    return (kind, column) in {("imu", "dt_s"), ("imu", "temperature_degC"), ("gnss", "fix_type"),
                              ("gnss", "num_sv"), ("nav", "gnss_week")}
