//! The lines of an input made ready for the CSV reader: bounded in length, comments and blank
//! lines removed, cells separated by single commas whatever the file separates them by. Each
//! line handed on is one record; the file's line number of each is kept until the reader takes
//! it ([`Prepared::take_line`]), so that messages name the file's lines.

use std::io::{self, BufRead, Read};

use super::MAX_LINE_BYTES;

/// How the file separates its cells, decided on its first line that is not a comment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Separator {
    /// Commas (blanks around a cell are not part of it).
    Comma,
    /// Runs of spaces and tabs.
    Blanks,
}

/// An input error found while preparing a line; carried through the CSV reader inside an
/// [`io::Error`] and turned back into the message ([`LineError::message`]).
#[derive(Debug)]
pub struct LineError(pub String);

impl std::fmt::Display for LineError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for LineError {}

impl LineError {
    /// The message of a [`LineError`] inside `error`, if it holds one.
    pub fn message(error: &io::Error) -> Option<&str> {
        error.get_ref().and_then(|e| e.downcast_ref::<LineError>()).map(|e| e.0.as_str())
    }
}

fn refuse(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, LineError(message))
}

/// `input`'s lines, prepared ([`prepare`]), as bytes for [`csv::Reader`].
pub struct Prepared<R> {
    input: R,
    raw: Vec<u8>,
    ready: Vec<u8>,
    served: usize,
    line: usize,
    separator: Option<(Separator, usize)>,
    /// The file's line numbers of the lines handed on whose records are not yet taken.
    lines: std::collections::VecDeque<usize>,
}

impl<R: BufRead> Prepared<R> {
    pub fn new(input: R) -> Self {
        Self {
            input,
            raw: Vec::new(),
            ready: Vec::new(),
            served: 0,
            line: 0,
            separator: None,
            lines: Default::default(),
        }
    }

    /// The file's line number of the next record (records are taken in order, one per line).
    pub fn take_line(&mut self) -> usize {
        self.lines.pop_front().unwrap_or(self.line)
    }

