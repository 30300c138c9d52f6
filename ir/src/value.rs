//! Values of PLC variables as the runner sees them: read from a machine, shown in IEC
//! literal form, parsed from scenario files.

use crate::types::{ElemType, Type};
use std::fmt;

/// A value of an elementary type: the type and its raw bits (the IR representation,
/// zero-extended to 64 bits; REAL is the binary32 encoding in the low half).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct PlcValue {
    /// The IEC type.
    pub ty: ElemType,
    /// The bits, zero-extended from the type's width.
    pub bits: u64,
}

impl PlcValue {
    /// A value from raw bits (masked to the type's width).
    pub fn from_bits(ty: ElemType, bits: u64) -> PlcValue {
        PlcValue {
            ty,
            bits: ty.ir_type().zext_bits(bits as i64),
        }
    }

    /// A value from an integer (wrapped to the type's width).
    pub fn from_i64(ty: ElemType, v: i64) -> PlcValue {
        PlcValue::from_bits(ty, v as u64)
    }

    /// A BOOL.
    pub fn from_bool(b: bool) -> PlcValue {
        PlcValue {
            ty: ElemType::Bool,
            bits: b as u64,
        }
    }

    /// A REAL.
    pub fn from_f32(v: f32) -> PlcValue {
        PlcValue {
            ty: ElemType::Real,
            bits: v.to_bits() as u64,
        }
    }

    /// An LREAL.
    pub fn from_f64(v: f64) -> PlcValue {
        PlcValue {
            ty: ElemType::LReal,
            bits: v.to_bits(),
        }
    }

    /// The value as a signed integer (sign-extended for signed types).
    pub fn as_i64(self) -> i64 {
        if self.ty.is_signed() {
            self.ty.ir_type().canon_int(self.bits as i64)
        } else {
            self.bits as i64
        }
    }

    /// The value as a float (REAL and LREAL), else as an integer converted.
    pub fn as_f64(self) -> f64 {
        match self.ty {
            ElemType::Real => f32::from_bits(self.bits as u32) as f64,
            ElemType::LReal => f64::from_bits(self.bits),
            t if t.is_signed() => self.as_i64() as f64,
            _ => self.bits as f64,
        }
    }

    /// True unless the bits are all zero.
    pub fn as_bool(self) -> bool {
        self.bits != 0
    }

    /// Parses a value of type `ty` as written in a scenario or on the command line:
    /// The same value: of one type and bit for bit, except that any two NaNs are
    /// equal (how the machines are compared with one another).
    pub fn same(self, other: PlcValue) -> bool {
        if self.ty != other.ty {
            return false;
        }
        match self.ty {
            ElemType::Real | ElemType::LReal if self.as_f64().is_nan() => other.as_f64().is_nan(),
            _ => self.bits == other.bits,
        }
    }

