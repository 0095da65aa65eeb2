#!/usr/bin/env python3
"""Summarise `sweetspot locate --json` on a Statcast season (docs/locate-season.md).

    python3 scripts/locate_season.py attack SEASON.csv ATTACK.csv OUT.csv
    python3 scripts/locate_season.py SEASON.csv BAG LOCATED.json [--exit-sigma-mph 1.0]

`attack` writes SEASON.csv with an `attack_angle` column added (2024 files have none): the median attack angle
of ATTACK.csv (the 2025 sample, ../shared/reference/statcast/batted_balls_attack_angle.csv) in the ball's 5°
launch-angle bin (bins with fewer than 20 balls borrow the next lower bin's).

SEASON.csv is the Savant CSV the bag was imported from (the import's side table, BAG/import_rows.csv, maps each
swing to its line there), LOCATED.json the output of `sweetspot locate BAG --json`. Prints, per 5-mph bin of the
measured bat speed, the share of swings the model reproduces (located: an impact point and undercut give the
measured exit speed and launch angle; or faster than the model's best by less than two exit-speed
uncertainties; or missed by the closest impact point and undercut with χ² ≤ 4), and the largest groups it cannot reproduce (verdict × launch angle × exit speed). Only derived
counts are printed: no raw rows.
"""

import argparse
import collections
import csv
import json
import math
import re
import statistics
import sys

MPH = 0.44704


def add_attack_angle(season, attack, out):
    by = collections.defaultdict(list)
    with open(attack, newline="") as f:
        for r in csv.DictReader(f):
            try:
                by[5 * math.floor(float(r["launch_angle"]) / 5)].append(float(r["attack_angle"]))
            except ValueError:
                continue
    median = {k: statistics.median(v) for k, v in by.items() if len(v) >= 20}
    keys = sorted(median)

    def at(launch):
        k = min(max(5 * math.floor(launch / 5), keys[0]), keys[-1])
        while k not in median:
            k -= 5
        return median[k]

    with open(season, newline="") as f, open(out, "w", newline="") as g:
        reader, writer = csv.reader(f), csv.writer(g)
        header = next(reader)
        i = header.index("launch_angle")
        writer.writerow(header + ["attack_angle"])
        for row in reader:
            writer.writerow(row + [f"{at(float(row[i])):.2f}" if row[i] else ""])
    print(", ".join(f"{k}°: {median[k]:.1f}°" for k in keys))
    return 0


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "attack":
        return add_attack_angle(*sys.argv[2:])
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("season")
    ap.add_argument("bag")
    ap.add_argument("located")
    ap.add_argument("--exit-sigma-mph", type=float, default=1.0, help="exit-speed accuracy (default 1 mph)")
    args = ap.parse_args()

    with open(args.season, newline="") as f:
        rows = list(csv.DictReader(f))
    line_of = {}
    with open(f"{args.bag}/import_rows.csv", newline="") as f:
        for r in csv.DictReader(f):
            line_of[int(r["swing_id"])] = int(r["line"])
    with open(args.located) as f:
        report = json.load(f)

    sigma = args.exit_sigma_mph * MPH
    bins = collections.defaultdict(collections.Counter)
    groups = collections.Counter()
    excess_by_bin = collections.defaultdict(list)
    squared = collections.defaultdict(collections.Counter)
    for s in report["swings"]:
        row = rows[line_of[s["swing_id"]] - 2]
        bat = float(row["bat_speed"])
        la = float(row["launch_angle"])
        ev = float(row["launch_speed"])
        b = 5 * math.floor(bat / 5)
        verdict = s["verdict"]
        if verdict == "too_fast" and s["excess"] <= 2 * sigma:
            verdict = "too_fast_within_2sigma"
        if verdict == "failed":
            m = re.search(r"χ² = ([0-9.]+)", s.get("reason", ""))
            if m and float(m.group(1)) <= 4.0:
                # The closest (z, D) misses the two measurements by at most 2σ together.
                verdict = "failed_within_2sigma"
        bins[b][verdict] += 1
        bins[b]["all"] += 1
        if verdict == "too_fast":
            excess_by_bin[b].append(s["excess"] / MPH)
        if verdict == "located":
            squared[b][s["squared_up"]] += 1
            squared[b][("solutions", len(s["solutions"]))] += 1
        if verdict in ("too_fast", "failed", "not_measured"):
            groups[(verdict, 10 * math.floor(la / 10), 10 * math.floor(ev / 10))] += 1

    print(
        "bat speed (mph) | swings | reproduced | located | too fast ≤ 2σ | missed ≤ 2σ | "
        "too fast (median excess mph) | failed"
    )
    print("---|---|---|---|---|---|---|---")
    total = collections.Counter()
    for b in sorted(bins):
        c = bins[b]
        total.update(c)
        n = c["all"]
        rep = c["located"] + c["too_fast_within_2sigma"] + c["failed_within_2sigma"]
        ex = excess_by_bin[b]
        med = f" ({statistics.median(ex):.1f})" if ex else ""
        print(
            f"{b}–{b + 5} | {n} | {100 * rep / n:.1f} % | {100 * c['located'] / n:.1f} % | "
            f"{100 * c['too_fast_within_2sigma'] / n:.1f} % | {100 * c['failed_within_2sigma'] / n:.1f} % | "
            f"{100 * c['too_fast'] / n:.1f} %{med} | "
            f"{100 * c['failed'] / n:.1f} %"
        )
    n = total["all"]
    rep = total["located"] + total["too_fast_within_2sigma"] + total["failed_within_2sigma"]
    print(
        f"all | {n} | {100 * rep / n:.1f} % | {100 * total['located'] / n:.1f} % | "
        f"{100 * total['too_fast_within_2sigma'] / n:.1f} % | {100 * total['failed_within_2sigma'] / n:.1f} % | "
        f"{100 * total['too_fast'] / n:.1f} % | "
        f"{100 * total['failed'] / n:.1f} %"
    )
    print()
    print("largest groups not reproduced: verdict | launch angle (°) | exit speed (mph) | swings")
    print("---|---|---|---")
    for (verdict, la, ev), k in groups.most_common(12):
        print(f"{verdict} | {la}–{la + 10} | {ev}–{ev + 10} | {k}")
    print()
    print("located: share squared up (favoured or every solution within ±2 cm of the sweet spot) per bin")
    for b in sorted(squared):
        c = squared[b]
        n = c[True] + c[False]
        if n >= 20:
            print(f"{b}–{b + 5}: {100 * c[True] / n:.1f} % of {n}; two solutions {100 * c[('solutions', 2)] / n:.0f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
