"""`read_tracker`, `locate` and `read_bag` against the command line run as a process (`sweetspot import`,
`sweetspot locate --json`, `sweetspot bag export`) and against the export's own cells; `read_bag(arrow=True)`
against the pandas frames."""

import io
import json
import math
import tempfile

import numpy as np
import pandas as pd
import pyarrow as pa
import pytest

import sweetspot

MPH = 0.44704


def test_read_tracker_skips_and_refuses_rows_as_import_does(repo, tmp_path, cli_json):
    export = repo / "tests/data/trackman_bad.csv"
    report = cli_json("import", export, "-o", tmp_path / "bag")
    frame = sweetspot.read_tracker(export)
    assert frame.attrs["format"] == "trackman"
    assert frame["swing_id"].notna().sum() == report["swings"]
    assert frame["skipped"].value_counts().to_dict() == report["skipped"]
    assert [f"{export}, {m}" for m in frame["refused"].dropna()] == report["refused"]


def test_read_tracker_takes_a_savant_frame_as_is_in_si_units(repo):
    export = repo / "tests/data/statcast_search.csv"
    savant = pd.read_csv(export)
    frame = sweetspot.read_tracker(savant)
    assert frame.attrs["format"] == "statcast"
    assert list(frame.index) == list(savant.index)
    np.testing.assert_allclose(frame["exit_speed"], savant["launch_speed"] * MPH, rtol=1e-15)
    np.testing.assert_allclose(frame["launch_angle"], np.radians(savant["launch_angle"]), rtol=1e-15)
    from_file = sweetspot.read_tracker(export)
    pd.testing.assert_frame_equal(frame, from_file)


def test_a_frame_is_read_as_the_csv_pandas_writes_of_it(repo, tmp_path):
    """A frame as pybaseball gives it (dates as datetime64, integer ids, a text cell with a comma, quotes and a
    line break) reads as the file pandas writes of it, the line break a space."""
    savant = pd.read_csv(repo / "tests/data/statcast_search.csv")
    savant["game_date"] = pd.to_datetime(savant["game_date"])
    savant.loc[0, "player_name"] = 'Doe, "J"\r\nJr'
    one_line = savant.copy()
    one_line.loc[0, "player_name"] = 'Doe, "J" Jr'
    export = tmp_path / "savant.csv"
    one_line.to_csv(export, index=False)
    from_file = sweetspot.read_tracker(export)
    pd.testing.assert_frame_equal(sweetspot.read_tracker(savant), from_file)
    assert from_file["swing_id"].notna().sum() == 3


def test_an_export_of_no_known_kind_is_a_value_error_and_a_missing_one_file_not_found(tmp_path):
    with pytest.raises(ValueError, match="matches no known export"):
        sweetspot.read_tracker(pd.DataFrame({"speed": [1.0]}))
    with pytest.raises(ValueError, match="not a hittrax export"):
        sweetspot.read_tracker(pd.DataFrame({"speed": [1.0]}), kind="hittrax")
    with pytest.raises(FileNotFoundError):
        sweetspot.read_tracker(tmp_path / "absent.csv")


def located_by_cli(cli_json, tmp_path, export, *flags):
    bag = tmp_path / "cli-bag"
    cli_json("import", export, "-o", bag, *flags)
    return bag, cli_json("locate", bag)


def test_locate_of_a_savant_frame_is_sweetspot_locate_of_its_import(repo, tmp_path, cli_json):
    export = repo / "tests/data/statcast_search.csv"
    bag, document = located_by_cli(cli_json, tmp_path, export)
    savant = pd.read_csv(export)
    savant.index = [f"pitch-{i}" for i in range(len(savant))]
    frame = sweetspot.locate(savant)
    assert len(frame) == len(document["swings"])
    for (index, row), swing in zip(frame.iterrows(), document["swings"]):
        assert row["verdict"] == swing["verdict"]
        # Joined back to the frame's own row: the measured exit speed is that row's launch_speed.
        if not math.isnan(row["measured_exit_speed"]):
            assert row["measured_exit_speed"] == pytest.approx(savant.loc[index, "launch_speed"] * MPH, rel=1e-15)
        for solution in swing.get("solutions", [])[:1]:
            for key in ("impact_z", "impact_z_sigma", "undercut", "undercut_sigma", "sweet_spot_z", "chi2"):
                assert row[key] == solution[key], key
            assert row["side"] == solution["side"]
    # A bag goes straight through, with the whole report.
    from_bag = sweetspot.locate(bag)
    assert from_bag.attrs["report"]["located"] == document["located"]
    assert from_bag["swing_id"].tolist() == [s["swing_id"] for s in document["swings"]]
    assert from_bag["impact_z"].equals(frame["impact_z"].set_axis(from_bag.index))


