"""Type stubs of the extension module (the Rust side); use the functions of ``sweetspot`` itself."""

from typing import Any

import numpy as np
import numpy.typing as npt

class BagError(Exception):
    """A bag that cannot be read (damaged, not MCAP, not a bag)."""

class Bat:
    @staticmethod
    def preset(name: str) -> Bat: ...
    @staticmethod
    def from_file(path: str) -> Bat: ...
    @staticmethod
    def preset_names() -> list[str]: ...
    @property
    def name(self) -> str: ...
    def properties_json(self) -> str: ...
    def modes_json(self, count: int) -> str: ...

class Ball:
    @staticmethod
    def preset(
        name: str,
        *,
        mass: float | None = None,
        radius: float | None = None,
        cor: float | None = None,
        stiffness: float | None = None,
        exponent: float | None = None,
        cor_speed_exponent: float | None = None,
        cor_reference_speed: float | None = None,
    ) -> Ball: ...
    @staticmethod
    def preset_names() -> list[str]: ...
    @property
    def mass(self) -> float: ...
    @property
    def radius(self) -> float: ...
    @property
    def cor(self) -> float: ...
    @property
    def stiffness(self) -> float: ...
    @property
    def exponent(self) -> float: ...
    @property
    def cor_speed_exponent(self) -> float: ...
    @property
    def cor_reference_speed(self) -> float: ...

def simulate_document(
    bat: Bat,
    ball: Ball,
    ball_speed: float,
    bat_cm_speed: float,
    bat_angular_speed: float,
    impact_z: list[float],
    *,
    modes: int = 18,
    dt: float = 5e-6,
    **oblique: float | str | None,
) -> str: ...
def simulate_columns(
    bat: Bat, ball: Ball, columns: dict[str, npt.NDArray[np.float64]], *, modes: int = 18, dt: float = 5e-6
) -> dict[str, Any]: ...
def bbcor_document(bat: Bat, ball: Ball | None = None, *, modes: int = 18, dt: float = 5e-6) -> str: ...
def compare_document(
    bats: list[Bat], ball: Ball, *, batter: str | None = None, pitch_speed: float = 40.0, modes: int = 18,
    dt: float = 5e-6
) -> str: ...
def read_tracker_columns(
    *,
    path: str | None = None,
    columns: list[tuple[str, Any]] | None = None,
    name: str = "DataFrame",
    kind: str | None = None,
    bat: Bat,
    bat_spec: str,
    ball: str = "mlb2024",
    batter: str | None = None,
    undercut: float = 0.0,
    tee: bool = False,
) -> dict[str, Any]: ...
def locate_export(
    columns: list[tuple[str, Any]],
    *,
    name: str = "DataFrame",
    kind: str | None = None,
    bat: Bat,
    bat_spec: str,
    ball: str = "mlb2024",
    batter: str | None = None,
    undercut: float = 0.0,
    tee: bool = False,
    exit_speed_sigma: float = 0.45,
    launch_angle_sigma: float = 1.0,
    spin_sigma: float = 100.0,
    fit_bat_speed: bool = False,
) -> tuple[str, dict[str, Any], npt.NDArray[np.uint64]]: ...
def locate_bag(
    bag: str,
    *,
    exit_speed_sigma: float = 0.45,
    launch_angle_sigma: float = 1.0,
    spin_sigma: float = 100.0,
    fit_bat_speed: bool = False,
) -> tuple[str, dict[str, Any]]: ...
def read_bag_document(path: str) -> str: ...
def sweep_document(
    bat: Bat,
    ball: Ball,
    ball_speed: float,
    bat_cm_speed: float,
    bat_angular_speed: float,
    *,
    over: str = "z",
    impact_z: float | None = None,
    from_: float | None = None,
    to: float | None = None,
    step: float | None = None,
    points: int | None = None,
    modes: int = 18,
    dt: float = 5e-6,
    **oblique: float | str | None,
) -> str: ...
def validate_document(
    data: str | None = None,
    *,
    tangential_stiffness_ratio: float | None = None,
    modes: int = 18,
    dt: float = 5e-6,
) -> str: ...
