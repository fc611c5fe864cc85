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