def test_locate_of_a_frame_writes_no_file_and_refuses_rows_as_import_does(repo, tmp_path, cli_json, monkeypatch):
    """The frame is located in memory: nothing goes through a temporary file or bag, and a row `import` refuses
    (an exit speed of -5 mph) is left out exactly as `sweetspot import` + `sweetspot locate` leave it out."""
    savant = pd.read_csv(repo / "tests/data/statcast_search.csv")
    bad = savant.index[savant["launch_speed"].notna()][0]
    savant.loc[bad, "launch_speed"] = -5.0
    export = tmp_path / "edited.csv"
    savant.to_csv(export, index=False)
    bag, document = located_by_cli(cli_json, tmp_path, export)
    assert len(cli_json("import", export, "-o", tmp_path / "refused")["refused"]) == 1

    def no_temporary_files(*args, **kwargs):
        raise AssertionError("locate wrote a temporary file")

    for name in ("TemporaryDirectory", "mkdtemp", "mkstemp", "NamedTemporaryFile"):
        monkeypatch.setattr(tempfile, name, no_temporary_files)
    frame = sweetspot.locate(savant)
    assert bad not in frame.index
    assert len(frame) == len(document["swings"])
    for (_, row), swing in zip(frame.iterrows(), document["swings"]):
        assert row["verdict"] == swing["verdict"]
        for solution in swing.get("solutions", [])[:1]:
            assert row["impact_z"] == solution["impact_z"]
            assert row["undercut"] == solution["undercut"]
    assert frame.attrs["report"] == {k: v for k, v in document.items() if k != "swings"}


def frame_of_document(document, index):
    """`locate`'s DataFrame as the docstring defines it, read off the command line's `locate --json` document:
    the favoured solution, else the first; null numbers NaN; what a verdict does not have missing."""
    rows = []
    for swing in document["swings"]:
        solutions = swing.get("solutions") or []
        favoured = swing.get("favoured")
        shown = solutions[favoured if favoured is not None else 0] if solutions else {}
        located = swing["verdict"] == "located"

        def number(v):
            return math.nan if v is None else v

        row = {"bat_id": swing["bat_id"], "verdict": swing["verdict"]}
        for name, value in zip(("exit_speed", "launch_angle", "spin"), swing["measured"]):
            row[f"measured_{name}"] = number(value)
        for name in ("impact_z", "impact_z_sigma", "undercut", "undercut_sigma"):
            row[name] = number(shown.get(name))
        row["undercut_fitted"] = shown.get("undercut_fitted", pd.NA)
        row["side"] = shown.get("side", pd.NA)
        row["sweet_spot_z"] = number(swing["sweet_spot_z"] if "sweet_spot_z" in swing else shown.get("sweet_spot_z"))
        row["chi2"] = number(shown.get("chi2"))
        for name, value in zip(("exit_speed", "launch_angle", "spin"), shown.get("model", [None] * 3)):
            row[f"model_{name}"] = number(value)
        row["solutions"] = len(solutions)
        row["favoured"] = (favoured is not None) if located else pd.NA
        row["squared_up"] = swing.get("squared_up", pd.NA)
        row["max_exit_speed"] = number(swing.get("max_exit_speed"))
        row["excess"] = number(swing.get("excess"))
        row["reason"] = swing.get("reason", pd.NA)
        rows.append(row)
    return pd.DataFrame(rows, columns=list(sweetspot.LOCATE_COLUMNS), index=index).astype(sweetspot.LOCATE_COLUMNS)


