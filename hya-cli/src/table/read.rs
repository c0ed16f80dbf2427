//! Reading a table ([the format](super)): the csv crate splits the records of the prepared lines
//! ([`super::lines`]); this module finds the header, decides which columns a command reads, and
//! checks every row against them.

use std::collections::VecDeque;
use std::io::BufRead;

use hya_core::Short;

use super::columns::ColumnSpec;
use super::lines::{LineError, Prepared};
use super::{echo, Column, MAX_ROW_VALUES};
use crate::CliError;

/// How many rows [`Table::nominal_step`] reads ahead.
pub const NOMINAL_STEP_ROWS: usize = 1000;

/// Which columns a command reads, decided on the first data row.
#[derive(Debug)]
struct Layout {
    /// 0-based positions of the columns read, in the command's order.
    positions: Vec<usize>,
    /// How many cells every row holds.
    width: usize,
    /// What set that width, for the messages: the header or the first row.
    width_set_by: String,
}

/// The rows of a log reduced to the values a command reads, in its order.
pub struct Table<R> {
    records: csv::Reader<Prepared<R>>,
    record: csv::ByteRecord,
    spec: Option<ColumnSpec>,
    /// The columns the command reads, by hya's names; `None` for any number of them.
    wanted: Option<Vec<Column>>,
    /// What the command reads, for the messages.
    what: String,
    /// The header's line and columns, once read.
    header: Option<(usize, Vec<Column>)>,
    layout: Option<Layout>,
    values: Vec<f64>,
    /// Rows read ahead ([`Table::nominal_step`]), with their lines, handed out first.
    ahead: VecDeque<(usize, Vec<f64>)>,
}

impl<R: BufRead> Table<R> {
    /// Reads `input` for the columns `wanted` (described by `what` in messages): those `spec`
    /// selects, else those the header names, else the whole row, which must then hold exactly
    /// them.
    pub fn new(input: R, spec: Option<ColumnSpec>, wanted: Vec<Column>, what: String) -> Result<Self, CliError> {
        if let Some(selected) = spec.as_ref().and_then(ColumnSpec::len) {
            if selected != wanted.len() {
                return Err(selection_mismatch(selected, wanted.len(), &what));
            }
        }
        Ok(Self { wanted: Some(wanted), what, ..Self::any(input, spec) })
    }

    /// Reads every column of `input` (or those `spec` selects), as many as the header or the
    /// first row has.
    pub fn any(input: R, spec: Option<ColumnSpec>) -> Self {
        let records = csv::ReaderBuilder::new().has_headers(false).flexible(true).from_reader(Prepared::new(input));
        Self {
            records,
            record: csv::ByteRecord::new(),
            spec,
            wanted: None,
            what: "one value per channel".into(),
            header: None,
            layout: None,
            values: Vec::new(),
            ahead: VecDeque::new(),
        }
    }

    /// The next row's line number, its values then in [`values`](Self::values); `None` at the
    /// end of the input.
    pub fn next_line(&mut self) -> Option<Result<usize, CliError>> {
        if let Some((line, values)) = self.ahead.pop_front() {
            self.values = values;
            return Some(Ok(line));
        }
        self.read_row().transpose()
    }

    /// The values of the row [`next_line`](Self::next_line) returned.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The columns read, as the header names them (`None` without a header), once the first
    /// row is read.
    pub fn header_columns(&self) -> Option<Vec<Column>> {
        let (_, columns) = self.header.as_ref()?;
        Some(self.layout.as_ref()?.positions.iter().map(|&p| columns[p].clone()).collect())
    }

    fn read_row(&mut self) -> Result<Option<usize>, CliError> {
        loop {
            let more = self.records.read_byte_record(&mut self.record).map_err(csv_error)?;
            if !more {
                return Ok(None);
            }
            let line = self.records.get_mut().take_line();
            if self.record.len() > MAX_ROW_VALUES {
                return Err(CliError::Input(format!(
                    "line {line}: more than {MAX_ROW_VALUES} values, the most a row may hold"
                )));
            }
            // Only the first record may be a header: before it, neither a header nor a layout.
            let first = self.header.is_none() && self.layout.is_none();
            if first && self.is_header() {
                let columns = (0..self.record.len())
                    .map(|k| header_cell(&self.record, k, line))
                    .collect::<Result<Vec<_>, _>>()?;
                self.header = Some((line, columns));
                continue;
            }
            if self.layout.is_none() {
                self.layout = Some(self.layout(line)?);
            }
            self.take(line)?;
            return Ok(Some(line));
        }
    }

    /// Whether the record read is a header: its first cell is there and is not a number.
    fn is_header(&self) -> bool {
        let first = self.record.get(0).map(|c| String::from_utf8_lossy(c).trim().to_string()).unwrap_or_default();
        !first.is_empty() && first.parse::<f64>().is_err()
    }

