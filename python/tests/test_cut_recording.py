"""A recording cut off while it was written (its last line short, with no
line break): `read_trial` refused it ("expected 3 cells ..., found 2");
now the line is left out with a LimbfuseWarning, as the CLI warns."""
import warnings

import numpy as np
import pytest

import limbfuse
from limbfuse import LimbfuseError

WHOLE = "t,thigh_ref,knee_enc\n0,0.1,0.2\n0.01,0.1,0.2\n0.02,0.1,0.2\n"


def test_a_cut_last_line_is_left_out_with_a_warning(tmp_path):
    path = tmp_path / "cut.csv"
    path.write_text(WHOLE + "0.03,0.1")
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"cut.csv:5: the last line has 2 of 3 cells"):
        trial = limbfuse.read_trial(path)
    assert np.array_equal(trial.t, [0.0, 0.01, 0.02])


def test_a_whole_file_gives_no_warning_and_a_short_line_inside_is_an_error(tmp_path):
    path = tmp_path / "whole.csv"
    path.write_text(WHOLE)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(limbfuse.read_trial(path)) == 3
    path.write_text(WHOLE + "0.03,0.1\n")
    with pytest.raises(LimbfuseError, match=r"whole.csv:5: expected 3 cells"):
        limbfuse.read_trial(path)


def test_repair_time_leaves_a_cut_last_line_out_with_a_warning(tmp_path):
    path = tmp_path / "cut.csv"
    path.write_text(WHOLE + "0.03,0.1")
    with pytest.warns(limbfuse.LimbfuseWarning, match=r"cut.csv:5: the last line has 2 of 3 cells"):
        report = limbfuse.repair_time(path, tmp_path / "copy.csv")
    assert report["rows_read"] == 3 and report["rows_kept"] == 3
