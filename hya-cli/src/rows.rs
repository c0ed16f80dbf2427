//! Rows of numbers on stdin: whitespace- or comma-separated, `#` comments and blank lines skipped.
//!
//! Input is hostile until parsed: lines are read through a bounded buffer
//! ([`MAX_LINE_BYTES`]), rows hold at most [`MAX_ROW_VALUES`] values, and every value read or
//! written is finite. Messages show numbers in short form ([`Short`]) and echo at most
//! [`ECHO_CHARS`] characters of what the user wrote ([`echo`]).

use std::io::{BufRead, Read, Write};

use hya_core::{Clipped, Short};

use crate::CliError;

/// The longest line a row command reads, in bytes (1 MiB), newline excluded. A real row (a few
/// dozen numbers) is a few hundred bytes; a longer line is refused, naming it, as soon as its
/// first `MAX_LINE_BYTES + 1` bytes have been read, so memory stays bounded whatever the input
/// (`/dev/zero` included).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The most values one row may hold (4096): the widest real row is `hya id`'s `3n` for an arm of
/// `n` joints, and `hya filter` keeps a filter per value of its first row, so this also caps
/// its channels (and the memory of their states).
pub const MAX_ROW_VALUES: usize = 4096;

/// The shortest sample or output interval `--dt` a row command accepts, s (1 µs).
pub const MIN_DT_S: f64 = 1e-6;

/// The longest sample or output interval `--dt` a row command accepts, s.
pub const MAX_DT_S: f64 = 1.0;

/// How many characters of a field that is not a number an error message echoes.
pub const ECHO_CHARS: usize = 40;

/// One data row with the (1-based) line it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Line number in the input, from 1.
    pub line: usize,
    /// The values, all finite, at most [`MAX_ROW_VALUES`].
    pub values: Vec<f64>,
}

/// User text for a message: quoted, control characters escaped, cut after [`ECHO_CHARS`]
/// characters with an ellipsis.
pub fn echo(text: &str) -> String {
    format!("\"{}\"", Clipped(text, ECHO_CHARS))
}

/// Checks an interval option (`--dt`): finite and within [`MIN_DT_S`] to [`MAX_DT_S`].
pub fn check_dt(option: &str, dt: f64) -> Result<f64, CliError> {
    if dt.is_finite() && (MIN_DT_S..=MAX_DT_S).contains(&dt) {
        Ok(dt)
    } else {
        Err(CliError::Input(format!(
            "{option} {}: must be between {} and {} s",
            Short(dt),
            Short(MIN_DT_S),
            Short(MAX_DT_S)
        )))
    }
}

/// The fields of a line: separated by commas, tabs or spaces (runs of spaces and tabs count
/// once). A comma always ends a cell: an empty cell between two commas, before the first or after
/// the last (`1,,3`, `,2`, `1,2,`) is a missing value, and an error naming its line and column,
/// never skipped (a skipped cell would move every later value one column to the left).
fn fields(data: &str, line: usize) -> Result<Vec<&str>, CliError> {
    let mut fields = Vec::new();
    for cell in data.split(',') {
        let before = fields.len();
        fields.extend(cell.split_whitespace());
        if fields.len() == before && data.contains(',') {
            return Err(CliError::Input(format!(
                "line {line}, column {}: an empty cell (a missing value); fill it or remove the row",
                before + 1
            )));
        }
        if fields.len() > MAX_ROW_VALUES {
            return Err(CliError::Input(format!(
                "line {line}: more than {MAX_ROW_VALUES} values, the most a row may hold"
            )));
        }
    }
    Ok(fields)
}

/// Parses line `line` of the input; `None` for a blank or comment line.
pub fn parse(text: &str, line: usize) -> Result<Option<Row>, CliError> {
    let data = text.split('#').next().unwrap_or_default().trim();
    if data.is_empty() {
        return Ok(None);
    }
    let mut values = Vec::new();
    for (column, field) in fields(data, line)?.into_iter().enumerate() {
        let column = column + 1;
        match field.parse::<f64>() {
            Ok(v) if v.is_finite() => values.push(v),
            Ok(v) => {
                return Err(CliError::Input(format!("line {line}, column {column}: non-finite value {}", Short(v))))
            }
            Err(_) => {
                return Err(CliError::Input(format!("line {line}, column {column}: not a number: {}", echo(field))))
            }
        }
    }
    Ok(Some(Row { line, values }))
}

/// The data rows of an input, read one line at a time through a buffer of at most
/// [`MAX_LINE_BYTES`] + 1 bytes; see [`parse`]. Iteration ends after the first error.
pub struct Reader<R> {
    input: R,
    buffer: Vec<u8>,
    line: usize,
    done: bool,
    header: Header,
}

/// Whether a [`Reader`] takes a header line, and the one it read.
enum Header {
    /// Every line is data.
    Refused,
    /// The first line whose first field is not a number is a header, if it comes first.
    Allowed,
    /// The header read, with its line.
    Read(usize, Vec<String>),
}

