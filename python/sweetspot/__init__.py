"""sweetspot in Python: the bat-ball collision (Nathan 2000), tracker exports, ``locate`` and bags, in pandas.

Every number comes from the same Rust library as the ``sweetspot`` command line, through the same functions:
``simulate`` prints what ``sweetspot simulate --json`` prints, ``locate`` what ``sweetspot locate --json``
finds. SI units throughout (m, m/s, rad/s, kg, J, s), except where the command line takes degrees and rpm
(``attack_angle``, ``pitch_angle``, ``bat_tilt``, ``swing_direction`` in degrees, ``pitch_spin`` in rpm).

>>> import sweetspot
>>> r = sweetspot.simulate(sweetspot.Bat.preset("r161"), sweetspot.Ball.preset("mlb2024"),
...                        ball_speed=40, bat_cm_speed=25, bat_angular_speed=45, impact_z=0.7)
>>> round(r.exit_speed, 2)
47.1
"""

from __future__ import annotations

import json
import os
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from . import _sweetspot as _native
from ._sweetspot import BagError

__all__ = [
    "Bat",
    "Ball",
    "Collision",
    "BagError",
    "simulate",
    "sweep",
    "bbcor",
    "compare",
    "read_tracker",
    "locate",
    "locate_meta",
    "read_bag",
    "validate",
]

#: The swing fields ``simulate`` takes, in the command line's units.
SWING_FIELDS = ("ball_speed", "bat_cm_speed", "bat_angular_speed", "impact_z")
#: The oblique and three-dimensional fields (undercut m, angles degrees, pitch spin rpm, batter side).
OBLIQUE_FIELDS = (
    "undercut",
    "attack_angle",
    "pitch_angle",
    "pitch_spin",
    "tangential_cor",
    "friction",
    "tangential_stiffness_ratio",
    "bat_tilt",
    "swing_direction",
    "batter_side",
)


class Bat:
    """A bat: a preset (``r161``, ``r161-corked``, ``aluminum``, ``torpedo``) or a bat file (TOML).

    >>> bat = Bat.preset("r161")
    >>> round(bat.properties()["mass"], 3)
    0.869
    """

    def __init__(self, native: _native.Bat, spec: str):
        self._native = native
        self._spec = spec

    @classmethod
    def preset(cls, name: str) -> "Bat":
        """The built-in bat ``name``; ``ValueError`` for an unknown one."""
        return cls(_native.Bat.preset(name), name)

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> "Bat":
        """A bat file (TOML, profile inline or in a CSV beside it: docs/file-formats.md).

        ``FileNotFoundError`` when it does not exist, ``ValueError`` (with the command line's message) when
        it is not a valid bat."""
        path = os.fspath(path)
        return cls(_native.Bat.from_file(path), os.path.abspath(path))

    @staticmethod
    def preset_names() -> list[str]:
        """The built-in bats."""
        return list(_native.Bat.preset_names())

    @property
    def name(self) -> str:
        """The preset name or the file's ``name`` (its stem by default)."""
        return self._native.name

    def properties(self) -> dict[str, Any]:
        """Mass properties as ``sweetspot simulate --json``'s ``bat``: ``mass`` kg, ``length`` m,
        ``center_of_mass`` m from the knob, ``moment_of_inertia`` kg·m² about the CM, ``radius_of_gyration``
        m, ``pivot_z`` m, ``moment_about_pivot`` kg·m², ``center_of_percussion`` m from the knob."""
        return json.loads(self._native.properties_json())

    def modes(self, count: int = 8) -> pd.DataFrame:
        """The first ``count`` vibrational modes (free-free), as ``sweetspot modes --json``: one row per
        mode with ``frequency_hz``, ``nodes`` (m from the knob) and ``modal_mass`` (kg); a hollow bat's
        barrel hoop mode along the barrel is in ``attrs["hoop"]``.

        >>> modes = Bat.preset("r161").modes(2)
        >>> list(modes.columns)
        ['frequency_hz', 'nodes', 'modal_mass']
        """
        document = json.loads(self._native.modes_json(count))
        frame = pd.DataFrame(document["modes"]).set_index("mode")
        frame.attrs["bat"] = document["bat"]
        if document.get("hoop") is not None:
            frame.attrs["hoop"] = document["hoop"]
        return frame

    def __repr__(self) -> str:
        return f"Bat({self._spec!r})"


