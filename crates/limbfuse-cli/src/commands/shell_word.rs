//! A file name as one word of a POSIX shell command line, for the commands
//! that output files record (`# command:` of an estimate, a report's
//! commands): an audit pasted a recorded `limbfuse report wälk <b>&"x'.csv`
//! into a shell, which split it at `<` and `&`.

use std::borrow::Cow;

/// `text` unchanged when every character is one a shell takes literally,
/// else in single quotes (a `'` inside written `'\''`).
pub fn shell_word(text: &str) -> Cow<'_, str> {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-./:=+,@%".contains(c));
    if plain {
        Cow::Borrowed(text)
    } else {
        Cow::Owned(format!("'{}'", text.replace('\'', r"'\''")))
    }
}

/// The file name of `path` (not its directory, so the same run in another
/// directory records the same command) as one shell word.
pub fn file_word(path: &std::path::Path) -> String {
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    shell_word(&name).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_a_shell_would_split_are_quoted() {
        assert_eq!(shell_word("walk-1.csv"), "walk-1.csv");
        assert_eq!(shell_word("../data/w.csv"), "../data/w.csv");
        assert_eq!(shell_word("my walk.csv"), "'my walk.csv'");
        assert_eq!(shell_word(r#"w<b>&"x'.csv"#), r#"'w<b>&"x'\''.csv'"#);
        assert_eq!(shell_word("wälk.csv"), "'wälk.csv'");
        assert_eq!(shell_word(""), "''");
    }
}
