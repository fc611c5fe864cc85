"""The FES filters' model inputs from Python: a gap in the stimulation log."""

import numpy as np
import pytest

import limbfuse
from limbfuse import Filter, Trial


def test_a_stimulation_gap_past_the_hold_restarts_sdre_instead_of_failing():
    """Until 2026-12-06 a stimulation (`u_ke`) missing for more than the 0.1 s
    the FES filters hold it ended the whole estimate with an error. Now the
    rows past the hold have no estimate, the filter restarts when the
    stimulation is back, and the restart is said (as the CLI says it)."""
    sim = limbfuse.simulate("knee-fes", duration=6.0, seed=2)
    ch = {k: np.ma.array(v, copy=True) for k, v in sim.channels.items()}
    ch["u_ke"][200:230] = np.ma.masked  # 0.3 s at 100 Hz: held 0.1 s, then none
    tr = Trial(sim.t, ch, sim.meta)
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"restarted 1 time.*first at t = 2\.3 s\)"):
        est = limbfuse.estimate(tr, "sdre")
    knee = np.ma.masked_invalid(est.channels["knee"])
    assert knee.mask[210:230].all()
    assert not knee.mask[:210].any() and not knee.mask[230:].any()
    f = Filter("sdre", channels=list(ch), meta=sim.meta)
    out = [f.step({"t": float(sim.t[i]), **{n: ch[n][i] for n in ch}}) for i in range(240)]
    assert all(np.isfinite(o["knee"]) for o in out[:210] + out[230:])
    assert all(o["knee"] is None or np.isnan(o["knee"]) for o in out[210:230])


def test_knee_fes_cycles_set_the_extensions_and_a_long_rest_is_said():
    """`cycles` (session 45; `--cycles`): the extensions, default 5 (paper
    004's 30 s trials); a trial much longer than them warns that the leg
    rests after the last one."""
    import warnings

    from limbfuse import LimbfuseError, LimbfuseWarning

    def onsets(trial):
        u = np.ma.filled(trial.channels["u_ke"], 0.0)
        return int(((u[1:] > 0) & (u[:-1] <= 0)).sum())

    with pytest.warns(LimbfuseWarning, match="the 5 extension cycles end at 32 s; the leg rests for the last 28 s"):
        five = limbfuse.simulate("knee-fes", duration=60)
    assert onsets(five) == 5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        nine = limbfuse.simulate("knee-fes", duration=60, cycles=9)
    assert onsets(nine) == 9
    with pytest.raises(LimbfuseError, match=r"option `cycles` = 601: outside the allowed range \[0, 600\]"):
        limbfuse.simulate("knee-fes", cycles=601)
