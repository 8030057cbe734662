//! The one way host-sim writes a Markdown table: a header row, its rule, then one line per row,
//! each cell between `| ` and ` |`. Every report page (`design.md`, `compare.md`,
//! `ablation.md`, `rates.md`, `bounds.md`, the M4F bench table) uses it.

use std::fmt::Write as _;

/// How the rule under the header is drawn; both render the same table, and each page keeps the
/// one it has always written so regenerated pages stay byte for byte.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    /// `|---|---|`.
    Compact,
    /// `| --- | --- |`.
    Spaced,
}

/// A Markdown table appended to a page.
#[derive(Debug)]
pub struct Table<'a> {
    out: &'a mut String,
    columns: usize,
}

impl<'a> Table<'a> {
    /// Starts a table on `out`: writes the header row of `headers` and the rule under it.
    pub fn new(out: &'a mut String, headers: &[&str], rule: Rule) -> Self {
        let _ = writeln!(out, "| {} |", headers.join(" | "));
        let cell = match rule {
            Rule::Compact => "---",
            Rule::Spaced => " --- ",
        };
        let rule_line = vec![cell; headers.len()].join("|");
        let _ = writeln!(out, "|{rule_line}|");
        Self {
            out,
            columns: headers.len(),
        }
    }

    /// Appends one row. Cells are written as given (already formatted, with their units);
    /// a row with another number of cells than the header is a bug in the caller (debug assert).
    pub fn row<S: AsRef<str>>(&mut self, cells: &[S]) {
        debug_assert_eq!(cells.len(), self.columns, "cells in a row vs header");
        let _ = write!(self.out, "|");
        for c in cells {
            let _ = write!(self.out, " {} |", c.as_ref());
        }
        let _ = writeln!(self.out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Given a header and two rows, when written with each rule, then the text is the table a
    /// reader of the page sees, rule by rule.
    #[test]
    fn writes_the_header_its_rule_and_each_row() {
        let mut md = String::new();
        let mut t = Table::new(&mut md, &["a", "b [m]"], Rule::Compact);
        t.row(&["1", "2.5"]);
        t.row(&[String::from("x"), format!("{:.2}", 0.125)]);
        assert_eq!(md, "| a | b [m] |\n|---|---|\n| 1 | 2.5 |\n| x | 0.12 |\n");
        let mut md = String::new();
        Table::new(&mut md, &["a", "b", "c"], Rule::Spaced).row(&["1", "2", "3"]);
        assert_eq!(md, "| a | b | c |\n| --- | --- | --- |\n| 1 | 2 | 3 |\n");
    }
}
