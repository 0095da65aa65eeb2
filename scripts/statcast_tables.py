#!/usr/bin/env python3
"""Derive the Statcast comparison tables of `sweetspot validate` from the shared season files.

Reads (when present) ../shared/reference/statcast/statcast_2024_in_play_bat_tracking.csv.gz (112,730 balls in
play of the 2024 MLB season with measured bat speed) and batted_balls_attack_angle.csv (20,188 balls with the
measured attack angle), and writes derived facts only -- counts, medians and percentiles per bin, never a raw
row -- with their provenance into validation/:

  statcast_q.csv               q = (EV - bat)/(plate pitch + bat) percentiles per 5-mph bin of bat speed (55-85),
                               of plate pitch speed, and of the batter's season-median bat speed; for the whole
                               season and for its odd and even game_pk halves
  statcast_exit_undercut.csv   exit speed percentiles per 5-degree bin of launch angle - attack angle
  statcast_attack.csv          attack angle quartiles conditional on the launch-angle bin

Pitch speed at the plate: the 9-parameter fit (vx0, vy0, vz0 at y = 50 ft, constant ax, ay, az) integrated to
the front of the plate, y = 17/12 ft. Percentiles interpolate linearly between order statistics (position
p*(n - 1), "type 7", numpy's default). Standard library only.

  python3 scripts/statcast_tables.py            write the tables
  python3 scripts/statcast_tables.py --check    re-derive and compare with the committed tables (exit 1 on a
                                                difference, 0 with a message when the season file is absent)
  python3 scripts/statcast_tables.py --noise    the measurement-noise analysis of docs/statcast.md (stdout)
"""

import csv
import gzip
import io
import math
import os
import random
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("SWEETSPOT_STATCAST_DIR", os.path.join(ROOT, "..", "shared", "reference", "statcast"))
SEASON = os.path.join(SHARED, "statcast_2024_in_play_bat_tracking.csv.gz")
ATTACK = os.path.join(SHARED, "batted_balls_attack_angle.csv")
OUT = os.path.join(ROOT, "validation")

SEASON_SOURCE = (
    "Baseball Savant pitch-level output, 2024 regular season, balls in play with bat tracking (112,730 rows, "
    "2,418 games), as kept in teajay/baseball @8ddb6bc7e3f72f3dec20c4cfaf01614c9dee3d76 statcast_csv/sc_2024-*.csv; "
    "copied to ../shared/reference/statcast/statcast_2024_in_play_bat_tracking.csv.gz"
)
ATTACK_SOURCE = (
    "Baseball Savant bat tracking with attack angle (20,188 balls in play, likely the 2025 season), as kept in "
    "36-SURE/2026 @75971c2b32cf0a2e9279cc4db17d5899b6f17253 data/batted_balls.csv; copied to "
    "../shared/reference/statcast/batted_balls_attack_angle.csv"
)

Y0_FT = 50.0
Y_PLATE_FT = 17.0 / 12.0
FT_S_TO_MPH = 3600.0 / 5280.0
BAT_BINS = [(lo, lo + 5) for lo in range(55, 85, 5)]
PITCH_BINS = [(lo, lo + 5) for lo in range(65, 100, 5)]
PERCENTILES = (0.5, 0.97, 0.99, 0.998)
MIN_BATTER_BALLS = 50
UNDERCUT_BINS = [(lo, lo + 5) for lo in range(-40, 60, 5)]
LAUNCH_BINS = [(c - 5, c + 5) for c in range(-10, 55, 5)]


def quantile(sorted_values, p):
    """Type-7 quantile of an ascending list."""
    n = len(sorted_values)
    if n == 0:
        return None
    h = p * (n - 1)
    lo = math.floor(h)
    hi = min(lo + 1, n - 1)
    return sorted_values[lo] + (h - lo) * (sorted_values[hi] - sorted_values[lo])


def quantile_ci(sorted_values, p, z=1.96):
    """Distribution-free confidence interval of the p-quantile of an ascending list: the order statistics whose
    ranks are n*p -/+ z*sqrt(n*p*(1-p)) (the binomial count of values below the quantile), 1-based j and k."""
    n = len(sorted_values)
    centre, spread = n * p, z * math.sqrt(n * p * (1 - p))
    j = max(1, math.floor(centre - spread))
    k = min(n, math.ceil(centre + spread) + 1)
    return sorted_values[j - 1], sorted_values[k - 1]