    /// Reads the next line that holds a record into `ready`; `false` at the end of the input.
    fn next_line(&mut self) -> io::Result<bool> {
        while self.read_line()? {
            if !self.ready.is_empty() {
                self.ready.push(b'\n');
                self.lines.push_back(self.line);
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Reads and prepares the next line into `ready` (empty for a comment or blank line);
    /// `false` at the end of the input.
    fn read_line(&mut self) -> io::Result<bool> {
        self.raw.clear();
        self.ready.clear();
        self.served = 0;
        // At most one byte past the limit: enough to tell a line that is too long.
        let limit = MAX_LINE_BYTES as u64 + 1;
        if (&mut self.input).take(limit).read_until(b'\n', &mut self.raw)? == 0 {
            return Ok(false);
        }
        self.line += 1;
        let bytes = match self.raw.strip_suffix(b"\n") {
            Some(bytes) => bytes,
            None if self.raw.len() > MAX_LINE_BYTES => {
                return Err(refuse(format!(
                    "line {}: longer than {MAX_LINE_BYTES} bytes, the longest line a row may take",
                    self.line
                )))
            }
            None => &self.raw,
        };
        let bytes = bytes.strip_suffix(b"\r").unwrap_or(bytes);
        let (ready, separator) = prepare(bytes, self.line, self.separator)?;
        self.separator = self.separator.or(separator.map(|s| (s, self.line)));
        self.ready = ready;
        Ok(true)
    }
}

impl<R: BufRead> Read for Prepared<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.served == self.ready.len() && !self.next_line()? {
            return Ok(0);
        }
        let n = buf.len().min(self.ready.len() - self.served);
        buf[..n].copy_from_slice(&self.ready[self.served..self.served + n]);
        self.served += n;
        Ok(n)
    }
}

fn blank(byte: u8) -> bool {
    byte == b' ' || byte == b'\t'
}

/// The UTF-8 byte-order mark some editors put before a file's first line.
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Whether `line` has a comma outside quotes (a quote opens a cell at the line's start or after
/// a comma or a blank, whichever separator the file turns out to use): what decides a file's
/// separator on its first line that is not a comment.
fn has_comma(bytes: &[u8]) -> bool {
    let (mut quoted, mut at_start) = (false, true);
    let mut k = 0;
    while k < bytes.len() {
        let b = bytes[k];
        if quoted {
            if b == b'"' {
                if bytes.get(k + 1) == Some(&b'"') {
                    k += 1;
                } else {
                    quoted = false;
                }
            }
        } else {
            match b {
                b'#' => return false,
                b',' => return true,
                b'"' if at_start => quoted = true,
                _ => {}
            }
            at_start = b == b',' || blank(b);
        }
        k += 1;
    }
    false
}

/// Where a cell's reading stands.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Cell {
    /// Before the cell's first byte (blanks skipped).
    Start,
    /// In an unquoted cell (or after a quoted part: what follows is kept as it is, as the csv
    /// crate keeps it).
    Plain,
    /// Inside quotes.
    Quoted,
}

/// One line (`bytes`, line number `line`) as comma-separated cells: the comment cut off, blanks
/// around cells dropped, and, in a blank-separated file, each run of blanks between cells made
/// a comma. As in CSV, a quote opens quoted text only at a cell's start (`""` inside is a quote);
/// elsewhere it is a character. A quote left open at the end of the line, or a carriage return
/// outside quotes before it, is refused: a record never spans lines, so every line handed on
/// holds one record and every message names the right line. Returns the separator this line
/// decides, if it is the first that is not a comment and `known` is `None`.
fn prepare(bytes: &[u8], line: usize, known: Option<(Separator, usize)>) -> io::Result<(Vec<u8>, Option<Separator>)> {
    let bytes = if line == 1 { bytes.strip_prefix(BOM).unwrap_or(bytes) } else { bytes };
    let has_comma = has_comma(bytes);
    let (separator, decided) = match known {
        Some((Separator::Blanks, first)) if has_comma => {
            return Err(refuse(format!(
                "line {line}: a comma, but line {first} separates its cells by blanks: one separator per file"
            )))
        }
        Some((separator, _)) => (separator, None),
        None if has_comma => (Separator::Comma, Some(Separator::Comma)),
        None => (Separator::Blanks, Some(Separator::Blanks)),
    };
    let mut out = Vec::with_capacity(bytes.len());
    let mut state = Cell::Start;
    // The length of `out` before the blanks that trail the cell so far (outside quotes).
    let mut kept = 0;
    let mut k = 0;
    while k < bytes.len() {
        let b = bytes[k];
        k += 1;
        if state == Cell::Quoted {
            out.push(b);
            if b == b'"' {
                if bytes.get(k) == Some(&b'"') {
                    out.push(b'"');
                    k += 1;
                } else {
                    state = Cell::Plain;
                }
            }
            kept = out.len();
            continue;
        }
        match b {
            b'#' => break,
            b'\r' => {
                return Err(refuse(format!(
                    "line {line}: a carriage return (\\r) inside the line: one row per line, ended by \\n or \\r\\n"
                )))
            }
            b',' => {
                out.truncate(kept);
                out.push(b',');
                kept = out.len();
                state = Cell::Start;
            }
            b if blank(b) => match (state, separator) {
                (Cell::Plain, Separator::Blanks) => state = Cell::Start,
                (Cell::Plain, Separator::Comma) => out.push(b),
                _ => {}
            },
            b => {
                if state == Cell::Start {
                    // A new cell: in a blank-separated file, after the previous one.
                    if separator == Separator::Blanks && !out.is_empty() {
                        out.push(b',');
                    }
                    state = if b == b'"' { Cell::Quoted } else { Cell::Plain };
                }
                out.push(b);
                kept = out.len();
            }
        }
    }
    if state == Cell::Quoted {
        return Err(refuse(format!("line {line}: a quote (\") is not closed on its line")));
    }
    out.truncate(kept);
    // A comment or blank line decides nothing.
    let decided = decided.filter(|_| !out.is_empty());
    Ok((out, decided))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prepared(text: &str) -> Result<String, String> {
        let mut out = String::new();
        match Prepared::new(text.as_bytes()).read_to_string(&mut out) {
            Ok(_) => Ok(out),
            Err(e) => Err(LineError::message(&e).unwrap_or("not a line error").to_string()),
        }
    }

    #[test]
    fn blanks_and_commas_become_one_comma_per_cell_boundary() {
        assert_eq!(prepared(" 1.5 \t -2e-3  4 # note\n").unwrap(), "1.5,-2e-3,4\n");
        assert_eq!(prepared("t [s] , q 1 ,\"a, b\"\n1,2,3\n").unwrap(), "t [s],q 1,\"a, b\"\n1,2,3\n");
        assert_eq!(prepared("\"q 1\" \"q 2\"\n").unwrap(), "\"q 1\",\"q 2\"\n");
        assert_eq!(prepared("1,,3\n").unwrap(), "1,,3\n", "an empty cell stays empty, for the reader to name");
    }

    #[test]
    fn comments_and_blank_lines_go_and_lines_keep_their_number() {
        let mut lines = Prepared::new("# a log\n\n1 2\r\n\"#\" 3\n".as_bytes());
        let mut out = String::new();
        lines.read_to_string(&mut out).unwrap();
        assert_eq!(out, "1,2\n\"#\",3\n");
        assert_eq!((lines.take_line(), lines.take_line()), (3, 4));
    }

    #[test]
    fn quotes_open_only_at_a_cell_start_as_in_csv() {
        // A quote inside a cell is a character: the next lines are not swallowed.
        assert_eq!(prepared("0,a\"b,\"c\"\"d\"\n1,2,3\n").unwrap(), "0,a\"b,\"c\"\"d\"\n1,2,3\n");
        assert_eq!(prepared("0 a\"b \"c d\"\n").unwrap(), "0,a\"b,\"c d\"\n");
        let message = prepared("0,\"open\n1,2\n").unwrap_err();
        assert!(message.contains("line 1: a quote"), "{message}");
    }

    #[test]
    fn carriage_returns_inside_a_line_and_a_byte_order_mark() {
        let message = prepared("0 1\r2 3\n").unwrap_err();
        assert!(message.contains("line 1: a carriage return"), "{message}");
        let message = prepared("0,1\n\r\r\n").unwrap_err();
        assert!(message.contains("line 2: a carriage return"), "{message}");
        // A byte-order mark before a first line that is a comment does not make it a line of cells.
        assert_eq!(prepared("\u{feff}# log\nt,q\n0,1\n").unwrap(), "t,q\n0,1\n");
    }

    #[test]
    fn one_separator_per_file_and_closed_quotes() {
        let message = prepared("# c\n1 2\n3,4\n").unwrap_err();
        assert!(message.contains("line 3: a comma, but line 2 separates its cells by blanks"), "{message}");
        let message = prepared("1,\"2\n").unwrap_err();
        assert!(message.contains("line 1: a quote"), "{message}");
    }

    #[test]
    fn long_lines_are_refused_as_soon_as_read() {
        let message = prepared(&format!("1\n{}\n", "7".repeat(MAX_LINE_BYTES + 1))).unwrap_err();
        assert!(message.contains("line 2") && message.contains("1048576"), "{message}");
        let exact = format!("{}1", " ".repeat(MAX_LINE_BYTES - 1));
        assert_eq!(prepared(&exact).unwrap(), "1\n");
    }
}
