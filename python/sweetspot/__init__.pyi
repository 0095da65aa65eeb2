"""Type stubs of the ``sweetspot`` package (units in each function's docstring)."""

import os
from typing import Any, Literal, Sequence, overload

import numpy as np
import numpy.typing as npt
import pandas as pd
import pyarrow as pa

from ._sweetspot import BagError as BagError

SWING_FIELDS: tuple[str, ...]
OBLIQUE_FIELDS: tuple[str, ...]
LOCATE_COLUMNS: dict[str, str]
VALIDATE_COLUMNS: tuple[str, ...]

class Bat:
    @classmethod
    def preset(cls, name: str) -> Bat: ...
    @classmethod
    def from_file(cls, path: str | os.PathLike[str]) -> Bat: ...
    @staticmethod
    def preset_names() -> list[str]: ...
    @property
    def name(self) -> str: ...
    def properties(self) -> dict[str, Any]: ...
    def modes(self, count: int = 8) -> pd.DataFrame: ...

class Ball:
    @classmethod
    def preset(cls, name: str = "mlb2024", **overrides: float) -> Ball: ...
    @staticmethod
    def preset_names() -> list[str]: ...
    def to_dict(self) -> dict[str, float]: ...
    mass: float
    radius: float
    cor: float
    stiffness: float
    exponent: float
    cor_speed_exponent: float
    cor_reference_speed: float

class Collision:
    document: dict[str, Any]
    mode_energies: npt.NDArray[np.float64]
    mode_frequencies_hz: npt.NDArray[np.float64]
    impact_z: float
    exit_speed: float
    rigid_exit_speed: float
    effective_cor: float
    collision_efficiency: float
    contact_time: float
    peak_force: float
    impulse: float
    max_compression: float
    energy: dict[str, float]
    @property
    def bat(self) -> dict[str, Any]: ...
    @property
    def ball(self) -> dict[str, Any]: ...
    @property
    def swing(self) -> dict[str, Any]: ...
    @property
    def options(self) -> dict[str, Any]: ...
    @property
    def oblique_inputs(self) -> dict[str, Any] | None: ...
    @property
    def hoop(self) -> dict[str, float] | None: ...
    @property
    def oblique(self) -> dict[str, Any] | None: ...
    def to_dict(self) -> dict[str, Any]: ...

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
    undercut: Any = None,
    attack_angle: Any = None,
    pitch_angle: Any = None,
    pitch_spin: Any = None,
    tangential_cor: Any = None,
    friction: Any = None,
    tangential_stiffness_ratio: Any = None,
    bat_tilt: Any = None,
    swing_direction: Any = None,
    batter_side: Any = None,
) -> Collision | pd.DataFrame: ...
def sweep(
    bat: Bat | str,
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
    attack_angle: float | None = None,
    pitch_angle: float | None = None,
    pitch_spin: float | None = None,
    tangential_cor: float | None = None,
    friction: float | None = None,
    tangential_stiffness_ratio: float | None = None,
    bat_tilt: float | None = None,
    swing_direction: float | None = None,
    batter_side: str | None = None,
) -> pd.DataFrame: ...
def bbcor(bat: Bat | str, ball: Ball | None = None, *, modes: int = 18, dt: float = 5e-6) -> dict[str, Any]: ...
def compare(
    bats: Sequence[Bat | str],
    *,
    batter: str | os.PathLike[str] | None = None,
    ball: Ball | None = None,
    pitch_speed: float = 40.0,
    modes: int = 18,
    dt: float = 5e-6,
) -> pd.DataFrame: ...
def read_tracker(
    source: str | os.PathLike[str] | pd.DataFrame,
    kind: str | None = None,
    *,
    bat: Bat | str = "r161",
    ball: str = "mlb2024",
    batter: str | os.PathLike[str] | None = None,
    undercut: float = 0.0,
    tee: bool = False,
) -> pd.DataFrame: ...
def locate_meta() -> pd.DataFrame: ...
def locate(
    source: str | os.PathLike[str] | pd.DataFrame,
    *,
    bat: Bat | str = "r161",
    ball: str = "mlb2024",
    kind: str | None = None,
    batter: str | os.PathLike[str] | None = None,
    undercut: float = 0.0,
    tee: bool = False,
    exit_speed_sigma: float = 0.45,
    launch_angle_sigma: float = 1.0,
    spin_sigma: float = 100.0,
    fit_bat_speed: bool = False,
) -> pd.DataFrame: ...
@overload
def read_bag(path: str | os.PathLike[str], *, arrow: Literal[False] = False) -> dict[str, pd.DataFrame]: ...
@overload
def read_bag(path: str | os.PathLike[str], *, arrow: Literal[True]) -> dict[str, pa.Table]: ...
def validate(
    data: str | os.PathLike[str] | None = None,
    *,
    tangential_stiffness_ratio: float | None = None,
    modes: int = 18,
    dt: float = 5e-6,
) -> pd.DataFrame: ...