class Ball:
    """A ball: a preset (``baseball``, ``bbcor``, ``mlb``, ``mlb2024``) with any field replaced.

    >>> Ball.preset("mlb2024", cor=0.5).cor
    0.5
    """

    _FIELDS = ("mass", "radius", "cor", "stiffness", "exponent", "cor_speed_exponent", "cor_reference_speed")

    def __init__(self, native: _native.Ball):
        self._native = native

    @classmethod
    def preset(cls, name: str = "mlb2024", **overrides: float) -> "Ball":
        """The built-in ball ``name`` with ``overrides`` among ``mass`` (kg), ``radius`` (m), ``cor`` (e0),
        ``stiffness`` (k1, N/m^α), ``exponent`` (α), ``cor_speed_exponent`` (p of e0 ∝ v^−p),
        ``cor_reference_speed`` (m/s), checked as ``--ball-*`` are (``ValueError``)."""
        unknown = set(overrides) - set(cls._FIELDS)
        if unknown:
            raise TypeError(f"unknown ball field(s) {sorted(unknown)}: expected {', '.join(cls._FIELDS)}")
        return cls(_native.Ball.preset(name, **{k: float(v) for k, v in overrides.items()}))

    @staticmethod
    def preset_names() -> list[str]:
        """The built-in balls."""
        return list(_native.Ball.preset_names())

    def to_dict(self) -> dict[str, float]:
        """Every field, SI units."""
        return {f: getattr(self._native, f) for f in self._FIELDS}

    def __getattr__(self, name: str) -> float:
        if name in Ball._FIELDS:
            return getattr(self._native, name)
        raise AttributeError(name)

    def __repr__(self) -> str:
        return repr(self._native)


class Collision:
    """One collision: every field of ``sweetspot simulate --json``'s result, as attributes.

    ``exit_speed`` m/s, ``rigid_exit_speed`` m/s, ``effective_cor``, ``collision_efficiency``,
    ``contact_time`` s, ``peak_force`` N, ``impulse`` N·s, ``max_compression`` m, ``energy`` (dict, J),
    ``mode_energies`` (numpy array, J per vibrational mode) with ``mode_frequencies_hz``, ``hoop`` (dict or
    None), ``oblique`` (the batted ball of an oblique run: dict or None). The inputs as the command line
    echoes them are ``bat``, ``ball``, ``swing``, ``options``, ``oblique_inputs``; ``document`` is the whole
    JSON document.
    """

    def __init__(self, document: dict[str, Any], index: int = 0):
        self.document = document
        self._result = document["results"][index]
        self.mode_energies = np.array([m["energy"] for m in self._result["mode_energies"]], dtype=float)
        self.mode_frequencies_hz = np.array([m["frequency_hz"] for m in self._result["mode_energies"]], dtype=float)

    bat = property(lambda self: self.document["bat"], doc="The bat's mass properties (dict).")
    ball = property(lambda self: self.document["ball"], doc="The ball (dict, SI).")
    swing = property(lambda self: self.document["swing"], doc="The swing (dict, SI).")
    options = property(lambda self: self.document["options"], doc="Modes and time step (dict).")
    oblique_inputs = property(lambda self: self.document.get("oblique"), doc="Oblique inputs or None.")

    @property
    def hoop(self) -> dict[str, float] | None:
        """The barrel wall's hoop mode at the impact point (hollow bats), else None."""
        return self._result.get("hoop")

    @property
    def oblique(self) -> dict[str, Any] | None:
        """The batted ball of an oblique or three-dimensional run, else None."""
        return self._result.get("oblique")

    def __getattr__(self, name: str) -> Any:
        result = self.__dict__.get("_result", {})
        if name in result:
            return result[name]
        raise AttributeError(name)

    def to_dict(self) -> dict[str, Any]:
        """The result as the command line's JSON has it."""
        return dict(self._result)

    def __repr__(self) -> str:
        return f"Collision(impact_z={self.impact_z!r}, exit_speed={self.exit_speed!r})"