def num(text):
    try:
        v = float(text)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def plate_speed_mph(vx0, vy0, vz0, ax, ay, az):
    """Pitch speed at the front of the plate (mph) from the 9-parameter fit at y = 50 ft."""
    # y(t) = 50 + vy0 t + ay t^2 / 2 = 17/12, vy0 < 0: the first (smaller positive) root.
    disc = vy0 * vy0 - 2.0 * ay * (Y0_FT - Y_PLATE_FT)
    if disc < 0 or ay == 0:
        return None
    t = (-vy0 - math.sqrt(disc)) / ay
    if not t > 0:
        return None
    vx, vy, vz = vx0 + ax * t, vy0 + ay * t, vz0 + az * t
    return math.sqrt(vx * vx + vy * vy + vz * vz) * FT_S_TO_MPH


def read_season():
    """(game_pk, batter, bat mph, plate pitch mph, exit mph, q) of every usable ball of the season file."""
    balls = []
    with gzip.open(SEASON, "rt", newline="") as f:
        for r in csv.DictReader(f):
            bat, ev = num(r["bat_speed"]), num(r["launch_speed"])
            fit = [num(r[k]) for k in ("vx0", "vy0", "vz0", "ax", "ay", "az")]
            if bat is None or ev is None or any(v is None for v in fit):
                continue
            plate = plate_speed_mph(*fit)
            if plate is None:
                continue
            q = (ev - bat) / (plate + bat)
            balls.append((int(r["game_pk"]), r["batter"], bat, plate, ev, q))
    return balls


def fmt(v, digits):
    return "" if v is None else f"{v:.{digits}f}"


def q_row(by, half, lo, hi, group):
    qs = sorted(b[5] for b in group)
    bats = sorted(b[2] for b in group)
    plates = sorted(b[3] for b in group)
    return [by, half, lo, hi, len(group), fmt(quantile(bats, 0.5), 2), fmt(quantile(plates, 0.5), 2)] + [
        fmt(quantile(qs, p), 4) for p in PERCENTILES
    ]


def q_table(balls):
    medians = {}
    per_batter = {}
    for b in balls:
        per_batter.setdefault(b[1], []).append(b[2])
    for batter, bats in per_batter.items():
        if len(bats) >= MIN_BATTER_BALLS:
            medians[batter] = quantile(sorted(bats), 0.5)
    rows = []
    halves = [("all", lambda g: True), ("odd", lambda g: g % 2 == 1), ("even", lambda g: g % 2 == 0)]
    for half, keep in halves:
        part = [b for b in balls if keep(b[0])]
        for lo, hi in BAT_BINS:
            rows.append(q_row("bat", half, lo, hi, [b for b in part if lo <= b[2] < hi]))
        in_range = [b for b in part if BAT_BINS[0][0] <= b[2] < BAT_BINS[-1][1]]
        for lo, hi in PITCH_BINS:
            group = [b for b in in_range if lo <= b[3] < hi]
            if len(group) >= 100:
                rows.append(q_row("plate_pitch", half, lo, hi, group))
        for lo, hi in BAT_BINS:
            group = [b for b in in_range if b[1] in medians and lo <= medians[b[1]] < hi]
            if len(group) >= 100:
                rows.append(q_row("batter_median_bat", half, lo, hi, group))
    header = ["by", "half", "low", "high", "count", "median_bat_mph", "median_plate_pitch_mph", "q_p50", "q_p97",
              "q_p99", "q_p99_8"]
    plates = sorted(b[3] for b in balls)
    notes = [
        f"Derived by scripts/statcast_tables.py from {SEASON_SOURCE}.",
        f"{len(balls)} balls with bat_speed, launch_speed and the pitch's 9-parameter fit.",
        "q = (launch_speed - bat_speed)/(plate pitch + bat_speed), mph; plate pitch: the 9-parameter fit at y = 50 ft "
        "integrated to the front of the plate (y = 17/12 ft).",
        "by: bat = the swing's measured bat speed (6 in from the head); plate_pitch = plate pitch speed (balls with "
        "bat 55-85 mph); batter_median_bat = the batter's season-median bat speed (batters with >= "
        f"{MIN_BATTER_BALLS} balls; balls with bat 55-85 mph): a bin the swing's own measurement error does not sort.",
        "half: all, odd or even game_pk. Bins [low, high) in mph; plate_pitch and batter bins with >= 100 balls.",
        "Percentiles: linear between order statistics (type 7). Season median plate pitch speed "
        f"{quantile(plates, 0.5):.2f} mph (quartiles {quantile(plates, 0.25):.2f}, {quantile(plates, 0.75):.2f}).",
    ]
    return notes, header, rows


