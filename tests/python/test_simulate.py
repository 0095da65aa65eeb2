"""`sweetspot.simulate` against `sweetspot simulate --json` (the command line, run as a process), bit for bit,
and against the closed-form rigid bat; bats, balls and their refusals against the command line's."""

import json
import math
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

import sweetspot

R161 = sweetspot.Bat.preset("r161")
GAME = sweetspot.Ball.preset("mlb2024")


def flatten(result: dict) -> dict:
    """A result of the command line's JSON with nested names joined by `_`, as the package's frames name them."""
    out = {}
    for key, value in result.items():
        if key == "mode_energies":
            for m in value:
                out[f"mode_energy_{m['mode']}"] = m["energy"]
        elif isinstance(value, dict):
            for k, v in flatten(value).items():
                out[f"{key}_{k}"] = v
        else:
            out[key] = value
    return out


def same(a, b) -> bool:
    """Bit for bit (NaN is never in these documents)."""
    if isinstance(b, bool) or isinstance(a, (bool, np.bool_)):
        return bool(a) == b
    return float(a) == float(b) and math.copysign(1, float(a)) == math.copysign(1, float(b))


def test_the_issues_one_liner_prints_the_command_lines_exit_speed_bit_for_bit(cli_json):
    document = cli_json("simulate", "--bat", "r161", "--ball", "mlb2024", "--ball-speed", 40, "--bat-cm-speed", 25,
                        "--bat-angular-speed", 45, "--impact-z", 0.7)
    line = ("import sweetspot; print(sweetspot.simulate(sweetspot.Bat.preset('r161'), sweetspot.Ball.preset('mlb2024'), "
            "ball_speed=40, bat_cm_speed=25, bat_angular_speed=45, impact_z=0.7).exit_speed)")
    printed = subprocess.run([sys.executable, "-c", line], capture_output=True, text=True, check=True).stdout.strip()
    assert printed == repr(document["results"][0]["exit_speed"])


def test_a_collision_carries_the_whole_document_of_the_command_line(cli_json):
    document = cli_json("simulate", "--bat", "r161", "--impact-z", 0.62, "--ball-speed", 38.5, "--modes", 12)
    r = sweetspot.simulate(R161, GAME, ball_speed=38.5, impact_z=0.62, modes=12)
    assert r.document == document
    expected = document["results"][0]
    for key in ("exit_speed", "rigid_exit_speed", "effective_cor", "collision_efficiency", "contact_time",
                "peak_force", "impulse", "max_compression", "energy"):
        assert getattr(r, key) == expected[key]
    assert isinstance(r.mode_energies, np.ndarray) and r.mode_energies.shape == (12,)
    assert r.mode_energies.tolist() == [m["energy"] for m in expected["mode_energies"]]
    assert r.mode_frequencies_hz.tolist() == [m["frequency_hz"] for m in expected["mode_energies"]]


CASES = [
    ("head-on", "r161", {}, []),
    ("hollow", "aluminum", {}, []),
    ("oblique", "r161", {"undercut": 0.01, "attack_angle": 10.0, "pitch_angle": 7.0, "pitch_spin": 2000.0},
     ["--undercut", 0.01, "--attack-angle", 10, "--pitch-angle", 7, "--pitch-spin", 2000]),
    ("3-D", "r161", {"undercut": -0.005, "attack_angle": 8.0, "bat_tilt": 25.0, "swing_direction": -12.0,
                     "batter_side": "left", "friction": 0.3},
     ["--undercut", -0.005, "--attack-angle", 8, "--bat-tilt", 25, "--swing-direction", -12,
      "--batter-side", "left", "--friction", 0.3]),
]


@pytest.mark.parametrize("name,bat,kwargs,flags", CASES, ids=[c[0] for c in CASES])
def test_arrays_give_every_field_of_the_command_lines_results_bit_for_bit(cli_json, name, bat, kwargs, flags):
    zs = [0.55, 0.68, 0.79]
    speeds = [36.0, 40.0, 42.5]
    frame = sweetspot.simulate(sweetspot.Bat.preset(bat), GAME, ball_speed=np.array(speeds)[:, None],
                               impact_z=np.array(zs), **kwargs)
    assert len(frame) == 9
    for i, v in enumerate(speeds):
        document = cli_json("simulate", "--bat", bat, "--ball-speed", v, "--impact-z", ",".join(map(str, zs)), *flags)
        for j, result in enumerate(document["results"]):
            row = frame.iloc[3 * i + j]
            expected = flatten(result)
            missing = set(expected) - set(frame.columns)
            assert not missing, f"{name}: fields of the command line's JSON missing: {missing}"
            extra = {c for c in frame.columns if not pd.isna(row[c])} - set(expected)
            assert not extra, f"{name}: columns the command line's JSON does not have: {extra}"
            for key, value in expected.items():
                assert same(row[key], value), f"{name} v={v} z={zs[j]} {key}: {row[key]!r} ≠ {value!r}"


def test_a_dataframe_of_swings_comes_back_indexed_like_it():
    swings = pd.DataFrame({"ball_speed": [35.0, 41.0], "bat_cm_speed": [22.0, 27.0], "impact_z": [0.66, 0.71]},
                          index=["first", "second"])
    frame = sweetspot.simulate(R161, GAME, swings, bat_angular_speed=50.0)
    assert list(frame.index) == ["first", "second"]
    one = sweetspot.simulate(R161, GAME, ball_speed=41.0, bat_cm_speed=27.0, bat_angular_speed=50.0, impact_z=0.71)
    assert frame.loc["second", "exit_speed"] == one.exit_speed
    assert frame.attrs["mode_frequencies_hz"] == one.mode_frequencies_hz.tolist()


