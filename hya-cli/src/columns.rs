//! `--columns`: which columns of a log a row command reads, by header name or by position.
//!
//! A spec is a comma-separated list of items, each a column or a range of columns:
//!
//! - a position from 1 (`3`) or a range of positions (`2-7`);
//! - a name from the log's header line (`t`, `q1`), or a range of names sharing a prefix and
//!   ending in numbers (`q1-q6` is `q1, q2, …, q6`).
//!
//! The columns are read in the order listed; the command says what it expects in that order
//! (`hya estimate --timestamps`: `t`, then the joint angles, then the torques).

use std::io::BufRead;

use crate::rows::{self, echo, Reader, Row, MAX_ROW_VALUES};
use crate::CliError;

/// One column of a spec before it meets the header: a position or a name.
#[derive(Debug, Clone, PartialEq)]
enum Column {
    /// 1-based position.
    Position(usize),
    /// A header name.
    Name(String),
}

/// A parsed `--columns` spec: the columns to read, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnSpec {
    columns: Vec<Column>,
}

/// A spec resolved against the log: 0-based positions in the row, in the spec's order.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    positions: Vec<usize>,
    widest: usize,
}

fn bad_spec(item: &str, why: impl std::fmt::Display) -> CliError {
    CliError::Input(format!("--columns item {}: {why}", echo(item)))
}

/// `name` split into its prefix and trailing number (`tau12` → `("tau", 12)`), if it ends in one.
fn numbered(name: &str) -> Option<(&str, usize)> {
    let digits = name.len() - name.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let (prefix, number) = name.split_at(name.len() - digits);
    Some((prefix, number.parse().ok()?))
}

impl ColumnSpec {
    /// Parses `spec`; every error names the item and what is wrong with it.
    pub fn parse(spec: &str) -> Result<Self, CliError> {
        let mut columns = Vec::new();
        for item in spec.split(',').map(str::trim) {
            if item.is_empty() {
                return Err(CliError::Input(format!("--columns {}: an empty item", echo(spec))));
            }
            match item.split_once('-') {
                None => columns.push(match item.parse::<usize>() {
                    Ok(0) => return Err(bad_spec(item, "positions count from 1")),
                    Ok(position) => Column::Position(position),
                    Err(_) => Column::Name(item.to_string()),
                }),
                Some((first, last)) => Self::range(item, first.trim(), last.trim(), &mut columns)?,
            }
            if columns.len() > MAX_ROW_VALUES {
                return Err(bad_spec(item, format_args!("more than {MAX_ROW_VALUES} columns, the most a row holds")));
            }
        }
        Ok(Self { columns })
    }

    /// Appends the columns of the range `first-last` (positions or numbered names).
    fn range(item: &str, first: &str, last: &str, columns: &mut Vec<Column>) -> Result<(), CliError> {
        let (from, to, prefix) = match (first.parse::<usize>(), last.parse::<usize>()) {
            (Ok(from), Ok(to)) => (from, to, None),
            _ => match (numbered(first), numbered(last)) {
                (Some((p, from)), Some((q, to))) if p == q && !p.is_empty() => (from, to, Some(p)),
                _ => {
                    return Err(bad_spec(
                        item,
                        "a range is two positions (2-7) or two names with one prefix and numbers (q1-q6)",
                    ))
                }
            },
        };
        if prefix.is_none() && from == 0 {
            return Err(bad_spec(item, "positions count from 1"));
        }
        if to < from {
            return Err(bad_spec(item, "the range ends before it starts"));
        }
        if to - from >= MAX_ROW_VALUES {
            return Err(bad_spec(item, format_args!("more than {MAX_ROW_VALUES} columns, the most a row holds")));
        }
        columns.extend((from..=to).map(|k| match prefix {
            None => Column::Position(k),
            Some(p) => Column::Name(format!("{p}{k}")),
        }));
        Ok(())
    }

    /// How many columns the spec selects.
    pub fn len(&self) -> usize {
        self.columns.len()
    }

