#!/usr/bin/env python3
"""Derive the batted-ball spin-axis table of `sweetspot validate` (validation/trackman_hit_spin.csv).

Reads the two summer-collegiate TrackMan V3 game exports (../shared/reference/trackman/*_unverified.csv, files
marked "unverified" by the system) and keeps, unchanged, the columns the spin-axis rows need of every tracked
ball in play: PitchCall InPlay, HitLaunchConfidence High or Medium, and Angle, Direction, HitSpinRate and
HitSpinAxis all present. Columns: Game (the export's name), PitchNo, BatterSide, ExitSpeed (mph), Angle (launch,
deg), Direction (spray, deg, positive toward right field), HitSpinRate (total spin, rpm), HitSpinAxis (deg,
180 = pure backspin, 90 = curving toward left field). Standard library only.

  python3 scripts/trackman_hit_spin.py          write the table
  python3 scripts/trackman_hit_spin.py --check  re-derive and compare with the committed table (exit 1 on a
                                                difference, 0 with a message when the exports are absent)
"""

import csv
import glob
import io
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REFERENCE = os.environ.get("SWEETSPOT_REFERENCE_DIR", os.path.join(ROOT, "..", "shared", "reference"))
OUT = os.path.join(ROOT, "validation", "trackman_hit_spin.csv")
COLUMNS = ["PitchNo", "BatterSide", "ExitSpeed", "Angle", "Direction", "HitSpinRate", "HitSpinAxis"]
PROVENANCE = [
    "# Tracked balls in play (PitchCall InPlay, HitLaunchConfidence High or Medium, with Angle, Direction,",
    "# HitSpinRate and HitSpinAxis) of two TrackMan Baseball V3 game exports, summer-collegiate wood-bat games of",
    "# the Pacific Empire League, 12 June and 4 July 2025 (carson3m/TrackmanAnalyticsProgram @cd0579a,",
    "# data/Potters/; files marked unverified by the system). Cells copied unchanged. Derived by",
    "# scripts/trackman_hit_spin.py.",
]


def derive(paths):
    out = io.StringIO()
    for line in PROVENANCE:
        out.write(line + "\n")
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["Game"] + COLUMNS)
    for path in paths:
        game = os.path.basename(path)[: -len("_unverified.csv")]
        with open(path, newline="", encoding="utf-8-sig") as f:
            for row in csv.DictReader(f):
                tracked = row["PitchCall"] == "InPlay" and row["HitLaunchConfidence"] in ("High", "Medium")
                if tracked and all(row[c].strip() for c in ("Angle", "Direction", "HitSpinRate", "HitSpinAxis")):
                    writer.writerow([game] + [row[c] for c in COLUMNS])
    return out.getvalue()


def main():
    paths = sorted(glob.glob(os.path.join(REFERENCE, "trackman", "*_unverified.csv")))
    if not paths:
        print(f"skipped: no *_unverified.csv under {os.path.join(REFERENCE, 'trackman')}")
        return 0
    text = derive(paths)
    if "--check" in sys.argv[1:]:
        with open(OUT, encoding="utf-8") as f:
            if f.read() != text:
                print(f"{OUT} differs from a fresh derivation")
                return 1
        print(f"trackman_hit_spin.csv equals a fresh derivation from {len(paths)} exports")
        return 0
    with open(OUT, "w", encoding="utf-8") as f:
        f.write(text)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