def read_attack():
    rows = []
    with open(ATTACK, newline="") as f:
        for r in csv.DictReader(f):
            la, ev, bat, aa = (num(r[k]) for k in ("launch_angle", "launch_speed", "bat_speed", "attack_angle"))
            if None in (la, ev, bat, aa):
                continue
            rows.append((la, ev, bat, aa))
    return rows


def undercut_table(rows):
    out = []
    for lo, hi in UNDERCUT_BINS:
        group = [r for r in rows if lo <= r[0] - r[3] < hi and 55 <= r[2] < 85]
        if len(group) < 50:
            continue
        ev = sorted(r[1] for r in group)
        bats = sorted(r[2] for r in group)
        attacks = sorted(r[3] for r in group)
        p99_low, p99_high = quantile_ci(ev, 0.99)
        out.append([lo, hi, len(group), fmt(quantile(bats, 0.5), 2), fmt(quantile(attacks, 0.5), 2)]
                   + [fmt(quantile(ev, p), 2) for p in PERCENTILES] + [fmt(p99_low, 2), fmt(p99_high, 2)])
    header = ["low_deg", "high_deg", "count", "median_bat_mph", "median_attack_deg", "exit_p50_mph", "exit_p97_mph",
              "exit_p99_mph", "exit_p99_8_mph", "exit_p99_ci_low_mph", "exit_p99_ci_high_mph"]
    notes = [
        f"Derived by scripts/statcast_tables.py from {ATTACK_SOURCE}.",
        f"{len(rows)} balls with launch_angle, launch_speed, bat_speed and attack_angle; a bin holds the balls with "
        "bat 55-85 mph whose launch_angle - attack_angle lies in [low_deg, high_deg) (bins with >= 50 balls).",
        "No pitch speed in this file: the model meets the season's median plate pitch speed (statcast_q.csv).",
        "Percentiles: linear between order statistics (type 7). exit_p99_ci_*: the distribution-free 95% confidence "
        "interval of the 99th percentile, order statistics j = floor(np - 1.96 sqrt(np(1-p))) and "
        "k = ceil(np + 1.96 sqrt(np(1-p))) + 1 (1-based, clamped to 1..n).",
    ]
    return notes, header, out


def attack_table(rows):
    out = []
    for lo, hi in LAUNCH_BINS:
        group = [r for r in rows if lo <= r[0] < hi]
        if len(group) < 50:
            continue
        aa = sorted(r[3] for r in group)
        ev = sorted(r[1] for r in group)
        out.append([lo, hi, len(group), fmt(quantile(aa, 0.25), 2), fmt(quantile(aa, 0.5), 2),
                    fmt(quantile(aa, 0.75), 2), fmt(quantile(ev, 0.5), 2)])
    header = ["launch_low_deg", "launch_high_deg", "count", "attack_q1_deg", "attack_median_deg", "attack_q3_deg",
              "exit_median_mph"]
    notes = [
        f"Derived by scripts/statcast_tables.py from {ATTACK_SOURCE}.",
        "Attack angle quartiles of the balls launched in [launch_low_deg, launch_high_deg) (10-degree bins every 5 "
        "degrees, so neighbouring rows overlap; bins with >= 50 balls). Type-7 quantiles.",
    ]
    return notes, header, out


