//! Bad-input cases of the trial reader (issue 2, item 3): every error names
//! the file and line, and the column where there is one. None panics.

use std::path::Path;

use limbfuse_io::{FileError, TrialReader};

fn read_all(text: &str) -> Result<usize, FileError> {
    let mut r = TrialReader::from_reader(
        Path::new("bad.csv"),
        Box::new(std::io::Cursor::new(text.to_string())),
    )?;
    let mut n = 0;
    while r.next_record()?.is_some() {
        n += 1;
    }
    Ok(n)
}

fn message(text: &str) -> String {
    match read_all(text) {
        Ok(n) => panic!("expected an error, read {n} rows"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn nan_cell_names_line_and_column() {
    let m = message("# format: limbfuse-trial/1\nt,thigh_ref\n0.0,0.1\n0.01,NaN\n");
    assert!(m.starts_with("bad.csv:4: column 2 (`thigh_ref`)"), "{m}");
    assert!(m.contains("finite"), "{m}");
}

#[test]
fn infinity_cell_is_rejected() {
    let m = message("t,knee_enc\n0.0,inf\n");
    assert!(m.starts_with("bad.csv:2: column 2 (`knee_enc`)"), "{m}");
}

#[test]
fn text_in_numeric_cell_names_line_and_column() {
    let m = message("t,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z\n0,1,2,3\n0.01,1,two,3\n");
    assert!(
        m.starts_with("bad.csv:3: column 3 (`thigh_gyr_y`): expected a number"),
        "{m}"
    );
    assert!(m.contains("`two`"), "{m}");
}

#[test]
fn non_increasing_time_names_line_and_column() {
    let m = message("knee_enc,t\n0.1,0.00\n0.1,0.01\n0.1,0.01\n");
    assert!(
        m.starts_with("bad.csv:4: column 2 (`t`): time must increase strictly"),
        "{m}"
    );
    let m = message("t\n1.0\n0.5\n");
    assert!(m.starts_with("bad.csv:3: column 1 (`t`)"), "{m}");
}

#[test]
fn empty_time_cell_is_an_error() {
    let m = message("t,knee_enc\n,0.1\n");
    assert!(m.starts_with("bad.csv:2: column 1 (`t`)"), "{m}");
}

/// A time that is NaN, inf or not a number is named as a time, without the
/// advice for other cells to leave a missing value empty (a time cannot
/// be; 2026-12-06: the NaN message said "leave the cell empty").
#[test]
fn a_time_that_is_not_finite_is_named_as_a_time() {
    for bad in ["NaN", "inf", "abc", "1e400"] {
        let m = message(&format!("t,knee_enc\n0,0.1\n{bad},0.1\n"));
        assert!(m.starts_with("bad.csv:3: column 1 (`t`)"), "{m}");
        assert!(m.contains("t cannot be empty, NaN or inf"), "{m}");
        assert!(!m.contains("leave the cell empty"), "{m}");
        assert!(m.contains(&format!("found `{bad}`")), "{m}");
    }
}

#[test]
fn duplicate_column_names_header_line_and_columns() {
    let m = message("# a: b\nt,knee_enc,knee_enc\n0,1,2\n");
    assert!(
        m.starts_with("bad.csv:2: header: duplicate column `knee_enc` (columns 2 and 3)"),
        "{m}"
    );
}

#[test]
fn missing_time_column_is_named() {
    let m = message("time,knee_enc\n0,1\n");
    assert!(
        m.starts_with("bad.csv:1: header: missing required column `t`"),
        "{m}"
    );
}

#[test]
fn incomplete_vector_group_is_named() {
    let m = message("t,shank_acc_x,shank_acc_z\n0,1,2\n");
    assert!(
        m.starts_with("bad.csv:1: header: incomplete channel group"),
        "{m}"
    );
    assert!(m.contains("shank_acc_y"), "{m}");
}

#[test]
fn wrong_cell_count_names_line_and_counts() {
    let m = message("t,knee_enc,hip_enc\n0,1,2\n0.01,1\n");
    assert!(m.starts_with("bad.csv:3: expected 3 cells"), "{m}");
    assert!(m.contains("found 2"), "{m}");
    let m = message("t,knee_enc\n0,1,2\n");
    assert!(m.starts_with("bad.csv:2: expected 2 cells"), "{m}");
}

#[test]
fn empty_file_and_header_only_file() {
    let m = message("");
    assert!(m.starts_with("bad.csv:1: the file is empty"), "{m}");
    let m = message("# format: limbfuse-trial/1\n# g: 9.81\n");
    assert!(m.starts_with("bad.csv:3: the file is empty"), "{m}");
    let m = message("t,knee_enc\n");
    assert!(m.starts_with("bad.csv:2: no samples"), "{m}");
}

#[test]
fn bad_phase_label_is_named() {
    let m = message("t,phase_ref\n0,SS1\n0.01,walking\n");
    assert!(m.starts_with("bad.csv:3: column 2 (`phase_ref`)"), "{m}");
}

#[test]
fn missing_file_names_path() {
    let e = TrialReader::open(Path::new("/nonexistent/dir/trial.csv")).unwrap_err();
    assert!(
        e.to_string().starts_with("/nonexistent/dir/trial.csv:"),
        "{e}"
    );
}

#[test]
fn invalid_utf8_is_an_error_not_a_panic() {
    let bytes: Vec<u8> = b"t,knee_enc\n0,\xff\xfe\n".to_vec();
    let mut r =
        TrialReader::from_reader(Path::new("bad.csv"), Box::new(std::io::Cursor::new(bytes)))
            .unwrap();
    let m = r.next_record().unwrap_err().to_string();
    assert!(m.starts_with("bad.csv:2: column 2 (`knee_enc`)"), "{m}");
}

/// A row with several bad cells: the error is the first one in the order
/// the reader takes the channels (IMUs before encoders, whatever the
/// column order), the same when a row is parsed in one loop
/// (`Row::numbers_into`) as when it was parsed cell by cell.
#[test]
fn several_bad_cells_report_the_first_in_reading_order() {
    let m = message("t,knee_enc,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z\n0,x,1,y,3\n");
    assert!(m.starts_with("bad.csv:2: column 4 (`thigh_gyr_y`)"), "{m}");
    let m = message("t,knee_enc,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z\n0,x,1,2,3\n");
    assert!(m.starts_with("bad.csv:2: column 2 (`knee_enc`)"), "{m}");
    let m = message("knee_enc,t,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z\nx,,1,y,3\n");
    assert!(m.starts_with("bad.csv:2: column 2 (`t`)"), "{m}");
}

/// A spreadsheet's `;`-separated export (decimal commas) or a
/// tab-separated file reads as one header cell: the error says so instead
/// of only "missing required column `t`".
#[test]
fn another_separator_is_named() {
    let m = message("t;knee_enc\n0,0;1,5\n");
    assert!(
        m.starts_with("bad.csv:1: header: missing required column `t`"),
        "{m}"
    );
    assert!(
        m.contains("one column `t;knee_enc`") && m.contains("separated by `;`"),
        "{m}"
    );
    let m = message("t\tknee_enc\n0\t1\n");
    assert!(m.contains("`t\\tknee_enc`") && m.contains("tabs"), "{m}");
    // a plain missing `t` has no hint
    let m = message("clock,knee_enc\n0,1\n");
    assert!(m.ends_with("(time in seconds)"), "{m}");
}

/// A column that is `t` or a channel written another way (a
/// fresh-recording audit, session 42): the time was "missing required
/// column `t`" with nothing more, and `Thigh_Gyr_X` was ignored as an
/// unknown column, so a method then said the trial had no `thigh_gyr_x`.
#[test]
fn a_time_or_channel_column_spelt_another_way_is_named() {
    let m = message("Time (s),knee_enc\n0,1\n");
    assert!(
        m.contains("missing required column `t`")
            && m.contains("column `Time (s)` looks like it: name it `t`"),
        "{m}"
    );
    let m = message("t,Thigh_Gyr_X,Thigh_Gyr_Y,Thigh_Gyr_Z\n0,1,2,3\n");
    assert!(
        m.starts_with(
            "bad.csv:1: header: column 2 `Thigh_Gyr_X` is the channel `thigh_gyr_x` written \
             another way"
        ),
        "{m}"
    );
    let m = message("t,knee-enc\n0,1\n");
    assert!(
        m.contains("column 2 `knee-enc` is the channel `knee_enc`"),
        "{m}"
    );
    // a column that is not a channel, in any case, is still ignored
    assert_eq!(read_all("t,Knee_Note,knee_enc\n0.0,a,1.0\n").unwrap(), 1);
}

/// Loggers that end every line with the separator give a last column with
/// no name: it is ignored like any column no channel is named after. An
/// empty name anywhere else is still an error.
#[test]
fn a_trailing_separator_is_an_ignored_column() {
    assert_eq!(read_all("t,knee_enc,\n0.0,1.0,\n0.01,2.0,\n").unwrap(), 2);
    let m = message("t,,knee_enc\n0.0,,1.0\n");
    assert!(
        m.starts_with("bad.csv:1: header: column 2 has an empty name"),
        "{m}"
    );
}

/// An audit: `# format: limbfuse-trial/99` was read as version 1 with
/// nothing said. Another version is refused, naming the line; version 1
/// and other formats' names (not limbfuse's) are read as before.
#[test]
fn a_later_format_version_is_refused() {
    let body = "t,thigh_gyr_x,thigh_gyr_y,thigh_gyr_z\n0,0,0,0\n0.01,0,0,0\n";
    let m = message(&format!("# format: limbfuse-trial/99\n{body}"));
    assert!(
        m.contains("`# format: limbfuse-trial/99`") && m.contains("limbfuse-trial/1"),
        "{m}"
    );
    assert_eq!(
        read_all(&format!("# format: limbfuse-trial/1\n{body}")).unwrap(),
        2
    );
    assert_eq!(
        read_all(&format!("# format: my-export\n{body}")).unwrap(),
        2
    );
}