def _side_code(value: Any) -> float:
    text = str(value).strip().lower()
    if text in ("right", "r", "0", "0.0"):
        return 0.0
    if text in ("left", "l", "1", "1.0"):
        return 1.0
    raise ValueError(f"batter_side {value!r}: expected right or left")


def _is_scalar(value: Any) -> bool:
    return value is None or isinstance(value, str) or np.ndim(value) == 0


def simulate(
    bat: Bat,
    ball: Ball | None = None,
    swings: pd.DataFrame | None = None,
    *,
    ball_speed: Any = 40.0,
    bat_cm_speed: Any = 25.0,
    bat_angular_speed: Any = 45.0,
    impact_z: Any = None,
    modes: int = 18,
    dt: float = 5e-6,
    errors: str = "raise",
    **oblique: Any,
) -> "Collision | pd.DataFrame":
    """Collisions of ``bat`` and ``ball`` (default ``mlb2024``), as ``sweetspot simulate`` computes them.

    The swing: ``ball_speed`` (m/s toward the bat), ``bat_cm_speed`` (m/s), ``bat_angular_speed`` (rad/s,
    barrel leading positive), ``impact_z`` (m from the knob; None: 0.15 m from the barrel end). Oblique and
    three-dimensional keywords as the command line's flags: ``undercut`` (m), ``attack_angle``,
    ``pitch_angle`` (degrees), ``pitch_spin`` (rpm), ``tangential_cor``, ``friction``,
    ``tangential_stiffness_ratio``, ``bat_tilt``, ``swing_direction`` (degrees), ``batter_side``
    (``"right"``/``"left"``). ``modes`` vibrational modes, RK4 step ``dt`` (s).

    All scalars: one :class:`Collision`. Any numpy array (they broadcast), or a DataFrame ``swings`` whose
    columns are named like the keywords (the keywords fill the columns it lacks): a DataFrame with one row
    per swing (the frame's index), the result fields with nested names joined by ``_`` (``energy_ball``,
    ``oblique_exit_speed``, ``hoop_frequency_hz``), the per-mode energies as ``mode_energy_1`` … (J; their
    frequencies in ``attrs["mode_frequencies_hz"]``). Swings run on every core with the GIL released. A row
    that cannot be computed raises ``ValueError`` naming it; ``errors="nan"`` leaves its values NaN with
    the message in an ``error`` column instead.

    >>> import numpy as np
    >>> frame = simulate(Bat.preset("r161"), impact_z=np.array([0.6, 0.7]))
    >>> frame["exit_speed"].round(2).tolist()
    [35.9, 47.1]
    """
    if errors not in ("raise", "nan"):
        raise ValueError(f"errors={errors!r}: expected 'raise' or 'nan'")
    unknown = set(oblique) - set(OBLIQUE_FIELDS)
    if unknown:
        raise TypeError(f"simulate() got unexpected keyword(s) {sorted(unknown)}")
    ball = ball if ball is not None else Ball.preset()
    given = {"ball_speed": ball_speed, "bat_cm_speed": bat_cm_speed, "bat_angular_speed": bat_angular_speed,
             "impact_z": impact_z, **{k: v for k, v in oblique.items() if v is not None}}
    if swings is None and all(_is_scalar(v) for v in given.values()):
        zs = [] if impact_z is None else [float(impact_z)]
        kwargs = {k: (v if k == "batter_side" else float(v)) for k, v in oblique.items() if v is not None}
        text = _native.simulate_document(bat._native, ball._native, float(ball_speed), float(bat_cm_speed),
                                         float(bat_angular_speed), zs, modes=modes, dt=dt, **kwargs)
        return Collision(json.loads(text))
    return _simulate_frame(bat, ball, swings, given, modes, dt, errors)