impl<R: BufRead> Reader<R> {
    /// Reads the rows of `input`.
    pub fn new(input: R) -> Self {
        Self { input, buffer: Vec::new(), line: 0, done: false, header: Header::Refused }
    }

    /// Reads the rows of `input`, the first of which may be a header: a line whose first field
    /// is not a number, before any data row, is taken as column names (separated as values
    /// are, at most [`MAX_ROW_VALUES`]) instead of data; see [`header`](Self::header).
    pub fn with_header(input: R) -> Self {
        Self { header: Header::Allowed, ..Self::new(input) }
    }

    /// The header line's number and column names, once read (after the first row).
    pub fn header(&self) -> Option<(usize, &[String])> {
        match &self.header {
            Header::Read(line, names) => Some((*line, names)),
            _ => None,
        }
    }

    /// The next row, blank and comment lines skipped; `Ok(None)` at the end of the input.
    fn next_row(&mut self) -> Result<Option<Row>, CliError> {
        loop {
            self.buffer.clear();
            // At most one byte past the limit: enough to tell a line that is too long.
            let limit = MAX_LINE_BYTES as u64 + 1;
            if (&mut self.input).take(limit).read_until(b'\n', &mut self.buffer)? == 0 {
                return Ok(None);
            }
            self.line += 1;
            let bytes = match self.buffer.strip_suffix(b"\n") {
                Some(bytes) => bytes,
                None if self.buffer.len() > MAX_LINE_BYTES => {
                    return Err(CliError::Input(format!(
                        "line {}: longer than {MAX_LINE_BYTES} bytes, the longest line a row may take",
                        self.line
                    )))
                }
                None => &self.buffer,
            };
            let bytes = bytes.strip_suffix(b"\r").unwrap_or(bytes);
            let text = std::str::from_utf8(bytes)
                .map_err(|_| CliError::Input(format!("line {}: not valid UTF-8 text", self.line)))?;
            if take_header(&mut self.header, self.line, text)? {
                continue;
            }
            if let Some(row) = parse(text, self.line)? {
                return Ok(Some(row));
            }
        }
    }
}

impl<R: BufRead> Iterator for Reader<R> {
    type Item = Result<Row, CliError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let next = self.next_row().transpose();
        self.done = !matches!(next, Some(Ok(_)));
        next
    }
}

/// Takes `text` as the header if one is allowed here and its first field is not a number.
fn take_header(header: &mut Header, line: usize, text: &str) -> Result<bool, CliError> {
    if !matches!(header, Header::Allowed) {
        return Ok(false);
    }
    let data = text.split('#').next().unwrap_or_default();
    let first = data.split(|c: char| c == ',' || c.is_whitespace()).find(|field| !field.is_empty());
    match first {
        None => Ok(false),
        Some(first) if first.parse::<f64>().is_ok() => {
            *header = Header::Refused;
            Ok(false)
        }
        Some(_) => {
            let names = fields(data, line)?;
            *header = Header::Read(line, names.iter().map(|n| n.to_string()).collect());
            Ok(true)
        }
    }
}

/// Checks that `row` has `expected` values.
pub fn expect_width(row: &Row, expected: usize, what: &str) -> Result<(), CliError> {
    if row.values.len() == expected {
        Ok(())
    } else {
        Err(CliError::Input(format!(
            "line {}: expected {expected} values ({what}), found {}",
            row.line,
            row.values.len()
        )))
    }
}

/// Writes `values` as one row; `{:?}` prints the shortest text that parses back to the same `f64`.
///
/// Refuses, before writing anything of the row, a row with a non-finite value: the error names
/// the value and its place in the row ([`at`] adds the line or time).
pub fn write<I>(out: &mut impl Write, values: I) -> Result<(), CliError>
where
    I: IntoIterator<Item = f64>,
    I::IntoIter: Clone,
{
    let values = values.into_iter();
    if let Some((j, v)) = values.clone().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(CliError::Input(format!(
            "output value {} would be {}: the result overflows, and a non-finite number is never written",
            j + 1,
            Short(v)
        )));
    }
    let mut first = true;
    for v in values {
        if !first {
            out.write_all(b" ")?;
        }
        write!(out, "{v:?}")?;
        first = false;
    }
    out.write_all(b"\n")?;
    Ok(())
}

