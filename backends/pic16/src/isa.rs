//! The PIC16 mid-range instruction set: the 35 instructions, their encodings and cycle
//! counts, and the core registers the code generator names.
//!
//! File operands are full 9-bit data addresses (`0x000..=0x1FF`); the encoding keeps
//! the low 7 bits and the bank bits come from STATUS, as on the chip. Code addresses
//! are 13-bit word addresses; CALL and GOTO encode the low 11 bits.

/// Where the result of a byte-oriented operation goes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum Dest {
    /// The W register (`d = 0`).
    W,
    /// The file register (`d = 1`).
    F,
}

/// One instruction with its operands. `f` is a data address, `b` a bit number (0–7),
/// `k` a literal (8 bits, or an 11-bit code address for CALL/GOTO).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum Inst {
    Addwf(u16, Dest),
    Andwf(u16, Dest),
    Clrf(u16),
    Clrw,
    Comf(u16, Dest),
    Decf(u16, Dest),
    Decfsz(u16, Dest),
    Incf(u16, Dest),
    Incfsz(u16, Dest),
    Iorwf(u16, Dest),
    Movf(u16, Dest),
    Movwf(u16),
    Nop,
    Rlf(u16, Dest),
    Rrf(u16, Dest),
    Subwf(u16, Dest),
    Swapf(u16, Dest),
    Xorwf(u16, Dest),
    Bcf(u16, u8),
    Bsf(u16, u8),
    Btfsc(u16, u8),
    Btfss(u16, u8),
    Addlw(u8),
    Andlw(u8),
    Call(u16),
    Clrwdt,
    Goto(u16),
    Iorlw(u8),
    Movlw(u8),
    Retfie,
    Retlw(u8),
    Return,
    Sleep,
    Sublw(u8),
    Xorlw(u8),
}

/// The W register is not a file register; these are the core registers that every
/// bank mirrors, plus the peripheral registers the runtime uses.
pub mod reg {
    /// Indirect data through FSR (any bank).
    pub const INDF: u16 = 0x00;
    /// Timer0 (bank 0).
    pub const TMR0: u16 = 0x01;
    /// Low byte of the program counter (any bank).
    pub const PCL: u16 = 0x02;
    /// STATUS (any bank).
    pub const STATUS: u16 = 0x03;
    /// File select register for INDF (any bank).
    pub const FSR: u16 = 0x04;
    /// Port A (bank 0).
    pub const PORTA: u16 = 0x05;
    /// Port B (bank 0).
    pub const PORTB: u16 = 0x06;
    /// Port C (bank 0).
    pub const PORTC: u16 = 0x07;
    /// Upper program counter bits for writes to PCL, CALL and GOTO (any bank).
    pub const PCLATH: u16 = 0x0A;
    /// Interrupt control (any bank).
    pub const INTCON: u16 = 0x0B;
    /// Peripheral interrupt flags 1 (bank 0).
    pub const PIR1: u16 = 0x0C;
    /// Timer1 low byte (bank 0).
    pub const TMR1L: u16 = 0x0E;
    /// Timer1 high byte (bank 0).
    pub const TMR1H: u16 = 0x0F;
    /// Timer1 control (bank 0).
    pub const T1CON: u16 = 0x10;
    /// CCP1 compare value, low byte (bank 0).
    pub const CCPR1L: u16 = 0x15;
    /// CCP1 compare value, high byte (bank 0).
    pub const CCPR1H: u16 = 0x16;
    /// CCP1 control (bank 0).
    pub const CCP1CON: u16 = 0x17;
    /// OPTION_REG (bank 1).
    pub const OPTION_REG: u16 = 0x81;
    /// Port A direction (bank 1).
    pub const TRISA: u16 = 0x85;
    /// Port B direction (bank 1).
    pub const TRISB: u16 = 0x86;
    /// Port C direction (bank 1).
    pub const TRISC: u16 = 0x87;
    /// Peripheral interrupt enables 1 (bank 1).
    pub const PIE1: u16 = 0x8C;
    /// A/D port configuration (bank 1).
    pub const ADCON1: u16 = 0x9F;

    /// STATUS bits.
    pub const C: u8 = 0;
    /// Digit carry.
    pub const DC: u8 = 1;
    /// Zero.
    pub const Z: u8 = 2;
    /// Bank select, low bit.
    pub const RP0: u8 = 5;
    /// Bank select, high bit.
    pub const RP1: u8 = 6;
    /// Indirect bank select (banks 2/3 for FSR).
    pub const IRP: u8 = 7;

