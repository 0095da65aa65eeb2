"""docs/python.md's ```python blocks run, in order, in one namespace (```py blocks are shown, not run: a
cluster address); examples/python/season.py runs on a small Savant export and writes a PNG."""

import re
import subprocess
import sys

import pandas as pd

import sweetspot


def test_the_python_guides_code_runs(repo, monkeypatch):
    text = (repo / "docs/python.md").read_text(encoding="utf-8")
    blocks = re.findall(r"^```python\n(.*?)^```$", text, flags=re.S | re.M)
    assert len(blocks) >= 5
    monkeypatch.chdir(repo)
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)


def test_the_season_example_locates_and_plots(repo, tmp_path):
    export = repo / "tests/data/statcast_search.csv"
    png = tmp_path / "season.png"
    done = subprocess.run([sys.executable, repo / "examples/python/season.py", export, "-o", png],
                          capture_output=True, text=True, check=True)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    located = sweetspot.locate(pd.read_csv(export))
    count = int((located["verdict"] == "located").sum())
    assert done.stdout.startswith(f"{count} of {len(located)} swings located")
