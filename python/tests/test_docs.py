"""docs/python.md runs as written, and its API types as the stubs say.

An audit ran the tutorial's blocks in order and found a SyntaxError (a
`{"t": 0.01, ...}` sample), names used before the block that makes them
(`cal`), placeholders never defined (`t_block`, `trial_a`) and a call
Python could not make (`simulate("knee-fes", calibration=...)`); and it
found `mypy --strict` rejecting calls the docs show while passing a
misspelt `limbfuse.estimat`.
"""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOC = REPO / "docs" / "python.md"


def python_blocks(text):
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def test_python_md_runs_in_order(cli, tmp_path, monkeypatch):
    """Every ```python block of docs/python.md, run in order in one namespace
    (as a notebook would), from a folder holding the files its comments say
    the CLI makes."""
    cli("simulate", "walking", "--duration", "20", "-o", tmp_path / "trial.csv")
    cli("simulate", "walking", "--duration", "20", "-o", tmp_path / "trial.arrow")
    cli("params", "--method", "mjls", "-o", tmp_path / "mjls.toml")
    cli("simulate", "walking", "--duration", "20", "--gait-reference", "-o", tmp_path / "walk.csv")
    cli("estimate", "--method", "mjls", tmp_path / "walk.csv", "-o", tmp_path / "walk-mjls.csv")
    cli("estimate", "--method", "gait-events", tmp_path / "walk.csv", "-o", tmp_path / "walk-events.csv")
    for folder, extra in (("data", []), ("walks", ["--gait-reference"])):
        (tmp_path / folder).mkdir()
        for seed in (1, 2):
            cli("simulate", "walking", "--duration", "15", "--seed", seed, *extra,
                "-o", tmp_path / folder / f"w{seed}.csv")
    monkeypatch.chdir(tmp_path)
    blocks = python_blocks(DOC.read_text(encoding="utf-8"))
    assert len(blocks) >= 8, "the tutorial's blocks were not found"
    namespace = {"__name__": "__main__"}
    for i, code in enumerate(blocks):
        try:
            exec(compile(code, f"docs/python.md block {i}", "exec"), namespace)
        except Exception as e:  # (the block's number and first line name it)
            pytest.fail(f"docs/python.md block {i} ({code.splitlines()[0]!r}) failed: {e!r}")
    assert (tmp_path / "standing.csv").is_file()
    assert (tmp_path / "report.html").is_file()


USER_SCRIPT = '''
from typing import List
import numpy as np
import pandas as pd
import limbfuse
from limbfuse import cohort

trial = limbfuse.simulate("walking", duration=5)
est = limbfuse.estimate(trial, "mjls")
ev = limbfuse.evaluate(trial, est, max_lag=np.int64(5))
f = limbfuse.Filter("mjls", channels=trial.channels, meta=trial.meta)
f2 = limbfuse.Filter("mjls", channels=trial.channels.keys())
out = f.step({"t": 0.01, "thigh_gyr_x": np.ma.masked, "thigh_gyr_y": np.float32(0.1)})
e2 = f.run(trial.to_pandas())
limbfuse.report(trial, est, "r.html")
limbfuse.gait_library("lib.json", np.linspace(0.5, 0.7, 3))
names: List[str] = f.channels + est.columns + est.header
method: str = est.method

def metrics() -> pd.DataFrame:
    return cohort.run("data/*.csv", "mjls")

limbfuse.estimat(trial, "mjls")  # type: ignore[attr-defined]
est.method = 5  # type: ignore[assignment]
'''


def test_the_documented_calls_type_check_and_a_misspelling_does_not(tmp_path):
    """`mypy --strict` on a user's script: the documented calls pass, a
    misspelt function and a wrong attribute type are errors (each line's
    `type: ignore` would be reported unused otherwise:
    `--warn-unused-ignores`, part of `--strict`)."""
    import mypy.api as mypy  # (in the package's [test] extra)
    script = tmp_path / "user.py"
    script.write_text(USER_SCRIPT, encoding="utf-8")
    out, err, status = mypy.run(
        ["--strict", "--no-incremental", "--cache-dir", os.devnull, str(script)]
    )
    assert status == 0, out + err


def test_the_package_type_checks(tmp_path):
    """The package's own annotations are consistent (mypy, default mode)."""
    import mypy.api as mypy  # (in the package's [test] extra)

    out, err, status = mypy.run(
        ["--no-incremental", "--cache-dir", os.devnull, "-p", "limbfuse"]
    )
    assert status == 0, out + err
