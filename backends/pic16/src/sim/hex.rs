//! Intel HEX reader for program images (INHX8M/INHX32, as gpasm and gplink write them).

use super::{SimError, PROG_WORDS};

/// Parses `text` into program words 0..=highest word used (gaps read 0x3FFF). Byte
/// addresses are twice the word address, low byte first. Words at or above 0x2000
/// (user IDs, the configuration word at byte 0x400E, data EEPROM at 0x4200) are skipped.
pub(super) fn parse(text: &str) -> Result<Vec<u16>, SimError> {
    let mut words = vec![0x3FFFu16; PROG_WORDS];
    let mut used: Option<usize> = None;
    let mut base: u32 = 0;
    let mut eof = false;
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let err = |msg: &str| SimError(format!("hex line {}: {msg}", n + 1));
        if eof {
            return Err(err("record after the end-of-file record"));
        }
        let digits = line
            .strip_prefix(':')
            .ok_or_else(|| err("record does not start with ':'"))?;
        if digits.len() % 2 != 0 || digits.len() < 10 {
            return Err(err("record too short or odd number of hex digits"));
        }
        let bytes = digits
            .as_bytes()
            .chunks(2)
            .map(|p| {
                std::str::from_utf8(p)
                    .ok()
                    .and_then(|s| u8::from_str_radix(s, 16).ok())
            })
            .collect::<Option<Vec<u8>>>()
            .ok_or_else(|| err("bad hex digit"))?;
        let len = bytes[0] as usize;
        if bytes.len() != len + 5 {
            return Err(err("byte count does not match the record length"));
        }
        if bytes.iter().fold(0u8, |s, &b| s.wrapping_add(b)) != 0 {
            return Err(err("checksum mismatch"));
        }
        let addr = u32::from(bytes[1]) << 8 | u32::from(bytes[2]);
        let data = &bytes[4..4 + len];
        match bytes[3] {
            0x00 => {
                for (i, &b) in data.iter().enumerate() {
                    let byte_addr = base + addr + i as u32;
                    let wa = (byte_addr / 2) as usize;
                    if wa >= PROG_WORDS {
                        continue;
                    }
                    let w = &mut words[wa];
                    *w = if byte_addr.is_multiple_of(2) {
                        (*w & 0xFF00) | u16::from(b)
                    } else {
                        (*w & 0x00FF) | u16::from(b) << 8
                    };
                    used = Some(used.map_or(wa, |u| u.max(wa)));
                }
            }
            0x01 => eof = true,
            0x02 | 0x04 => {
                if len != 2 {
                    return Err(err("extended address record needs 2 data bytes"));
                }
                let v = u32::from(data[0]) << 8 | u32::from(data[1]);
                base = if bytes[3] == 0x02 { v << 4 } else { v << 16 };
            }
            0x03 | 0x05 => {}
            t => return Err(err(&format!("unknown record type {t:02X}"))),
        }
    }
    if !eof {
        return Err(SimError("hex: missing end-of-file record".into()));
    }
    words.truncate(used.map_or(0, |u| u + 1));
    for w in &mut words {
        *w &= 0x3FFF;
    }
    Ok(words)
}
