//! Rows of numbers on stdin: whitespace- or comma-separated, `#` comments and blank lines skipped.

use crate::CliError;

/// One data row with the (1-based) line it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Line number in the input, from 1.
    pub line: usize,
    /// The values, all finite.
    pub values: Vec<f64>,
}

/// Parses line `line` of the input; `None` for a blank or comment line.
pub fn parse(text: &str, line: usize) -> Result<Option<Row>, CliError> {
    let data = text.split('#').next().unwrap_or_default().trim();
    if data.is_empty() {
        return Ok(None);
    }
    let values = data
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|field| !field.is_empty())
        .enumerate()
        .map(|(column, field)| match field.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(v) => Err(CliError::Input(format!("line {line}, column {}: non-finite value {v}", column + 1))),
            Err(_) => Err(CliError::Input(format!("line {line}, column {}: not a number: {field:?}", column + 1))),
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Some(Row { line, values }))
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
pub fn write(out: &mut impl std::io::Write, values: impl IntoIterator<Item = f64>) -> Result<(), CliError> {
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
    fn bad_fields_name_line_and_column() {
        let message = parse("1 x 3", 12).unwrap_err().to_string();
        assert!(message.contains("line 12") && message.contains("column 2"), "{message}");
        let message = parse("1 NaN", 3).unwrap_err().to_string();
        assert!(message.contains("line 3") && message.contains("non-finite"), "{message}");
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
