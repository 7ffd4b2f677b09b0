//! Markdown tables for the reports of every crate: a header, a separator row that sets each
//! column's alignment, and rows of cells the caller has already formatted.
//!
//! ```
//! use sins_config::markdown::{Align, Table};
//!
//! let mut t = Table::new(["run", "max (m)"]).align(&[Align::Left, Align::Right]);
//! t.row(["a", "12.5"]);
//! t.row(["b", "7.0"]);
//! assert_eq!(
//!     t.render(),
//!     "| run | max (m) |\n|---|--:|\n| a | 12.5 |\n| b | 7.0 |\n"
//! );
//! ```

use std::fmt;

/// Column alignment, as written in the separator row.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Align {
    /// `---` (renderers align such a column left).
    #[default]
    Left,
    /// `--:`.
    Right,
    /// `:-:`.
    Center,
}

impl Align {
    fn marker(self) -> &'static str {
        match self {
            Align::Left => "---",
            Align::Right => "--:",
            Align::Center => ":-:",
        }
    }
}

/// A Markdown table built row by row.
///
/// [`render`](Table::render) (and `Display`) give one line per row, each ending in `\n`:
/// `| a | b |\n|---|---|\n| 1 | 2 |\n`. Cells are written as given (callers format numbers),
/// with one space either side, except that a `|` in a header or body cell is escaped as `\|` so
/// that it cannot split the cell; a `|` already written `\|` is kept as it is.
///
/// Every row has as many cells as the header: a row with fewer is padded with empty cells, and a
/// row with a different count is a programming error that `debug_assert!` reports in debug
/// builds (in release builds the cells beyond the header's are written as given).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Table {
    header: Vec<String>,
    align: Vec<Align>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with this header row, every column aligned [`Align::Left`] and no rows.
    pub fn new<S: Into<String>>(header: impl IntoIterator<Item = S>) -> Self {
        let header: Vec<String> = header.into_iter().map(|h| escape(&h.into())).collect();
        let align = vec![Align::Left; header.len()];
        Table {
            header,
            align,
            rows: Vec::new(),
        }
    }

    /// The alignment of the first `align.len()` columns (the others stay [`Align::Left`]); more
    /// entries than columns is a programming error (`debug_assert!`), the surplus is ignored.
    pub fn align(mut self, align: &[Align]) -> Self {
        debug_assert!(
            align.len() <= self.header.len(),
            "{} alignments for {} columns",
            align.len(),
            self.header.len()
        );
        for (a, &b) in self.align.iter_mut().zip(align) {
            *a = b;
        }
        self
    }

    /// Append a row of cells (written with `to_string`, `|` escaped; missing cells are empty).
    pub fn row<S: ToString>(&mut self, cells: impl IntoIterator<Item = S>) -> &mut Self {
        let mut row: Vec<String> = cells.into_iter().map(|c| escape(&c.to_string())).collect();
        debug_assert_eq!(
            row.len(),
            self.header.len(),
            "a Markdown row of {} cells under a header of {}: {row:?}",
            row.len(),
            self.header.len()
        );
        if row.len() < self.header.len() {
            row.resize(self.header.len(), String::new());
        }
        self.rows.push(row);
        self
    }

    /// No body row yet (the header does not count).
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The number of body rows (the header and separator do not count).
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// The table as Markdown: header, separator and rows, each line ending in `\n`.
    pub fn render(&self) -> String {
        self.to_string()
    }
}

impl fmt::Display for Table {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        line(f, &self.header)?;
        f.write_str("|")?;
        for a in &self.align {
            write!(f, "{}|", a.marker())?;
        }
        f.write_str("\n")?;
        for r in &self.rows {
            line(f, r)?;
        }
        Ok(())
    }
}

/// One line `| a | b |\n`.
fn line(f: &mut fmt::Formatter<'_>, cells: &[String]) -> fmt::Result {
    f.write_str("|")?;
    for c in cells {
        write!(f, " {c} |")?;
    }
    f.write_str("\n")
}

/// `s` with every `|` not already preceded by a backslash written `\|`.
fn escape(s: &str) -> String {
    if !s.contains('|') {
        return s.to_string();
    }
    let mut out = String::with_capacity(s.len() + 4);
    let mut prev = None;
    for c in s.chars() {
        if c == '|' && prev != Some('\\') {
            out.push('\\');
        }
        out.push(c);
        prev = Some(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_header_separator_and_rows() {
        let mut t = Table::new(["a", "b"]);
        assert!(t.is_empty());
        assert_eq!(t.len(), 0);
        assert_eq!(t.render(), "| a | b |\n|---|---|\n");
        t.row(["1", "2"]).row([3.5, 4.0]);
        assert!(!t.is_empty());
        assert_eq!(t.len(), 2);
        assert_eq!(t.render(), "| a | b |\n|---|---|\n| 1 | 2 |\n| 3.5 | 4 |\n");
        assert_eq!(t.to_string(), t.render());
    }

    #[test]
    fn owned_and_formatted_cells() {
        let head: Vec<String> = vec!["run".into(), format!("`{}`", "k")];
        let mut t = Table::new(head);
        t.row(vec![String::from("r1"), format!("{:.2}", 1.0 / 3.0)]);
        t.row(["", "x"]);
        assert_eq!(
            t.render(),
            "| run | `k` |\n|---|---|\n| r1 | 0.33 |\n|  | x |\n"
        );
    }

    #[test]
    fn alignment_row() {
        let t = Table::new(["n", "x", "y", "z"]).align(&[
            Align::Left,
            Align::Right,
            Align::Center,
            Align::Right,
        ]);
        assert_eq!(t.render(), "| n | x | y | z |\n|---|--:|:-:|--:|\n");
        // Columns beyond the alignments given stay left.
        let t = Table::new(["n", "x", "y"]).align(&[Align::Right]);
        assert_eq!(t.render(), "| n | x | y |\n|--:|---|---|\n");
    }

    #[test]
    fn escapes_pipes_once() {
        let mut t = Table::new(["max \\|gap\\|", "a|b"]);
        t.row(["|x|", "already \\| escaped"]);
        assert_eq!(
            t.render(),
            "| max \\|gap\\| | a\\|b |\n|---|---|\n| \\|x\\| | already \\| escaped |\n"
        );
        assert_eq!(escape("||"), "\\|\\|");
        assert_eq!(escape("no pipe"), "no pipe");
    }

    #[test]
    fn empty_header_renders_bare_lines() {
        assert_eq!(Table::new(Vec::<String>::new()).render(), "|\n|\n");
    }

    #[test]
    #[cfg_attr(debug_assertions, should_panic(expected = "a Markdown row of 1 cells"))]
    fn pads_a_short_row() {
        let mut t = Table::new(["a", "b", "c"]);
        t.row(["1"]);
        assert_eq!(t.render(), "| a | b | c |\n|---|---|---|\n| 1 |  |  |\n");
    }
}