    /// `TRUE`, `FALSE`, `-5`, `16#FF`, `2#1010`, `INT#5`, `2.5`, `1.0E3`, `T#1s500ms`,
    /// `T#1500ms`. A plain integer for a TIME means milliseconds.
    pub fn parse(ty: ElemType, text: &str) -> Result<PlcValue, String> {
        let t = text.trim();
        let bad = || format!("`{t}` is not a valid {} value", ty.name());
        // An optional type prefix such as INT# or BOOL# (not T#, which is a duration).
        let body = match t.find('#') {
            Some(i)
                if ElemType::from_name(&t[..i]).is_some()
                    && !matches!(ty, ElemType::Time | ElemType::LTime) =>
            {
                &t[i + 1..]
            }
            _ => t,
        };
        match ty {
            ElemType::Bool => match body.to_ascii_uppercase().as_str() {
                "TRUE" | "1" => Ok(PlcValue::from_bool(true)),
                "FALSE" | "0" => Ok(PlcValue::from_bool(false)),
                _ => Err(bad()),
            },
            ElemType::Real => {
                let v = parse_real(body).ok_or_else(bad)?;
                Ok(PlcValue::from_f32(v as f32))
            }
            ElemType::LReal => parse_real(body).map(PlcValue::from_f64).ok_or_else(bad),
            ElemType::Time | ElemType::LTime => {
                let ns = if let Some(i) = parse_int(body) {
                    i * 1_000_000
                } else {
                    parse_duration_literal(body).ok_or_else(bad)?
                };
                let raw = if ty == ElemType::Time {
                    (ns / 1_000_000) as i64
                } else {
                    ns as i64
                };
                Ok(PlcValue::from_i64(ty, raw))
            }
            ElemType::LDate | ElemType::LTod | ElemType::LDt if parse_int(body).is_none() => {
                let text = t.rsplit_once('#').map_or(t, |(_, b)| b);
                let v = parse_long_date(ty, text).ok_or_else(bad)?;
                Ok(PlcValue::from_i64(ty, v))
            }
            ElemType::Date | ElemType::Tod | ElemType::Dt if parse_int(body).is_none() => {
                let text = t.rsplit_once('#').map_or(t, |(_, b)| b);
                let v = parse_date(ty, text).ok_or_else(bad)?;
                Ok(PlcValue::from_i64(ty, v))
            }
            _ => {
                let v = parse_int(body).ok_or_else(bad)?;
                let bits = ty.ir_type().bits();
                let (lo, hi) = if ty.is_signed() {
                    (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
                } else {
                    (0, (1i128 << bits) - 1)
                };
                if v < lo || v > hi {
                    return Err(format!("{t} is out of the range of {}", ty.name()));
                }
                Ok(PlcValue::from_i64(ty, v as i64))
            }
        }
    }
}

/// Parses the text after `D#`, `TOD#` or `DT#` (`2024-01-31`, `12:30:15.5`,
/// `2024-01-31-12:30:15`) into the count the type holds (seconds since 1970 for DATE
/// and DATE_AND_TIME, milliseconds since midnight for TIME_OF_DAY).
fn parse_date(ty: ElemType, text: &str) -> Option<i64> {
    let day = |s: &str| -> Option<i64> {
        let mut it = s.splitn(3, '-');
        let y: i64 = it.next()?.parse().ok()?;
        let m: u32 = it.next()?.parse().ok()?;
        let d: u32 = it.next()?.parse().ok()?;
        ((1..=12).contains(&m) && (1..=31).contains(&d)).then(|| days_from_civil(y, m, d))
    };
    let tod_ms = |s: &str| -> Option<i64> {
        let mut it = s.splitn(3, ':');
        let h: i64 = it.next()?.parse().ok()?;
        let mi: i64 = it.next()?.parse().ok()?;
        let sec: f64 = it.next()?.parse().ok()?;
        (h < 24 && mi < 60 && (0.0..60.0).contains(&sec))
            .then(|| (h * 3600 + mi * 60) * 1000 + (sec * 1000.0).round() as i64)
    };
    let v = match ty {
        ElemType::Date => day(text)? * 86_400,
        ElemType::Tod => tod_ms(text)?,
        _ => {
            // The date is the first three dash-separated fields.
            let cut = text.match_indices('-').nth(2)?.0;
            day(&text[..cut])? * 86_400 + tod_ms(&text[cut + 1..])? / 1000
        }
    };
    (0..=u32::MAX as i64).contains(&v).then_some(v)
}

/// Parses the text after `LDATE#`, `LTOD#` or `LDT#` into nanoseconds (since 1970 for
/// LDATE and LDATE_AND_TIME, since midnight for LTIME_OF_DAY), fractions of a second
/// to the nanosecond.
fn parse_long_date(ty: ElemType, text: &str) -> Option<i64> {
    const NS: i128 = 1_000_000_000;
    let day = |s: &str| -> Option<i128> {
        let mut it = s.splitn(3, '-');
        let y: i64 = it.next()?.parse().ok()?;
        let m: u32 = it.next()?.parse().ok()?;
        let d: u32 = it.next()?.parse().ok()?;
        ((1..=12).contains(&m) && (1..=31).contains(&d))
            .then(|| days_from_civil(y, m, d) as i128 * 86_400 * NS)
    };
    let tod = |s: &str| -> Option<i128> {
        let mut it = s.splitn(3, ':');
        let h: i128 = it.next()?.parse().ok()?;
        let mi: i128 = it.next()?.parse().ok()?;
        let sec = it.next()?;
        let (whole, frac) = sec.split_once('.').unwrap_or((sec, ""));
        let s: i128 = whole.parse().ok()?;
        if frac.len() > 9 || !frac.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        let f: i128 = format!("{frac:0<9}").parse().ok()?;
        (h < 24 && mi < 60 && s < 60).then_some(((h * 60 + mi) * 60 + s) * NS + f)
    };
    let v = match ty {
        ElemType::LDate => day(text)?,
        ElemType::LTod => tod(text)?,
        _ => {
            let cut = text.match_indices('-').nth(2)?.0;
            day(&text[..cut])? + tod(&text[cut + 1..])?
        }
    };
    i64::try_from(v).ok()
}

/// The text of `ns` nanoseconds since midnight: `12:30:15`, `12:30:15.5`.
fn format_tod_ns(f: &mut fmt::Formatter<'_>, ns: i64) -> fmt::Result {
    let (secs, frac) = (ns.div_euclid(1_000_000_000), ns.rem_euclid(1_000_000_000));
    write!(
        f,
        "{:02}:{:02}:{:02}",
        secs / 3600,
        secs / 60 % 60,
        secs % 60
    )?;
    if frac != 0 {
        let digits = format!("{frac:09}");
        write!(f, ".{}", digits.trim_end_matches('0'))?;
    }
    Ok(())
}

/// Days since 1970-01-01 of a proleptic Gregorian date (Howard Hinnant's algorithm).
fn days_from_civil(y: i64, m: u32, d: u32) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m as i64 + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d as i64 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// Parses a decimal or based integer (`-5`, `1_000`, `16#FF`, `2#1010`, `8#17`).
pub fn parse_int(text: &str) -> Option<i128> {
    let (neg, t) = match text.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let (radix, digits) = match t.find('#') {
        Some(i) => (t[..i].parse::<u32>().ok()?, &t[i + 1..]),
        None => (10, t),
    };
    if !matches!(radix, 2 | 8 | 10 | 16) || digits.is_empty() || digits.starts_with('_') {
        return None;
    }
    let mut v: i128 = 0;
    for c in digits.chars() {
        if c == '_' {
            continue;
        }
        v = v
            .checked_mul(radix as i128)?
            .checked_add(c.to_digit(radix)? as i128)?;
    }
    Some(if neg { -v } else { v })
}

/// Parses a real number (`2.5`, `-1.0E3`, `1e-3`, `3`, `NaN`, `inf`).
pub fn parse_real(text: &str) -> Option<f64> {
    let t: String = text.chars().filter(|&c| c != '_').collect();
    if t.is_empty() || t.ends_with('.') && !t.ends_with("..") && t.len() == 1 {
        return None;
    }
    t.parse::<f64>().ok()
}

/// Parses a duration literal with or without its prefix (`T#1h2m3s4ms`, `TIME#-5s`,
/// `LT#1.5ms`, `1m30s`, `100us`) into nanoseconds.
pub fn parse_duration_literal(text: &str) -> Option<i128> {
    let body = match text.find('#') {
        Some(i) => {
            let prefix = text[..i].to_ascii_uppercase();
            if !matches!(prefix.as_str(), "T" | "TIME" | "LT" | "LTIME") {
                return None;
            }
            &text[i + 1..]
        }
        None => text,
    };
    let (neg, body) = match body.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, body.strip_prefix('+').unwrap_or(body)),
    };
    let lower = body.to_ascii_lowercase();
    let b = lower.as_bytes();
    let mut i = 0;
    let mut total: i128 = 0;
    let mut any = false;
    while i < b.len() {
        if b[i] == b'_' {
            i += 1;
            continue;
        }
        // number: digits with optional fraction
        let start = i;
        while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'_') {
            i += 1;
        }
        let int_part: String = lower[start..i].chars().filter(|&c| c != '_').collect();
        let mut frac = String::new();
        if i < b.len() && b[i] == b'.' {
            i += 1;
            let fs = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'_') {
                i += 1;
            }
            frac = lower[fs..i].chars().filter(|&c| c != '_').collect();
        }
        if int_part.is_empty() && frac.is_empty() {
            return None;
        }
        let us = i;
        while i < b.len() && b[i].is_ascii_alphabetic() {
            i += 1;
        }
        let unit_ns: i128 = match &lower[us..i] {
            "d" => 86_400_000_000_000,
            "h" => 3_600_000_000_000,
            "m" => 60_000_000_000,
            "s" => 1_000_000_000,
            "ms" => 1_000_000,
            "us" => 1_000,
            "ns" => 1,
            _ => return None,
        };
        let whole: i128 = if int_part.is_empty() {
            0
        } else {
            int_part.parse().ok()?
        };
        total = total.checked_add(whole.checked_mul(unit_ns)?)?;
        if !frac.is_empty() {
            // exact decimal fraction of the unit, truncated to whole nanoseconds
            let digits: i128 = frac.parse().ok()?;
            let scale = 10i128.checked_pow(frac.len() as u32)?;
            total = total.checked_add(digits.checked_mul(unit_ns)? / scale)?;
        }
        any = true;
    }
    if !any {
        return None;
    }
    Some(if neg { -total } else { total })
}

