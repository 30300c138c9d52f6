//! Values of literal tokens: numbers, durations, dates, times of day and strings.
//!
//! The lexer finds where a literal ends; these functions turn its text into a value
//! or say in words what is wrong with it. They work on exact integers throughout so
//! that `T#1.1s` is 1,100,000,000 ns and not a float rounding of it.

/// Nanoseconds in a day.
const NS_PER_DAY: i128 = 86_400_000_000_000;

/// Parses digits (with `_` separators) in `base` into an i128.
///
/// `Err(None)` means a digit that is not valid in the base (or no digit at all);
/// `Err(Some(()))` means the value does not fit.
pub fn parse_digits(digits: &[u8], base: u32) -> Result<i128, DigitError> {
    let mut value: i128 = 0;
    let mut any = false;
    for &b in digits {
        if b == b'_' {
            continue;
        }
        let d = match (b as char).to_digit(16) {
            Some(d) if d < base => d,
            _ => return Err(DigitError::BadDigit(b)),
        };
        any = true;
        value = value
            .checked_mul(base as i128)
            .and_then(|v| v.checked_add(d as i128))
            .ok_or(DigitError::TooLarge)?;
    }
    if any {
        Ok(value)
    } else {
        Err(DigitError::NoDigits)
    }
}

/// Why a digit string has no value.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum DigitError {
    /// A character that is not a digit of the base.
    BadDigit(u8),
    /// Only separators, or nothing.
    NoDigits,
    /// More than an i128 holds.
    TooLarge,
}

/// The value of a duration written after `T#` (sign included), in nanoseconds.
///
/// Components are `<number>[.<fraction>]<unit>` with units d, h, m, s, ms, us, ns in
/// decreasing order, optionally separated by `_`. Fractions finer than 1 ns are
/// dropped (truncated towards zero).
pub fn duration(text: &str) -> Result<i128, String> {
    let b = text.as_bytes();
    let (neg, mut i) = match b.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    if i >= b.len() {
        return Err("expected a duration such as `T#1h2m3s` after `#`".into());
    }
    let mut total: i128 = 0;
    let mut last_rank = usize::MAX;
    let mut first = true;
    while i < b.len() {
        if !first && b[i] == b'_' {
            i += 1;
        }
        first = false;
        let int_start = i;
        while i < b.len() && (b[i].is_ascii_digit() || (b[i] == b'_' && i > int_start)) {
            i += 1;
        }
        let int_digits = &b[int_start..i];
        if int_digits.is_empty() {
            return Err(match b.get(i) {
                Some(&c) => format!("expected a number in the duration, found `{}`", c as char),
                None => "expected a number after `_` in the duration".into(),
            });
        }
        let mut frac: &[u8] = &[];
        if i < b.len() && b[i] == b'.' {
            i += 1;
            let fs = i;
            while i < b.len() && (b[i].is_ascii_digit() || (b[i] == b'_' && i > fs)) {
                i += 1;
            }
            frac = &b[fs..i];
            if frac.is_empty() {
                return Err("expected digits after `.` in the duration".into());
            }
        }
        let us = i;
        while i < b.len() && b[i].is_ascii_alphabetic() {
            i += 1;
        }
        let unit = &text[us..i];
        let (rank, unit_ns) = match unit.to_ascii_lowercase().as_str() {
            "d" => (0, NS_PER_DAY),
            "h" => (1, 3_600_000_000_000),
            "m" => (2, 60_000_000_000),
            "s" => (3, 1_000_000_000),
            "ms" => (4, 1_000_000),
            "us" => (5, 1_000),
            "ns" => (6, 1),
            "" => {
                return Err(format!(
                    "missing unit after `{}` (use d, h, m, s, ms, us or ns)",
                    &text[int_start..us]
                ))
            }
            _ => {
                return Err(format!(
                    "unknown duration unit `{unit}` (use d, h, m, s, ms, us or ns)"
                ))
            }
        };
        if last_rank != usize::MAX && rank <= last_rank {
            return Err(format!(
                "duration unit `{unit}` is out of order (units go from d down to ns, each at most once)"
            ));
        }
        last_rank = rank;
        let whole = parse_digits(int_digits, 10).map_err(|_| "duration out of range")?;
        let mut value = whole.checked_mul(unit_ns).ok_or("duration out of range")?;
        if !frac.is_empty() {
            value = value
                .checked_add(fraction_of(frac, unit_ns))
                .ok_or("duration out of range")?;
        }
        total = total.checked_add(value).ok_or("duration out of range")?;
        if i < b.len() && !(b[i] == b'_' || b[i].is_ascii_digit()) {
            return Err(format!(
                "unexpected `{}` in the duration",
                text[i..].chars().next().unwrap_or('?')
            ));
        }
        if i < b.len() && b[i] == b'_' && i + 1 == b.len() {
            return Err("a duration cannot end with `_`".into());
        }
    }
    Ok(if neg { -total } else { total })
}

