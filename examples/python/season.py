#!/usr/bin/env python3
"""Where on the bat a Statcast season was hit, and how hard: exit speed against impact point.

    python examples/python/season.py [SEASON.csv[.gz]] [-o season.png] [--rows N]

SEASON is a Baseball Savant search export (or pybaseball's `statcast()` saved as CSV); by default the shared
2024 season, ../shared/reference/statcast/statcast_2024_in_play_bat_tracking.csv.gz beside the repository.
Every ball is located on the R161 (`sweetspot.locate`), and the located ones are plotted, exit speed
(mph) against impact point (inches from the barrel end), the sweet spot marked.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

import sweetspot  # noqa: E402

MPH = 0.44704
INCH = 0.0254
SEASON = Path(__file__).resolve().parents[2] / "../shared/reference/statcast/statcast_2024_in_play_bat_tracking.csv.gz"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("season", nargs="?", type=Path, default=SEASON)
    parser.add_argument("-o", "--output", type=Path, default=Path("season.png"))
    parser.add_argument("--rows", type=int, default=None, help="only the first ROWS rows")
    args = parser.parse_args()

    season = pd.read_csv(args.season, nrows=args.rows)
    bat = sweetspot.Bat.preset("r161")
    located = sweetspot.locate(season, bat=bat)
    hit = located[located["verdict"] == "located"]
    length = bat.properties()["length"]

    figure, axes = plt.subplots(figsize=(8, 5))
    axes.scatter((length - hit["impact_z"]) / INCH, hit["measured_exit_speed"] / MPH, s=4, alpha=0.4)
    axes.axvline((length - hit["sweet_spot_z"].median()) / INCH, color="tab:red", label="sweet spot")
    axes.set_xlabel("impact point (in from the barrel end)")
    axes.set_ylabel("exit speed (mph)")
    axes.set_title(f"{len(hit)} of {len(season)} balls located on the {bat.name}")
    axes.legend()
    figure.savefig(args.output, dpi=120)
    print(f"{len(hit)} of {len(located)} swings located ({len(season)} rows); wrote {args.output}")


if __name__ == "__main__":
    main()
