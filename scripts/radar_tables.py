#!/usr/bin/env python3
"""Derive the radar spin table of `sweetspot validate` (validation/mlb2018_radar_spin.csv) from the shared files.

Reads (when present) ../shared/reference/trackman/mlb_2018_batted_ball_spin.csv.gz (7,917 MLB balls in play,
1-9 April 2018, TrackMan radar: launch angle, exit speed, exit direction, total spin),
../shared/reference/statcast/batted_balls_attack_angle.csv (20,188 balls with the measured attack angle and
swing_path_tilt) and statcast_2024_in_play_bat_tracking.csv.gz (the batter's side of 112,730 balls in play),
and writes derived facts only -- counts, quantiles per bin, never a raw row -- with their provenance.

One row per launch-angle bin centred every 5 degrees from 5 to 45 (launch in [centre - 2.5, centre + 2.5)), over
the balls leaving at 80-88 mph (exit in [80, 88)) with a measured spin (hit_spin_rate > 0: 0 or NULL means not
measured) and an exit direction:
  count, spin_q1/median/q3_rpm       the total spin's quartiles
  exit_median_mph                    the bin's median exit speed (the model's swing is matched to it)
  spray_p05_deg ... spray_p95_deg    the exit direction's 5th, 10th, ..., 95th percentiles (TrackMan's
                                     Direction: degrees, positive toward right field)
  attack_median_deg, tilt_median_deg the median attack angle and swing_path_tilt of the balls launched within
                                     +-5 degrees of the centre (the attack-angle file, the same bins as
                                     statcast_attack.csv)
  right_handed_share                 the share of 2024 balls in play hit by right-handed batters (stand = R)

Quantiles interpolate linearly between order statistics (position p*(n - 1), "type 7"). Standard library only.

  python3 scripts/radar_tables.py          write the table
  python3 scripts/radar_tables.py --check  re-derive and compare with the committed table (exit 1 on a
                                           difference, 0 with a message when a source file is absent)
"""

import csv
import gzip
import io
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REFERENCE = os.environ.get("SWEETSPOT_REFERENCE_DIR", os.path.join(ROOT, "..", "shared", "reference"))
RADAR = os.path.join(REFERENCE, "trackman", "mlb_2018_batted_ball_spin.csv.gz")
ATTACK = os.path.join(REFERENCE, "statcast", "batted_balls_attack_angle.csv")
SEASON = os.path.join(REFERENCE, "statcast", "statcast_2024_in_play_bat_tracking.csv.gz")
OUT = os.path.join(ROOT, "validation", "mlb2018_radar_spin.csv")

PROVENANCE = [
    "Derived by scripts/radar_tables.py. Spin, exit speed and direction: every MLB ball in play of 1-9 April 2018 "
    "measured by TrackMan radar (7,917 rows), as published in danhogan/batted-ball @e5ffdc8 BattedBallData.csv; "
    "copied to ../shared/reference/trackman/mlb_2018_batted_ball_spin.csv.gz.",
    "Attack angle and swing_path_tilt: Baseball Savant bat tracking (20,188 balls in play, likely 2025), as kept in "
    "36-SURE/2026 @75971c2b32cf0a2e9279cc4db17d5899b6f17253 data/batted_balls.csv. Batter side: Baseball Savant 2024 "
    "balls in play with bat tracking (112,730 rows), teajay/baseball @8ddb6bc7e3f72f3dec20c4cfaf01614c9dee3d76.",
    "A bin: launch in [launch_deg - 2.5, launch_deg + 2.5), exit speed in [80, 88) mph, hit_spin_rate > 0 and an exit "
    "direction. Quantiles type 7. attack/tilt medians: balls launched in [launch_deg - 5, launch_deg + 5).",
]
PERCENTILES = list(range(5, 100, 5))


def quantile(values, p):
    v = sorted(values)
    pos = p * (len(v) - 1)
    lo = int(pos)
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (v[hi] - v[lo]) * (pos - lo)


def number(cell):
    try:
        return float(cell)
    except (TypeError, ValueError):
        return None


def table():
    with gzip.open(RADAR, "rt", newline="") as f:
        radar = list(csv.DictReader(f))
    with open(ATTACK, newline="") as f:
        attack = list(csv.DictReader(f))
    with gzip.open(SEASON, "rt", newline="") as f:
        sides = [r["stand"] for r in csv.DictReader(f) if r["stand"] in ("R", "L")]
    right_share = sides.count("R") / len(sides)
    header = ["launch_deg", "count", "spin_q1_rpm", "spin_median_rpm", "spin_q3_rpm", "exit_median_mph"]
    header += [f"spray_p{p:02d}_deg" for p in PERCENTILES]
    header += ["attack_median_deg", "tilt_median_deg", "right_handed_share"]
    rows = []
    for centre in range(5, 50, 5):
        balls = []
        for r in radar:
            launch, exit_mph = number(r["launch_angle"]), number(r["exit_speed"])
            spin, direction = number(r["hit_spin_rate"]), number(r["exit_direction"])
            if None in (launch, exit_mph, spin, direction) or spin <= 0:
                continue
            if centre - 2.5 <= launch < centre + 2.5 and 80.0 <= exit_mph < 88.0:
                balls.append((spin, exit_mph, direction))
        swings = [
            (float(r["attack_angle"]), float(r["swing_path_tilt"]))
            for r in attack
            if centre - 5 <= float(r["launch_angle"]) < centre + 5
        ]
        spins = [b[0] for b in balls]
        row = [centre, len(balls)] + [round(quantile(spins, p), 1) for p in (0.25, 0.5, 0.75)]
        row.append(round(quantile([b[1] for b in balls], 0.5), 2))
        row += [round(quantile([b[2] for b in balls], p / 100), 2) for p in PERCENTILES]
        row.append(round(quantile([s[0] for s in swings], 0.5), 2))
        row.append(round(quantile([s[1] for s in swings], 0.5), 2))
        row.append(round(right_share, 4))
        rows.append(row)
    out = io.StringIO()
    for line in PROVENANCE:
        out.write(f"# {line}\n")
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return out.getvalue()


def main():
    missing = [p for p in (RADAR, ATTACK, SEASON) if not os.path.isfile(p)]
    if missing:
        print(f"radar_tables: {', '.join(missing)} absent; nothing derived")
        return 0
    text = table()
    if "--check" in sys.argv[1:]:
        with open(OUT) as f:
            committed = f.read()
        if committed != text:
            print(f"radar_tables: {OUT} differs from what the shared files give; rerun scripts/radar_tables.py")
            return 1
        print(f"radar_tables: {OUT} matches the shared files")
        return 0
    with open(OUT, "w") as f:
        f.write(text)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