def test_every_cell_of_locate_is_the_command_lines_document(repo, tmp_path, cli_json):
    """Every column, bit for bit, of a frame with swings of each verdict (located, too fast, not measured, failed)
    and of the bag `import` writes of it, against `sweetspot locate --json` of that bag."""
    savant = pd.read_csv(repo / "tests/data/statcast_search.csv")
    too_fast, not_measured, failed = (savant.iloc[[0]].copy() for _ in range(3))
    too_fast["launch_speed"] = 140.0
    not_measured["launch_speed"] = np.nan
    failed["launch_angle"] = 85.0
    savant = pd.concat([savant, too_fast, not_measured, failed], ignore_index=True)
    savant.index = [f"pitch-{i}" for i in range(len(savant))]
    export = tmp_path / "verdicts.csv"
    savant.to_csv(export, index=False)
    bag, document = located_by_cli(cli_json, tmp_path, export)
    frame = sweetspot.locate(savant)
    assert {"located", "too_fast", "not_measured", "failed"} <= set(frame["verdict"])
    pd.testing.assert_frame_equal(frame, frame_of_document(document, frame.index), check_exact=True)
    from_bag = sweetspot.locate(bag)
    expected = frame_of_document(document, None)
    expected.insert(0, "swing_id", pd.array([s["swing_id"] for s in document["swings"]], dtype="UInt64"))
    pd.testing.assert_frame_equal(from_bag, expected, check_exact=True)
    assert from_bag.attrs["report"] == document


def test_a_frame_with_no_swing_locates_to_an_empty_frame():
    savant = pd.read_csv(io.StringIO("launch_speed,launch_angle,release_speed,description,events,bat_speed,"
                                     "game_date,batter,pitcher,game_pk,at_bat_number,pitch_number,stand,"
                                     "vx0,vy0,vz0,ax,ay,az,release_spin_rate,spin_axis\n"))
    try:
        frame = sweetspot.locate(savant)
    except ValueError as e:  # a header the importer does not know says so
        assert "export" in str(e)
    else:
        assert frame.empty and list(frame.columns) == list(sweetspot.LOCATE_COLUMNS)


def test_read_bag_joins_swings_to_their_answers_as_bag_export_does(repo, cli):
    bag = repo / "bags/golden/sweetspot_golden"
    exported = pd.read_csv(io.StringIO(cli("bag", "export", bag).stdout))
    frames = sweetspot.read_bag(bag)
    swings = frames["swings"]
    assert swings["swing_id"].tolist() == exported["swing_id"].tolist()
    np.testing.assert_array_equal(swings["exit_velocity_exit_speed"].to_numpy(float), exported["exit_speed"])
    np.testing.assert_array_equal(swings["ball_speed"].to_numpy(float), exported["ball_speed"])
    topics = {name: f.attrs["type"] for name, f in frames.items() if name != "swings"}
    assert topics["/golden/swing"] == "sweetspot_msgs/msg/Swing"
    assert len(frames["/golden/swing"]) == len(swings)


def test_a_file_that_is_not_a_bag_is_a_bag_error(tmp_path):
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not an mcap file at all" * 10)
    with pytest.raises(sweetspot.BagError, match="not an MCAP file"):
        sweetspot.read_bag(junk)
    with pytest.raises(sweetspot.BagError):
        sweetspot.locate(junk)
    with pytest.raises(FileNotFoundError):
        sweetspot.read_bag(tmp_path / "absent")


def test_read_bag_as_arrow_tables_holds_the_pandas_frames(repo):
    bag = repo / "bags/golden/sweetspot_golden"
    frames = sweetspot.read_bag(bag)
    tables = sweetspot.read_bag(bag, arrow=True)
    assert tables.keys() == frames.keys()
    for name, frame in frames.items():
        table = tables[name]
        assert isinstance(table, pa.Table)
        assert sorted(table.column_names) == sorted(frame.columns), name
        assert table.column_names[:2] == list(frame.columns[:2]), name
        assert table.num_rows == len(frame)
        assert table.column("log_time_ns").type == pa.uint64()
        for column in frame.columns:
            ours = table.column(column).to_pylist()
            theirs = frame[column].tolist()
            for a, b in zip(ours, theirs):
                if isinstance(b, float) and math.isnan(b):
                    assert a is None or math.isnan(a), (name, column)
                elif isinstance(b, (list, np.ndarray)):
                    assert list(a) == list(b), (name, column)
                else:
                    assert a == b, (name, column, a, b)
