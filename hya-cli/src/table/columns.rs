//! `--columns`: which columns of a log a row command reads, by header name or by position.
//!
//! A spec is a comma-separated list of items, each a column or a range of columns:
//!
//! - a position from 1 (`3`) or a range of positions (`2-7`);
//! - a name from the log's header line (`t`, `q1`, its unit left out), or a range of names:
//!   two names sharing a prefix and ending in numbers count (`q1-q6` is `q1, q2, …, q6`), any
//!   other two span the header from the first to the second (`q_SAA-q_WFE`). An item the header
//!   holds as a name is that name, hyphen or not (`joint-1`).
//!
//! The columns are read in the order listed; the command says what it expects in that order
//! (`hya estimate --timestamps`: `t`, then the joint angles, then the torques).

use super::{echo, Column, MAX_ROW_VALUES};
use crate::CliError;

/// One item of a spec before it meets the header.
#[derive(Debug, Clone, PartialEq)]
enum Item {
    /// 1-based position.
    Position(usize),
    /// A header name.
    Name(String),
    /// Every column of the header from the first name to the second, both included.
    Span(String, String),
    /// A name with a hyphen: a header name if the header has it, else a range of names.
    Dashed(String),
}

/// A parsed `--columns` spec: the columns to read, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnSpec {
    items: Vec<Item>,
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
        let mut items = Vec::new();
        for item in spec.split(',').map(str::trim) {
            if item.is_empty() {
                return Err(CliError::Input(format!("--columns {}: an empty item", echo(spec))));
            }
            match item.split_once('-') {
                None => items.push(match item.parse::<usize>() {
                    Ok(0) => return Err(bad_spec(item, "positions count from 1")),
                    Ok(position) => Item::Position(position),
                    Err(_) => Item::Name(item.to_string()),
                }),
                // Two positions, or two names of one prefix ending in numbers: a range whose
                // length is known before the header is read.
                Some((first, last)) if Self::counted(first.trim(), last.trim()) => {
                    Self::range(item, first.trim(), last.trim(), &mut items)?
                }
                Some(_) => items.push(Item::Dashed(item.to_string())),
            }
            if items.len() > MAX_ROW_VALUES {
                return Err(bad_spec(item, format_args!("more than {MAX_ROW_VALUES} columns, the most a row holds")));
            }
        }
        Ok(Self { items })
    }

    /// Whether `first-last` is a range of positions (`2-7`) or of numbered names (`q1-q6`).
    fn counted(first: &str, last: &str) -> bool {
        let positions = first.parse::<usize>().is_ok() && last.parse::<usize>().is_ok();
        let named =
            matches!((numbered(first), numbered(last)), (Some((p, _)), Some((q, _))) if p == q && !p.is_empty());
        positions || named
    }

    /// Appends the columns of the range `first-last`.
    fn range(item: &str, first: &str, last: &str, items: &mut Vec<Item>) -> Result<(), CliError> {
        if first.is_empty() || last.is_empty() {
            return Err(bad_spec(item, "a range needs a first and a last column (2-7, q1-q6)"));
        }
        let (from, to, prefix) = match (first.parse::<usize>(), last.parse::<usize>()) {
            (Ok(from), Ok(to)) => (from, to, None),
            (Ok(_), Err(_)) | (Err(_), Ok(_)) => {
                return Err(bad_spec(item, "a range is two positions (2-7) or two names (q1-q6, q_SAA-q_WFE)"))
            }
            _ => match (numbered(first), numbered(last)) {
                (Some((p, from)), Some((q, to))) if p == q && !p.is_empty() => (from, to, Some(p)),
                _ => {
                    items.push(Item::Span(first.to_string(), last.to_string()));
                    return Ok(());
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
        items.extend((from..=to).map(|k| match prefix {
            None => Item::Position(k),
            Some(p) => Item::Name(format!("{p}{k}")),
        }));
        Ok(())
    }

    /// How many columns the spec selects, if that is known before the header is read (a span's
    /// length is not).
    pub fn len(&self) -> Option<usize> {
        (!self.items.iter().any(|i| matches!(i, Item::Span(..) | Item::Dashed(..)))).then_some(self.items.len())
    }

    /// 0-based positions in the row for the spec's columns, names looked up in `header` (its
    /// line and columns). A name without a header, a name the header lacks, or a column selected
    /// twice is an error naming it.
    pub fn resolve(&self, header: Option<(usize, &[Column])>) -> Result<Vec<usize>, CliError> {
        let find = |name: &str| -> Result<usize, CliError> {
            match header {
                None => Err(CliError::Input(format!(
                    "--columns names column {} but the log has no header line naming its columns",
                    echo(name)
                ))),
                Some((line, columns)) => columns.iter().position(|c| c.name == name).ok_or_else(|| {
                    CliError::Input(format!("--columns: no column {} in the header on line {line}", echo(name)))
                }),
            }
        };
        let mut positions = Vec::with_capacity(self.items.len());
        let mut items = Vec::with_capacity(self.items.len());
        for item in &self.items {
            match item {
                Item::Dashed(raw) if header.is_some_and(|(_, columns)| columns.iter().any(|c| &c.name == raw)) => {
                    items.push(Item::Name(raw.clone()))
                }
                Item::Dashed(raw) => {
                    let (first, last) = raw.split_once('-').unwrap_or((raw, ""));
                    Self::range(raw, first.trim(), last.trim(), &mut items)?
                }
                other => items.push(other.clone()),
            }
        }
        for item in &items {
            match item {
                Item::Position(p) => positions.push(p - 1),
                Item::Name(name) => positions.push(find(name)?),
                Item::Span(first, last) => {
                    let (from, to) = (find(first)?, find(last)?);
                    if to < from {
                        return Err(CliError::Input(format!(
                            "--columns {}-{}: the header has {} after {}",
                            echo(first),
                            echo(last),
                            echo(first),
                            echo(last)
                        )));
                    }
                    positions.extend(from..=to);
                }
                Item::Dashed(_) => {}
            }
        }
        for (k, position) in positions.iter().enumerate() {
            if positions[..k].contains(position) {
                return Err(CliError::Input(format!("--columns selects column {} twice", position + 1)));
            }
        }
        Ok(positions)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(names: &str) -> Vec<Column> {
        names.split(',').map(Column::from_header).collect()
    }

    #[test]
    fn names_ranges_spans_and_positions_resolve_in_order() {
        let names = header("time [s],q1,q2,qd1,qd2,tau1 [N m],tau2");
        let spec = ColumnSpec::parse("time, q1-q2 ,tau1-tau2").unwrap();
        assert_eq!(spec.len(), Some(5));
        let selection = spec.resolve(Some((1, &names))).unwrap();
        assert_eq!(selection, [0, 1, 2, 5, 6]);
        assert_eq!(ColumnSpec::parse("1,2-3,6-7").unwrap().resolve(None).unwrap(), selection);
        assert_eq!(ColumnSpec::parse("7,1").unwrap().resolve(None).unwrap(), [6, 0]);
        let span = ColumnSpec::parse("qd1-tau1").unwrap();
        assert_eq!(span.len(), None);
        assert_eq!(span.resolve(Some((1, &names))).unwrap(), [3, 4, 5]);
        let names = header("t,q_SAA,q_SFE,q_HFE");
        assert_eq!(ColumnSpec::parse("q_SAA-q_HFE").unwrap().resolve(Some((1, &names))).unwrap(), [1, 2, 3]);
        let message = ColumnSpec::parse("q_HFE-q_SAA").unwrap().resolve(Some((1, &names))).unwrap_err().to_string();
        assert!(message.contains("after"), "{message}");
    }

    #[test]
    fn bad_specs_name_the_item() {
        let names = header("t,q1,q2");
        for (spec, expected) in [
            ("t,,q1", "empty item"),
            ("0,1", "count from 1"),
            ("0-3", "count from 1"),
            ("q6-q1", "ends before"),
            ("7-2", "ends before"),
            ("q1-3", "two positions"),
            ("-3", "a first and a last"),
            ("1-99999", "4096"),
        ] {
            // Names with a hyphen are told from ranges once the header is known.
            let message = match ColumnSpec::parse(spec) {
                Err(e) => e.to_string(),
                Ok(parsed) => parsed.resolve(Some((1, &names))).unwrap_err().to_string(),
            };
            assert!(message.contains(expected), "{spec}: {message}");
        }
    }

    #[test]
    fn a_header_name_with_a_hyphen_is_that_name() {
        let names = header("t,joint-1,joint-2,q1,q2");
        assert_eq!(ColumnSpec::parse("joint-2,t").unwrap().resolve(Some((1, &names))).unwrap(), [2, 0]);
        // Not in the header: a range, as before.
        assert_eq!(ColumnSpec::parse("q1-q2").unwrap().resolve(Some((1, &names))).unwrap(), [3, 4]);
    }

    #[test]
    fn unknown_names_and_repeats_are_named() {
        let names = header("t,q1,tau1");
        let message = ColumnSpec::parse("t,q1,tau2").unwrap().resolve(Some((3, &names))).unwrap_err().to_string();
        assert!(message.contains("\"tau2\"") && message.contains("line 3"), "{message}");
        let message = ColumnSpec::parse("t").unwrap().resolve(None).unwrap_err().to_string();
        assert!(message.contains("no header"), "{message}");
        let message = ColumnSpec::parse("1,2,1").unwrap().resolve(None).unwrap_err().to_string();
        assert!(message.contains("column 1 twice"), "{message}");
    }
}