/// Formats a float the IEC way: always with a `.`, exponent as `E`, shortest digits
/// that read back to the same value.
fn format_real<T: fmt::Debug + Copy + Into<f64>>(v: T) -> String {
    let f: f64 = v.into();
    if f.is_nan() {
        return "NaN".to_string();
    }
    if f.is_infinite() {
        return if f > 0.0 { "+Inf" } else { "-Inf" }.to_string();
    }
    let s = format!("{v:?}");
    match s.find('e') {
        Some(i) => {
            let (mant, exp) = s.split_at(i);
            let mant = if mant.contains('.') {
                mant.to_string()
            } else {
                format!("{mant}.0")
            };
            format!("{mant}E{}", &exp[1..])
        }
        None => s,
    }
}

/// Days since 1970-01-01 to (year, month, day), proleptic Gregorian.
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (if m <= 2 { y + 1 } else { y }, m, d)
}

impl fmt::Display for PlcValue {
    /// The IEC literal form: `TRUE`, `-5`, `16#FF` (bit strings), `2.5`, `T#1500ms`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ElemType::*;
        match self.ty {
            Bool => f.write_str(if self.bits != 0 { "TRUE" } else { "FALSE" }),
            Byte | Word | DWord | LWord => write!(f, "16#{:X}", self.bits),
            Real => f.write_str(&format_real(f32::from_bits(self.bits as u32))),
            LReal => f.write_str(&format_real(f64::from_bits(self.bits))),
            Time => write!(f, "T#{}ms", self.as_i64()),
            LTime => write!(f, "LTIME#{}ns", self.as_i64()),
            Date => {
                let (y, m, d) = civil_from_days((self.bits as u32 as i64).div_euclid(86_400));
                write!(f, "D#{y:04}-{m:02}-{d:02}")
            }
            Tod => {
                let ms = self.bits as u32 as u64;
                let (h, mi, s, frac) =
                    (ms / 3_600_000, ms / 60_000 % 60, ms / 1000 % 60, ms % 1000);
                write!(f, "TOD#{h:02}:{mi:02}:{s:02}")?;
                if frac != 0 {
                    write!(f, ".{frac:03}")?;
                }
                Ok(())
            }
            Dt => {
                let secs = self.bits as u32 as i64;
                let (y, m, d) = civil_from_days(secs.div_euclid(86_400));
                let sod = secs.rem_euclid(86_400);
                write!(
                    f,
                    "DT#{y:04}-{m:02}-{d:02}-{:02}:{:02}:{:02}",
                    sod / 3600,
                    sod / 60 % 60,
                    sod % 60
                )
            }
            LDate => {
                let days = self.as_i64().div_euclid(86_400 * 1_000_000_000);
                let (y, m, d) = civil_from_days(days);
                write!(f, "LDATE#{y:04}-{m:02}-{d:02}")
            }
            LTod => {
                f.write_str("LTOD#")?;
                format_tod_ns(f, self.as_i64())
            }
            LDt => {
                let ns = self.as_i64();
                let day_ns = 86_400 * 1_000_000_000;
                let (y, m, d) = civil_from_days(ns.div_euclid(day_ns));
                write!(f, "LDT#{y:04}-{m:02}-{d:02}-")?;
                format_tod_ns(f, ns.rem_euclid(day_ns))
            }
            Char => write!(f, "16#{:02X}", self.bits),
            WChar => write!(f, "16#{:04X}", self.bits),
            Ref => write!(f, "16#{:X}", self.bits),
            _ if !self.ty.is_signed() => write!(f, "{}", self.bits),
            _ => write!(f, "{}", self.as_i64()),
        }
    }
}

