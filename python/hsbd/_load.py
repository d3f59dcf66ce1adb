"""Reading run directories: hsbd.load(DIR) -> Run, each table a Table of named columns.

A table of hsbd is text: '#' lines (the first says what the table is, then one
'# section.key = value' line per parameter of the run), the column names (on a line of
their own, or on the last '#' line), then rows of numbers separated by tabs. Both forms
of the column-name line are read.
"""
import json
import os
import re
from collections.abc import Mapping

import numpy as np

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.+\-]*$")
_PARAMETER = re.compile(r"^([a-z_]+\.[A-Za-z_0-9]+) = ?(.*)$")


def _column_names(line):
    """The names on a line, or None when it is not a line of column names."""
    words = line.split()
    return words if words and all(_NAME.match(w) for w in words) else None


class Table(Mapping):
    """One table of a run: its columns by name (``t["rho"]``, numpy arrays), in order
    (``t.names``), all of them as one array (``t.data``, rows x columns), what it is
    (``t.title``), the run's parameters it was written with (``t.params``,
    ``{"system.N": "50", ...}`` as text) and its file (``t.path``)."""

    def __init__(self, path):
        self.path = os.fspath(path)
        self.name = os.path.basename(self.path).removesuffix(".tsv")
        with open(self.path) as f:
            lines = f.read().splitlines()
        header, k = [], 0
        while k < len(lines) and lines[k].startswith("#"):
            header.append(lines[k][1:].strip())
            k += 1
        names = _column_names(lines[k]) if k < len(lines) and lines[k][:1].isalpha() else None
        if names is not None:
            k += 1  # the names on a line of their own
        elif header and _column_names(header[-1]) and " = " not in header[-1]:
            names = header.pop().split()  # the names on the last '#' line
        rows = [ln for ln in lines[k:] if ln.strip()]
        if rows:
            self.data = np.loadtxt(rows, ndmin=2)
        else:
            self.data = np.empty((0, len(names or [])))
        if names is None or len(names) != self.data.shape[1]:
            raise ValueError(f"{self.path}: not a table of hsbd (column names "
                             f"{names} for {self.data.shape[1]} columns)")
        self.names = names
        self.title = ""
        if header and header[0].startswith("hsbd "):
            self.title = header[0].split(": ", 1)[-1]
        self.params = {}
        for h in header:
            m = _PARAMETER.match(h)
            if m:
                self.params[m.group(1)] = m.group(2).strip()

    def __getitem__(self, name):
        try:
            return self.data[:, self.names.index(name)]
        except ValueError:
            raise KeyError(f"{name!r}: the columns of {self.name} are "
                           f"{', '.join(self.names)}") from None

    def __iter__(self):
        return iter(self.names)

    def __len__(self):
        return len(self.names)

    def __repr__(self):
        return f"<hsbd.Table {self.name}: {len(self.data)} rows of {', '.join(self.names)}>"


class Run(Mapping):
    """A run directory read by ``hsbd.load``: ``summary`` (summary.json as a dict; {} when
    the run wrote none yet), ``parameters`` (the configuration as run, by section),
    ``tables`` (each table by its file's name without .tsv: ``run["density"]``,
    ``run["msd"]``, ...), ``blocks`` (the per-block estimates behind the error bars,
    X_blocks.tsv as ``run.blocks["X"]``: a column x, then one per block or, for an
    ensemble, per replica), ``replicas`` (an ensemble's replica-k directories, each a
    Run) and ``path``. The Run itself maps table names to tables."""

    def __init__(self, path):
        self.path = os.fspath(path)
        if os.path.isfile(self.path):
            raise NotADirectoryError(f"{self.path}: a file; hsbd.load reads a run directory")
        if not os.path.isdir(self.path):
            raise FileNotFoundError(f"{self.path}: no such run directory")
        names = sorted(os.listdir(self.path))
        self.summary = {}
        summary = os.path.join(self.path, "summary.json")
        if os.path.exists(summary):
            with open(summary) as f:
                self.summary = json.load(f)
        self.tables, self.blocks = {}, {}
        for name in names:
            if not name.endswith(".tsv"):
                continue  # temporary files (*.part) and everything else
            table = Table(os.path.join(self.path, name))
            if table.name.endswith("_blocks"):
                self.blocks[table.name.removesuffix("_blocks")] = table
            else:
                self.tables[table.name] = table
        replicas = [n for n in names if re.fullmatch(r"replica-\d+", n)]
        self.replicas = [Run(os.path.join(self.path, n))
                         for n in sorted(replicas, key=lambda n: int(n.split("-")[1]))]
        if not self.summary and not self.tables and not self.replicas:
            raise ValueError(f"{self.path}: not a run directory of hsbd (no summary.json, "
                             "no tables)")

    @property
    def parameters(self):
        return self.summary.get("parameters", {})

    @property
    def model(self):
        """'rods' or 'spheres' (disks too)."""
        return self.summary.get("model") or self.parameters.get("system", {}).get("model")

    def __getitem__(self, name):
        try:
            return self.tables[name]
        except KeyError:
            raise KeyError(f"{name!r}: the tables of {self.path} are "
                           f"{', '.join(self.tables) or 'none'}") from None

    def __iter__(self):
        return iter(self.tables)

    def __len__(self):
        return len(self.tables)

    def __repr__(self):
        done = self.summary.get("completed")
        state = "completed" if done else "not completed" if done is False else "no summary"
        return (f"<hsbd.Run {self.path}: {self.model}, {state}; tables "
                f"{', '.join(self.tables) or 'none'}>")


def load(path):
    """Read a run directory written by ``hsbd run`` or ``hsbd.run`` (also an ensemble's,
    with its replicas) as a ``Run``: ``load(d).summary["Z_virial"]``,
    ``load(d)["density"]["rho"]``, ``load(d).blocks["density"]``."""
    return Run(path)
