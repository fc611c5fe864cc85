"""Cohort processing on Dask: one method over many trial files.

``run(paths_or_glob, method)`` maps read + estimate + evaluate over the
trials as Dask tasks and returns one pandas DataFrame with a row per trial
and angle channel (one row per trial with the event or gait figures for
``gait-events``, ``lowback-speed`` and ``imm-bslip``). Without a client it uses Dask's local threaded scheduler
(``estimate`` releases the GIL, so the trials run in parallel on threads);
given a ``dask.distributed`` client, the tasks run on its workers.

The command ``limbfuse-cohort`` (or ``python -m limbfuse.cohort``) runs the
same from a shell, with a progress bar, and writes the DataFrame as CSV.
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
import uuid
import warnings
from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

from ._estimate import LimbfuseWarning, estimate, evaluate, methods
from ._lazy import LazyModule
from ._native import LimbfuseError
from ._trial import Trial, read_trial

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd
else:  # (pandas is imported on first use; `_lazy`)
    pd = LazyModule("pandas")

__all__ = ["COLUMNS", "EVENT_METRICS", "GAIT_METRICS", "METRICS", "TRIAL_SUFFIXES", "main", "run"]

#: One cohort item: a trial file, an in-memory trial, or an in-memory
#: trial without a file and the name its rows give it.
Item = Union[str, Trial, Tuple[str, Trial]]

#: The trial files a directory contributes (CSV, Arrow IPC / Feather).
TRIAL_SUFFIXES = (".csv", ".arrow", ".feather")

#: The per-channel metrics of ``limbfuse evaluate --json`` (degrees).
METRICS = ("rmse_deg", "max_abs_err_deg", "mean_err_deg", "corr")
COLUMNS = ("trial", "method", "channel", "n_samples") + METRICS + ("mean_rmse_deg",)
#: The timing figures of each kind of gait event (``initial_contact``,
#: ``final_contact`` of ``evaluate --json``), as ``ic_*`` / ``fc_*`` columns.
EVENT_TIMING = ("n_reference", "n_matched", "missed", "extra", "median_abs_ms", "p95_abs_ms", "mean_ms")
#: The ``side_*`` columns, from ``evaluate --json``'s ``contact_sides``
#: (``lowback-speed``: the contacts whose foot it told); empty otherwise.
SIDE_FIELDS = ("n_paired", "n_sided", "n_correct", "accuracy_pct")
#: The columns of a trial evaluated for gait events and walking speed
#: (``gait-events``, ``lowback-speed``; channel ``events``): one row per trial.
EVENT_METRICS = (
    tuple(f"ic_{k}" for k in EVENT_TIMING)
    + tuple(f"fc_{k}" for k in EVENT_TIMING)
    + ("contact_accuracy_pct", "phase_accuracy_pct", "speed_mae_mps", "speed_bias_mps",
       "n_strides", "stride_length_error_pct", "n_withheld",
       "stance_time_mae_ms", "stance_time_bias_ms", "swing_time_mae_ms", "swing_time_bias_ms",
       "n_stance_swing")
    + tuple(f"side_{k}" for k in SIDE_FIELDS)
)
#: The columns of a paper-003 gait trial (``imm-bslip``; channel ``gait``).
GAIT_METRICS = ("phase_accuracy_pct", "com_pos_rmse_m", "com_pos_max_m", "speed_mean_mps",
                "speed_ref_mps", "speed_error_mps")


def expand(p: str) -> List[str]:
    """One path given: a directory's trial files (``TRIAL_SUFFIXES``, not
    its README.md or parameter .toml files), a glob pattern's matches
    (folders skipped), else the file itself; sorted. An error when nothing
    matches."""
    if os.path.isdir(p):
        found = sorted(
            f for f in glob.glob(os.path.join(p, "*")) if f.endswith(TRIAL_SUFFIXES) and os.path.isfile(f)
        )
        if not found:
            raise LimbfuseError(
                f"cohort: the folder `{p}` holds no trial file ({', '.join('*' + s for s in TRIAL_SUFFIXES)})"
            )
        return found
    if any(ch in p for ch in "*?[") and not os.path.isfile(p):
        # (an audit: `data/*` matched the sub-folders too, each then a failed trial)
        found = sorted(f for f in glob.glob(p) if not os.path.isdir(f))
        if not found:
            raise LimbfuseError(f"cohort: no trial file matches `{p}`")
        return found
    return [p]


def trial_paths(paths_or_glob: Union[str, "os.PathLike[str]", Iterable[Any]]) -> Sequence[Union[str, Trial]]:
    """The trials: a glob pattern, a directory (its ``*.csv``, ``*.arrow``
    and ``*.feather`` files), a file, or a list of those or of in-memory
    ``Trial``s (each path expanded in place, ``expand``). A file given
    twice (under the same or another spelling, or matched by two patterns)
    runs once, where it first appears, with a ``LimbfuseWarning``."""
    if isinstance(paths_or_glob, Trial):
        return [paths_or_glob]
    if isinstance(paths_or_glob, (str, bytes, os.PathLike)):
        # (bytes: one path, not a list of its byte values; an audit: "expected
        # str, bytes or os.PathLike object, not int")
        return unique(expand(os.fsdecode(paths_or_glob)))
    try:
        given = list(paths_or_glob)
    except TypeError:
        raise TypeError(
            "cohort: expected a glob pattern, a directory, a trial file or a list of files or "
            f"limbfuse.Trials, found {type(paths_or_glob).__name__}"
        ) from None
    items: List[Union[str, Trial]] = []
    for i, x in enumerate(given):
        if isinstance(x, Trial):
            items.append(x)
        elif isinstance(x, (str, bytes, os.PathLike)):
            # (an audit: `limbfuse-cohort "a/*.csv" "b/*.csv"` and a list of
            # folders were read as file names, each "no such file")
            items.extend(expand(os.fsdecode(x)))
        else:
            raise TypeError(
                f"cohort: item {i} of the list: expected a trial file path or a limbfuse.Trial, "
                f"found {type(x).__name__}"
            )
    if not items:
        raise LimbfuseError("cohort: the list of trial files is empty")
    return unique(items)


def unique(items: Sequence[Union[str, Trial]]) -> List[Union[str, Trial]]:
    """The items without a file given twice (the same real path), with a
    warning naming it (an audit: `data/*.csv data/w1.csv` ran w1 twice, and
    its rows counted twice in every mean)."""
    seen: Dict[str, str] = {}
    out: List[Union[str, Trial]] = []
    for x in items:
        if isinstance(x, str):
            key = os.path.realpath(x)
            if key in seen:
                same = f" (as `{seen[key]}`)" if seen[key] != x else ""
                warnings.warn(f"cohort: `{x}` is given twice{same}: it runs once", LimbfuseWarning, stacklevel=3)
                continue
            seen[key] = x
        out.append(x)
    return out


def trial_name(trial: Any, index: int) -> str:
    """How a cohort row names its trial: the path given, an in-memory
    trial's file name (``Trial.source``), else ``<trial N>``."""
    if not isinstance(trial, Trial):
        return str(trial)
    return trial.source[0] if trial.source else f"<trial {index}>"