def _simulate_frame(bat: Bat, ball: Ball, swings: pd.DataFrame | None, given: dict[str, Any], modes: int,
                    dt: float, errors: str) -> pd.DataFrame:
    columns: dict[str, Any] = {}
    index = None
    if swings is not None:
        if not isinstance(swings, pd.DataFrame):
            raise TypeError("swings: expected a pandas DataFrame")
        index = swings.index
        for name in SWING_FIELDS + OBLIQUE_FIELDS:
            if name in swings.columns:
                columns[name] = swings[name].to_numpy()
    for name, value in given.items():
        if name not in columns and value is not None:
            columns[name] = value
    if "batter_side" in columns:
        columns["batter_side"] = np.vectorize(_side_code, otypes=[float])(np.asarray(columns["batter_side"]))
    if columns.get("impact_z") is None:
        columns["impact_z"] = np.nan
    if "tangential_stiffness_ratio" in columns:
        columns["tangential_stiffness_ratio"] = np.asarray(columns["tangential_stiffness_ratio"], dtype=float)
    names = list(columns)
    try:
        arrays = np.broadcast_arrays(*[np.asarray(columns[n], dtype=float) for n in names])
    except ValueError as e:
        raise ValueError(f"the swing's arrays do not broadcast together: {e}") from None
    if index is not None and arrays[0].shape != (len(index),):
        arrays = [np.broadcast_to(a, (len(index),)) for a in arrays]
    shape = arrays[0].shape
    flat = {n: np.ascontiguousarray(a.reshape(-1), dtype=np.float64) for n, a in zip(names, arrays)}
    out = _native.simulate_columns(bat._native, ball._native, flat, modes=modes, dt=dt)
    failures = out.pop("errors")
    if failures and errors == "raise":
        row, message = failures[0]
        where = index[row] if index is not None else np.unravel_index(row, shape) if len(shape) > 1 else row
        more = f" (and {len(failures) - 1} more rows)" if len(failures) > 1 else ""
        raise ValueError(f"swing {where!r}: {message}{more}")
    energies = out.pop("mode_energies")
    frequencies = out.pop("mode_frequencies_hz")
    data = {}
    for name, values in out.items():
        optional = name.startswith(("hoop_", "oblique_", "energy_hoop"))
        if optional and np.isnan(values).all():
            continue
        data[name] = values
    frame = pd.DataFrame(data, index=index)
    if "oblique_sliding" in frame:
        frame["oblique_sliding"] = frame["oblique_sliding"].map({1.0: True, 0.0: False}).astype("boolean")
    for k in range(energies.shape[1]):
        frame[f"mode_energy_{k + 1}"] = energies[:, k]
    if failures:
        messages = pd.Series(pd.NA, index=frame.index, dtype="string")
        for row, message in failures:
            messages.iloc[row] = message
        frame["error"] = messages
    frame.attrs["mode_frequencies_hz"] = frequencies.tolist()
    return frame


def sweep(
    bat: "Bat | str",
    ball: Ball | None = None,
    *,
    over: str = "z",
    ball_speed: float = 40.0,
    bat_cm_speed: float = 25.0,
    bat_angular_speed: float = 45.0,
    impact_z: float | None = None,
    from_: float | None = None,
    to: float | None = None,
    step: float | None = None,
    points: int | None = None,
    modes: int = 18,
    dt: float = 5e-6,
    **oblique: Any,
) -> pd.DataFrame:
    """``sweetspot sweep --json`` as a DataFrame, one row per point of the sweep.

    ``over="z"``: head-on collisions of the swing (``ball_speed``, ``bat_cm_speed`` m/s,
    ``bat_angular_speed`` rad/s) at impact points ``from_`` … ``to`` (m from the knob; default the last
    0.35 m of the bat to 1 cm from its end) by ``step`` (m, default 0.005) or in ``points`` points: each
    row the command line's result (``impact_z`` m, ``exit_speed`` and ``rigid_exit_speed`` m/s, …, nested
    fields joined by ``_``); the sweet-spot set (m from the knob, m/s) in ``attrs["sweet_spots"]``, the
    nodes of modes 1 and 2 in ``attrs["nodes"]``.

    ``over="undercut"``: oblique collisions at ``impact_z`` (m; default 0.15 m from the barrel end) over
    undercuts ``from_`` … ``to`` (m; default ±0.75 of ball plus barrel radius, 37 points), the other
    oblique keywords of :func:`simulate` held (degrees, rpm): each row ``undercut`` m, ``exit_speed`` m/s,
    ``launch_angle_deg``, ``spin_rpm``, spray and spin axis, ``sliding``.

    The bat, ball, swing and options as echoed are in ``attrs``. Bad inputs raise ``ValueError`` with the
    command line's message.

    >>> frame = sweep("r161", from_=0.6, to=0.8, points=3)
    >>> frame["impact_z"].round(2).tolist(), frame["exit_speed"].round(1).tolist()
    ([0.6, 0.7, 0.8], [35.9, 47.1, 32.9])
    """
    unknown = set(oblique) - set(OBLIQUE_FIELDS)
    if unknown:
        raise TypeError(f"sweep() got unexpected keyword(s) {sorted(unknown)}")
    if "undercut" in oblique:
        raise ValueError("undercut is the swept variable of over='undercut': give its range with from_/to")
    bat = _bat_of(bat)
    ball = ball if ball is not None else Ball.preset()
    kwargs = {k: (v if k == "batter_side" else float(v)) for k, v in oblique.items() if v is not None}
    text = _native.sweep_document(bat._native, ball._native, float(ball_speed), float(bat_cm_speed),
                                  float(bat_angular_speed), over=over,
                                  impact_z=None if impact_z is None else float(impact_z),
                                  from_=None if from_ is None else float(from_), to=None if to is None else float(to),
                                  step=None if step is None else float(step), points=points, modes=modes, dt=dt,
                                  **kwargs)
    document = json.loads(text)
    frame = _flat(document.pop("points"))
    document.pop("plot", None)
    frame.attrs.update(document)
    return frame


