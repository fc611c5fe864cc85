"""limbfuse.report: the HTML report of `limbfuse report` from Python."""

import pytest

import limbfuse
from limbfuse import LimbfuseError


def test_report_of_in_memory_trial_and_estimates(walking_trial, tmp_path):
    mjls = limbfuse.estimate(walking_trial, "mjls")
    events = limbfuse.estimate(walking_trial, "gait-events")
    out = tmp_path / "r.html"
    n = limbfuse.report(walking_trial, [mjls, events], out)
    html = out.read_text()
    assert n == len(html.encode()) and html.startswith("<!DOCTYPE html>")
    for element in ("plot-angle-knee", "rmse-table", "panel-events", "plot-contact-right"):
        assert f'id="{element}"' in html, element
    thigh = limbfuse.evaluate(walking_trial, mjls)["rmse_deg"]["thigh"]
    assert f"<td>{thigh:.3f}</td>" in html, "the RMSE table holds evaluate's number"
    assert "mjls.csv" in html and "gait-events.csv" in html


def test_report_of_files_checks_the_trial(walking_file, tmp_path):
    trial = limbfuse.read_trial(walking_file)
    est = tmp_path / "e.csv"
    limbfuse.estimate(trial, "local").write(est)
    limbfuse.report(walking_file, [est], tmp_path / "r.html")
    other = limbfuse.simulate("walking", duration=3.0, seed=9)
    other.write(tmp_path / "other.csv")
    with pytest.raises(LimbfuseError, match="another trial"):
        limbfuse.report(tmp_path / "other.csv", [est], tmp_path / "x.html")


def test_report_bad_input(walking_trial, tmp_path):
    est = limbfuse.estimate(walking_trial, "local", diagnostics="none")
    with pytest.raises(LimbfuseError, match="buckets"):
        limbfuse.report(walking_trial, [est], tmp_path / "x.html", buckets=0)
    with pytest.raises(LimbfuseError, match="at least one estimate"):
        limbfuse.report(walking_trial, [], tmp_path / "x.html")
    with pytest.raises(LimbfuseError, match="nope.csv"):
        limbfuse.report(tmp_path / "nope.csv", [est], tmp_path / "x.html")


def _section(html, start_id):
    """The text from element `start_id` to the end of its section."""
    start = html.index(f'id="{start_id}"')
    return html[start : html.index("</section>", start)]


def test_report_scores_with_evaluates_options_as_the_cli(walking_file, tmp_path, cli):
    """window=, offset_free=, max_lag= (session 29; before, report took
    none): the tables are evaluate's with the same options, and equal to
    the CLI's report with --window --offset-free --max-lag; the page states them."""
    trial = limbfuse.read_trial(walking_file)
    est = tmp_path / "local.csv"
    limbfuse.estimate(trial, "local").write(est)
    out = tmp_path / "py.html"
    limbfuse.report(walking_file, [est], out, window=(2, 8), offset_free=True, max_lag=3)
    html = out.read_text()
    ev = limbfuse.evaluate(trial, limbfuse.read_estimate(est), window="2:8", offset_free=True, max_lag=3)
    assert f"<td>{ev['rmse_deg']['thigh']:.3f}</td>" in html
    assert "window=&#39;2.0:8.0&#39;, offset_free=True, max_lag=3" in html, "the recorded call (escaped)"
    cli("report", walking_file, est, "-o", tmp_path / "cli.html", "--window", "2:8", "--offset-free", "--max-lag", "3")
    cli_html = (tmp_path / "cli.html").read_text()
    assert _section(html, "rmse-table") == _section(cli_html, "rmse-table"), "tables and notes as the CLI's"
    with pytest.raises(LimbfuseError, match="max_lag 100000"):
        limbfuse.report(walking_file, [est], tmp_path / "x.html", max_lag=100000)
    with pytest.raises(LimbfuseError, match="window: "):
        limbfuse.report(walking_file, [est], tmp_path / "x.html", window="8:2")
    with pytest.raises(TypeError, match="offset_free"):
        limbfuse.report(walking_file, [est], tmp_path / "x.html", offset_free="yes")
    events = tmp_path / "events.csv"
    limbfuse.estimate(trial, "gait-events").write(events)
    with pytest.raises(LimbfuseError, match="offset_free: applies to angle errors only"):
        limbfuse.report(walking_file, [events], tmp_path / "x.html", offset_free=True)
