"""results(path): a batch results database (docs/batch.md, "The results database") as tables.

With pandas installed each table is a pandas.DataFrame; without it, a list of sqlite3.Row
(indexable by column name). A database of another schema version is refused, as the batch
refuses it.
"""
import os
import sqlite3

SCHEMA_VERSION = 2
TABLES = ("meta", "tasks", "runs", "statistics", "outages", "predictive_intervals", "effects",
          "cross_checks")


class Results:
    """The tables of one results database: attributes named like the tables (r.statistics),
    r.table(name) for any table, r.tables for the names present."""

    def __init__(self, path, tables, frames):
        self.path = path
        self.tables = tables
        self._frames = frames
        for name, value in frames.items():
            setattr(self, name, value)

    def table(self, name):
        if name not in self._frames:
            raise KeyError(f"{self.path}: no table '{name}' (tables: {', '.join(self.tables)})")
        return self._frames[name]

    def __repr__(self):
        return f"<graftnav.Results {self.path}: {', '.join(self.tables)}>"


def results(path, use_pandas=None):
    """Opens a batch results database (results.sqlite or a task.sqlite) read-only.

    use_pandas: None: DataFrames when pandas imports, else sqlite3 rows; False: rows always.
    FileNotFoundError names a missing path; ValueError a database of another schema version.
    """
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(2, f"batch results database '{path}' not found", path)
    pd = None
    if use_pandas is not False:
        try:
            import pandas as pd
        except ImportError:
            if use_pandas:
                raise
    con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        con.row_factory = sqlite3.Row
        names = [r[0] for r in con.execute(
            "SELECT name FROM sqlite_master WHERE type='table' ORDER BY name")]
        if "meta" not in names:
            raise ValueError(f"'{path}' is not a batch results database (no meta table)")
        meta = {r["key"]: r["value"] for r in con.execute("SELECT key, value FROM meta")}
        version = meta.get("schema_version")
        if str(version) != str(SCHEMA_VERSION):
            raise ValueError(f"'{path}' is a batch results database of schema version {version}; "
                             f"this graftnav reads version {SCHEMA_VERSION}")
        tables = [t for t in TABLES if t in names] + [t for t in names if t not in TABLES]
        frames = {}
        for t in tables:
            query = f'SELECT * FROM "{t}"'
            frames[t] = pd.read_sql_query(query, con) if pd else con.execute(query).fetchall()
        return Results(path, tables, frames)
    finally:
        con.close()
