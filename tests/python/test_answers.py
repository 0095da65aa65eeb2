"""`sweep` and `validate` against the command line run as a process (`sweetspot sweep --json`,
`sweetspot validate --json`), value for value."""

import json
import math

import pandas as pd

import sweetspot


def flattened(value, prefix=""):
    """(name, value) of a JSON object's leaves, nested names joined by `_` (lists are leaves)."""
    if isinstance(value, dict):
        for key, inner in value.items():
            yield from flattened(inner, f"{prefix}{key}_")
    else:
        yield prefix[:-1], value


def same(a, b):
    """Equal bit for bit, NaN (pandas) standing for null (JSON)."""
    if b is None:
        return a is None or a is pd.NA or (isinstance(a, float) and math.isnan(a))
    return a == b


def assert_points_match(frame, points):
    assert len(frame) == len(points)
    for i, point in enumerate(points):
        for name, value in flattened(point):
            assert same(frame[name].iloc[i], value), (i, name, frame[name].iloc[i], value)


def test_a_sweep_over_impact_points_is_sweetspot_sweep(cli_json):
    document = cli_json("sweep", "--bat", "r161", "--ball", "mlb2024", "--ball-speed", "38", "--from", "0.55",
                        "--to", "0.82", "--points", "7")
    frame = sweetspot.sweep("r161", sweetspot.Ball.preset("mlb2024"), ball_speed=38, from_=0.55, to=0.82, points=7)
    assert_points_match(frame, document["points"])
    assert frame.attrs["sweet_spots"] == document["sweet_spots"]
    assert frame.attrs["nodes"] == document["nodes"]
    assert frame.attrs["swing"] == document["swing"]


def test_a_sweep_over_the_undercut_is_sweetspot_sweep_over_undercut(cli_json):
    document = cli_json("sweep", "--over", "undercut", "--bat", "r161", "--impact-z", "0.7", "--attack-angle", "10",
                        "--pitch-spin", "2000", "--points", "5")
    frame = sweetspot.sweep("r161", over="undercut", impact_z=0.7, attack_angle=10, pitch_spin=2000, points=5)
    assert_points_match(frame, document["points"])
    assert frame.attrs["oblique"] == document["oblique"]
    assert frame.attrs["impact_z"] == 0.7


def test_a_sweep_refuses_what_the_command_line_refuses(cli):
    done = cli("sweep", "--attack-angle", "10", check=False)
    assert done.returncode != 0
    try:
        sweetspot.sweep("r161", attack_angle=10)
    except ValueError as e:
        assert str(e) in done.stderr
    else:
        raise AssertionError("an attack angle on a sweep over z is refused")


def test_validate_gives_the_command_lines_rows(repo, cli):
    done = cli("validate", "--json", check=False, cwd=repo)
    document = json.loads(done.stdout)
    rows = sweetspot.validate(repo / "validation")
    assert rows.index.tolist() == [r["id"] for r in document["rows"]]
    for row in document["rows"]:
        ours = rows.loc[row["id"]]
        for name in sweetspot.VALIDATE_COLUMNS[1:]:
            assert same(ours[name], row[name]), (row["id"], name, ours[name], row[name])
    assert (rows.attrs["pass"], rows.attrs["fail"]) == (document["pass"], document["fail"])
    assert rows.attrs["pass"] == int((rows["verdict"] == "PASS").sum())
