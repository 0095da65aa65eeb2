#!/usr/bin/env python3
"""Where `sweetspot.locate(DataFrame)` spends its time, phase by phase, against the command line's `locate` of
the same rows done in the same process (BENCHMARKS.md, "Python package").

    .venv/bin/python scripts/locate_phases.py [--season FILE] [--rows N|0] [--runs N] [--bin SWEETSPOT]

The first N rows of the season file (0: all; docs/locate-season.md makes it) are read with pandas (not timed)
and imported once with `sweetspot import` into a bag (any build of the command line: the bag is the same).
Then, alternating in each run:

- the DataFrame path, by phase: the frame's columns taken out (`export`, Python), the extension's call
  (`native`: the columns copied, written as the export's CSV, imported, located and turned into the answer's
  columns, the GIL released), the DataFrame built (`frame`);
- the bag path's native call (`bag`): the bag read, located and its `--json` document written, which is
  `sweetspot locate BAG --json`'s work without the process.

Each phase's wall time, the CPU time of the process over it (cores used = CPU / wall) and the load average are
printed; the summary gives DataFrame / bag, summed over the runs. Build the extension in release first
(`maturin develop --release`).
"""

import argparse
import os
import resource
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

import sweetspot
from sweetspot import _native

REPO = Path(__file__).resolve().parents[1]


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


class Clock:
    """Wall and CPU time of named phases."""

    def __init__(self):
        self.wall, self.cpu = {}, {}

    def time(self, name, work):
        wall, cpu = time.perf_counter(), cpu_seconds()
        result = work()
        self.wall[name] = time.perf_counter() - wall
        self.cpu[name] = cpu_seconds() - cpu
        return result

    def line(self, names):
        return ", ".join(f"{n} {self.wall[n]:.3f} s ({self.cpu[n] / max(self.wall[n], 1e-9):.2f} cores)"
                         for n in names)


def frame_path(clock, frame):
    bat = sweetspot.Bat.preset("r161")
    columns = clock.time("export", lambda: sweetspot._export_columns(frame))
    counts, located, lines = clock.time("native", lambda: _native.locate_export(
        columns, bat=bat._native, bat_spec="r161", ball="mlb2024"))
    answer = clock.time("frame", lambda: sweetspot._locate_frame(located, index=frame.index[lines.astype(np.int64) - 2]))
    clock.wall["dataframe"] = sum(clock.wall[n] for n in ("export", "native", "frame"))
    clock.cpu["dataframe"] = sum(clock.cpu[n] for n in ("export", "native", "frame"))
    return answer


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--season", type=Path, default=Path("/tmp/season2024_aa.csv"))
    parser.add_argument("--rows", type=int, default=10_000, help="rows of the season file (0: all)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--bin", type=Path, default=REPO / "target/debug/sweetspot")
    args = parser.parse_args()
    frame = pd.read_csv(args.season, nrows=args.rows or None)
    totals = {"dataframe": 0.0, "bag": 0.0}
    cpu = {"dataframe": 0.0, "bag": 0.0}
    with tempfile.TemporaryDirectory() as scratch:
        csv, bag = Path(scratch, "season.csv"), Path(scratch, "bag")
        frame.to_csv(csv, index=False)
        subprocess.run([str(args.bin), "import", str(csv), "-o", str(bag)], check=True, stdout=subprocess.DEVNULL)
        for run in range(1, args.runs + 1):
            clock = Clock()
            answer = frame_path(clock, frame)
            text, from_bag = clock.time("bag", lambda: _native.locate_bag(str(bag)))
            same = np.array_equal(answer["impact_z"].to_numpy(), from_bag["impact_z"], equal_nan=True)
            for key in totals:
                totals[key] += clock.wall[key]
                cpu[key] += clock.cpu[key]
            print(f"run {run}, {len(frame)} rows ({len(answer)} swings): "
                  f"{clock.line(['export', 'native', 'frame', 'dataframe', 'bag'])}; "
                  f"dataframe/bag {clock.wall['dataframe'] / clock.wall['bag']:.3f}; impact points identical: {same}; "
                  f"load {os.getloadavg()[0]:.1f}", flush=True)
    print(f"{args.runs} runs summed: dataframe {totals['dataframe']:.2f} s, bag {totals['bag']:.2f} s, "
          f"dataframe/bag {totals['dataframe'] / totals['bag']:.3f}; CPU dataframe {cpu['dataframe']:.2f} s, "
          f"bag {cpu['bag']:.2f} s, dataframe/bag {cpu['dataframe'] / cpu['bag']:.3f}")


if __name__ == "__main__":
    main()