/// The IR type's width in bytes as memory holds it on hosts (BOOL takes a byte).
pub fn host_size(ty: Type) -> u32 {
    match ty {
        Type::I1 | Type::I8 => 1,
        Type::I16 => 2,
        Type::I32 | Type::F32 => 4,
        Type::I64 | Type::F64 | Type::Ptr => 8,
    }
}

/// A string's characters as an IEC 61131-3 literal: `'text'` for a STRING (Latin-1
/// code units), `"text"` for a WSTRING (UTF-16), with `$$`, `$'` (`$"`), `$N`, `$R`,
/// `$T` and `$hh` (`$hhhh`) for what is not printable.
pub fn format_string_literal(chars: &[u16], wide: bool) -> String {
    let quote = if wide { '"' } else { '\'' };
    let mut out = String::with_capacity(chars.len() + 2);
    out.push(quote);
    let decoded: Vec<Result<char, u16>> = if wide {
        char::decode_utf16(chars.iter().copied())
            .map(|r| r.map_err(|e| e.unpaired_surrogate()))
            .collect()
    } else {
        chars
            .iter()
            .map(|&c| {
                if (0x20..0x7f).contains(&c) {
                    Ok(c as u8 as char)
                } else {
                    Err(c)
                }
            })
            .collect()
    };
    for c in decoded {
        match c {
            Ok('$') => out.push_str("$$"),
            Ok(c) if c == quote => {
                out.push('$');
                out.push(c);
            }
            Ok('\n') => out.push_str("$N"),
            Ok('\r') => out.push_str("$R"),
            Ok('\t') => out.push_str("$T"),
            Ok(c) if !c.is_control() => out.push(c),
            Ok(c) => out.push_str(&format!("${:04X}", c as u32)),
            Err(u) if wide => out.push_str(&format!("${u:04X}")),
            Err(u) => out.push_str(&match u {
                0x0a => "$N".to_string(),
                0x0d => "$R".to_string(),
                0x09 => "$T".to_string(),
                _ => format!("${:02X}", u & 0xff),
            }),
        }
    }
    out.push(quote);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shows_unsigned_64_bit_values_above_2_pow_63() {
        let max = PlcValue::parse(ElemType::ULInt, "18446744073709551615").unwrap();
        assert_eq!(max.to_string(), "18446744073709551615");
        let top = PlcValue::parse(ElemType::ULInt, "9223372036854775808").unwrap();
        assert_eq!(top.to_string(), "9223372036854775808");
        let w = PlcValue::parse(ElemType::LWord, "16#8000000000000001").unwrap();
        assert_eq!(w.to_string(), "16#8000000000000001");
        assert_eq!(
            PlcValue::parse(ElemType::UDInt, "4294967295")
                .unwrap()
                .to_string(),
            "4294967295"
        );
        assert_eq!(
            PlcValue::parse(ElemType::LInt, "-5").unwrap().to_string(),
            "-5"
        );
    }

    #[test]
    fn parses_scenario_values() {
        assert_eq!(PlcValue::parse(ElemType::Bool, "TRUE").unwrap().bits, 1);
        assert_eq!(PlcValue::parse(ElemType::Int, "-5").unwrap().as_i64(), -5);
        assert_eq!(PlcValue::parse(ElemType::Byte, "16#FF").unwrap().bits, 255);
        assert_eq!(PlcValue::parse(ElemType::Int, "INT#7").unwrap().as_i64(), 7);
        assert!(PlcValue::parse(ElemType::SInt, "200").is_err());
        assert_eq!(
            PlcValue::parse(ElemType::Time, "T#1s500ms")
                .unwrap()
                .as_i64(),
            1500
        );
        assert_eq!(
            PlcValue::parse(ElemType::Time, "T#1500ms")
                .unwrap()
                .as_i64(),
            1500
        );
        assert_eq!(
            PlcValue::parse(ElemType::Time, "250").unwrap().as_i64(),
            250
        );
        assert_eq!(
            PlcValue::parse(ElemType::Real, "2.5").unwrap().as_f64(),
            2.5
        );
        assert_eq!(
            PlcValue::parse(ElemType::ULInt, "18446744073709551615")
                .unwrap()
                .bits,
            u64::MAX
        );
    }

    #[test]
    fn shows_iec_literals() {
        assert_eq!(PlcValue::from_bool(true).to_string(), "TRUE");
        assert_eq!(PlcValue::from_i64(ElemType::Int, -3).to_string(), "-3");
        assert_eq!(PlcValue::from_f32(3.0).to_string(), "3.0");
        assert_eq!(PlcValue::from_f32(2.5).to_string(), "2.5");
        assert_eq!(PlcValue::from_f64(1e20).to_string(), "1.0E20");
        assert_eq!(
            PlcValue::from_i64(ElemType::Time, 1500).to_string(),
            "T#1500ms"
        );
        assert_eq!(PlcValue::from_i64(ElemType::Byte, 255).to_string(), "16#FF");
        assert_eq!(
            PlcValue::from_i64(ElemType::Date, 86_400 * 366).to_string(),
            "D#1971-01-02"
        );
    }

    #[test]
    fn durations_are_exact() {
        assert_eq!(
            parse_duration_literal("T#1h2m3s4ms"),
            Some(3_723_004_000_000)
        );
        assert_eq!(parse_duration_literal("t#1.5s"), Some(1_500_000_000));
        assert_eq!(parse_duration_literal("TIME#-5s"), Some(-5_000_000_000));
        assert_eq!(parse_duration_literal("T#1m_30s"), Some(90_000_000_000));
        assert_eq!(parse_duration_literal("T#5x"), None);
    }
}