/// `0.<frac>` of `unit` (an integer), truncated; digits past the 20th cannot change
/// the result for units up to a day and are ignored.
fn fraction_of(frac: &[u8], unit: i128) -> i128 {
    let mut num: i128 = 0;
    let mut den: i128 = 1;
    for &c in frac.iter().filter(|c| c.is_ascii_digit()).take(20) {
        num = num * 10 + (c - b'0') as i128;
        den *= 10;
    }
    num * unit / den
}

/// Days since 1970-01-01 of a proleptic Gregorian date (Hinnant's algorithm).
pub fn days_from_civil(y: i64, m: u32, d: u32) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = if y >= 0 { y } else { y - 399 } / 400;
    let yoe = y - era * 400;
    let m = m as i64;
    let doy = (153 * (if m > 2 { m - 3 } else { m + 9 }) + 2) / 5 + d as i64 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

fn is_leap(y: i64) -> bool {
    (y % 4 == 0 && y % 100 != 0) || y % 400 == 0
}

fn days_in_month(y: i64, m: u32) -> u32 {
    match m {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        _ if is_leap(y) => 29,
        _ => 28,
    }
}

fn small_number(s: &str, what: &str) -> Result<u64, String> {
    if s.is_empty() || !s.bytes().all(|c| c.is_ascii_digit()) || s.len() > 9 {
        return Err(format!("expected the {what} as a number, found `{s}`"));
    }
    s.parse::<u64>()
        .map_err(|_| format!("expected the {what} as a number, found `{s}`"))
}

/// Days since 1970-01-01 of `YYYY-MM-DD`.
pub fn date(text: &str) -> Result<i64, String> {
    let mut parts = text.split('-');
    let (Some(y), Some(m), Some(d), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(format!("expected a date as YYYY-MM-DD, found `{text}`"));
    };
    let y = small_number(y, "year")? as i64;
    let m = small_number(m, "month")? as u32;
    let d = small_number(d, "day")? as u32;
    if !(1..=12).contains(&m) {
        return Err(format!("month {m} is not between 1 and 12"));
    }
    let dim = days_in_month(y, m);
    if d < 1 || d > dim {
        return Err(format!(
            "day {d} is not between 1 and {dim} for {y:04}-{m:02}"
        ));
    }
    Ok(days_from_civil(y, m, d))
}

/// Nanoseconds since midnight of `HH:MM[:SS[.fraction]]` (CODESYS allows leaving
/// out the seconds).
pub fn time_of_day(text: &str) -> Result<i64, String> {
    let mut parts = text.split(':');
    let (Some(h), Some(m), s, None) = (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(format!(
            "expected a time of day as HH:MM:SS, found `{text}`"
        ));
    };
    let s = s.unwrap_or("0");
    let h = small_number(h, "hour")?;
    let m = small_number(m, "minute")?;
    let (s, frac) = match s.split_once('.') {
        Some((s, f)) => (s, Some(f)),
        None => (s, None),
    };
    let s = small_number(s, "second")?;
    if h > 23 {
        return Err(format!("hour {h} is not between 0 and 23"));
    }
    if m > 59 {
        return Err(format!("minute {m} is not between 0 and 59"));
    }
    if s > 59 {
        return Err(format!("second {s} is not between 0 and 59"));
    }
    let mut ns = ((h * 60 + m) * 60 + s) as i64 * 1_000_000_000;
    if let Some(f) = frac {
        if f.is_empty() || !f.bytes().all(|c| c.is_ascii_digit()) {
            return Err(format!(
                "expected digits after `.` in the seconds, found `{f}`"
            ));
        }
        ns += fraction_of(f.as_bytes(), 1_000_000_000) as i64;
    }
    Ok(ns)
}

