//! Numbers and user text as messages show them: short, whatever was typed.
//!
//! A message that echoes `1e-300` as Rust's `{}` prints it (301 characters), or a 10 MB name
//! whole, is no message. [`Short`] prints at most four significant digits, in exponent form
//! outside `[1e-3, 1e6)`; [`Clipped`] prints at most a given number of characters of a text,
//! with an ellipsis where it cut. Both write without allocating, for `no_std` errors too.

use core::fmt::{self, Display, Write};

/// `x` in at most four significant digits: `0.05`, `123.5`, `1e-300`, `-2.5e8`, `NaN`, `inf`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Short(pub f64);

/// A fixed buffer that [`Short`] formats into before trimming trailing zeros.
struct Buffer {
    bytes: [u8; 40],
    len: usize,
}

impl Write for Buffer {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        self.bytes.get_mut(self.len..end).ok_or(fmt::Error)?.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

impl Display for Short {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        let magnitude = x.abs();
        let mut buffer = Buffer { bytes: [0; 40], len: 0 };
        if !x.is_finite() || x == 0.0 {
            return write!(f, "{x}");
        }
        if (1e-3..1e6).contains(&magnitude) {
            // Decimals for four significant digits: 3 − floor(log10 |x|).
            let exponent = libm::floor(libm::log10(magnitude)) as i32;
            let decimals = (3 - exponent).clamp(0, 6) as usize;
            write!(buffer, "{x:.decimals$}")?;
        } else {
            write!(buffer, "{x:.3e}")?;
        }
        let text = core::str::from_utf8(&buffer.bytes[..buffer.len]).map_err(|_| fmt::Error)?;
        let (mantissa, exponent) = text.split_once('e').map_or((text, None), |(m, e)| (m, Some(e)));
        let mantissa =
            if mantissa.contains('.') { mantissa.trim_end_matches('0').trim_end_matches('.') } else { mantissa };
        match exponent {
            Some(e) => write!(f, "{mantissa}e{e}"),
            None => f.write_str(mantissa),
        }
    }
}

/// At most `.1` characters of the text `.0`, control characters escaped, `…` where it was cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Clipped<'a>(pub &'a str, pub usize);

impl Display for Clipped<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Clipped(text, limit) = *self;
        for (shown, c) in text.chars().enumerate() {
            if shown == limit {
                return f.write_char('…');
            }
            if c.is_control() {
                write!(f, "{}", c.escape_default())?;
            } else {
                f.write_char(c)?;
            }
        }
        Ok(())
    }
}

/// The candidate nearest to `text` by edit distance (insertions, deletions, substitutions of
/// characters), if it is close enough to be a slip: at most 2 edits, or a third of its length for
/// longer names. For "did you mean" in messages (`pnada` → `panda`); texts beyond 63
/// characters are never matched (the distance runs in a fixed buffer, without allocating).
pub fn closest<'a>(text: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    const LONGEST: usize = 63;
    let distance = |a: &str, b: &str| -> Option<usize> {
        let (a_len, b_len) = (a.chars().count(), b.chars().count());
        if a_len > LONGEST || b_len > LONGEST {
            return None;
        }
        let mut row = [0usize; LONGEST + 1];
        for (j, slot) in row.iter_mut().enumerate().take(b_len + 1) {
            *slot = j;
        }
        for (i, ca) in a.chars().enumerate() {
            let mut diagonal = row[0];
            row[0] = i + 1;
            for (j, cb) in b.chars().enumerate() {
                let above = row[j + 1];
                row[j + 1] = (above + 1).min(row[j] + 1).min(diagonal + usize::from(ca != cb));
                diagonal = above;
            }
        }
        Some(row[b_len])
    };
    let allowed = (text.chars().count() / 3).max(2);
    candidates
        .into_iter()
        .filter_map(|c| distance(text, c).map(|d| (d, c)))
        .filter(|(d, _)| *d <= allowed)
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::format;

    #[test]
    fn numbers_are_short_whatever_their_size() {
        let cases = [
            (1e-300, "1e-300"),
            (4.9e-324, "4.941e-324"),
            (1e308, "1e308"),
            (0.05, "0.05"),
            (123.456, "123.5"),
            (-2.5e8, "-2.5e8"),
            (1.0, "1"),
            (0.001, "0.001"),
            (999_999.0, "999999"),
            (0.0, "0"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (x, shown) in cases {
            assert_eq!(format!("{}", Short(x)), shown, "{x:e}");
        }
    }

    #[test]
    fn slips_find_their_name_and_strangers_none() {
        let arms = ["hya", "ur5", "panda", "iiwa14", "planar2"];
        assert_eq!(closest("pnada", arms), Some("panda"));
        assert_eq!(closest("iiwa", arms), Some("iiwa14"));
        assert_eq!(closest("panda_gotoo", ["panda_goto", "ur5_goto"]), Some("panda_goto"));
        assert_eq!(closest("kuka", arms), None);
        assert_eq!(closest(&"x".repeat(100), arms), None);
    }

    #[test]
    fn text_is_clipped_and_control_characters_escaped() {
        assert_eq!(format!("{}", Clipped("goto_internal", 40)), "goto_internal");
        assert_eq!(format!("{}", Clipped("abcdef", 3)), "abc…");
        assert_eq!(format!("{}", Clipped("a\nb", 10)), "a\\nb");
    }
}