    /// Positions in the row for the spec's columns, names looked up in `header` (its line and
    /// names). A name without a header, a name the header lacks, or a column selected twice is an
    /// error naming it.
    pub fn resolve(&self, header: Option<(usize, &[String])>) -> Result<Selection, CliError> {
        let mut positions = Vec::with_capacity(self.columns.len());
        for column in &self.columns {
            let position = match column {
                Column::Position(p) => p - 1,
                Column::Name(name) => match header {
                    None => {
                        return Err(CliError::Input(format!(
                            "--columns names column {} but the log has no header line naming its columns",
                            echo(name)
                        )))
                    }
                    Some((line, names)) => names.iter().position(|n| n == name).ok_or_else(|| {
                        CliError::Input(format!("--columns: no column {} in the header on line {line}", echo(name)))
                    })?,
                },
            };
            if positions.contains(&position) {
                return Err(CliError::Input(format!("--columns selects column {} twice", position + 1)));
            }
            positions.push(position);
        }
        let widest = positions.iter().max().map_or(0, |p| p + 1);
        Ok(Selection { positions, widest })
    }
}

impl Selection {
    /// The selected values of `row`, in the spec's order, into `out` (cleared first); an error
    /// names the line if the row is too short for a selected column.
    pub fn pick(&self, row: &Row, out: &mut Vec<f64>) -> Result<(), CliError> {
        if row.values.len() < self.widest {
            return Err(CliError::Input(format!(
                "line {}: --columns reads column {}, but the row has {} values",
                row.line,
                self.widest,
                row.values.len()
            )));
        }
        out.clear();
        out.extend(self.positions.iter().map(|&p| row.values[p]));
        Ok(())
    }
}

/// The rows of a log reduced to the values a command reads, in its order: the whole row
/// (checked to be `width` wide) or the columns a `--columns` spec selects (resolved against the
/// log's header when the first row comes). A first line whose first field is not a number is
/// the header, with or without a spec.
pub struct Picked<R> {
    reader: Reader<R>,
    spec: Option<ColumnSpec>,
    selection: Option<Selection>,
    width: usize,
    what: String,
    values: Vec<f64>,
    /// How many values every row of the log holds, once known, and where that was set: by the
    /// header (its line and names) or by the first row.
    row_width: Option<(usize, String)>,
    /// Rows read ahead ([`Picked::nominal_step`]), with their lines, handed out first.
    ahead: std::collections::VecDeque<(usize, Vec<f64>)>,
}

/// How many rows [`Picked::nominal_step`] reads ahead.
pub const NOMINAL_STEP_ROWS: usize = 1000;

impl<R: BufRead> Picked<R> {
    /// Reads `input` for rows of `width` values described by `what` (for the errors), or the
    /// columns `spec` selects, which must be `width` of them.
    pub fn new(input: R, spec: Option<ColumnSpec>, width: usize, what: String) -> Result<Self, CliError> {
        if let Some(spec) = &spec {
            if spec.len() != width {
                return Err(CliError::Input(format!(
                    "--columns selects {} columns; {width} are read: {what}",
                    spec.len()
                )));
            }
        }
        let reader = Reader::with_header(input);
        Ok(Self {
            reader,
            spec,
            selection: None,
            width,
            what,
            values: Vec::with_capacity(width),
            row_width: None,
            ahead: Default::default(),
        })
    }

    /// The next row's line number, its values then in [`values`](Self::values); `None` at the
    /// end of the input.
    pub fn next_line(&mut self) -> Option<Result<usize, CliError>> {
        if let Some((line, values)) = self.ahead.pop_front() {
            self.values = values;
            return Some(Ok(line));
        }
        let row = match self.reader.next()? {
            Ok(row) => row,
            Err(e) => return Some(Err(e)),
        };
        Some(self.take(row))
    }