def evaluate_trial(
    path: Any,
    method: str,
    params: Any = None,
    options: Optional[Mapping[str, Any]] = None,
    eval_options: Optional[Mapping[str, Any]] = None,
    name: Optional[str] = None,
) -> List[Dict[str, Any]]:
    """One task: read, estimate, evaluate one trial; its rows. An error
    names the trial by the path given (messages from estimating name the
    file only: in a cohort, `s2/trial.csv` is not `s1/trial.csv`), or by
    ``name`` (an in-memory trial's ``<trial N>``)."""
    if name is None:
        name = trial_name(path, 0) if isinstance(path, Trial) else str(path)
    try:
        trial = path if isinstance(path, Trial) else read_trial(path)
        est = estimate(trial, method, params, **dict(options or {}))
        ev = evaluate(trial, est, **dict(eval_options or {}))
    except LimbfuseError as e:
        text = str(e)
        # (evaluate calls every trial in memory: "s.csv: <in-memory trial>: ...",
        # and estimate names the file alone: "d/s.csv: s.csv: ...")
        for prefix in (IN_MEMORY, os.path.basename(name) + ": "):
            if text.startswith(prefix):
                text = text[len(prefix):]
        if name in text:
            raise (e if text == str(e) else LimbfuseError(text)) from None
        raise LimbfuseError(f"{name}: {text}") from e
    rows = rows_of(name, ev)
    if not rows:  # (never a trial without a row: its absence would go unseen)
        raise LimbfuseError(f"{name}: evaluate scored no channel of the `{method}` estimate")
    return rows


IN_MEMORY = "<in-memory trial>: "

#: The runs interrupted (Ctrl-C): their tasks stop before their next trial.
_cancelled: "set[str]" = set()