    /// Decides which columns to read on the first data row, at `line`.
    fn layout(&self, line: usize) -> Result<Layout, CliError> {
        let header = self.header.as_ref().map(|(line, columns)| (*line, columns.as_slice()));
        let (width, width_set_by) = match header {
            Some((line, columns)) => (columns.len(), format!("the header on line {line} names")),
            None => (self.record.len(), format!("the first row, line {line}, has")),
        };
        let positions = match (&self.spec, &self.wanted) {
            (Some(spec), wanted) => {
                let positions = spec.resolve(header)?;
                match wanted {
                    Some(wanted) if wanted.len() != positions.len() => {
                        return Err(selection_mismatch(positions.len(), wanted.len(), &self.what))
                    }
                    _ => positions,
                }
            }
            (None, Some(wanted)) => {
                // Where the header names each column read, if it does.
                let found: Vec<Option<usize>> = match header {
                    Some((_, columns)) => {
                        wanted.iter().map(|w| columns.iter().position(|c| c.name == w.name)).collect()
                    }
                    None => vec![None; wanted.len()],
                };
                if found.iter().all(Option::is_some) {
                    found.into_iter().flatten().collect()
                } else if let Some(k) = (0..found.len()).find(|&k| found[k].is_some_and(|p| p != k)) {
                    // A column read named away from its place in the command's order: reading by
                    // position would put it under another's name.
                    return Err(self.partly_named(line, k, &found, wanted));
                } else if width == wanted.len() {
                    (0..width).collect()
                } else {
                    return Err(self.unreadable(line, width, &found, wanted));
                }
            }
            (None, None) => (0..width).collect(),
        };
        if let Some(widest) = positions.iter().max().filter(|&&p| p >= width) {
            return Err(CliError::Input(format!(
                "line {line}: --columns reads column {}, but {width_set_by} {width}",
                widest + 1
            )));
        }
        if let (Some((header_line, columns)), Some(wanted)) = (header, &self.wanted) {
            for (&p, want) in positions.iter().zip(wanted) {
                if !columns[p].unit_fits(want) {
                    return Err(CliError::Input(format!(
                        "line {header_line}, column {}: {} is read as {want}; a unit is never converted: \
                         convert the log, or name the column without its unit",
                        p + 1,
                        echo(&columns[p].to_string()),
                    )));
                }
            }
        }
        Ok(Layout { positions, width, width_set_by })
    }

    /// The error for a log whose columns are neither named as hya names them nor exactly the
    /// command's; `found` is where the header names each column read.
    fn unreadable(&self, line: usize, width: usize, found: &[Option<usize>], wanted: &[Column]) -> CliError {
        let names = match &self.header {
            Some((header_line, _)) => {
                format!(" in the header on line {header_line}, which names no column {}", missing(found, wanted))
            }
            None => String::new(),
        };
        CliError::Input(format!(
            "line {line}: expected {} values ({}), found {width}{names}; pick the columns with --columns",
            wanted.len(),
            self.what
        ))
    }

    /// The error for a header that names column `k` of those read away from its place.
    fn partly_named(&self, line: usize, k: usize, found: &[Option<usize>], wanted: &[Column]) -> CliError {
        CliError::Input(format!(
            "line {line}: the header names {} in column {}, where reading by position would take column {}, and \
             names no column {}: {} are read ({}); name them all, or pick them with --columns",
            echo(&wanted[k].name),
            found[k].map_or(0, |p| p + 1),
            k + 1,
            missing(found, wanted),
            wanted.len(),
            self.what
        ))
    }

    /// Checks the record read at `line` against the layout and parses its columns into `values`.
    fn take(&mut self, line: usize) -> Result<(), CliError> {
        let Some(layout) = &self.layout else { return Ok(()) };
        if self.record.len() != layout.width {
            return Err(CliError::Input(format!(
                "line {line}: {} values, but {} {}: a row with a cell too few or too many is refused, \
                 as its values would stand under the wrong columns",
                self.record.len(),
                layout.width_set_by,
                layout.width
            )));
        }
        self.values.clear();
        for &p in &layout.positions {
            self.values.push(number(&self.record, p, line)?);
        }
        Ok(())
    }

