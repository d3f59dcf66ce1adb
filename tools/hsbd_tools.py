"""What the plotting tools share: the package hsbd (installed, or the build's
build/python), reading hsbd's tables ('#' header lines, of which '# section.key = value'
give the run's parameters, the column names on a line of their own or on the last '#'
line, then rows of numbers) and writing a figure atomically."""
import os
import sys
from collections import namedtuple

import numpy as np

Table = namedtuple("Table", "params names data")


def read_table(path):
    """The table at path as (params dict, column names or None, data array)."""
    params, names, rows, last = {}, None, [], ""
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                if " = " in line:
                    k, v = line[1:].split(" = ", 1)
                    params[k.strip()] = v.strip()
                last = line[1:].strip()
                continue
            if not rows and names is None and last[:1].isalpha() and " = " not in last \
                    and len(last.split()) == len(line.split()):
                names = last.split()  # the names on the last '#' line
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


def import_hsbd():
    """The package hsbd: installed (pip install .), else the build's (build/python)."""
    try:
        import hsbd
    except ImportError:
        here = os.path.dirname(os.path.abspath(__file__))
        sys.path.insert(0, os.path.join(here, "..", "build", "python"))
        try:
            import hsbd
        except ImportError:
            sys.exit("the Python package hsbd is neither installed nor built: make build "
                     "(build/python), or pip install . (docs/python.md)")
    return hsbd


def load_run(tool, run_dir, refusal):
    """The package and the run in run_dir, or exit with tool's message when the run cannot
    be read or refusal(hsbd, run) names why it is not the tool's kind of run."""
    hsbd = import_hsbd()
    try:
        run = hsbd.load(run_dir)
    except (OSError, ValueError) as e:
        sys.exit(f"{tool}: {e}")
    why = refusal(hsbd, run)
    if why:
        sys.exit(f"{tool}: {run_dir} {why}")
    return hsbd, run