def evaluate_trials(
    paths: Sequence[Item],
    method: str,
    params: Any = None,
    options: Optional[Mapping[str, Any]] = None,
    eval_options: Optional[Mapping[str, Any]] = None,
    record: bool = False,
    token: Optional[str] = None,
) -> Tuple[List[Dict[str, Any]], Optional[LimbfuseError]]:
    """One task over several trials, in order: their rows (an in-memory
    trial without a file name is a ``(name, Trial)`` pair), and the error of
    the first trial that failed (the task stops there). The error is
    returned, not raised, so that ``run`` raises the first failing trial's
    in the cohort's order, whichever task finished first (an audit: a bad
    argument was blamed on a different trial at every run).

    With ``record``, a failing trial is one row, ``error_row``, and the task
    goes on. A task of an interrupted run (``token`` in ``_cancelled``)
    stops before its next trial (an audit: after Ctrl-C the threads went on
    through their chunks, 25 trials each in a cohort of 200 on 2 cores)."""
    rows: List[Dict[str, Any]] = []
    for i, p in enumerate(paths):
        if token is not None and token in _cancelled:
            return rows, LimbfuseError("cohort: interrupted")
        name, trial = p if isinstance(p, tuple) else (None, p)
        label = name if name is not None else trial_name(trial, i)
        try:
            trial_rows = evaluate_trial(trial, method, params, options, eval_options, label)
        except LimbfuseError as e:
            if not record:
                return rows, e
            trial_rows = [error_row(label, method, str(e))]
        except (KeyboardInterrupt, SystemExit):
            raise
        except BaseException as e:  # (a Rust panic is a BaseException)
            if not record:
                raise
            trial_rows = [error_row(label, method, f"{label}: {type(e).__name__}: {e}")]
        rows.extend(trial_rows)
    return rows, None


def error_row(name: str, method: str, message: str) -> Dict[str, Any]:
    """The row of a trial that failed (``on_error="record"``): no channel,
    no figures, the message in ``error`` (it names the file)."""
    return {"trial": name, "method": method, "channel": None, "error": message}


