//! Run names: they become file names (`<run>.parquet`, `gap_<run>.png`, `<run>_errors.png`), so
//! every place a user gives one (`--dataset NAME=PATH`, an experiment's `[[run]] name`, `--run`,
//! a report configuration's dataset names) checks it here, before any work starts.

/// The rule a run name must follow, as the messages quote it.
pub const RUN_NAME_RULE: &str =
    "1 to 100 of the characters [A-Za-z0-9_.-], not starting with '.' (so not '.' or '..')";

/// Longest run name accepted (characters); file names add a prefix and a suffix to it.
pub const MAX_RUN_NAME_CHARS: usize = 100;

/// A run name that breaks [`RUN_NAME_RULE`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "run name {shown} is not usable as a file name: a run name must be {RUN_NAME_RULE}{why}",
    shown = quoted(name),
    why = reason(name)
)]
pub struct RunNameError {
    /// The name as given.
    pub name: String,
}

/// The name in quotes with control characters escaped (a newline shows as `\n`).
fn quoted(name: &str) -> String {
    format!("'{}'", name.escape_debug())
}

/// What in `name` breaks the rule, as a clause starting with "; ".
fn reason(name: &str) -> String {
    if name.is_empty() {
        return "; it is empty".into();
    }
    if name.chars().count() > MAX_RUN_NAME_CHARS {
        return format!("; it has {} characters", name.chars().count());
    }
    if name.starts_with('.') {
        return "; it starts with '.'".into();
    }
    match name.chars().find(|c| !allowed(*c)) {
        Some(c) => format!("; it contains '{}'", c.escape_debug()),
        None => String::new(),
    }
}

fn allowed(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-')
}

/// Checks a run name against [`RUN_NAME_RULE`]: `Ok(name)` when it can be used in a file name
/// as it is, else an error that quotes the name and the rule.
pub fn run_name(name: &str) -> Result<&str, RunNameError> {
    let ok = !name.is_empty()
        && name.chars().count() <= MAX_RUN_NAME_CHARS
        && !name.starts_with('.')
        && name.chars().all(allowed);
    if ok {
        Ok(name)
    } else {
        Err(RunNameError {
            name: name.to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_names_that_are_plain_file_names_pass_and_others_are_refused_with_the_rule() {
        for good in ["nav1", "cal", "a.b-c_D9", "x", "run.2026-11-28"] {
            assert_eq!(run_name(good), Ok(good));
        }
        for (bad, why) in [
            ("", "empty"),
            (".", "starts with '.'"),
            ("..", "starts with '.'"),
            ("../../x", "starts with '.'"),
            ("a/b", "contains '/'"),
            ("nav\n1", "contains '\\n'"),
            ("my run", "contains ' '"),
            ("nav\u{e9}", "contains '\u{e9}'"),
        ] {
            let e = run_name(bad).expect_err(bad).to_string();
            assert!(e.contains(RUN_NAME_RULE) && e.contains(why), "{bad:?}: {e}");
            assert!(
                !e.contains('\n'),
                "{bad:?}: the message stays on one line: {e}"
            );
        }
        let long = "a".repeat(MAX_RUN_NAME_CHARS + 1);
        assert!(run_name(&long).is_err());
        assert!(run_name(&long[1..]).is_ok());
    }
}
