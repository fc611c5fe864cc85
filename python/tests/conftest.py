"""Shared fixtures: short simulated trials (written by the `limbfuse` CLI
when the binary is there, else by the package) and the CLI runner."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

import limbfuse

REPO = Path(__file__).resolve().parents[2]


def cli_binary():
    """The `limbfuse` binary: $LIMBFUSE_BIN, else the workspace's most
    recently built one (debug or release: a stale debug build left beside a
    fresh release build made the equivalence tests compare against old code)."""
    env = os.environ.get("LIMBFUSE_BIN")
    if env:
        if not Path(env).is_file():
            raise RuntimeError(f"LIMBFUSE_BIN={env} does not exist")
        return env
    built = [p for p in (REPO / "target" / prof / "limbfuse" for prof in ("debug", "release")) if p.is_file()]
    if built:
        return str(max(built, key=lambda p: p.stat().st_mtime))
    return shutil.which("limbfuse")


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI; skips the test when the binary is absent (scripts/test-all
    builds it first and sets LIMBFUSE_BIN, so CI never skips)."""
    exe = cli_binary()
    if exe is None:
        pytest.skip("the limbfuse CLI binary is not built (cargo build -p limbfuse-cli, or set LIMBFUSE_BIN)")

    def run(*args, check=True):
        r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"limbfuse {' '.join(map(str, args))} failed ({r.returncode}): {r.stderr}")
        return r

    return run


@pytest.fixture(scope="session")
def walking_trial():
    """A 10 s walking trial at 100 Hz, in memory."""
    return limbfuse.simulate("walking", duration=10.0, seed=3)


@pytest.fixture(scope="session")
def walking_file(tmp_path_factory, walking_trial):
    p = tmp_path_factory.mktemp("walking") / "walk.csv"
    walking_trial.write(p)
    return p


@pytest.fixture(scope="session")
def gait_library(tmp_path_factory):
    """A one-gait B-SLIP library (0.7 m/s), built once by the package:
    (file, the gait summaries `limbfuse.gait_library` returned)."""
    p = tmp_path_factory.mktemp("gait") / "lib.json"
    return p, limbfuse.gait_library(p, [0.7])


SHARED_DATA = REPO.parent / "shared" / "data"


@pytest.fixture(scope="session")
def shared_data():
    """The path of a file or folder of ../shared/data (the real recordings
    and the independent simulator's trials); the test is skipped, saying
    which, when it is absent."""

    def path(rel):
        p = SHARED_DATA / rel
        if not p.exists():
            pytest.skip(f"the shared data {p} is absent (../shared/data next to the repository)")
        return p

    return path