    /// INTCON: global interrupt enable.
    pub const GIE: u8 = 7;
    /// INTCON: peripheral interrupt enable.
    pub const PEIE: u8 = 6;
    /// PIR1/PIE1: CCP1 interrupt flag/enable.
    pub const CCP1IF: u8 = 2;
    /// T1CON: Timer1 on.
    pub const TMR1ON: u8 = 0;
}

/// True if `f` is the same register in every bank (core registers and common RAM), so
/// an access needs no bank select.
pub fn is_unbanked(f: u16) -> bool {
    let low = f & 0x7F;
    matches!(low, 0x00 | 0x02 | 0x03 | 0x04 | 0x0A | 0x0B) || (0x70..=0x7F).contains(&low)
}

/// The bank (0–3) a direct access to `f` needs, or `None` if any bank works.
pub fn bank_of(f: u16) -> Option<u8> {
    if is_unbanked(f) {
        None
    } else {
        Some(((f >> 7) & 3) as u8)
    }
}

impl Inst {
    /// The file operand, if the instruction has one.
    pub fn file(self) -> Option<u16> {
        use Inst::*;
        match self {
            Addwf(f, _)
            | Andwf(f, _)
            | Clrf(f)
            | Comf(f, _)
            | Decf(f, _)
            | Decfsz(f, _)
            | Incf(f, _)
            | Incfsz(f, _)
            | Iorwf(f, _)
            | Movf(f, _)
            | Movwf(f)
            | Rlf(f, _)
            | Rrf(f, _)
            | Subwf(f, _)
            | Swapf(f, _)
            | Xorwf(f, _)
            | Bcf(f, _)
            | Bsf(f, _)
            | Btfsc(f, _)
            | Btfss(f, _) => Some(f),
            _ => None,
        }
    }

    /// True for the conditional skips (BTFSC, BTFSS, DECFSZ, INCFSZ).
    pub fn is_skip(self) -> bool {
        matches!(
            self,
            Inst::Btfsc(..) | Inst::Btfss(..) | Inst::Decfsz(..) | Inst::Incfsz(..)
        )
    }

    /// Instruction cycles, not counting the extra cycle of a taken skip.
    pub fn cycles(self) -> u32 {
        use Inst::*;
        match self {
            Goto(_) | Call(_) | Return | Retlw(_) | Retfie => 2,
            Addwf(reg::PCL, Dest::F)
            | Movwf(reg::PCL)
            | Clrf(reg::PCL)
            | Iorwf(reg::PCL, Dest::F)
            | Andwf(reg::PCL, Dest::F)
            | Xorwf(reg::PCL, Dest::F)
            | Subwf(reg::PCL, Dest::F)
            | Incf(reg::PCL, Dest::F)
            | Decf(reg::PCL, Dest::F) => 2,
            _ => 1,
        }
    }

    /// The 14-bit machine word (Table 15-2 of the data sheet).
    pub fn encode(self) -> u16 {
        use Inst::*;
        let bo = |op: u16, f: u16, d: Dest| op << 8 | (d as u16) << 7 | (f & 0x7F);
        let bit = |op: u16, f: u16, b: u8| op << 10 | (b as u16 & 7) << 7 | (f & 0x7F);
        match self {
            Addwf(f, x) => bo(0b00_0111, f, x),
            Andwf(f, x) => bo(0b00_0101, f, x),
            Clrf(f) => 0b00_0001_1000_0000 | (f & 0x7F),
            Clrw => 0b00_0001_0000_0011,
            Comf(f, x) => bo(0b00_1001, f, x),
            Decf(f, x) => bo(0b00_0011, f, x),
            Decfsz(f, x) => bo(0b00_1011, f, x),
            Incf(f, x) => bo(0b00_1010, f, x),
            Incfsz(f, x) => bo(0b00_1111, f, x),
            Iorwf(f, x) => bo(0b00_0100, f, x),
            Movf(f, x) => bo(0b00_1000, f, x),
            Movwf(f) => 0b00_0000_1000_0000 | (f & 0x7F),
            Nop => 0,
            Rlf(f, x) => bo(0b00_1101, f, x),
            Rrf(f, x) => bo(0b00_1100, f, x),
            Subwf(f, x) => bo(0b00_0010, f, x),
            Swapf(f, x) => bo(0b00_1110, f, x),
            Xorwf(f, x) => bo(0b00_0110, f, x),
            Bcf(f, b) => bit(0b0100, f, b),
            Bsf(f, b) => bit(0b0101, f, b),
            Btfsc(f, b) => bit(0b0110, f, b),
            Btfss(f, b) => bit(0b0111, f, b),
            Addlw(k) => 0b11_1110_0000_0000 | k as u16,
            Andlw(k) => 0b11_1001_0000_0000 | k as u16,
            Call(k) => 0b10_0000_0000_0000 | (k & 0x7FF),
            Clrwdt => 0b00_0000_0110_0100,
            Goto(k) => 0b10_1000_0000_0000 | (k & 0x7FF),
            Iorlw(k) => 0b11_1000_0000_0000 | k as u16,
            Movlw(k) => 0b11_0000_0000_0000 | k as u16,
            Retfie => 0b00_0000_0000_1001,
            Retlw(k) => 0b11_0100_0000_0000 | k as u16,
            Return => 0b00_0000_0000_1000,
            Sleep => 0b00_0000_0110_0011,
            Sublw(k) => 0b11_1100_0000_0000 | k as u16,
            Xorlw(k) => 0b11_1010_0000_0000 | k as u16,
        }
    }