    /// The nominal sample time of a log whose rows start with their time: the median step of its
    /// first [`NOMINAL_STEP_ROWS`] rows (those that go forward; `None` if none does), which are
    /// read ahead and handed out as usual after. For `--timestamps` without `--dt`: a log's own
    /// rate, where a fixed default (1 ms) once made a 100 Hz log report every step as a gap.
    pub fn nominal_step(&mut self) -> Result<Option<f64>, CliError> {
        while self.ahead.len() < NOMINAL_STEP_ROWS {
            match self.read_row()? {
                None => break,
                Some(line) => self.ahead.push_back((line, self.values.clone())),
            }
        }
        let times: Vec<f64> = self.ahead.iter().map(|(_, values)| values[0]).collect();
        // Steps that do not go forward are left to the command, which names their line.
        let mut steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).filter(|s| s.is_finite() && *s > 0.0).collect();
        if steps.is_empty() {
            return Ok(None);
        }
        steps.sort_by(f64::total_cmp);
        let median = steps[steps.len() / 2];
        super::check_dt("the log's median step (no --dt given)", median).map(Some)
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
            eprintln!("hya: no --dt, and no step in time order to take it from: {} s", Short(dt));
            return Ok((*params, max_step.unwrap_or(2.5 * dt)));
        };
        eprintln!("hya: no --dt: the log's median step, {} s, is the nominal one", Short(dt));
        // The command line's own checks of the filter at that step, as for a --dt given.
        let params = crate::filter::params(params.zeta(), params.omega1_rad_s(), params.omega2_rad_s(), dt)
            .map_err(|e| super::at(format_args!("the log's median step {} s taken as --dt", Short(dt)), e))?;
        Ok((params, max_step.unwrap_or(2.5 * dt)))
    }
}

/// The first three of the `wanted` columns the header does not name (`found[k]` is `None`).
fn missing(found: &[Option<usize>], wanted: &[Column]) -> String {
    let names = wanted.iter().zip(found).filter(|(_, f)| f.is_none()).map(|(w, _)| echo(&w.name));
    names.take(3).collect::<Vec<_>>().join(", ")
}

fn selection_mismatch(selected: usize, wanted: usize, what: &str) -> CliError {
    CliError::Input(format!("--columns selects {selected} columns; {wanted} are read: {what}"))
}

/// The error of the CSV reader as the user's: a refused line's own message, else what csv says.
fn csv_error(error: csv::Error) -> CliError {
    let message = error.to_string();
    match error.into_kind() {
        csv::ErrorKind::Io(e) => match LineError::message(&e) {
            Some(message) => CliError::Input(message.to_string()),
            None => CliError::Io(e),
        },
        _ => CliError::Input(message),
    }
}

/// Cell `k` of `record` as text, or an error naming its line and column.
fn text(record: &csv::ByteRecord, k: usize, line: usize) -> Result<&str, CliError> {
    let cell = record.get(k).unwrap_or_default();
    std::str::from_utf8(cell)
        .map(str::trim)
        .map_err(|_| CliError::Input(format!("line {line}, column {}: not valid UTF-8 text", k + 1)))
}

/// Cell `k` of a header.
fn header_cell(record: &csv::ByteRecord, k: usize, line: usize) -> Result<Column, CliError> {
    match text(record, k, line)? {
        "" => Err(CliError::Input(format!(
            "line {line}, column {}: an empty cell in the header (a column without a name)",
            k + 1
        ))),
        cell => Ok(Column::from_header(cell)),
    }
}