def render(notes, header, rows):
    buf = io.StringIO()
    for n in notes:
        buf.write(f"# {n}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for r in rows:
        w.writerow(r)
    return buf.getvalue()


def tables():
    out = {}
    if os.path.exists(SEASON):
        out["statcast_q.csv"] = render(*q_table(read_season()))
    if os.path.exists(ATTACK):
        rows = read_attack()
        out["statcast_exit_undercut.csv"] = render(*undercut_table(rows))
        out["statcast_attack.csv"] = render(*attack_table(rows))
    return out


def noise(seed=20240403):
    """The measurement-noise analysis: how much of the fall of q's upper percentiles with bat speed a noisy bat
    speed makes by itself (see docs/statcast.md)."""
    balls = [b for b in read_season() if 50 <= b[2] < 90]
    rng = random.Random(seed)
    # A noise-free model population: every ball keeps its measured pitch speed and its q's shortfall below the
    # season's flat envelope, but gets a true bat speed drawn from the measured ones; the envelope is flat (the
    # same q at every bat speed), so any fall the binning shows is made by the noise.
    central = sorted(b[5] for b in balls if 65 <= b[2] < 75)
    q_top = quantile(central, 0.99)
    print(f"balls: {len(balls)}; flat envelope of the model population: q99 of the 65-75 bin = {q_top:.4f}")
    bats = [b[2] for b in balls]
    mean = sum(bats) / len(bats)
    sd = math.sqrt(sum((x - mean) ** 2 for x in bats) / (len(bats) - 1))
    print(f"measured bat speed: mean {mean:.2f} mph, sd {sd:.2f} mph")

    def binned(pop):
        res = []
        for lo, hi in BAT_BINS:
            qs = sorted(q for bat, q in pop if lo <= bat < hi)
            res.append((lo, hi, len(qs), quantile(qs, 0.97), quantile(qs, 0.99)))
        return res

    measured = binned([(b[2], b[5]) for b in balls])
    print("measured:     " + "  ".join(f"{lo}-{hi}: {p97:.4f}/{p99:.4f}" for lo, hi, n, p97, p99 in measured))
    central_balls = [b for b in balls if 65 <= b[2] < 75]
    for sigma_bat in (0.0, 1.0, 2.0, 3.0, 4.0):
        # True bat speeds: the measured distribution shrunk so that adding the noise restores its spread; the
        # true q of each ball: that of a ball drawn from the 65-75 mph bin (so the envelope is flat by
        # construction); the measured bat speed: the true one plus Gaussian noise of sigma_bat.
        shrink = math.sqrt(max(sd * sd - sigma_bat * sigma_bat, 0.0)) / sd
        pop = []
        for b in balls:
            true_bat = mean + (b[2] - mean) * shrink
            true_q = rng.choice(central_balls)[5]
            ev = true_bat + true_q * (b[3] + true_bat)
            seen_bat = true_bat + rng.gauss(0.0, sigma_bat)
            pop.append((seen_bat, (ev - seen_bat) / (b[3] + seen_bat)))
        res = binned(pop)
        fall97 = res[0][3] - res[-1][3]
        print(f"sigma_bat {sigma_bat:.0f} mph: " + "  ".join(
            f"{lo}-{hi}: {p97:.4f}/{p99:.4f}" for lo, hi, n, p97, p99 in res) + f"   fall of p97 55-60 -> 80-85: {fall97:.4f}")
    print(f"measured fall of p97 55-60 -> 80-85: {measured[0][3] - measured[-1][3]:.4f}")


def main(argv):
    if "--noise" in argv:
        if not os.path.exists(SEASON):
            print(f"skipped: the season file {SEASON} is absent")
            return 0
        noise()
        return 0
    got = tables()
    if not got:
        print(f"skipped: neither {SEASON} nor {ATTACK} is present")
        return 0
    if "--check" in argv:
        bad = []
        for name, text in got.items():
            path = os.path.join(OUT, name)
            committed = open(path).read() if os.path.exists(path) else None
            if committed != text:
                bad.append(name)
        if bad:
            print("differ from a fresh derivation: " + ", ".join(bad))
            return 1
        print("equal to a fresh derivation: " + ", ".join(sorted(got)))
        return 0
    for name, text in got.items():
        with open(os.path.join(OUT, name), "w") as f:
            f.write(text)
        print(f"wrote validation/{name}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