def bbcor(bat: "Bat | str", ball: Ball | None = None, *, modes: int = 18, dt: float = 5e-6) -> dict[str, Any]:
    """The NCAA BBCOR and ASTM BESR of ``bat`` as ``sweetspot bbcor --json`` reports them (the protocol ball
    ``bbcor`` unless ``ball`` is given): ``bbcor`` (dimensionless, its ``impact_z`` m from the knob) and
    ``besr``, with the bat, ball and options.

    >>> round(bbcor("r161")["bbcor"]["bbcor"], 3)
    0.498
    """
    bat = _bat_of(bat)
    return json.loads(_native.bbcor_document(bat._native, None if ball is None else ball._native, modes=modes,
                                             dt=dt))


def compare(
    bats: "Sequence[Bat | str]",
    *,
    batter: "str | os.PathLike | None" = None,
    ball: Ball | None = None,
    pitch_speed: float = 40.0,
    modes: int = 18,
    dt: float = 5e-6,
) -> pd.DataFrame:
    """``bats`` swung by one batter (a batter file as ``compare --batter`` reads; default the Statcast-average
    batter) against a pitch at ``pitch_speed`` m/s, as ``sweetspot compare --json``: one row per bat (indexed
    by name) with its swing weight (kg·m²), bat speeds (m/s, rad/s), impact point and sweet spot (m from the
    knob), exit speeds (m/s), BBCOR, swing time (s); the batter, ball and options in ``attrs``."""
    natives = [_bat_of(b)._native for b in bats]
    ball = ball if ball is not None else Ball.preset()
    document = json.loads(_native.compare_document(natives, ball._native,
                                                   batter=None if batter is None else os.fspath(batter),
                                                   pitch_speed=float(pitch_speed), modes=modes, dt=dt))
    frame = pd.DataFrame(document["bats"]).set_index("name")
    frame.attrs.update({k: v for k, v in document.items() if k != "bats"})
    return frame


def _export_columns(frame: pd.DataFrame) -> list[tuple[str, Any]]:
    """The frame's columns as the export it stands for, for the importer to read as it reads a file: numbers
    as float64/int64 arrays (no copy where the frame's own are), every other column as its text (missing
    cells None). The extension writes them as CSV (``to_csv``'s numbers and quoting, a line break inside a
    text cell a space, so line ``n + 2`` is row ``n``)."""
    columns = []
    for k, name in enumerate(frame.columns):
        series = frame.iloc[:, k]
        kind = series.dtype.kind
        if kind == "f":
            values = np.ascontiguousarray(series.to_numpy(dtype=np.float64, na_value=np.nan))
        elif kind == "i" and not series.hasnans:
            values = np.ascontiguousarray(series.to_numpy(dtype=np.int64))
        else:
            values = series.astype("string").to_numpy(dtype=object, na_value=None).tolist()
        columns.append((str(name), values))
    return columns