/// Nanoseconds since 1970-01-01T00:00:00 of `YYYY-MM-DD-HH:MM:SS[.fraction]`.
pub fn date_time(text: &str) -> Result<i128, String> {
    let split = text
        .match_indices('-')
        .nth(2)
        .map(|(i, _)| i)
        .ok_or_else(|| {
            format!("expected a date and time as YYYY-MM-DD-HH:MM:SS, found `{text}`")
        })?;
    let days = date(&text[..split])?;
    let tod = time_of_day(&text[split + 1..])?;
    Ok(days as i128 * NS_PER_DAY + tod as i128)
}

/// A problem inside a string literal, at a byte offset of the literal's content.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StringError {
    /// Offset of the offending `$` from the start of the content.
    pub offset: usize,
    /// Length of the offending escape.
    pub len: usize,
    /// What is wrong.
    pub message: String,
}

/// Decodes the content of a string literal (between the quotes).
///
/// STRING (`wide == false`) holds Latin-1 code units: characters up to U+00FF are one
/// unit each (so ISO-8859-1 sources keep their bytes); other characters are stored as
/// their UTF-8 bytes. WSTRING holds UTF-16 code units.
pub fn decode_string(content: &str, wide: bool, errors: &mut Vec<StringError>) -> Vec<u16> {
    let mut units = Vec::with_capacity(content.len());
    let b = content.as_bytes();
    let mut chars = content.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        if c != '$' {
            push_char(&mut units, c, wide);
            continue;
        }
        let hex_len = if wide { 4 } else { 2 };
        let next = b.get(i + 1).copied();
        match next {
            Some(h) if h.is_ascii_hexdigit() => {
                let digits = b.get(i + 1..i + 1 + hex_len);
                match digits {
                    Some(d) if d.iter().all(|c| c.is_ascii_hexdigit()) => {
                        let v = d.iter().fold(0u32, |acc, &c| {
                            acc * 16 + (c as char).to_digit(16).unwrap_or(0)
                        });
                        units.push(v as u16);
                        for _ in 0..hex_len {
                            chars.next();
                        }
                    }
                    _ => {
                        let n = b[i + 1..]
                            .iter()
                            .take(hex_len)
                            .take_while(|c| c.is_ascii_hexdigit())
                            .count();
                        errors.push(StringError {
                            offset: i,
                            len: 1 + n,
                            message: format!(
                                "`$` followed by a hex digit needs exactly {hex_len} hex digits in a {}",
                                if wide { "WSTRING" } else { "STRING" }
                            ),
                        });
                        for _ in 0..n {
                            chars.next();
                        }
                    }
                }
            }
            Some(e) => {
                let v = match e.to_ascii_uppercase() {
                    b'$' => Some(b'$'),
                    b'\'' => Some(b'\''),
                    b'"' => Some(b'"'),
                    b'L' | b'N' => Some(b'\n'),
                    b'P' => Some(0x0c),
                    b'R' => Some(b'\r'),
                    b'T' => Some(b'\t'),
                    _ => None,
                };
                let (_, ec) = chars.next().unwrap_or((i + 1, '?'));
                match v {
                    Some(v) => units.push(v as u16),
                    None => errors.push(StringError {
                        offset: i,
                        len: 1 + ec.len_utf8(),
                        message: format!(
                            "invalid escape `${ec}` (use $$, $', $\", $L, $N, $P, $R, $T or hex digits)"
                        ),
                    }),
                }
            }
            None => errors.push(StringError {
                offset: i,
                len: 1,
                message: "`$` at the end of a string must be written `$$`".into(),
            }),
        }
    }
    units
}

