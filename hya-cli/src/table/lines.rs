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

/// `input`'s lines, prepared ([`Prepared::prepare`]), as bytes for [`csv::Reader`].
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

/// One line (`bytes`, line number `line`) as comma-separated cells: the comment cut off, blanks
/// around cells dropped, and, in a blank-separated file, each run of blanks between cells made
/// a comma. Quoted text is kept as it is; a quote left open at the end of the line is refused
/// (a record never spans lines, so every message names the right one). Returns the separator
/// this line decides, if it is the first that is not a comment and `known` is `None`.
fn prepare(bytes: &[u8], line: usize, known: Option<(Separator, usize)>) -> io::Result<(Vec<u8>, Option<Separator>)> {
    // The line without its comment: up to the first `#` outside quotes.
    let mut quoted = false;
    let mut end = bytes.len();
    for (k, &b) in bytes.iter().enumerate() {
        match b {
            b'"' => quoted = !quoted,
            b'#' if !quoted => {
                end = k;
                break;
            }
            _ => {}
        }
    }
    if quoted {
        return Err(refuse(format!("line {line}: a quote (\") is not closed on its line")));
    }
    let data = &bytes[..end];
    if data.iter().all(|&b| blank(b)) {
        return Ok((Vec::new(), None));
    }
    let has_comma = {
        let mut quoted = false;
        data.iter().any(|&b| {
            quoted ^= b == b'"';
            b == b',' && !quoted
        })
    };
    let (separator, decided) = match known {
        Some((separator, _)) => (separator, None),
        None => {
            let separator = if has_comma { Separator::Comma } else { Separator::Blanks };
            (separator, Some(separator))
        }
    };
    if let (Some((Separator::Blanks, first)), true) = (known, has_comma) {
        return Err(refuse(format!(
            "line {line}: a comma, but line {first} separates its cells by blanks: one separator per file"
        )));
    }
    let mut out = Vec::with_capacity(data.len());
    let mut quoted = false;
    // Blanks seen outside quotes and not yet written: written only if a cell goes on after them.
    let mut pending_blanks = 0;
    let mut cell_started = false;
    for &b in data {
        if quoted {
            quoted = b != b'"';
            out.push(b);
            continue;
        }
        match b {
            b',' => {
                pending_blanks = 0;
                out.push(b',');
                cell_started = false;
            }
            b if blank(b) => pending_blanks += 1,
            b => {
                if pending_blanks > 0 && cell_started && separator == Separator::Blanks {
                    out.push(b',');
                    pending_blanks = 0;
                    cell_started = false;
                }
                flush_blanks(&mut out, &mut pending_blanks, cell_started);
                out.push(b);
                cell_started = true;
                quoted = b == b'"';
            }
        }
    }
    Ok((out, decided))
}

/// Writes blanks held back inside a cell (`q 1` keeps its space); drops them before a cell.
fn flush_blanks(out: &mut Vec<u8>, pending: &mut usize, cell_started: bool) {
    if cell_started {
        out.extend(std::iter::repeat_n(b' ', *pending));
    }
    *pending = 0;
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
