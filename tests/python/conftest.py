"""Shared fixtures of the Python package's tests: the repository, and the `sweetspot` command line they
compare the package with (the binary `cargo test`/`cargo build` made: SWEETSPOT_BIN, else target/{debug,release})."""

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def _binary() -> Path | None:
    if os.environ.get("SWEETSPOT_BIN"):
        return Path(os.environ["SWEETSPOT_BIN"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    found = [target / p / "sweetspot" for p in ("debug", "release") if (target / p / "sweetspot").is_file()]
    if found:
        return max(found, key=lambda p: p.stat().st_mtime)
    on_path = shutil.which("sweetspot")
    return Path(on_path) if on_path else None


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def cli():
    """Runs `sweetspot ARGS…`; returns the completed process (text)."""
    binary = _binary()
    if binary is None:
        pytest.fail("no sweetspot binary: run `cargo build` (or set SWEETSPOT_BIN)")

    def run(*args, check=True, cwd=None):
        done = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True, cwd=cwd)
        if check and done.returncode != 0:
            raise AssertionError(f"sweetspot {' '.join(map(str, args))} failed: {done.stderr}")
        return done

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    """Runs `sweetspot ARGS… --json` and parses its document."""

    def run(*args):
        return json.loads(cli(*args, "--json").stdout)

    return run
