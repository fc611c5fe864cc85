"""Python `estimate` equals the CLI's estimate file bit for bit, for every
method of the registry (a method added to the registry is tested here
without a change: it runs on the first trial kind the CLI accepts it on)."""

import numpy as np
import pytest

import limbfuse

# Trial kinds, as `limbfuse` commands writing FILE (short: the test's time).
KINDS = {
    "walking": ["simulate", "walking", "--duration", "8", "--seed", "11"],
    "knee": ["simulate", "knee", "--duration", "20", "--seed", "3"],
    "knee-fes": ["simulate", "knee-fes", "--subject", "P1-L", "--duration", "6", "--seed", "2"],
    "fixed-hip": ["simulate", "fixed-hip", "--duration", "6", "--seed", "2"],
    "bslip": ["simulate", "bslip", "--speed", "0.7", "--duration", "3", "--seed", "2"],
}

# Settings a method needs besides the trial (the CLI flag is the option
# name with `-`), and the trial kind it is meant for.
OPTIONS = {"knee-selfalign": {"window": 500, "order": 6}}


@pytest.fixture(scope="module")
def files(cli, tmp_path_factory, gait_library):
    d = tmp_path_factory.mktemp("equivalence")
    lib = gait_library[0]
    out = {}
    for kind, cmd in KINDS.items():
        p = d / f"{kind}.csv"
        extra = ["--library", lib] if kind == "bslip" else []
        cli(*cmd, *extra, "-o", p)
        out[kind] = p
    return d, lib, out


def bits(a):
    return np.ascontiguousarray(np.ma.filled(a, np.nan), dtype=np.float64).view(np.uint64)


@pytest.mark.parametrize("method", limbfuse.METHODS)
# knee-kinematic runs on the walking trial first (the CLI's warning, expected)
@pytest.mark.filterwarnings("ignore:.*models a fixed thigh")
def test_python_estimate_equals_the_cli_file(cli, files, method):
    d, lib, trials = files
    options = dict(OPTIONS.get(method, {}))
    if method == "imm-bslip":
        options["library"] = str(lib)
    flags = []
    for k, v in options.items():
        flags += [f"--{k.replace('_', '-')}", str(v)]
    tried = []
    for kind, trial_file in trials.items():
        out = d / f"{method}-{kind}.csv"
        r = cli("estimate", "--method", method, *flags, trial_file, "-o", out, check=False)
        if r.returncode != 0:
            tried.append(f"{kind}: {r.stderr.strip()}")
            continue
        trial = limbfuse.read_trial(trial_file)
        est = limbfuse.estimate(trial, method, **options)
        ref = limbfuse.read_estimate(out)
        # `# command:` records how a file was made: the CLI's flags in the
        # CLI's file; an in-memory Python estimate has none. All else equal.
        made_by = lambda h: [x for x in h if not x.startswith("command:")]  # noqa: E731
        assert est.columns == ref.columns and made_by(est.header) == made_by(ref.header)
        assert np.array_equal(bits(est.t), bits(ref.t))
        for name in ref.channels:
            assert np.array_equal(bits(est.channels[name]), bits(ref.channels[name])), name
        if ref.phase is not None:
            assert list(est.phase) == list(ref.phase)
        mine = d / f"{method}-{kind}-py.csv"
        est.write(mine)
        cli_bytes = b"".join(
            l for l in out.read_bytes().splitlines(keepends=True) if not l.startswith(b"# command:")
        )
        assert mine.read_bytes() == cli_bytes
        return
    pytest.fail(f"the CLI ran {method} on none of the trial kinds:\n" + "\n".join(tried))


@pytest.mark.parametrize(
    "selection, flag",
    [("none", "none"), (["sd_thigh", "rho_shank"], "sd_thigh,rho_shank"), ("diag_rho_shank,sd_thigh", "diag_rho_shank,sd_thigh")],
)
def test_diagnostics_option_equals_the_cli_flag(cli, files, selection, flag):
    """`estimate(..., diagnostics=...)` writes the columns of the CLI's
    `--diagnostics` (in the method's order), bit for bit."""
    d, _, trials = files
    out = d / f"mjls-diag-{flag.replace(',', '-')}.csv"
    cli("estimate", "--method", "mjls", "--diagnostics", flag, trials["walking"], "-o", out)
    ref = limbfuse.read_estimate(out)
    est = limbfuse.estimate(limbfuse.read_trial(trials["walking"]), "mjls", diagnostics=selection)
    assert est.columns == ref.columns
    n_diag = {"none": 0}.get(flag, 2)
    assert len([c for c in est.columns if c.startswith("diag_")]) == n_diag
    for name in ref.channels:
        assert np.array_equal(bits(est.channels[name]), bits(ref.channels[name])), name


def test_diagnostics_option_bad_input(files):
    _, _, trials = files
    trial = limbfuse.read_trial(trials["walking"])
    with pytest.raises(limbfuse.LimbfuseError, match="`banana` is not a diagnostic of `mjls`"):
        limbfuse.estimate(trial, "mjls", diagnostics="banana")
    with pytest.raises(limbfuse.LimbfuseError, match="option `diagnostics`: expected"):
        limbfuse.estimate(trial, "mjls", diagnostics=3)


@pytest.mark.parametrize("method", ["knee-selfalign", "knee-gyro-axis"])
def test_backfill_option_equals_the_cli_flag(cli, files, method):
    """`estimate(..., backfill=True)` equals `limbfuse estimate --backfill`
    bit for bit, and fills the rows before the first identified window
    that the real-time run leaves empty."""
    d, _, trials = files
    out = d / f"{method}-backfill.csv"
    cli("estimate", "--method", method, "--backfill", trials["knee"], "-o", out)
    ref = limbfuse.read_estimate(out)
    trial = limbfuse.read_trial(trials["knee"])
    est = limbfuse.estimate(trial, method, backfill=True)
    made_by = lambda h: [x for x in h if not x.startswith("command:")]  # noqa: E731
    assert est.columns == ref.columns and made_by(est.header) == made_by(ref.header)
    for name in ref.channels:
        assert np.array_equal(bits(est.channels[name]), bits(ref.channels[name])), name
    plain = limbfuse.estimate(trial, method)
    knee, filled = np.ma.getmaskarray(plain.channels["knee"]), np.ma.getmaskarray(est.channels["knee"])
    assert knee[:400].all() and not filled.any()
    first = int(np.argmin(knee))
    assert np.array_equal(bits(est.channels["knee"][first:]), bits(plain.channels["knee"][first:]))


def test_backfill_option_bad_input(files):
    _, _, trials = files
    trial = limbfuse.read_trial(trials["walking"])
    with pytest.raises(limbfuse.LimbfuseError, match="nothing to backfill"):
        limbfuse.estimate(trial, "mjls", backfill=True)
    with pytest.raises(limbfuse.LimbfuseError, match="option `backfill`: expected True or False"):
        limbfuse.estimate(trial, "knee-selfalign", backfill="yes")