def _bat_of(bat: "Bat | str") -> Bat:
    if isinstance(bat, Bat):
        return bat
    if bat in _native.Bat.preset_names():
        return Bat.preset(bat)
    return Bat.from_file(bat)


def read_tracker(
    source: "str | os.PathLike | pd.DataFrame",
    kind: str | None = None,
    *,
    bat: "Bat | str" = "r161",
    ball: str = "mlb2024",
    batter: "str | os.PathLike | None" = None,
    undercut: float = 0.0,
    tee: bool = False,
) -> pd.DataFrame:
    """A tracker export (TrackMan, Baseball Savant/Statcast, HitTrax CSV; ``kind`` forces one) read as
    ``sweetspot import`` reads it, one row per record: ``line`` in the file, the tracker's values in SI
    units and the model's signs (speeds m/s, angles rad, spins rad/s; NaN = not measured), the swing it
    became (``swing_id``, ``bat_cm_speed``, ``bat_angular_speed``, ``impact_z``, the fields ``assumed``) or
    why not (``skipped``; ``refused`` holds the message of a row refused as bad input).

    ``source`` is a path or a DataFrame (e.g. pybaseball's ``statcast()``). An unknown header raises
    ``ValueError``; a missing file ``FileNotFoundError``."""
    bat = _bat_of(bat)
    common = dict(kind=kind, bat=bat._native, bat_spec=bat._spec, ball=ball,
                  batter=None if batter is None else os.fspath(batter), undercut=float(undercut), tee=tee)
    if isinstance(source, pd.DataFrame):
        columns = _native.read_tracker_columns(columns=_export_columns(source), name="DataFrame", **common)
        index = source.index
    else:
        columns = _native.read_tracker_columns(path=os.fspath(source), **common)
        index = None
    fmt = columns.pop("format")
    frame = pd.DataFrame(columns)
    frame["swing_id"] = frame["swing_id"].astype("UInt64")
    frame["time_ns"] = frame["time_ns"].astype("UInt64")
    frame["contact"] = frame["contact"].astype("boolean")
    for name in ("skipped", "refused"):
        frame[name] = frame[name].astype("string")
    if index is not None and len(index) == len(frame):
        frame.index = index
    frame.attrs["format"] = fmt
    return frame


#: The columns of ``locate``'s DataFrame, with their dtypes.
LOCATE_COLUMNS = {
    "bat_id": "string",
    "verdict": "string",
    "measured_exit_speed": "float64",
    "measured_launch_angle": "float64",
    "measured_spin": "float64",
    "impact_z": "float64",
    "impact_z_sigma": "float64",
    "undercut": "float64",
    "undercut_sigma": "float64",
    "undercut_fitted": "boolean",
    "side": "string",
    "sweet_spot_z": "float64",
    "chi2": "float64",
    "model_exit_speed": "float64",
    "model_launch_angle": "float64",
    "model_spin": "float64",
    "solutions": "int64",
    "favoured": "boolean",
    "squared_up": "boolean",
    "max_exit_speed": "float64",
    "excess": "float64",
    "reason": "string",
}


def locate_meta() -> pd.DataFrame:
    """An empty frame shaped like ``locate``'s answer (Dask's ``meta``)."""
    return pd.DataFrame({k: pd.Series(dtype=v) for k, v in LOCATE_COLUMNS.items()})


def _locate_frame(columns: dict[str, Any], index: Any = None) -> pd.DataFrame:
    """``locate``'s DataFrame of the columns the extension built (nullable booleans as 1/0/-1)."""
    data: dict[str, Any] = {}
    for name, dtype in LOCATE_COLUMNS.items():
        values = columns[name]
        if dtype == "boolean":
            values = pd.arrays.BooleanArray(values == 1, values < 0)
        data[name] = values
    return pd.DataFrame(data, index=index).astype(LOCATE_COLUMNS)


