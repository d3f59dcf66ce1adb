"""What the plotting tools share: reading hsbd's tables ('#' header lines, of which
'# section.key = value' give the run's parameters and the last, '# ' and tab-separated
names, the columns; then rows of numbers; older tables had the names without '#') and
writing a figure atomically."""
import os
from collections import namedtuple

import numpy as np

Table = namedtuple("Table", "params names data")


def read_table(path):
    """The table at path as (params dict, column names or None, data array)."""
    params, names, rows = {}, None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                if " = " in line:
                    k, v = line[1:].split(" = ", 1)
                    params[k.strip()] = v.strip()
                elif "\t" in line and not rows:
                    names = line[1:].split()
                continue
            if not rows and names is None and line[:1].isalpha():
                names = line.split()
                continue
            if line.strip():
                rows.append([float(x) for x in line.split()])
    return Table(params, names, np.array(rows))


def save_figure(fig, out, dpi=110):
    """Write fig to out under a temporary name, then rename (never a half-written PNG)."""
    tmp = out + ".part.png"
    fig.savefig(tmp, dpi=dpi)
    os.replace(tmp, out)
    print(f"plot: {out}")