    /// Decodes a 14-bit word (`None` for the few unused encodings). File operands come
    /// back as 7-bit addresses (bank 0 view).
    pub fn decode(w: u16) -> Option<Inst> {
        use Inst::*;
        let w = w & 0x3FFF;
        let f = w & 0x7F;
        let dst = if w & 0x80 != 0 { Dest::F } else { Dest::W };
        let b = ((w >> 7) & 7) as u8;
        let k = (w & 0xFF) as u8;
        Some(match w >> 12 {
            0b00 => match (w >> 8) & 0xF {
                0b0000 => {
                    if w & 0x80 != 0 {
                        Movwf(f)
                    } else {
                        match w {
                            0x0008 => Return,
                            0x0009 => Retfie,
                            0x0063 => Sleep,
                            0x0064 => Clrwdt,
                            0x0000 | 0x0020 | 0x0040 | 0x0060 => Nop,
                            _ => return None,
                        }
                    }
                }
                0b0001 => {
                    if w & 0x80 != 0 {
                        Clrf(f)
                    } else {
                        Clrw
                    }
                }
                0b0010 => Subwf(f, dst),
                0b0011 => Decf(f, dst),
                0b0100 => Iorwf(f, dst),
                0b0101 => Andwf(f, dst),
                0b0110 => Xorwf(f, dst),
                0b0111 => Addwf(f, dst),
                0b1000 => Movf(f, dst),
                0b1001 => Comf(f, dst),
                0b1010 => Incf(f, dst),
                0b1011 => Decfsz(f, dst),
                0b1100 => Rrf(f, dst),
                0b1101 => Rlf(f, dst),
                0b1110 => Swapf(f, dst),
                _ => Incfsz(f, dst),
            },
            0b01 => match (w >> 10) & 3 {
                0 => Bcf(f, b),
                1 => Bsf(f, b),
                2 => Btfsc(f, b),
                _ => Btfss(f, b),
            },
            0b10 => {
                if w & 0x800 != 0 {
                    Goto(w & 0x7FF)
                } else {
                    Call(w & 0x7FF)
                }
            }
            _ => match (w >> 8) & 0xF {
                0b0000..=0b0011 => Movlw(k),
                0b0100..=0b0111 => Retlw(k),
                0b1000 => Iorlw(k),
                0b1001 => Andlw(k),
                0b1010 => Xorlw(k),
                0b1100 | 0b1101 => Sublw(k),
                0b1110 | 0b1111 => Addlw(k),
                _ => return None,
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encodings_match_the_data_sheet() {
        assert_eq!(Inst::Movlw(0x55).encode(), 0x3055);
        assert_eq!(Inst::Movwf(0x21).encode(), 0x00A1);
        assert_eq!(Inst::Addwf(0x21, Dest::F).encode(), 0x07A1);
        assert_eq!(Inst::Bsf(reg::STATUS, reg::RP0).encode(), 0x1683);
        assert_eq!(Inst::Bcf(reg::STATUS, reg::RP0).encode(), 0x1283);
        assert_eq!(Inst::Btfss(reg::STATUS, reg::Z).encode(), 0x1D03);
        assert_eq!(Inst::Goto(0x123).encode(), 0x2923);
        assert_eq!(Inst::Call(0x10).encode(), 0x2010);
        assert_eq!(Inst::Return.encode(), 0x0008);
        assert_eq!(Inst::Retfie.encode(), 0x0009);
        assert_eq!(Inst::Clrw.encode(), 0x0103);
        assert_eq!(Inst::Sublw(1).encode(), 0x3C01);
        assert_eq!(Inst::Addlw(1).encode(), 0x3E01);
    }

    #[test]
    fn decode_inverts_encode() {
        for w in 0u16..0x4000 {
            if let Some(i) = Inst::decode(w) {
                let back = i.encode();
                // Don't-care bits (NOP forms, MOVLW/RETLW/SUBLW/ADDLW x bits) differ.
                assert_eq!(Inst::decode(back), Some(i), "word {w:#06x}");
            }
        }
    }
}