fn push_char(units: &mut Vec<u16>, c: char, wide: bool) {
    if wide {
        let mut buf = [0u16; 2];
        units.extend_from_slice(c.encode_utf16(&mut buf));
    } else if (c as u32) <= 0xFF {
        units.push(c as u32 as u16);
    } else {
        let mut buf = [0u8; 4];
        units.extend(c.encode_utf8(&mut buf).bytes().map(u16::from));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: i128 = 1_000_000_000;

    #[test]
    fn durations_are_exact() {
        assert_eq!(duration("1h2m3s4ms"), Ok(3723 * S + 4_000_000));
        assert_eq!(duration("5s"), Ok(5 * S));
        assert_eq!(duration("1.5s"), Ok(1_500_000_000));
        assert_eq!(duration("-5s"), Ok(-5 * S));
        assert_eq!(duration("1d"), Ok(86_400 * S));
        assert_eq!(duration("100us"), Ok(100_000));
        assert_eq!(duration("10ns"), Ok(10));
        assert_eq!(duration("1m_30s"), Ok(90 * S));
        assert_eq!(duration("1.5h"), Ok(5400 * S));
        assert_eq!(duration("1.1s"), Ok(1_100_000_000));
        assert_eq!(duration("0.001ms"), Ok(1_000));
        assert_eq!(duration("1.5ns"), Ok(1));
        assert_eq!(duration("1H2M"), Ok(3720 * S));
        assert_eq!(duration("1_000ms"), Ok(S));
        assert_eq!(duration("1d2h3m4s5ms6us7ns"), Ok(93_784 * S + 5_006_007));
        assert_eq!(
            duration("0.333333333333333333333333333333d"),
            Ok(28_799_999_999_999)
        );
    }

    #[test]
    fn malformed_durations() {
        for bad in [
            "", "-", "5", "5x", "1s2h", "1s1s", "1.s", "s", "1s_", "1m__2s", "1ms.5",
        ] {
            assert!(duration(bad).is_err(), "{bad:?} should be rejected");
        }
        assert!(duration("99999999999999999999999999999999999999d").is_err());
    }

    #[test]
    fn dates_and_times() {
        assert_eq!(date("1970-01-01"), Ok(0));
        assert_eq!(date("2024-01-31"), Ok(19753));
        assert_eq!(date("2000-02-29"), Ok(11016));
        assert_eq!(date("1969-12-31"), Ok(-1));
        assert!(date("2023-02-29").is_err());
        assert!(date("2024-13-01").is_err());
        assert!(date("2024-01").is_err());
        assert!(date("2024-01-01-").is_err());
        assert_eq!(
            time_of_day("12:30:15.25"),
            Ok((12 * 3600 + 30 * 60 + 15) * 1_000_000_000 + 250_000_000)
        );
        assert_eq!(time_of_day("00:00:00"), Ok(0));
        assert!(time_of_day("24:00:00").is_err());
        assert!(time_of_day("12:60:00").is_err());
        assert_eq!(
            time_of_day("12:30"),
            Ok((12 * 60 + 30) * 60 * 1_000_000_000)
        );
        assert!(time_of_day("12").is_err());
        assert!(time_of_day("12:30:").is_err());
        assert!(time_of_day("12:30:1.").is_err());
        assert_eq!(
            date_time("2024-01-31-12:30:15.5"),
            Ok(19753 * NS_PER_DAY + (45015 * S + 500_000_000))
        );
        assert!(date_time("2024-01-31").is_err());
    }

    #[test]
    fn strings_and_escapes() {
        let mut e = Vec::new();
        assert_eq!(
            decode_string("a$$b$'$L$N$P$R$T$0A", false, &mut e),
            vec![
                b'a' as u16,
                b'$' as u16,
                b'b' as u16,
                b'\'' as u16,
                10,
                10,
                12,
                13,
                9,
                10
            ]
        );
        assert!(e.is_empty());
        assert_eq!(
            decode_string("$0041$\"\u{e4}", true, &mut e),
            vec![0x41, b'"' as u16, 0xe4]
        );
        assert_eq!(
            decode_string("\u{e4}\u{20ac}", false, &mut e),
            vec![0xe4, 0xe2, 0x82, 0xac]
        );
        assert_eq!(
            decode_string("\u{1F600}", true, &mut e),
            vec![0xD83D, 0xDE00]
        );
        assert!(e.is_empty());
        decode_string("$q", false, &mut e);
        decode_string("$4", false, &mut e);
        decode_string("$", false, &mut e);
        decode_string("$00", true, &mut e);
        assert_eq!(e.len(), 4);
    }

    #[test]
    fn digits() {
        assert_eq!(parse_digits(b"1010_0101", 2), Ok(0xA5));
        assert_eq!(parse_digits(b"ff", 16), Ok(255));
        assert_eq!(parse_digits(b"19", 8), Err(DigitError::BadDigit(b'9')));
        assert_eq!(parse_digits(b"_", 10), Err(DigitError::NoDigits));
        assert_eq!(
            parse_digits(b"999999999999999999999999999999999999999999", 10),
            Err(DigitError::TooLarge)
        );
    }
}