/// `error` prefixed with `place` (`line 3`, `t = 0.5 s`) if it is an input error.
pub fn at(place: impl std::fmt::Display, error: CliError) -> CliError {
    match error {
        CliError::Input(message) => CliError::Input(format!("{place}: {message}")),
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commas_spaces_and_comments_are_accepted() {
        let row = parse(" 1.5, -2e-3\t4 # note", 7).unwrap().unwrap();
        assert_eq!(row, Row { line: 7, values: vec![1.5, -2e-3, 4.0] });
        assert!(parse("   # only a comment", 1).unwrap().is_none());
    }

    #[test]
    fn empty_cells_are_refused_with_their_column() {
        for (text, column) in [("0.001,0.1,,1", 3), (",2,3", 1), ("1,2,", 3), ("1, ,3", 2), ("1 2,,3", 3)] {
            let message = parse(text, 4).unwrap_err().to_string();
            assert!(message.contains(&format!("line 4, column {column}: an empty cell")), "{text}: {message}");
        }
        // Spaces alone never make an empty cell: runs of them separate once.
        assert_eq!(parse("1   2\t\t3", 1).unwrap().unwrap().values, [1.0, 2.0, 3.0]);
        let mut reader = Reader::with_header("t,,q2\n0,1,2\n".as_bytes());
        let message = reader.next().unwrap().unwrap_err().to_string();
        assert!(message.contains("line 1, column 2: an empty cell"), "{message}");
    }

    #[test]
    fn bad_fields_name_line_and_column() {
        let message = parse("1 x 3", 12).unwrap_err().to_string();
        assert!(message.contains("line 12") && message.contains("column 2"), "{message}");
        let message = parse("1 NaN", 3).unwrap_err().to_string();
        assert!(message.contains("line 3") && message.contains("non-finite"), "{message}");
    }

    #[test]
    fn long_fields_are_echoed_cut() {
        let field = "y".repeat(10_000);
        let message = parse(&format!("1 {field}"), 2).unwrap_err().to_string();
        assert!(message.len() < 120 && message.contains("column 2") && message.contains("yyy…"), "{message}");
    }

    #[test]
    fn rows_are_capped_in_values() {
        let wide = "1 ".repeat(MAX_ROW_VALUES);
        assert_eq!(parse(&wide, 1).unwrap().unwrap().values.len(), MAX_ROW_VALUES);
        let message = parse(&format!("{wide} 1"), 5).unwrap_err().to_string();
        assert!(message.contains("line 5") && message.contains("4096"), "{message}");
    }

    #[test]
    fn the_reader_stops_at_a_long_line_and_counts_lines() {
        let input = format!("1 2\n\n# c\r\n3 4\r\n{}\n5 6\n", "7".repeat(MAX_LINE_BYTES + 1));
        let rows: Vec<_> = Reader::new(input.as_bytes()).collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[1].as_ref().unwrap(), &Row { line: 4, values: vec![3.0, 4.0] });
        let message = rows[2].as_ref().unwrap_err().to_string();
        assert!(message.contains("line 5") && message.contains("1048576"), "{message}");
        // A line of exactly the limit is read, with or without its newline.
        let exact = format!("{}1", " ".repeat(MAX_LINE_BYTES - 1));
        for input in [format!("{exact}\n"), exact.clone()] {
            let rows: Vec<_> = Reader::new(input.as_bytes()).collect();
            assert_eq!(rows.len(), 1);
            assert_eq!(rows[0].as_ref().unwrap().values, vec![1.0]);
        }
    }

    #[test]
    fn a_header_is_read_only_where_allowed_and_only_first() {
        let input = "# a log\ntime,q1\tq2 tau\n0, 1, 2, 3\nt q\n";
        let mut reader = Reader::with_header(input.as_bytes());
        assert_eq!(reader.next().unwrap().unwrap(), Row { line: 3, values: vec![0.0, 1.0, 2.0, 3.0] });
        let (line, names) = reader.header().unwrap();
        assert_eq!((line, names), (2, &["time".to_string(), "q1".into(), "q2".into(), "tau".into()][..]));
        let message = reader.next().unwrap().unwrap_err().to_string();
        assert!(message.contains("line 4, column 1"), "a second header is data: {message}");
        let message = Reader::new(input.as_bytes()).next().unwrap().unwrap_err().to_string();
        assert!(message.contains("line 2, column 1"), "{message}");
        let mut numbers_first = Reader::with_header("1 2\nt q\n".as_bytes());
        assert!(numbers_first.next().unwrap().is_ok() && numbers_first.header().is_none());
        assert!(numbers_first.next().unwrap().is_err());
    }

    #[test]
    fn non_finite_values_are_never_written() {
        let mut out = Vec::new();
        let message = write(&mut out, [1.0, f64::INFINITY]).unwrap_err().to_string();
        assert!(message.contains("output value 2") && message.contains("inf"), "{message}");
        assert!(out.is_empty(), "nothing of the row is written");
    }

    #[test]
    fn written_values_round_trip() {
        let values = [0.1 + 0.2, 1e-300, -123456.789e10, 1.0 / 3.0];
        let mut out = Vec::new();
        write(&mut out, values).unwrap();
        let text = String::from_utf8(out).unwrap();
        let back: Vec<f64> = text.split_whitespace().map(|s| s.parse().unwrap()).collect();
        assert_eq!(back, values);
    }
}