    fn take(&mut self, row: Row) -> Result<usize, CliError> {
        match &self.spec {
            None => {
                rows::expect_width(&row, self.width, &self.what)?;
                self.values.clear();
                self.values.extend_from_slice(&row.values);
            }
            Some(spec) => {
                if self.selection.is_none() {
                    self.selection = Some(spec.resolve(self.reader.header())?);
                }
                self.check_ragged(&row)?;
                if let Some(selection) = &self.selection {
                    selection.pick(&row, &mut self.values)?;
                }
            }
        }
        Ok(row.line)
    }

    /// The nominal sample time of a log whose rows start with their time: the median step of its
    /// first [`NOMINAL_STEP_ROWS`] rows (those that go forward; `None` if none does), which are
    /// read ahead and handed out as usual after. For
    /// `--timestamps` without `--dt`: a log's own rate, where a fixed default (1 ms) once made a
    /// 100 Hz log report every step as a gap.
    pub fn nominal_step(&mut self) -> Result<Option<f64>, CliError> {
        while self.ahead.len() < NOMINAL_STEP_ROWS {
            match self.reader.next() {
                None => break,
                Some(row) => {
                    let line = self.take(row?)?;
                    self.ahead.push_back((line, self.values.clone()));
                }
            }
        }
        let times: Vec<f64> = self.ahead.iter().map(|(_, values)| values[0]).collect();
        // Steps that do not go forward are left to the reader, which names their line.
        let mut steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).filter(|s| s.is_finite() && *s > 0.0).collect();
        if steps.is_empty() {
            return Ok(None);
        }
        steps.sort_by(f64::total_cmp);
        let median = steps[steps.len() / 2];
        crate::rows::check_dt("the log's median step (no --dt given)", median).map(Some)
    }

    /// `params` at the log's [`nominal_step`](Self::nominal_step), and the gap limit: `max_step`
    /// if given, else 2.5 steps; says on stderr which step it took.
    pub fn adopt_nominal_step(
        &mut self,
        params: &hya_core::FilterParams,
        max_step: Option<f64>,
    ) -> Result<(hya_core::FilterParams, f64), CliError> {
        let Some(dt) = self.nominal_step()? else {
            let dt = params.dt_s();
            eprintln!("hya: no --dt, and no step in time order to take it from: {} s", hya_core::Short(dt));
            return Ok((*params, max_step.unwrap_or(2.5 * dt)));
        };
        eprintln!("hya: no --dt: the log's median step, {} s, is the nominal one", hya_core::Short(dt));
        // The command line's own checks of the filter at that step, as for a --dt given.
        let params =
            crate::filter::params(params.zeta(), params.omega1_rad_s(), params.omega2_rad_s(), dt).map_err(|e| {
                crate::rows::at(format_args!("the log's median step {} s taken as --dt", hya_core::Short(dt)), e)
            })?;
        Ok((params, max_step.unwrap_or(2.5 * dt)))
    }

    /// Refuses a row whose width differs from the header's, or from the first row's where the log
    /// has no header: a row with a cell too few or too many would put values under the wrong
    /// names.
    fn check_ragged(&mut self, row: &Row) -> Result<(), CliError> {
        let (expected, set_by) = self.row_width.get_or_insert_with(|| match self.reader.header() {
            Some((line, names)) => (names.len(), format!("the header on line {line} names")),
            None => (row.values.len(), format!("the first row, line {}, has", row.line)),
        });
        if row.values.len() == *expected {
            Ok(())
        } else {
            Err(CliError::Input(format!(
                "line {}: {} values, but {set_by} {expected}: a row with a cell too few or too many is refused, \
                 as its values would stand under the wrong columns",
                row.line,
                row.values.len()
            )))
        }
    }

    /// The values of the row [`next_line`](Self::next_line) returned.
    pub fn values(&self) -> &[f64] {
        &self.values
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(names: &str) -> Vec<String> {
        names.split(',').map(String::from).collect()
    }

    #[test]
    fn names_ranges_and_positions_resolve_in_order() {
        let names = header("time,q1,q2,qd1,qd2,tau1,tau2");
        let spec = ColumnSpec::parse("time, q1-q2 ,tau1-tau2").unwrap();
        assert_eq!(spec.len(), 5);
        let selection = spec.resolve(Some((1, &names))).unwrap();
        let row = Row { line: 2, values: vec![0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0] };
        let mut out = Vec::new();
        selection.pick(&row, &mut out).unwrap();
        assert_eq!(out, [0.5, 1.0, 2.0, 5.0, 6.0]);
        let by_position = ColumnSpec::parse("1,2-3,6-7").unwrap().resolve(None).unwrap();
        assert_eq!(by_position, selection);
        let reordered = ColumnSpec::parse("7,1").unwrap().resolve(None).unwrap();
        reordered.pick(&row, &mut out).unwrap();
        assert_eq!(out, [6.0, 0.5]);
    }

    /// The values [`Picked`] reads from `input` with `spec`, or the first error.
    fn picked(input: &str, spec: &str) -> Result<Vec<Vec<f64>>, String> {
        let spec = ColumnSpec::parse(spec).unwrap();
        let width = spec.len();
        let mut picked = Picked::new(input.as_bytes(), Some(spec), width, "test".into()).unwrap();
        let mut rows = Vec::new();
        while let Some(line) = picked.next_line() {
            line.map_err(|e| e.to_string())?;
            rows.push(picked.values().to_vec());
        }
        Ok(rows)
    }

    #[test]
    fn ragged_rows_are_refused_against_the_header_or_the_first_row() {
        assert_eq!(picked("t,q1,q2\n0,1,2\n1,3,4\n", "t,q2").unwrap(), [[0.0, 2.0], [1.0, 4.0]]);
        let message = picked("t,q1,q2,x\n0,1,2,5\n1,3,4\n", "t,q2").unwrap_err();
        assert!(message.contains("line 3: 3 values, but the header on line 1 names 4"), "{message}");
        let message = picked("t,q1\n0,1,2\n", "t,q1").unwrap_err();
        assert!(message.contains("line 2: 3 values") && message.contains("names 2"), "{message}");
        let message = picked("0 1 2\n1 3\n", "1,2").unwrap_err();
        assert!(message.contains("line 2: 2 values, but the first row, line 1, has 3"), "{message}");
    }

    #[test]
    fn bad_specs_name_the_item() {
        for (spec, expected) in [
            ("t,,q1", "empty item"),
            ("0,1", "count from 1"),
            ("0-3", "count from 1"),
            ("q6-q1", "ends before"),
            ("7-2", "ends before"),
            ("q1-tau3", "one prefix"),
            ("a-b", "one prefix"),
            ("1-99999", "4096"),
        ] {
            let message = ColumnSpec::parse(spec).unwrap_err().to_string();
            assert!(message.contains(expected), "{spec}: {message}");
        }
    }

    #[test]
    fn unknown_names_repeats_and_short_rows_are_named() {
        let names = header("t,q1,tau1");
        let message = ColumnSpec::parse("t,q1,tau2").unwrap().resolve(Some((3, &names))).unwrap_err().to_string();
        assert!(message.contains("\"tau2\"") && message.contains("line 3"), "{message}");
        let message = ColumnSpec::parse("t").unwrap().resolve(None).unwrap_err().to_string();
        assert!(message.contains("no header"), "{message}");
        let message = ColumnSpec::parse("1,2,1").unwrap().resolve(None).unwrap_err().to_string();
        assert!(message.contains("column 1 twice"), "{message}");
        let selection = ColumnSpec::parse("1,5").unwrap().resolve(None).unwrap();
        let row = Row { line: 9, values: vec![1.0, 2.0] };
        let message = selection.pick(&row, &mut Vec::new()).unwrap_err().to_string();
        assert!(
            message.contains("line 9") && message.contains("column 5") && message.contains("2 values"),
            "{message}"
        );
    }
}
