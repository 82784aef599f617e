//! Byte-level helpers shared by the text readers (OBJ, ASCII PLY, ASCII STL).

/// Iterates the lines of a buffer as `(1-based line number, line without '\n' or '\r')`.
pub(crate) struct Lines<'a> {
    rest: &'a [u8],
    line: usize,
    done: bool,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(bytes: &'a [u8], first_line: usize) -> Self {
        Lines {
            rest: bytes,
            line: first_line.saturating_sub(1),
            done: false,
        }
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        self.line += 1;
        let (mut line, rest) = match self.rest.iter().position(|&b| b == b'\n') {
            Some(i) => (&self.rest[..i], &self.rest[i + 1..]),
            None => {
                self.done = true;
                if self.rest.is_empty() {
                    return None;
                }
                (self.rest, &[][..])
            }
        };
        self.rest = rest;
        if let [head @ .., b'\r'] = line {
            line = head;
        }
        Some((self.line, line))
    }
}

#[inline]
pub(crate) fn is_space(b: u8) -> bool {
    b == b' ' || b == b'\t' || b == b'\r' || b == 0x0c || b == 0x0b
}

/// Splits a line into whitespace-separated tokens.
#[inline]
pub(crate) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|&b| is_space(b)).filter(|t| !t.is_empty())
}

/// Parses a decimal floating-point token exactly (correctly rounded).
/// Returns `None` for anything that is not a number; NaN and infinity parse (callers
/// reject them with their own message).
#[inline]
pub(crate) fn parse_f64(tok: &[u8]) -> Option<f64> {
    std::str::from_utf8(tok).ok()?.parse::<f64>().ok()
}

/// Parses an optionally signed decimal integer; `None` on anything else or overflow.
#[inline]
pub(crate) fn parse_i64(tok: &[u8]) -> Option<i64> {
    let (neg, digits) = match tok {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, tok),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut v: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        v = v * 10 + i64::from(d - b'0');
    }
    Some(if neg { -v } else { v })
}

/// A token shortened for an error message (at most 40 characters, lossy UTF-8).
pub(crate) fn show(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(tok);
    if s.chars().count() > 40 {
        format!("{}…", s.chars().take(40).collect::<String>())
    } else {
        s.into_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_numbers_and_crlf() {
        let v: Vec<_> = Lines::new(b"a\r\nb\n\nc", 1).collect();
        assert_eq!(
            v,
            vec![
                (1, &b"a"[..]),
                (2, &b"b"[..]),
                (3, &b""[..]),
                (4, &b"c"[..])
            ]
        );
        assert_eq!(Lines::new(b"a\n", 1).count(), 1);
        assert_eq!(Lines::new(b"", 1).count(), 0);
    }

    #[test]
    fn ints() {
        assert_eq!(parse_i64(b"-12"), Some(-12));
        assert_eq!(parse_i64(b"+7"), Some(7));
        assert_eq!(parse_i64(b"7a"), None);
        assert_eq!(parse_i64(b"-"), None);
        assert_eq!(parse_i64(b"9999999999999999999999"), None);
    }

    #[test]
    fn floats_exact() {
        assert_eq!(parse_f64(b"0.1"), Some(0.1));
        assert_eq!(
            parse_f64(b"-0.0").map(f64::to_bits),
            Some((-0.0f64).to_bits())
        );
        assert_eq!(parse_f64(b"1e-300"), Some(1e-300));
        assert_eq!(parse_f64(b"x"), None);
    }
}
