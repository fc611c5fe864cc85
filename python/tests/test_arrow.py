"""Issue 18 item 6: Arrow IPC trial and estimate files (docs/ARROW.md) are
read by pyarrow and pandas with the CSV files' values, and limbfuse reads
the Feather files pandas writes."""

import os
import subprocess

import numpy as np
import pytest

import limbfuse

pa = pytest.importorskip("pyarrow")
pd = pytest.importorskip("pandas")


def test_an_arrow_trial_holds_the_csv_trials_columns_and_metadata(tmp_path):
    tr = limbfuse.simulate("walking", duration=3, seed=2)
    tr.write(tmp_path / "w.csv")
    tr.write(tmp_path / "w.arrow")
    f = pa.ipc.open_file(tmp_path / "w.arrow")
    meta = {k.decode(): v.decode() for k, v in f.schema.metadata.items()}
    assert meta["format"] == "limbfuse-trial/1" and meta["seed"] == "2"
    arrow = f.read_all().to_pandas()
    csv = pd.read_csv(tmp_path / "w.csv", comment="#")
    assert list(arrow.columns) == list(csv.columns)
    assert arrow.dtypes.eq(np.float64).all()
    np.testing.assert_array_equal(arrow.to_numpy(), csv.to_numpy())
    # And limbfuse reads it back to the same trial.
    back = limbfuse.read_trial(tmp_path / "w.arrow")
    np.testing.assert_array_equal(back.t, tr.t)
    for name, values in tr.channels.items():
        np.testing.assert_array_equal(np.ma.filled(back.channels[name], np.nan), np.ma.filled(values, np.nan))


def test_limbfuse_reads_a_trial_that_pandas_wrote_as_feather(tmp_path):
    tr = limbfuse.simulate("walking", duration=3, seed=3)
    df = tr.to_pandas()
    df.to_feather(tmp_path / "p.feather")  # pandas' default: LZ4 compressed
    back = limbfuse.read_trial(tmp_path / "p.feather")
    est_a = limbfuse.estimate(back, "mjls")
    est_b = limbfuse.estimate(tr, "mjls")
    for name in ("thigh", "knee"):
        np.testing.assert_array_equal(np.ma.filled(est_a.channels[name], 0), np.ma.filled(est_b.channels[name], 0))


def test_the_cli_writes_an_arrow_estimate_that_pandas_reads(tmp_path):
    binary = os.environ.get("LIMBFUSE_BIN")
    if not binary:
        pytest.skip("LIMBFUSE_BIN (the limbfuse binary) is not set")
    limbfuse.simulate("walking", duration=3, seed=4).write(tmp_path / "w.arrow")
    for out in ("e.csv", "e.arrow"):
        subprocess.run([binary, "estimate", "--method", "mjls", "w.arrow", "-o", out], cwd=tmp_path, check=True, capture_output=True)
    a = pd.read_feather(tmp_path / "e.arrow")
    c = pd.read_csv(tmp_path / "e.csv", comment="#")
    assert list(a.columns) == list(c.columns) and len(a) == 300
    np.testing.assert_array_equal(a.to_numpy(), c.to_numpy())
    footer = pa.ipc.open_file(tmp_path / "e.arrow").metadata
    assert footer[b"trial_hash"].startswith(b"xxh3:")


def test_estimate_write_refuses_an_arrow_name(tmp_path):
    est = limbfuse.estimate(limbfuse.simulate("walking", duration=1, seed=1), "local")
    with pytest.raises(limbfuse.LimbfuseError, match="writes CSV"):
        est.write(tmp_path / "e.arrow")
    assert not (tmp_path / "e.arrow").exists()


def test_read_estimate_reads_the_clis_arrow_estimate(cli, tmp_path):
    """An audit: `read_estimate("e.arrow")` failed with "stream did not
    contain valid UTF-8" (its header was read as text lines); an Arrow
    estimate reads as the CSV one, header and columns."""
    limbfuse.simulate("walking", duration=3, seed=4).write(tmp_path / "w.csv")
    for out in ("e.csv", "e.arrow"):
        cli("estimate", "--method", "mjls", tmp_path / "w.csv", "-o", tmp_path / out)
    a = limbfuse.read_estimate(tmp_path / "e.arrow")
    c = limbfuse.read_estimate(tmp_path / "e.csv")
    assert a.method == c.method == "mjls" and len(a) == len(c) == 300
    assert set(a.header) - set(c.header) == {l for l in a.header if l.startswith("command:")}
    assert a.channels.keys() == c.channels.keys()
    for name in c.channels:
        np.testing.assert_array_equal(np.ma.filled(a.channels[name], np.nan), np.ma.filled(c.channels[name], np.nan))