/// Cell `k` of a data row as a finite number, or an error naming its line and column.
fn number(record: &csv::ByteRecord, k: usize, line: usize) -> Result<f64, CliError> {
    let column = k + 1;
    match text(record, k, line)? {
        "" => Err(CliError::Input(format!(
            "line {line}, column {column}: an empty cell (a missing value); fill it or remove the row"
        ))),
        cell => match cell.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(v) => Err(CliError::Input(format!("line {line}, column {column}: non-finite value {}", Short(v)))),
            Err(_) => Err(CliError::Input(format!("line {line}, column {column}: not a number: {}", echo(cell)))),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The values `input` gives for `wanted` (names) with `spec`, each with its line, or the
    /// first error.
    fn read(input: &str, spec: Option<&str>, wanted: &[&str]) -> Result<Vec<(usize, Vec<f64>)>, String> {
        let spec = spec.map(|s| ColumnSpec::parse(s).unwrap());
        let mut table = match wanted {
            [] => Table::any(input.as_bytes(), spec),
            wanted => {
                let wanted = wanted.iter().map(|w| Column::from_header(w)).collect();
                Table::new(input.as_bytes(), spec, wanted, "test".into()).map_err(|e| e.to_string())?
            }
        };
        let mut rows = Vec::new();
        while let Some(line) = table.next_line() {
            let line = line.map_err(|e| e.to_string())?;
            rows.push((line, table.values().to_vec()));
        }
        Ok(rows)
    }

    #[test]
    fn lines_are_the_files_lines() {
        let rows = read("# a log\n\n1 2\n\n# c\n3 4\r\n", None, &[]).unwrap();
        assert_eq!(rows, [(3, vec![1.0, 2.0]), (6, vec![3.0, 4.0])]);
        let rows = read("t,q\n\"0.5\", 1e-3\n", None, &[]).unwrap();
        assert_eq!(rows, [(2, vec![0.5, 1e-3])]);
    }

    #[test]
    fn hya_names_are_found_in_a_wider_log() {
        let log = "t [s],q_a [rad],qd_a [rad/s],tau_a [N m]\n0,1,2,3\n0.1,4,5,6\n";
        let rows = read(log, None, &["t [s]", "q_a [rad]", "tau_a [N·m]"]).unwrap();
        assert_eq!(rows, [(2, vec![0.0, 1.0, 3.0]), (3, vec![0.1, 4.0, 6.0])]);
        // A header of other names, exactly as wide as what is read: read in order.
        assert_eq!(read("time,x\n0,1\n", None, &["t", "q_a"]).unwrap(), [(2, vec![0.0, 1.0])]);
        // One that names some of them, elsewhere: never read by position.
        let message = read("tau_a,q\n1,2\n", None, &["q_a", "tau_a"]).unwrap_err();
        assert!(
            message.contains("names \"tau_a\" in column 1, where reading by position would take column 2"),
            "{message}"
        );
        // A name in its place (a log's own `t`) leaves the others to their positions.
        assert_eq!(read("t,q1\n0,1\n", None, &["t", "q_a"]).unwrap(), [(2, vec![0.0, 1.0])]);
        let message = read("time,x,y\n0,1,2\n", None, &["t", "q_a"]).unwrap_err();
        assert!(message.contains("expected 2 values (test), found 3 in the header on line 1"), "{message}");
        assert!(message.contains("names no column \"t\", \"q_a\""), "{message}");
        assert!(message.contains("--columns"), "{message}");
    }

    #[test]
    fn units_that_differ_are_refused() {
        let message = read("t [s],q_a [deg]\n0,90\n", None, &["t [s]", "q_a [rad]"]).unwrap_err();
        assert!(message.contains("line 1, column 2: \"q_a [deg]\" is read as q_a [rad]"), "{message}");
        assert!(read("t,q_a\n0,1\n", None, &["t [s]", "q_a [rad]"]).is_ok(), "no unit: nothing to check");
    }

    #[test]
    fn ragged_rows_and_empty_cells_are_refused_with_their_place() {
        let message = read("t,q1,q2,x\n0,1,2,5\n1,3,4\n", Some("t,q2"), &["t", "q"]).unwrap_err();
        assert!(message.contains("line 3: 3 values, but the header on line 1 names 4"), "{message}");
        let message = read("0 1 2\n1 3\n", Some("1,2"), &["t", "q"]).unwrap_err();
        assert!(message.contains("line 2: 2 values, but the first row, line 1, has 3"), "{message}");
        for (text, column) in [("0.001,0.1,,1", 3), (",2,3,4", 1), ("1,2,3,", 4), ("1, ,3,4", 2)] {
            let message = read(&format!("1,2,3,4\n{text}\n"), None, &[]).unwrap_err();
            assert!(message.contains(&format!("line 2, column {column}: an empty cell")), "{text}: {message}");
        }
        let message = read("t,,q2\n0,1,2\n", None, &[]).unwrap_err();
        assert!(message.contains("line 1, column 2: an empty cell in the header"), "{message}");
    }

    #[test]
    fn a_header_comes_first_or_not_at_all() {
        let message = read("1 2\nt q\n", None, &[]).unwrap_err();
        assert!(message.contains("line 2, column 1: not a number: \"t\""), "{message}");
        let message = read("1 NaN\n", None, &[]).unwrap_err();
        assert!(message.contains("line 1, column 2: non-finite"), "{message}");
        let field = "y".repeat(10_000);
        let message = read(&format!("1 {field}\n"), None, &[]).unwrap_err();
        assert!(message.len() < 120 && message.contains("column 2") && message.contains("yyy…"), "{message}");
    }

    #[test]
    fn rows_are_capped_in_values() {
        let wide = "1 ".repeat(MAX_ROW_VALUES);
        assert_eq!(read(&wide, None, &[]).unwrap()[0].1.len(), MAX_ROW_VALUES);
        let message = read(&format!("{wide} 1"), None, &[]).unwrap_err();
        assert!(message.contains("line 1") && message.contains("4096"), "{message}");
    }

    #[test]
    fn a_selection_wider_than_the_rows_is_named() {
        let message = read("1 2\n", Some("1,5"), &["a", "b"]).unwrap_err();
        assert!(message.contains("line 1: --columns reads column 5, but the first row, line 1, has 2"), "{message}");
        let message = read("a,b,c\n1,2,3\n", Some("a-c"), &["a", "b"]).unwrap_err();
        assert!(message.contains("selects 3 columns; 2 are read"), "{message}");
    }
}