def locate(
    source: "str | os.PathLike | pd.DataFrame",
    *,
    bat: "Bat | str" = "r161",
    ball: str = "mlb2024",
    kind: str | None = None,
    batter: "str | os.PathLike | None" = None,
    undercut: float = 0.0,
    tee: bool = False,
    exit_speed_sigma: float = 0.45,
    launch_angle_sigma: float = 1.0,
    spin_sigma: float = 100.0,
    fit_bat_speed: bool = False,
) -> pd.DataFrame:
    """Where on the bat each ball was hit, as ``sweetspot locate --json`` finds it: one row per swing with
    the ``verdict`` (located, too_fast, not_reproducible, not_measured, failed), the measured values (SI:
    m/s, rad, rad/s), and the solution the measurements favour (else the handle-side one): ``impact_z`` ±
    ``impact_z_sigma`` (m from the knob), ``undercut`` ± ``undercut_sigma`` (m), ``side`` of the sweet spot
    ``sweet_spot_z``, ``chi2``, the model's values there; ``solutions`` counts them all (the whole report
    is in ``attrs["report"]`` for a bag).

    ``source`` is a bag (directory or .mcap: its swings, bats and balls) or a tracker DataFrame (a
    pybaseball/Baseball Savant frame as is, TrackMan, HitTrax), imported as ``sweetspot import --bat BAT
    --ball BALL`` would import its CSV: the answer is indexed like the frame, one row per row that became a
    swing. Tracker accuracies: ``exit_speed_sigma`` m/s, ``launch_angle_sigma`` degrees, ``spin_sigma`` rpm.
    Swings run on every core with the GIL released."""
    sigmas = dict(exit_speed_sigma=float(exit_speed_sigma), launch_angle_sigma=float(launch_angle_sigma),
                  spin_sigma=float(spin_sigma), fit_bat_speed=fit_bat_speed)
    if not isinstance(source, pd.DataFrame):
        text, columns = _native.locate_bag(os.fspath(source), **sigmas)
        frame = _locate_frame(columns)
        frame.insert(0, "swing_id", pd.array(columns["swing_id"], dtype="UInt64"))
        frame.attrs["report"] = json.loads(text)
        return frame
    bat = _bat_of(bat)
    try:
        counts, columns, lines = _native.locate_export(_export_columns(source), kind=kind, bat=bat._native,
                                                       bat_spec=bat._spec, ball=ball,
                                                       batter=None if batter is None else os.fspath(batter),
                                                       undercut=float(undercut), tee=tee, **sigmas)
    except ValueError as e:
        if "no row became a swing" in str(e):
            return locate_meta().set_axis(source.index[:0])
        raise
    # Line n + 2 of the export is the frame's row n (the header is line 1).
    frame = _locate_frame(columns, index=source.index[lines.astype(np.int64) - 2])
    frame.attrs["report"] = {k: v for k, v in json.loads(counts).items() if k != "swings"}
    return frame


def _flat(messages: Sequence[Mapping[str, Any]]) -> pd.DataFrame:
    return pd.json_normalize(list(messages), sep="_") if messages else pd.DataFrame()


def _arrow_table(rows: Sequence[Mapping[str, Any]], log_time_ns: Sequence[int], namespace: Any) -> Any:
    """Messages as an Arrow table: struct fields flattened to columns named as the DataFrame's (``_``)."""
    import pyarrow as pa

    if rows:
        table = pa.Table.from_struct_array(pa.array(list(rows)))
        while any(pa.types.is_struct(field.type) for field in table.schema):
            table = table.flatten()
        table = table.rename_columns([name.replace(".", "_") for name in table.column_names])
    else:
        table = pa.table({})
    table = table.add_column(0, "log_time_ns", pa.array(log_time_ns, type=pa.uint64()))
    return table.add_column(1, "namespace", pa.array(namespace, type=pa.string()))