#[cfg(test)]
mod date_tests {
    use super::*;

    #[test]
    fn long_dates_read_back_as_they_print() {
        for (ty, text) in [
            (ElemType::LDate, "LDATE#2024-02-29"),
            (ElemType::LTod, "LTOD#23:59:59.999999999"),
            (ElemType::LTod, "LTOD#12:00:00.5"),
            (ElemType::LTod, "LTOD#00:00:00"),
            (ElemType::LDt, "LDT#2262-04-11-23:47:16.854775807"),
            (ElemType::LDt, "LDT#1970-01-01-00:00:00.000000001"),
        ] {
            let v = PlcValue::parse(ty, text).unwrap();
            assert_eq!(v.to_string(), text);
        }
        let v = PlcValue::parse(ElemType::LTod, "LTOD#00:00:01.25").unwrap();
        assert_eq!(v.as_i64(), 1_250_000_000);
        assert!(PlcValue::parse(ElemType::LDt, "LDT#2262-04-11-23:47:16.854775808").is_err());
        assert!(PlcValue::parse(ElemType::LTod, "LTOD#00:00:00.0000000001").is_err());
    }

    #[test]
    fn dates_read_back_as_they_print() {
        for (ty, text) in [
            (ElemType::Date, "D#2024-02-29"),
            (ElemType::Date, "D#1970-01-01"),
            (ElemType::Tod, "TOD#23:59:59.999"),
            (ElemType::Tod, "TOD#00:00:00"),
            (ElemType::Dt, "DT#2106-02-07-06:28:15"),
            (ElemType::Dt, "DT#2000-01-02-03:04:05"),
        ] {
            let v = PlcValue::parse(ty, text).unwrap();
            assert_eq!(v.to_string(), text);
        }
        assert_eq!(
            PlcValue::parse(ElemType::Dt, "DATE_AND_TIME#2000-01-02-03:04:05")
                .unwrap()
                .bits,
            946_782_245
        );
        assert!(PlcValue::parse(ElemType::Date, "D#2024-13-01").is_err());
        assert!(PlcValue::parse(ElemType::Dt, "DT#2106-02-07-06:28:16").is_err());
        assert!(PlcValue::parse(ElemType::Tod, "TOD#24:00:00").is_err());
    }
}

#[cfg(test)]
mod string_tests {
    use super::format_string_literal;

    #[test]
    fn strings_print_as_iec_literals() {
        let units = |s: &str| s.bytes().map(u16::from).collect::<Vec<_>>();
        assert_eq!(format_string_literal(&units("Hello"), false), "'Hello'");
        assert_eq!(
            format_string_literal(&units("it's $5\n"), false),
            "'it$'s $$5$N'"
        );
        assert_eq!(
            format_string_literal(&[0x41, 0xe9, 0x01], false),
            "'A$E9$01'"
        );
        assert_eq!(format_string_literal(&[], false), "''");
        let wide: Vec<u16> = "Grüße \"x\"\t".encode_utf16().collect();
        assert_eq!(format_string_literal(&wide, true), "\"Grüße $\"x$\"$T\"");
        assert_eq!(
            format_string_literal(&[0xd800, 0x7f], true),
            "\"$D800$007F\""
        );
    }
}
