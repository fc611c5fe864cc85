"""tune: `limbfuse tune` for local, mjls and global as a function (session 44)."""

import numpy as np
import pytest

import limbfuse
from limbfuse import LimbfuseError, LimbfuseWarning, Trial


@pytest.fixture(scope="module")
def walk_file(tmp_path_factory):
    p = tmp_path_factory.mktemp("tune") / "walk.csv"
    limbfuse.simulate("walking", duration=40.0, seed=3).write(p)
    return p


@pytest.mark.parametrize("method", ["local", "mjls", "global"])
def test_tune_gives_the_clis_parameter_file(cli, tmp_path, walk_file, method):
    out = tmp_path / "p.toml"
    r = cli("tune", "--method", method, walk_file, "--window", "0:20", "--budget", "40", "--particles", "20", "--starts", "3", "-o", out)
    with pytest.warns(LimbfuseWarning) if "warning:" in r.stderr else _no_warning():
        got = limbfuse.tune(limbfuse.read_trial(walk_file), method, "0:20", budget=40, particles=20, starts=3)
    cli_lines = out.read_text().splitlines()
    py_lines = got["params"].splitlines()
    # the first comment line says how each was called; everything else is the same
    assert cli_lines[0].startswith("# tuned by: limbfuse tune") and py_lines[0].startswith("# tuned by: limbfuse.tune(")
    assert py_lines[1:] == cli_lines[1:]
    assert got["table"] in r.stdout and got["method"] == method and got["evaluations"] == 40
    before, after = got["tuning_rmse_deg"]
    assert after <= before  # the swarm keeps the start among its candidates
    # the text is a parameter file `estimate` takes, and gives the CLI's estimate
    est = limbfuse.estimate(limbfuse.read_trial(walk_file), method, params=got["params"])
    cli("estimate", "--method", method, "--params", out, walk_file, "-o", tmp_path / "e.csv")
    ref = limbfuse.read_estimate(tmp_path / "e.csv")
    for k in ("thigh", "knee"):
        assert np.array_equal(np.ma.filled(est.channels[k], np.nan), np.ma.filled(ref.channels[k], np.nan), equal_nan=True)


class _no_warning:
    def __enter__(self):
        import warnings

        self._w = warnings.catch_warnings()
        self._w.__enter__()
        warnings.simplefilter("error", LimbfuseWarning)

    def __exit__(self, *a):
        return self._w.__exit__(*a)


def test_tune_bad_input(walk_file):
    t = limbfuse.read_trial(walk_file)
    cases = [
        (dict(method="chain"), LimbfuseError, "method `chain` has no tunable parameters; tune supports"),
        (dict(method="sdre"), LimbfuseError, "budget, starts apply to local, mjls and global only"),
        (dict(method="nope"), LimbfuseError, "unknown method `nope`"),
        (dict(window="20:0"), LimbfuseError, "tune: window: window end 0 s is not after its start 20 s"),
        (dict(window=None), LimbfuseError, "tune: window: expected"),
        (dict(starts=0), LimbfuseError, r"starts = 0: expected 1 to 10000 starting points"),
        (dict(particles=1), LimbfuseError, "particles = 1: expected a swarm of 2 to 10000 particles"),
        (dict(budget=10), LimbfuseError, "budget = 10: expected at least two generations"),
        (dict(preset="best"), LimbfuseError, 'preset: expected "default" or "paper-2014", found "best"'),
        (dict(params="missing.toml"), LimbfuseError, "missing.toml"),
        (dict(params={"segments": 3}), LimbfuseError, r"<params dict>:1:12: invalid type"),
        (dict(validate="a:b"), LimbfuseError, "tune: validate"),
        (dict(seed=-1), TypeError, "seed: expected a non-negative integer"),
        (dict(budget=True), TypeError, "budget: expected a non-negative integer"),
        (dict(length="5"), TypeError, "length: expected a number"),
    ]
    for kw, err, msg in cases:
        args = dict(method="mjls", window="0:20", budget=40, particles=20, starts=2)
        args.update(kw)
        m, w = args.pop("method"), args.pop("window")
        with pytest.raises(err, match=msg):
            limbfuse.tune(t, m, w, **args)
    no_ref = Trial(t.t, {k: v for k, v in t.channels.items() if not k.endswith("_ref")}, meta=t.meta)
    with pytest.raises(LimbfuseError, match="no reference angle column"):
        limbfuse.tune(no_ref, "mjls", "0:20", budget=40, particles=20, starts=2)
    with pytest.raises(TypeError, match="tune: expected a limbfuse.Trial"):
        limbfuse.tune(str(walk_file), "mjls", "0:20")