def read_bag(path: "str | os.PathLike", *, arrow: bool = False) -> "dict[str, pd.DataFrame] | dict[str, Any]":
    """A bag's messages (sweetspot's types) as one DataFrame per topic, keyed by topic name, each with
    ``log_time_ns`` (ns since the epoch) and ``namespace``; and ``"swings"``: every recorded swing joined to
    its answer by (namespace, swing_id) as ``bag export --csv`` joins them, the answer's ExitVelocity fields
    prefixed ``exit_velocity_`` and ModalEnergies ``modal_energies_``. Nested fields joined by ``_``
    (``header_stamp_sec``); numbers in the messages' SI units. A damaged or unreadable bag raises
    :class:`BagError`, a missing one ``FileNotFoundError``.

    ``arrow=True`` gives a ``pyarrow.Table`` per topic instead (the same columns, in the messages' field
    order; arrays as list columns, missing values null), built by Arrow from the messages without pandas; it
    needs pyarrow (``pip install sweetspot[arrow]``).

    >>> frames = read_bag("bags/golden/sweetspot_golden")
    >>> frames["swings"]["impact_z"].head(2).tolist()  # m from the knob
    [0.6, 0.65]
    >>> tables = read_bag("bags/golden/sweetspot_golden", arrow=True)
    >>> tables["swings"].column("swing_id").to_pylist()[:2]
    [1, 2]
    """
    if arrow:
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise ImportError("read_bag(arrow=True) needs pyarrow: pip install pyarrow") from None
    document = json.loads(_native.read_bag_document(os.fspath(path)))
    rows = []
    for s in document["swings"]:
        row = {"namespace": s["namespace"], "log_time_ns": s["log_time_ns"], **s["swing"]}
        for part in ("exit_velocity", "modal_energies"):
            if s[part] is not None:
                row[part] = s[part]
        rows.append(row)
    if arrow:
        tables = {t["topic"]: _arrow_table(t["messages"], t["log_time_ns"], [t["namespace"]] * len(t["messages"]))
                  for t in document["topics"]}
        answers = [{k: v for k, v in r.items() if k not in ("namespace", "log_time_ns")} for r in rows]
        swings = _arrow_table(answers, [r["log_time_ns"] for r in rows], [r["namespace"] for r in rows])
        tables["swings"] = swings.select(["namespace", "log_time_ns", *swings.column_names[2:]])
        return tables
    frames: dict[str, pd.DataFrame] = {}
    for topic in document["topics"]:
        frame = _flat(topic["messages"])
        frame.insert(0, "log_time_ns", pd.array(topic["log_time_ns"], dtype="UInt64"))
        frame.insert(1, "namespace", topic["namespace"])
        frame.attrs["type"] = topic["type"]
        frames[topic["topic"]] = frame
    swings = _flat(rows)
    if "log_time_ns" in swings:
        swings["log_time_ns"] = swings["log_time_ns"].astype("UInt64")
    frames["swings"] = swings
    return frames


#: The columns of ``validate``'s DataFrame (the command line's row fields), in order.
VALIDATE_COLUMNS = ("id", "quantity", "unit", "conditions", "rule", "low", "high", "reference", "model", "ratio",
                    "verdict", "model_detail", "tolerance", "source", "read_from", "note")


def validate(data: "str | os.PathLike | None" = None, *, tangential_stiffness_ratio: float | None = None,
             modes: int = 18, dt: float = 5e-6) -> pd.DataFrame:
    """The model against published measurements, as ``sweetspot validate --json``: one row per measurement,
    indexed by its ``id``, with the ``quantity`` compared, its ``unit`` and ``conditions``, the ``rule``
    and bounds (``low``, ``high``; ``reference`` of a ratio), the ``model``'s number and ``ratio``, the
    ``verdict`` (``PASS``, ``FAIL``, ``N/A``), how the model got it (``model_detail``), the ``tolerance``
    in words, the ``source`` and where in it the number was read (``read_from``), and a ``note``. Numbers
    are in the row's ``unit``. The counts (``pass``, ``fail``, ``not_applicable``), the TrackMan bins, what
    was not found and the files read are in ``attrs``. A FAIL row is a finding about the model, not an
    error: nothing is raised for it.

    ``data`` is the suite's directory (default ``./validation``, else the source tree's);
    ``tangential_stiffness_ratio`` runs the oblique rows with the compliant contact law (η² = k_n/k_t).

    >>> rows = validate()
    >>> rows.loc["wood-first-bending-mode", ["unit", "verdict"]].tolist()
    ['Hz', 'PASS']
    """
    text = _native.validate_document(None if data is None else os.fspath(data),
                                     tangential_stiffness_ratio=tangential_stiffness_ratio, modes=modes, dt=dt)
    document = json.loads(text)
    frame = pd.DataFrame(document.pop("rows"), columns=list(VALIDATE_COLUMNS))
    for name in ("low", "high", "reference", "model", "ratio"):
        frame[name] = frame[name].astype("float64")
    frame = frame.set_index("id")
    frame.attrs.update(document)
    return frame
