#!/usr/bin/env python3
"""The Python package against the command line on the same work (BENCHMARKS.md, "Python").

    .venv/bin/python scripts/bench_python.py [--collisions 100000] [--season FILE] [--rows N|0] [--runs N]
        [--skip-simulate] [--bin SWEETSPOT]

1. `sweetspot.simulate` of N collisions from numpy arrays (impact points spread over the barrel) against
   `sweetspot simulate --case` of the same N impact points (one case file, --json to /dev/null).
2. `sweetspot.locate` of a Statcast DataFrame (the first N rows of the season file, 0: all) against
   `sweetspot import` + `sweetspot locate --json` of the same rows as a CSV, in N alternating runs.
Build both in release first (`maturin develop --release`, `cargo build --release`); prints wall times and ratios.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

import sweetspot

REPO = Path(__file__).resolve().parents[1]
SEASON = REPO / "../shared/reference/statcast/statcast_2024_in_play_bat_tracking.csv.gz"


def timed(work):
    start = time.perf_counter()
    result = work()
    return time.perf_counter() - start, result


def run(binary, *args, stdout=subprocess.DEVNULL):
    subprocess.run([str(binary), *map(str, args)], check=True, stdout=stdout)


def bench_simulate(binary, n, scratch):
    zs = np.linspace(0.45, 0.83, n)
    bat, ball = sweetspot.Bat.preset("r161"), sweetspot.Ball.preset("mlb2024")
    python, frame = timed(lambda: sweetspot.simulate(bat, ball, ball_speed=40.0, bat_cm_speed=25.0,
                                                     bat_angular_speed=45.0, impact_z=zs))
    case = Path(scratch, "case.json")
    case.write_text(json.dumps({"bat": "r161", "ball": "mlb2024", "ball_speed": 40.0, "bat_cm_speed": 25.0,
                                "bat_angular_speed": 45.0, "impact_z": zs.tolist()}))
    out = Path(scratch, "simulate.json")
    with out.open("w") as f:
        cli, _ = timed(lambda: run(binary, "simulate", "--case", case, "--json", stdout=f))
    document = json.loads(out.read_text())
    same = [r["exit_speed"] for r in document["results"]] == frame["exit_speed"].tolist()
    print(f"simulate, {n} collisions: python {python:.2f} s, CLI {cli:.2f} s, python/CLI {python / cli:.3f} "
          f"(cores {os.cpu_count()}; exit speeds identical: {same})")


def bench_locate(binary, season, rows, runs, scratch):
    frame = pd.read_csv(season, nrows=rows or None)
    csv = Path(scratch, "season.csv")
    frame.to_csv(csv, index=False)
    totals = {"python": 0.0, "import": 0.0, "locate": 0.0}
    for run_no in range(1, runs + 1):
        python, located = timed(lambda: sweetspot.locate(frame))
        bag = Path(scratch, f"bag{run_no}")
        imported, _ = timed(lambda: run(binary, "import", csv, "-o", bag))
        out = Path(scratch, "located.json")
        with out.open("w") as f:
            cli, _ = timed(lambda: run(binary, "locate", bag, "--json", stdout=f))
        document = json.loads(out.read_text())
        same = len(document["swings"]) == len(located) and all(
            (s.get("solutions") or [{}])[0].get("impact_z", float("nan")) == z
            or (np.isnan(z) and not s.get("solutions"))
            for s, z in zip(document["swings"], located["impact_z"]))
        for key, value in (("python", python), ("import", imported), ("locate", cli)):
            totals[key] += value
        total = imported + cli
        print(f"locate run {run_no}, {len(frame)} Statcast rows ({len(located)} swings): python {python:.2f} s, "
              f"CLI import {imported:.2f} s + locate {cli:.2f} s = {total:.2f} s, python/CLI {python / total:.3f} "
              f"(python/locate alone {python / cli:.3f}; impact points identical: {same}; "
              f"load {os.getloadavg()[0]:.1f})", flush=True)
    cli_total = totals["import"] + totals["locate"]
    print(f"locate, {runs} alternating runs summed: python {totals['python']:.2f} s, CLI {cli_total:.2f} s, "
          f"python/CLI {totals['python'] / cli_total:.3f}, "
          f"python/locate alone {totals['python'] / totals['locate']:.3f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--collisions", type=int, default=100_000)
    parser.add_argument("--season", type=Path, default=Path(os.environ.get("SWEETSPOT_STATCAST", SEASON)))
    parser.add_argument("--rows", type=int, default=2000, help="rows of the season file (0: all)")
    parser.add_argument("--runs", type=int, default=1, help="alternating runs of the locate comparison")
    parser.add_argument("--skip-simulate", action="store_true")
    parser.add_argument("--bin", type=Path, default=REPO / "target/release/sweetspot")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        if not args.skip_simulate:
            bench_simulate(args.bin, args.collisions, scratch)
        if args.season.is_file():
            bench_locate(args.bin, args.season, args.rows, args.runs, scratch)
        else:
            print(f"locate skipped: {args.season} is absent", file=sys.stderr)


if __name__ == "__main__":
    main()
