//! Writing a table ([the format](super)): a header naming every column with its unit (unless
//! left out), then one comma-separated row of numbers per call, through the csv crate.

use std::fmt::Write as _;
use std::io::Write;

use hya_core::Short;

use super::Column;
use crate::CliError;

/// Rows of numbers under a header, written as a command produces them.
pub struct RowWriter<W: Write> {
    csv: csv::Writer<W>,
    /// The header, until it is written before the first row.
    header: Option<Vec<Column>>,
    width: usize,
    /// One number's text, reused.
    number: String,
}

impl<W: Write> RowWriter<W> {
    /// Rows of `columns` to `output`, under a header naming them if `header`.
    pub fn new(output: W, columns: Vec<Column>, header: bool) -> Self {
        let width = columns.len();
        Self {
            // A cell holding `#` is quoted, so that a reader of this format does not take it
            // for a comment.
            csv: csv::WriterBuilder::new().comment(Some(b'#')).from_writer(output),
            header: header.then_some(columns),
            width,
            number: String::new(),
        }
    }

    /// Rows to `output` whose columns are named later ([`name_columns`](Self::name_columns)),
    /// before the first row: `hya filter` learns its channels from the first row it reads.
    pub fn unnamed(output: W, header: bool) -> Self {
        Self::new(output, Vec::new(), header)
    }

    /// Names the columns, before the first row is written.
    pub fn name_columns(&mut self, columns: Vec<Column>) {
        self.width = columns.len();
        if let Some(header) = &mut self.header {
            *header = columns;
        }
    }

    /// Writes `values` as one row, each in the shortest text that reads back to the same `f64`
    /// (`{:?}`); the header goes first, before the first row.
    ///
    /// Refuses, before writing anything of the row, a row with a non-finite value: the error names
    /// the value and its place in the row ([`super::at`] adds the line or time).
    pub fn write<I>(&mut self, values: I) -> Result<(), CliError>
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
        if let Some(header) = self.header.take() {
            self.csv.write_record(header.iter().map(Column::to_string)).map_err(csv_error)?;
        }
        let mut count = 0;
        for v in values {
            self.number.clear();
            let _ = write!(self.number, "{v:?}");
            self.csv.write_field(&self.number).map_err(csv_error)?;
            count += 1;
        }
        debug_assert_eq!(count, self.width, "a row as wide as its header");
        self.csv.write_record(None::<&[u8]>).map_err(csv_error)
    }
}

/// A write error: the i/o error itself (a closed pipe ends the command quietly).
fn csv_error(error: csv::Error) -> CliError {
    let message = error.to_string();
    match error.into_kind() {
        csv::ErrorKind::Io(e) => CliError::Io(e),
        _ => CliError::Input(format!("writing a row: {message}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_comes_once_and_names_are_quoted_where_needed() {
        let mut out = Vec::new();
        let columns = vec![Column::new("t", "s"), Column::new("q_a,b", "rad"), Column::new("q#2", "rad")];
        let mut writer = RowWriter::new(&mut out, columns, true);
        writer.write([0.0, 1.5, 2.0]).unwrap();
        writer.write([0.1, -2e-300, 3.0]).unwrap();
        drop(writer);
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "t [s],\"q_a,b [rad]\",\"q#2 [rad]\"\n0.0,1.5,2.0\n0.1,-2e-300,3.0\n"
        );
        let mut raw = Vec::new();
        RowWriter::new(&mut raw, vec![Column::bare("x")], false).write([3.0]).unwrap();
        assert_eq!(raw, b"3.0\n");
    }

    #[test]
    fn non_finite_values_are_never_written() {
        let mut out = Vec::new();
        let mut writer = RowWriter::new(&mut out, vec![Column::bare("a"), Column::bare("b")], true);
        let message = writer.write([1.0, f64::INFINITY]).unwrap_err().to_string();
        drop(writer);
        assert!(message.contains("output value 2") && message.contains("inf"), "{message}");
        assert!(out.is_empty(), "nothing of the row, nor the header, is written");
    }

    #[test]
    fn written_values_round_trip() {
        let values = [0.1 + 0.2, 1e-300, -123456.789e10, 1.0 / 3.0];
        let mut out = Vec::new();
        RowWriter::new(&mut out, (0..4).map(|k| Column::bare(format!("c{k}"))).collect(), false).write(values).unwrap();
        let text = String::from_utf8(out).unwrap();
        let back: Vec<f64> = text.trim().split(',').map(|s| s.parse().unwrap()).collect();
        assert_eq!(back, values);
    }
}
