"""tune for sdre and ekf (session 45): `limbfuse tune --method sdre|ekf` as
a function, the CLI's file and choice, bad input named."""

import math

import pytest

import limbfuse
from limbfuse import LimbfuseError

EXTENDED = "[states]\nactivation = true\ngyro_bias = true\nacc_bias = true\n\n[measurement]\nshank_imu_m = 0.2\n"


@pytest.fixture(scope="module")
def pre_trial(tmp_path_factory, cli):
    d = tmp_path_factory.mktemp("fes")
    cli("simulate", "knee-fes", "--subject", "P1-L", "--seed", 2000, "--duration", 30, "-o", d / "pre.csv")
    (d / "ext.toml").write_text(EXTENDED)
    return d


@pytest.mark.parametrize("method", ["sdre", "ekf"])
def test_tune_fes_writes_the_clis_file(cli, pre_trial, tmp_path, method, monkeypatch):
    monkeypatch.chdir(pre_trial)
    out = tmp_path / "tuned.toml"
    printed = cli("tune", "--method", method, "pre.csv", "--params", "ext.toml", "--window", "0:30", "-o", out).stdout
    trial = limbfuse.read_trial("pre.csv")
    for params in ("ext.toml", EXTENDED):
        got = limbfuse.tune(trial, method, "0:30", params=params)
        cli_lines = out.read_text().splitlines()
        mine = got["params"].splitlines()
        # (all but the first comment line, which names the command)
        assert mine[1:] == cli_lines[1:]
        assert mine[0].startswith(f'# tuned by: limbfuse.tune(pre.csv, "{method}", window="0:30"')
        assert got["table"] in printed
        assert f"torque_error = {got['torque_error']}" in got["params"]
        assert got["torque_error"] == got["torque_errors"][got["rmse_deg"].index(min(got["rmse_deg"]))]
        assert got["pulse_windows"] >= 2 and got["warnings"] == []
        assert all(r > 0 for r in got["rmse_deg"]) and math.isfinite(got["cv_rmse_deg"])
    # the tuned model estimates the trial as the CLI's file does
    a = limbfuse.estimate(trial, method, params=got["params"])
    b = limbfuse.estimate(trial, method, params=str(out))
    assert (a.channels["knee"] == b.channels["knee"]).all()


def test_tune_fes_takes_a_dict(pre_trial):
    trial = limbfuse.read_trial(pre_trial / "pre.csv")
    as_dict = {"states": {"activation": True, "gyro_bias": True, "acc_bias": True}, "measurement": {"shank_imu_m": 0.2}}
    a = limbfuse.tune(trial, "sdre", (0, 30), params=as_dict)
    b = limbfuse.tune(trial, "sdre", (0, 30), params=EXTENDED)
    assert a["rmse_deg"] == b["rmse_deg"] and a["torque_error"] == b["torque_error"]


@pytest.mark.parametrize(
    "kwargs,message",
    [
        ({}, "give the knee model's parameters with `params`"),
        ({"params": "[tuning]\nq = [1e-6, 1e-4]\n"}, "the file has neither \\[states\\] nor \\[measurement\\]"),
        ({"params": EXTENDED, "budget": 50}, "budget applies to local, mjls and global only"),
        ({"params": EXTENDED, "seed": 3, "starts": 5}, "seed, starts apply to local, mjls and global only"),
        ({"params": EXTENDED, "window": "0:3"}, "fewer than two stimulation pulses .* in window \"0:3\""),
        ({"params": EXTENDED, "window": "40:50"}, "no `knee_ref` sample in window \"40:50\""),
        ({"params": "no-such-model.toml"}, "no-such-model.toml"),
    ],
)
def test_tune_fes_bad_input_is_named(pre_trial, kwargs, message):
    trial = limbfuse.read_trial(pre_trial / "pre.csv")
    window = kwargs.pop("window", "0:30")
    with pytest.raises(LimbfuseError, match=message):
        limbfuse.tune(trial, "sdre", window, **kwargs)


def test_tune_fes_needs_the_stimulation():
    walk = limbfuse.simulate("walking", duration=5)
    with pytest.raises(LimbfuseError, match="no `u_ke` column: the pre-trial needs the quadriceps stimulation"):
        limbfuse.tune(walk, "ekf", "0:5", params=EXTENDED)