def test_without_modes_the_exit_speed_is_the_closed_form_rigid_bat():
    # A rigid bat and a constant-COR ball: v_f = e_A v + (1 + e_A) V_z, e_A = (e − m/M_e)/(1 + m/M_e),
    # 1/M_e = 1/M + (z − z_cm)²/I_cm, V_z = V + ω (z − z_cm).
    ball = sweetspot.Ball.preset("baseball")
    assert ball.cor_speed_exponent == 0
    p = R161.properties()
    for z in (0.45, 0.6, 0.7, 0.8):
        r = sweetspot.simulate(R161, ball, ball_speed=40, bat_cm_speed=25, bat_angular_speed=45, impact_z=z, modes=0)
        d = z - p["center_of_mass"]
        r_m = ball.mass * (1 / p["mass"] + d * d / p["moment_of_inertia"])
        e_a = (ball.cor - r_m) / (1 + r_m)
        closed = e_a * 40 + (1 + e_a) * (25 + 45 * d)
        assert r.exit_speed == pytest.approx(closed, rel=1e-6), z


def test_bad_inputs_raise_value_error_with_the_command_lines_message(cli):
    done = cli("simulate", "--bat", "r161", "--ball-cor", 1.5, check=False)
    assert done.returncode != 0
    with pytest.raises(ValueError) as raised:
        sweetspot.Ball.preset("mlb2024", cor=1.5)
    assert f"error: {raised.value}" == done.stderr.strip()
    done = cli("simulate", "--bat", "r161", "--impact-z", 2.0, check=False)
    with pytest.raises(ValueError) as raised:
        sweetspot.simulate(R161, GAME, impact_z=2.0)
    assert f"error: {raised.value}" == done.stderr.strip()
    with pytest.raises(ValueError, match="swing 1: collision at impact_z = 2 m"):
        sweetspot.simulate(R161, GAME, impact_z=np.array([0.7, 2.0]))
    frame = sweetspot.simulate(R161, GAME, impact_z=np.array([0.7, 2.0]), errors="nan")
    assert not math.isnan(frame["exit_speed"][0]) and math.isnan(frame["exit_speed"][1])
    assert frame["error"][1] == str(raised.value) and pd.isna(frame["error"][0])
    with pytest.raises(ValueError, match="ball_speed = NaN is not allowed"):
        sweetspot.simulate(R161, GAME, ball_speed=float("nan"))
    with pytest.raises(ValueError, match="unknown"):
        sweetspot.Bat.preset("balsa")


def test_a_bat_file_loads_and_a_missing_one_is_file_not_found(tmp_path, cli_json):
    toml = tmp_path / "plank.toml"
    toml.write_text('slice_length = 0.01\n[shell]\ndensity = 649.0\nyoungs_modulus = 1.814e10\nshear_modulus = 1.05e9\n'
                    '[[station]]\nz = 0.0\nouter_radius = 0.016\n[[station]]\nz = 0.84\nouter_radius = 0.033\n')
    bat = sweetspot.Bat.from_file(toml)
    assert bat.name == "plank"
    document = cli_json("simulate", "--bat", toml, "--impact-z", 0.7)
    assert sweetspot.simulate(bat, GAME, impact_z=0.7).document == document
    with pytest.raises(FileNotFoundError):
        sweetspot.Bat.from_file(tmp_path / "absent.toml")


def test_modes_are_the_command_lines(cli_json):
    document = cli_json("modes", "--bat", "r161", "--modes", 4)
    frame = R161.modes(4)
    assert frame["frequency_hz"].tolist() == [m["frequency_hz"] for m in document["modes"]]
    assert frame["nodes"].tolist() == [m["nodes"] for m in document["modes"]]
    assert frame["modal_mass"].tolist() == [m["modal_mass"] for m in document["modes"]]


def test_the_gil_is_released_while_rust_computes():
    # With a switch interval of an hour the interpreter never takes the GIL from a thread: the main thread
    # runs during the worker's call only if the call itself lets go of it.
    import threading

    seen_running = 0
    # 20,000 collisions: a tenth of a second or more even in a release build on two cores.
    worker = threading.Thread(target=lambda: sweetspot.simulate(R161, GAME, impact_z=np.linspace(0.5, 0.8, 20_000)))
    interval = sys.getswitchinterval()
    sys.setswitchinterval(3600.0)
    try:
        worker.start()
        worker.join(0.01)  # blocks, so the worker takes the GIL and gets into the call
        while worker.is_alive():
            seen_running += 1
            worker.join(0.001)
    finally:
        sys.setswitchinterval(interval)
    assert seen_running > 0


def test_bbcor_and_compare_are_the_command_lines_documents(cli_json, repo):
    assert sweetspot.bbcor("aluminum", modes=12) == cli_json("bbcor", "--bat", "aluminum", "--modes", 12)
    document = cli_json("compare", "--bats", "r161,torpedo", "--pitch-speed", 38)
    frame = sweetspot.compare(["r161", sweetspot.Bat.preset("torpedo")], pitch_speed=38)
    assert frame.index.tolist() == [b["name"] for b in document["bats"]]
    for row in document["bats"]:
        for key, value in row.items():
            if key != "name":
                assert frame.loc[row["name"], key] == value, key
    assert frame.attrs["batter"] == document["batter"]
    with pytest.raises(ValueError, match="pitch-speed"):
        sweetspot.compare(["r161"], pitch_speed=0)
