"""montecarlo: the CLI's `limbfuse montecarlo` (paper 000 Fig. 9) as a
function (session 45): the CLI's numbers, bad settings named."""

import pandas as pd
import pytest

import limbfuse
from limbfuse import LimbfuseError


def _body(text):
    """The CSV without its `#` provenance lines."""
    return "".join(line for line in text.splitlines(True) if not line.startswith("#"))


@pytest.mark.parametrize("levels", ["0:10:5", [0, 5, 10], (0.0, 5.0, 10.0)])
def test_montecarlo_gives_the_clis_rows(cli, tmp_path, levels):
    out = tmp_path / "mc.csv"
    cli("montecarlo", "--runs", 3, "--levels", "0:10:5", "--seed", 4, "--speed", 1.2, "--duration", 4, "-o", out)
    df = limbfuse.montecarlo(3, levels, seed=4, speed=1.2, duration=4)
    assert list(df.columns) == ["method", "level_pct", "mean_rmse_deg", "std_rmse_deg", "runs"]
    assert _body(df.attrs["csv"]) == _body(out.read_text())
    cli_df = pd.read_csv(out, comment="#")
    # (bit for bit: the CSV's shortest round-trip digits)
    pd.testing.assert_frame_equal(df, cli_df, check_exact=True, check_dtype=False)
    assert df["method"].tolist() == ["local"] * 3 + ["mjls"] * 3 + ["global"] * 3
    assert (df["mean_rmse_deg"] > 0).all() and (df["runs"] == 3).all()
    assert "limbfuse.montecarlo(runs=3" in df.attrs["provenance"]
    assert "# trial_seeds: 4 to 6" in df.attrs["csv"]


def test_montecarlo_seed_changes_the_runs_and_draws_the_plot(tmp_path):
    svg = tmp_path / "mc.svg"
    a = limbfuse.montecarlo(2, [0, 20], seed=1, duration=3, svg=svg)
    b = limbfuse.montecarlo(2, [0, 20], seed=2, duration=3)
    assert not a["mean_rmse_deg"].equals(b["mean_rmse_deg"])
    text = svg.read_text()
    assert text.startswith("<svg") and "<metadata" in text and "limbfuse.montecarlo(runs=2" in text
    assert limbfuse.montecarlo(2, [0, 20], seed=1, duration=3).equals(a)


@pytest.mark.parametrize(
    "kwargs,message",
    [
        ({"runs": 0}, "runs = 0: expected at least 1 run"),
        ({"runs": 200_000}, "runs = 200000: expected 1 to 100000 runs per level"),
        ({"levels": "0:20"}, "levels: expected START:END:STEP in percent"),
        ({"levels": "0:10:3"}, "levels: `0:10:3`: END is not START \\+ k STEP"),
        ({"levels": [5, 100]}, "levels: expected percents in \\[0, 100\\), found 100"),
        ({"levels": [float("nan")]}, "levels: expected percents in \\[0, 100\\), found NaN"),
        ({"levels": []}, "levels: expected 1 to 1001 levels, found 0"),
        ({"levels": {"a": 1}}, "levels: expected \"START:END:STEP\" in percent"),
        ({"speed": 0.0}, "montecarlo: speed = 0: outside the allowed range"),
        ({"duration": 0.0}, "montecarlo: duration = 0: expected 0 < duration <= 86400 s"),
        ({"duration": float("inf")}, "montecarlo: duration = inf: expected"),
        ({"seed": -1}, "montecarlo: seed = -1: expected a seed from 0 to 2\\^64 - 1"),
        ({"seed": 2**64}, "montecarlo: seed = 18446744073709551616: expected a seed from 0"),
        ({"duration": 1e-9}, "montecarlo: duration = 1e-9: less than one sample at the simulator's 100 Hz"),
        ({"levels": [0, "a"]}, "levels: expected \"START:END:STEP\" in percent"),
    ],
)
def test_montecarlo_bad_settings_are_named(kwargs, message):
    with pytest.raises(LimbfuseError, match=message):
        limbfuse.montecarlo(**{"runs": 2, "duration": 2, **kwargs})


@pytest.mark.parametrize("kwargs", [{"runs": 2.5}, {"runs": True}, {"seed": "1"}, {"speed": "fast"}, {"duration": None}])
def test_montecarlo_wrong_types_are_type_errors(kwargs):
    with pytest.raises(TypeError, match="montecarlo: "):
        limbfuse.montecarlo(**kwargs)


def test_montecarlo_progress_counts_the_runs_on_stderr(capsys):
    """`progress=True` (session 45) writes `montecarlo: N/M runs` to
    `sys.stderr` as the runs end and ends the line; the rows are the same."""
    quiet = limbfuse.montecarlo(4, [0, 10], duration=2)
    assert capsys.readouterr().err == ""
    shown = limbfuse.montecarlo(4, [0, 10], duration=2, progress=True)
    err = capsys.readouterr().err
    assert err.endswith("\rmontecarlo: 4/4 runs\n"), repr(err)
    counts = [int(part.split("/")[0]) for part in err.replace("montecarlo: ", "").strip().split("\r") if part]
    assert counts == sorted(counts) and counts[-1] == 4
    pd.testing.assert_frame_equal(quiet, shown)