def chunks(paths: Sequence[Item], slots: int) -> List[List[Item]]:
    """The trials in consecutive chunks, about four per worker slot: a
    scheduler's cost per task (in the tens of milliseconds for a
    distributed task) is paid per chunk, not per trial, while every slot
    still gets several tasks to balance uneven trials."""
    size = max(1, -(-len(paths) // (4 * max(1, slots))))
    return [list(paths[i : i + size]) for i in range(0, len(paths), size)]


def rows_of(path: str, ev: Mapping[str, Any]) -> List[Dict[str, Any]]:
    """The rows of one ``evaluate`` result: one per evaluated angle channel;
    for gait events and walking speed one row, channel ``events``
    (``EVENT_METRICS``); for a paper-003 gait trial one row, channel ``gait``
    (``GAIT_METRICS``)."""
    base = {"trial": path, "method": ev["method"], "n_samples": ev["n_samples"]}
    if "initial_contact" in ev:
        row = dict(base, channel="events")
        for prefix, key in (("ic", "initial_contact"), ("fc", "final_contact")):
            timing = ev.get(key) or {}
            for k in EVENT_TIMING:
                row[f"{prefix}_{k}"] = timing.get(k)
        for k in EVENT_METRICS[2 * len(EVENT_TIMING):-len(SIDE_FIELDS)]:
            row[k] = ev.get(k)
        sides = ev.get("contact_sides") or {}
        for k in SIDE_FIELDS:
            row[f"side_{k}"] = sides.get(k)
        return [row]
    if "phase_accuracy_pct" in ev and "com_pos_rmse_m" in ev:
        row = dict(base, channel="gait")
        for k in GAIT_METRICS:
            row[k] = ev.get(k)
        return [row]
    rows = []
    for channel in ev.get("rmse_deg", {}):
        row = {"trial": path, "method": ev["method"], "channel": channel, "n_samples": ev["n_samples"]}
        for m in METRICS:
            row[m] = ev[m].get(channel)
        row["mean_rmse_deg"] = ev.get("mean_rmse_deg")
        rows.append(row)
    return rows


def run(
    paths_or_glob: Union[str, "os.PathLike[str]", Iterable[Any]],
    method: str,
    params: Any = None,
    client: Any = None,
    *,
    options: Optional[Mapping[str, Any]] = None,
    eval_options: Optional[Mapping[str, Any]] = None,
    scheduler: str = "threads",
    progress: bool = False,
    on_error: str = "raise",
    **estimate_options: Any,
) -> "pd.DataFrame":
    """Estimates and evaluates every trial; one DataFrame row per trial and
    channel (``trial, method, channel, n_samples, rmse_deg,
    max_abs_err_deg, mean_err_deg, corr, mean_rmse_deg``); for gait events
    and walking speed one row per trial (channel ``events``) with the
    ``EVENT_METRICS`` columns, for a paper-003 gait trial (channel ``gait``)
    the ``GAIT_METRICS`` ones (``rows_of``). The rows are in the order of
    the trials given (a pattern's or folder's: sorted), whatever the
    scheduler.

    Args:
        paths_or_glob: a glob pattern, a directory, a list of files or of
            in-memory ``Trial``s (rows name them by ``Trial.source`` or
            ``<trial N>``, N their place in the list).
        method, params: as ``limbfuse.estimate``; its flags are keywords
            (``diagnostics="none"``) or the ``options`` dict.
        client: a ``dask.distributed.Client``; None uses the local
            ``scheduler`` (``"threads"``, ``"processes"`` or ``"sync"``).
        eval_options: ``limbfuse.evaluate`` keywords (window, offset_free, ...).
        progress: show a progress bar on stderr.
        on_error: ``"raise"``: a trial that fails raises its error (which
            names the file), the first in the cohort's order. ``"record"``:
            it gives one row, ``channel`` None, its message in an ``error``
            column (None in the other trials' rows), and the others run.

    A trial fails when it cannot be read, estimated or scored (evaluate
    finds no reference to score against), or when the Dask worker running
    it dies.
    """
    import dask
    import pandas as pd

    if on_error not in ("raise", "record"):
        raise LimbfuseError(f'cohort: on_error: expected "raise" or "record", found {on_error!r}')
    # (an audit: a misspelt method was reported as the first trial's error)
    known = [name for name, _ in methods()]
    if method not in known:
        raise LimbfuseError(f"cohort: unknown method `{method}` (one of: {', '.join(known)})")
    if estimate_options:
        options = dict(options or {}, **estimate_options)
    for k in EVALUATE_ONLY:
        if k in (options or {}):
            raise LimbfuseError(
                f"cohort: `{k}` is an option of evaluate, not of estimate: pass it as "
                f"eval_options={{{k!r}: ...}}"
            )
    if client is not None and not callable(getattr(client, "nthreads", None)):
        raise TypeError(
            f"cohort: client: expected a dask.distributed Client (or None: local threads), "
            f"found {type(client).__name__}"
        )
    check_arguments(params, eval_options)
    paths: List[Item] = [
        (trial_name(x, i), x) if isinstance(x, Trial) and not x.source else x
        for i, x in enumerate(trial_paths(paths_or_glob))
    ]
    record = on_error == "record"
    p = os.fspath(params) if isinstance(params, os.PathLike) else params
    kw = dict(method=method, params=p, options=options, eval_options=eval_options, record=record)
    if client is not None:
        results = run_distributed(client, paths, kw, progress)
    else:
        token = uuid.uuid4().hex
        tasks = [
            dask.delayed(evaluate_trials, pure=False)(part, token=token, **kw)
            for part in chunks(paths, os.cpu_count() or 1)
        ]
        try:
            if progress:
                from dask.diagnostics import ProgressBar

                with ProgressBar(out=sys.stderr):
                    results = dask.compute(*tasks, scheduler=scheduler)
            else:
                results = dask.compute(*tasks, scheduler=scheduler)
        except KeyboardInterrupt:
            _cancelled.add(token)  # (the running tasks stop before their next trial)
            raise
    for _, error in results:
        if error is not None:
            raise error
    rows = [row for rs, _ in results for row in rs]
    if record:
        for row in rows:
            row.setdefault("error", None)
    columns = columns_of(rows) + (["error"] if record else [])
    df = pd.DataFrame(rows, columns=columns)
    for c in [c for c in columns[3:] if c != "error" and df[c].dtype == object]:
        df[c] = pd.to_numeric(df[c])  # (a figure the method lacks: NaN, not None; audit 31)
    return df


def run_distributed(client: Any, paths: List[Item], kw: Dict[str, Any], progress: bool) -> List[Any]:
    """The chunks' results on a ``dask.distributed`` client, in order. A
    chunk whose worker died (``KilledWorker``, after Dask's retries):
    raised naming its trials, or with ``record`` run again one trial per
    task (a task that was waiting on the dying worker fails with it), the
    trial that kills its worker again recorded (an audit: it was a
    ``KilledWorker`` naming a task key, no trial, and lost the run)."""
    from distributed import wait

    parts = chunks(paths, sum(client.nthreads().values()))
    futures = client.map(evaluate_trials, [scattered(client, part) for part in parts], pure=False, **kw)
    try:
        if progress:
            from distributed import progress as dist_progress

            dist_progress(futures)
        wait(futures)
        results = []
        for part, future in zip(parts, futures):
            if future.status != "error":
                results.append(future.result())
                continue
            error = future.exception()
            names = [item_name(x) for x in part]
            if not kw["record"]:
                raise LimbfuseError(f"cohort: {', '.join(names)}: {task_failure(error)}") from error
            results.append(run_distributed_one_by_one(client, part, kw))
        return results
    except KeyboardInterrupt:
        client.cancel(futures)
        raise


def run_distributed_one_by_one(client: Any, part: List[Item], kw: Dict[str, Any]) -> Tuple[List[Any], None]:
    """A chunk again, one trial per task: its rows, the trial whose task
    fails again recorded (``run_distributed``)."""
    from distributed import wait

    futures = client.map(evaluate_trials, [scattered(client, [x]) for x in part], pure=False, **kw)
    wait(futures)
    rows: List[Dict[str, Any]] = []
    for x, future in zip(part, futures):
        if future.status == "error":
            error = future.exception()
            name = item_name(x)
            message = f"{name}: {task_failure(error)}"
            rows.append(error_row(name, kw["method"], message))
        else:
            rows.extend(future.result()[0])
    return rows, None


def scattered(client: Any, part: List[Item]) -> List[Any]:
    """A chunk with its in-memory trials sent to the workers first, each on
    its own (an audit: a 10-minute in-memory trial went in the task graph,
    Dask's "Sending large graph of size 16.03 MiB" warning)."""
    return [
        (x[0], client.scatter(x[1], hash=False)) if isinstance(x, tuple)
        else client.scatter(x, hash=False) if isinstance(x, Trial) else x
        for x in part
    ]


def task_failure(error: BaseException) -> str:
    """What a failed Dask task says: a worker that died is said in words
    (``KilledWorker``'s text names a task key and a worker address)."""
    if type(error).__name__ == "KilledWorker":
        return "the Dask worker running it died (KilledWorker; the worker's log may say why)"
    return f"its Dask task failed: {type(error).__name__}: {error}"


def item_name(x: Item) -> str:
    """How an item of ``run``'s list is named (``trial_name``)."""
    return x[0] if isinstance(x, tuple) else trial_name(x, 0)


#: ``evaluate``'s keywords that ``estimate`` does not take (``window`` is
#: both: the knee methods' window there).
EVALUATE_ONLY = ("offset_free", "max_lag", "allow_trial_mismatch")


def check_arguments(params: Any, eval_options: Optional[Mapping[str, Any]]) -> None:
    """What can be checked before any trial runs: a parameter file that
    does not exist, an evaluation window that is not START:END with START <
    END (an audit: each failed on every trial, reported as one of them)."""
    if isinstance(params, os.PathLike) or (isinstance(params, str) and "\n" not in params):
        if not os.path.isfile(os.fspath(params)):
            raise LimbfuseError(f"cohort: params `{os.fspath(params)}`: no such file")
    window = (eval_options or {}).get("window")
    if isinstance(window, str):
        start, sep, end = window.partition(":")
        try:
            ends = [float(x) if x.strip() else None for x in (start, end)]
        except ValueError:
            ends = []
        a, b = (ends + [None, None])[:2]
        if not sep or len(ends) != 2 or (a is not None and b is not None and not a < b):
            raise LimbfuseError(
                f"cohort: window `{window}`: expected START:END in seconds with START < END "
                "(either end may be empty)"
            )


def columns_of(rows: Sequence[Mapping[str, Any]]) -> List[str]:
    """``COLUMNS``, then ``EVENT_METRICS`` / ``GAIT_METRICS`` when some row
    is of that kind (a cohort of angle estimates keeps its nine columns)."""
    cols = list(COLUMNS)
    for channel, extra in (("events", EVENT_METRICS), ("gait", GAIT_METRICS)):
        if any(r.get("channel") == channel for r in rows):
            cols += [c for c in extra if c not in cols]
    return cols


def worker_count(text: str) -> int:
    """``--workers N``: a positive number of workers (an audit: -1 hung,
    0 fell back to threads without a word)."""
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"expected a positive number of workers, found {text!r}")
    return n


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``limbfuse-cohort TRIALS --method NAME [-o metrics.csv]``: exit
    status 0, 1 on an error (or with ``--keep-going`` when some trial
    failed), 130 when interrupted (Ctrl-C)."""
    ap = argparse.ArgumentParser(
        prog="limbfuse-cohort",
        description="Estimate and evaluate every trial of a cohort on Dask; "
        "one row per trial and channel (degrees), as CSV.",
    )
    ap.add_argument("trials", nargs="+", help="trial files, directories or glob patterns (quoted)")
    ap.add_argument("--method", required=True, help="method name (limbfuse methods)")
    ap.add_argument("--params", help="parameter file (limbfuse params --method NAME)")
    ap.add_argument("-o", "--output", help="output CSV (default: print to stdout)")
    ap.add_argument("--scheduler", default="threads", choices=["threads", "processes", "sync"],
                    help="local Dask scheduler (default threads)")
    ap.add_argument("--address", help="a dask.distributed scheduler address (tcp://host:port)")
    ap.add_argument("--workers", type=worker_count, help="start a LocalCluster with this many workers")
    ap.add_argument("--window", help="evaluation window START:END (s)")
    ap.add_argument("--offset-free", action="store_true", help="remove each channel's mean error")
    ap.add_argument("--max-lag", type=int, default=0, help="synchronise within +-N samples")
    ap.add_argument("-k", "--keep-going", action="store_true",
                    help="a trial that fails gets a row with its message in an `error` column and the "
                    "others run; a summary on stderr, exit status 1 if any failed")
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    a = ap.parse_args(argv)
    if a.output:
        folder = os.path.dirname(a.output) or "."
        if not os.path.isdir(folder):  # (an audit: found after every trial had run)
            print(f"error: -o {a.output}: the folder {folder} does not exist", file=sys.stderr)
            return 1
    paths: Union[str, List[str]] = a.trials[0] if len(a.trials) == 1 else a.trials
    eval_options = {"window": a.window, "offset_free": a.offset_free, "max_lag": a.max_lag}
    progress = not a.quiet and sys.stderr.isatty()
    client = cluster = None
    try:
        with warnings.catch_warnings():
            warnings.showwarning = show_warning
            if a.address or a.workers:
                from distributed import Client, LocalCluster

                if a.address:
                    try:
                        client = Client(a.address)
                    except ValueError as e:  # (an unparsable address: a traceback before)
                        print(f"error: --address {a.address}: {e}", file=sys.stderr)
                        return 1
                else:
                    cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True)
                    client = Client(cluster)
            df = run(paths, a.method, a.params, client, eval_options=eval_options, scheduler=a.scheduler,
                     progress=progress, on_error="record" if a.keep_going else "raise")
    except LimbfuseError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    except OSError as e:  # (an unreachable --address: a traceback before)
        where = f"the Dask scheduler at {a.address}" if a.address else "the Dask cluster"
        print(f"error: cannot reach {where}: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        # (an audit: a traceback, then the threads ran on through their chunks)
        print("limbfuse-cohort: interrupted; no output written", file=sys.stderr)
        return 130
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
    if a.output:
        df.to_csv(a.output, index=False)
        print(f"{df['trial'].nunique()} trials, {len(df)} rows -> {a.output}", file=sys.stderr)
    else:
        df.to_csv(sys.stdout, index=False)
    if a.keep_going:
        failed = df[df["error"].notna()]
        if len(failed):
            print(failure_summary(list(failed["error"]), df["trial"].nunique()), file=sys.stderr)
            return 1
    return 0


def failure_summary(errors: Sequence[str], n_trials: int, shown: int = 10) -> str:
    """``--keep-going``'s last words: "3 of 200 trials failed:" and the
    first ``shown`` messages."""
    lines = [f"{len(errors)} of {n_trials} trials failed:"]
    lines += [f"  {e}" for e in errors[:shown]]
    if len(errors) > shown:
        lines.append(f"  ... and {len(errors) - shown} more (the `error` column of the output)")
    return "\n".join(lines)


def show_warning(message: Any, category: Any, filename: str, lineno: int, file: Any = None, line: Any = None) -> None:
    """A warning as the command prints it: ``warning: TEXT`` on stderr."""
    print(f"warning: {message}", file=sys.stderr)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
