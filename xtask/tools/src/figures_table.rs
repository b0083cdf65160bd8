//! The CSV tables behind `docs/figures.md`: every figure's data is written as a plain CSV file
//! (header line, comma-separated cells without quoting) and the prose is generated from those
//! files only, so the check test can regenerate it and recompute every number it states.

use std::path::Path;

use anyhow::{Context, Result, bail};

/// One CSV table: a header and rows of as many cells.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// Column names.
    pub header: Vec<String>,
    /// Rows, each with one cell per column.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// An empty table with these columns.
    pub fn new(header: &[&str]) -> Table {
        Table {
            header: header.iter().map(|h| h.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row; its cells must not contain commas or line breaks.
    pub fn push(&mut self, row: Vec<String>) {
        debug_assert_eq!(row.len(), self.header.len());
        debug_assert!(row.iter().all(|c| !c.contains([',', '\n'])));
        self.rows.push(row);
    }

    /// The table as CSV text.
    pub fn to_csv(&self) -> String {
        let mut s = self.header.join(",");
        s.push('\n');
        for r in &self.rows {
            s.push_str(&r.join(","));
            s.push('\n');
        }
        s
    }

    /// Parses CSV text written by [`Table::to_csv`]; `what` names it in errors.
    pub fn parse(text: &str, what: &str) -> Result<Table> {
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header: Vec<String> = match lines.next() {
            Some(h) => h.split(',').map(|c| c.trim().to_string()).collect(),
            None => bail!("{what}: empty file"),
        };
        let mut rows = Vec::new();
        for (i, l) in lines.enumerate() {
            let row: Vec<String> = l.split(',').map(|c| c.trim().to_string()).collect();
            if row.len() != header.len() {
                bail!(
                    "{what}: line {} has {} cells, the header {}",
                    i + 2,
                    row.len(),
                    header.len()
                );
            }
            rows.push(row);
        }
        Ok(Table { header, rows })
    }

    /// Writes the table to `path`.
    pub fn write(&self, path: &Path) -> Result<()> {
        std::fs::write(path, self.to_csv()).with_context(|| format!("writing {}", path.display()))
    }

    /// Reads a table from `path`.
    pub fn read(path: &Path) -> Result<Table> {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        Table::parse(&text, &path.display().to_string())
    }

    /// Index of column `name`.
    pub fn col(&self, name: &str) -> Result<usize> {
        self.header
            .iter()
            .position(|h| h == name)
            .with_context(|| format!("no column {name} in {:?}", self.header))
    }

    /// Column `name` as numbers.
    pub fn f64s(&self, name: &str) -> Result<Vec<f64>> {
        let c = self.col(name)?;
        self.rows
            .iter()
            .enumerate()
            .map(|(i, r)| {
                r[c].parse::<f64>()
                    .with_context(|| format!("row {i}, column {name}: {:?} is not a number", r[c]))
            })
            .collect()
    }

    /// The rows whose column `key` equals `value`, as a table of the same columns.
    pub fn filter(&self, key: &str, value: &str) -> Result<Table> {
        let c = self.col(key)?;
        Ok(Table {
            header: self.header.clone(),
            rows: self
                .rows
                .iter()
                .filter(|r| r[c] == value)
                .cloned()
                .collect(),
        })
    }

    /// The one cell of column `name` in the row whose column `key` equals `value`.
    pub fn lookup(&self, key: &str, value: &str, name: &str) -> Result<&str> {
        let (k, c) = (self.col(key)?, self.col(name)?);
        self.rows
            .iter()
            .find(|r| r[k] == value)
            .map(|r| r[c].as_str())
            .with_context(|| format!("no row with {key} = {value}"))
    }

    /// [`Table::lookup`] as a number.
    pub fn number(&self, key: &str, value: &str, name: &str) -> Result<f64> {
        let cell = self.lookup(key, value, name)?;
        cell.parse()
            .with_context(|| format!("{key} = {value}, {name}: {cell:?} is not a number"))
    }
}

/// Replaces the part of `doc` between `begin` and `end` (markers included) by `section`, or
/// appends `section` when the markers are missing.
pub fn splice(doc: &str, begin: &str, end: &str, section: &str) -> String {
    match (doc.find(begin), doc.find(end)) {
        (Some(b), Some(e)) if e > b => {
            format!(
                "{}{}{}",
                &doc[..b],
                section.trim_end(),
                &doc[e + end.len()..]
            )
        }
        _ => format!("{}\n\n{}\n", doc.trim_end(), section.trim_end()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trips_and_refuses_ragged_rows() {
        let mut t = Table::new(&["frame", "fps"]);
        t.push(vec!["0".into(), "12.5".into()]);
        t.push(vec!["1".into(), "13".into()]);
        let back = Table::parse(&t.to_csv(), "t").unwrap();
        assert_eq!(back, t);
        assert_eq!(back.f64s("fps").unwrap(), vec![12.5, 13.0]);
        assert_eq!(back.number("frame", "1", "fps").unwrap(), 13.0);
        assert!(back.f64s("nope").is_err());
        assert!(Table::parse("a,b\n1\n", "t").is_err());
        assert!(Table::parse("a\nx\n", "t").unwrap().f64s("a").is_err());
    }

    #[test]
    fn splice_replaces_only_the_marked_section() {
        let doc = "head\n<!-- a -->old<!-- b -->\ntail\n";
        let new = splice(doc, "<!-- a -->", "<!-- b -->", "<!-- a -->new<!-- b -->\n");
        assert_eq!(new, "head\n<!-- a -->new<!-- b -->\ntail\n");
        assert_eq!(
            crate::figures_check::section(&new, "<!-- a -->", "<!-- b -->"),
            Some("<!-- a -->new<!-- b -->")
        );
    }
}
