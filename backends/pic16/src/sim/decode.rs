//! The decoded form of program memory: one compact [`Op`] per word and bank, with the
//! kind of instruction, its resolved operand, and the fused pairs of frequent
//! consecutive instructions.

use super::*;

/// Decoded instruction kinds. There is one decoded table per bank (STATUS<RP1:RP0>
/// selects the table the run loop reads), so a direct file operand is resolved when
/// the program is decoded: the byte- and bit-oriented kinds below name a storage index
/// (`Op::a`) of general-purpose RAM or of a register without side effects; MOVF INDF,W
/// and MOVWF INDF have their own kinds, and every other file operand becomes
/// [`Kind::Slow`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(super) enum Kind {
    AddwfW,
    AddwfF,
    AndwfW,
    AndwfF,
    Clrf,
    ComfW,
    ComfF,
    DecfW,
    DecfF,
    DecfszW,
    DecfszF,
    IncfW,
    IncfF,
    IncfszW,
    IncfszF,
    IorwfW,
    IorwfF,
    MovfW,
    MovfF,
    Movwf,
    RlfW,
    RlfF,
    RrfW,
    RrfF,
    SubwfW,
    SubwfF,
    SwapfW,
    SwapfF,
    XorwfW,
    XorwfF,
    /// Bit operations: `b` holds the bit mask.
    Bcf,
    Bsf,
    Btfsc,
    Btfss,
    /// BCF/BSF on STATUS bits other than Z (`b`: the mask without TO and PD, which are
    /// read-only), and BTFSC/BTFSS on them (`b`: the mask).
    BcfStatus,
    BsfStatus,
    BtfscStatus,
    BtfssStatus,
    /// The same on STATUS<Z>.
    BcfZ,
    BsfZ,
    BtfscZ,
    BtfssZ,
    /// MOVF INDF,W and MOVWF INDF.
    MovfWIndf,
    MovwfIndf,
    /// Literal instructions: `b` holds the literal.
    Addlw,
    Andlw,
    Iorlw,
    Xorlw,
    Movlw,
    Sublw,
    Retlw,
    Clrw,
    Nop,
    /// CALL/GOTO: `a` holds the 11-bit target.
    Call,
    Goto,
    Return,
    Retfie,
    Clrwdt,
    Sleep,
    /// A byte- or bit-oriented instruction on a special or unimplemented address (`a`
    /// holds the word), executed by [`Core::exec_slow`].
    Slow,
    /// An unused encoding (`a` holds the word).
    Invalid,
    /// A stop address of the current `run_until` (the real op is saved aside).
    Break,
    // Fused pairs (see `PAIRS`): the first instruction with `a`, `b`, the second with
    // `a2`, `b2`; one dispatch for two instructions.
    MovfWMovwf,
    MovwfMovfW,
    AddwfFMovfW,
    RlfFRlfF,
    BcfStatusRlfF,
    MovwfGoto,
    MovfWXorlw,
    MovwfClrf,
    MovfWAddwfF,
    ClrfMovfW,
    MovwfIncfF,
    MovfWBtfscStatus,
    MovwfMovlw,
    ClrfClrf,
    IncfFMovfW,
    MovlwAddwfF,
    MovfWSublw,
    MovfWBtfscZ,
    BcfBtfsc,
    SublwBtfssStatus,
    MovwfBcfStatus,
    SubwfFMovfW,
    RlfFDecfszF,
    RrfFBtfssStatus,
    BcfStatusRrfF,
    MovfWBtfssStatus,
    XorlwMovwf,
    MovlwMovwf,
    MovfWSubwfF,
    AndlwMovwf,
    MovfWAndlw,
    MovfWSubwfW,
    RlfFBtfscStatus,
    SubwfFBtfscStatus,
    MovfWBtfssZ,
    IncfFGoto,
    MovwfBsf,
    MovwfBcf,
    MovfWIndfMovwf,
    BcfStatusBtfsc,
    IncfFBtfscZ,
    AddwfFGoto,
    AddwfWMovwf,
    IncfFMovfWIndf,
    BsfBtfss,
    MovlwAddwfW,
    SubwfWBtfssZ,
    RlfFMovlw,
    MovlwSubwfW,
    BcfBtfssStatus,
    SublwBtfssZ,
    BcfBtfssZ,
    BcfBtfss,
    MovlwBtfscStatus,
    MovlwBtfssStatus,
    DecfszFGoto,
    BtfssZGoto,
    BtfscStatusGoto,
    BtfssStatusGoto,
    IncfszWAddwfF,
    IncfszWSubwfF,
    BtfssBcf,
    BtfssGoto,
}

/// A decoded instruction: `a` a storage index (plain file operands), a CALL/GOTO
/// target or a word; `b` a bit mask or a literal; `a2`, `b2` the same for the second
/// instruction of a fused pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(C, align(8))]
pub(super) struct Op {
    pub(super) kind: Kind,
    pub(super) b: u8,
    pub(super) a: u16,
    pub(super) a2: u16,
    pub(super) b2: u8,
}

/// The pairs of consecutive instructions fused into one op: (first, second, fused).
/// The first is a plain instruction that goes on to the next address or skips it (then
/// the second does not run); the pairs are the most frequent in plcc's code
/// (bench/pic16).
const PAIRS: [(Kind, Kind, Kind); 63] = [
    (Kind::MovfW, Kind::Movwf, Kind::MovfWMovwf),
    (Kind::Movwf, Kind::MovfW, Kind::MovwfMovfW),
    (Kind::AddwfF, Kind::MovfW, Kind::AddwfFMovfW),
    (Kind::RlfF, Kind::RlfF, Kind::RlfFRlfF),
    (Kind::BcfStatus, Kind::RlfF, Kind::BcfStatusRlfF),
    (Kind::Movwf, Kind::Goto, Kind::MovwfGoto),
    (Kind::MovfW, Kind::Xorlw, Kind::MovfWXorlw),
    (Kind::Movwf, Kind::Clrf, Kind::MovwfClrf),
    (Kind::MovfW, Kind::AddwfF, Kind::MovfWAddwfF),
    (Kind::Clrf, Kind::MovfW, Kind::ClrfMovfW),
    (Kind::Movwf, Kind::IncfF, Kind::MovwfIncfF),
    (Kind::MovfW, Kind::BtfscStatus, Kind::MovfWBtfscStatus),
    (Kind::Movwf, Kind::Movlw, Kind::MovwfMovlw),
    (Kind::Clrf, Kind::Clrf, Kind::ClrfClrf),
    (Kind::IncfF, Kind::MovfW, Kind::IncfFMovfW),
    (Kind::Movlw, Kind::AddwfF, Kind::MovlwAddwfF),
    (Kind::MovfW, Kind::Sublw, Kind::MovfWSublw),
    (Kind::MovfW, Kind::BtfscZ, Kind::MovfWBtfscZ),
    (Kind::Bcf, Kind::Btfsc, Kind::BcfBtfsc),
    (Kind::Sublw, Kind::BtfssStatus, Kind::SublwBtfssStatus),
    (Kind::Movwf, Kind::BcfStatus, Kind::MovwfBcfStatus),
    (Kind::SubwfF, Kind::MovfW, Kind::SubwfFMovfW),
    (Kind::RlfF, Kind::DecfszF, Kind::RlfFDecfszF),
    (Kind::RrfF, Kind::BtfssStatus, Kind::RrfFBtfssStatus),
    (Kind::BcfStatus, Kind::RrfF, Kind::BcfStatusRrfF),
    (Kind::MovfW, Kind::BtfssStatus, Kind::MovfWBtfssStatus),
    (Kind::Xorlw, Kind::Movwf, Kind::XorlwMovwf),
    (Kind::Movlw, Kind::Movwf, Kind::MovlwMovwf),
    (Kind::MovfW, Kind::SubwfF, Kind::MovfWSubwfF),
    (Kind::Andlw, Kind::Movwf, Kind::AndlwMovwf),
    (Kind::MovfW, Kind::Andlw, Kind::MovfWAndlw),
    (Kind::MovfW, Kind::SubwfW, Kind::MovfWSubwfW),
    (Kind::RlfF, Kind::BtfscStatus, Kind::RlfFBtfscStatus),
    (Kind::SubwfF, Kind::BtfscStatus, Kind::SubwfFBtfscStatus),
    (Kind::MovfW, Kind::BtfssZ, Kind::MovfWBtfssZ),
    (Kind::IncfF, Kind::Goto, Kind::IncfFGoto),
    (Kind::Movwf, Kind::Bsf, Kind::MovwfBsf),
    (Kind::Movwf, Kind::Bcf, Kind::MovwfBcf),
    (Kind::MovfWIndf, Kind::Movwf, Kind::MovfWIndfMovwf),
    (Kind::BcfStatus, Kind::Btfsc, Kind::BcfStatusBtfsc),
    (Kind::IncfF, Kind::BtfscZ, Kind::IncfFBtfscZ),
    (Kind::AddwfF, Kind::Goto, Kind::AddwfFGoto),
    (Kind::AddwfW, Kind::Movwf, Kind::AddwfWMovwf),
    (Kind::IncfF, Kind::MovfWIndf, Kind::IncfFMovfWIndf),
    (Kind::Bsf, Kind::Btfss, Kind::BsfBtfss),
    (Kind::Movlw, Kind::AddwfW, Kind::MovlwAddwfW),
    (Kind::SubwfW, Kind::BtfssZ, Kind::SubwfWBtfssZ),
    (Kind::RlfF, Kind::Movlw, Kind::RlfFMovlw),
    (Kind::Movlw, Kind::SubwfW, Kind::MovlwSubwfW),
    (Kind::Bcf, Kind::BtfssStatus, Kind::BcfBtfssStatus),
    (Kind::Sublw, Kind::BtfssZ, Kind::SublwBtfssZ),
    (Kind::Bcf, Kind::BtfssZ, Kind::BcfBtfssZ),
    (Kind::Bcf, Kind::Btfss, Kind::BcfBtfss),
    (Kind::Movlw, Kind::BtfscStatus, Kind::MovlwBtfscStatus),
    (Kind::Movlw, Kind::BtfssStatus, Kind::MovlwBtfssStatus),
    (Kind::DecfszF, Kind::Goto, Kind::DecfszFGoto),
    (Kind::BtfssZ, Kind::Goto, Kind::BtfssZGoto),
    (Kind::BtfscStatus, Kind::Goto, Kind::BtfscStatusGoto),
    (Kind::BtfssStatus, Kind::Goto, Kind::BtfssStatusGoto),
    (Kind::IncfszW, Kind::AddwfF, Kind::IncfszWAddwfF),
    (Kind::IncfszW, Kind::SubwfF, Kind::IncfszWSubwfF),
    (Kind::Btfss, Kind::Bcf, Kind::BtfssBcf),
    (Kind::Btfss, Kind::Goto, Kind::BtfssGoto),
];

impl Op {
    pub(super) const fn new(kind: Kind, b: u8, a: u16) -> Op {
        Op {
            kind,
            b,
            a,
            a2: 0,
            b2: 0,
        }
    }

    /// Decodes `word` as executed with STATUS<RP1:RP0> giving data address offset
    /// `bank` (0, 0x80, 0x100 or 0x180).
    pub(super) fn decode(word: u16, bank: u16) -> Op {
        use Inst::*;
        use Kind as K;
        let op = Op::new;
        let slow = op(K::Slow, 0, word & 0x3FFF);
        let Some(i) = Inst::decode(word) else {
            return op(K::Invalid, 0, word & 0x3FFF);
        };
        let addr = |f: u16| usize::from(bank | (f & 0x7F));
        let rd = |f: u16| Some(RMAP[addr(f)]).filter(|&m| m < SPECIAL);
        let wr = |f: u16| Some(WMAP[addr(f)]).filter(|&m| m < SPECIAL);
        let rmw = |f: u16| rd(f).filter(|&m| wr(f) == Some(m));
        let read = |kind, f, b| rd(f).map_or(slow, |m| op(kind, b, m));
        let modify = |kind, f, b| rmw(f).map_or(slow, |m| op(kind, b, m));
        let bo = |f, d, kw, kf| {
            if d == Dest::W {
                read(kw, f, 0)
            } else {
                modify(kf, f, 0)
            }
        };
        let indf = |f: u16, map: &[u16; RAM_SIZE]| map[addr(f)] == SPECIAL + INDF;
        let status = |f: u16| f & 0x7F == STATUS;
        match i {
            Addwf(f, d) => bo(f, d, K::AddwfW, K::AddwfF),
            Andwf(f, d) => bo(f, d, K::AndwfW, K::AndwfF),
            Clrf(f) => wr(f).map_or(slow, |m| op(K::Clrf, 0, m)),
            Clrw => op(K::Clrw, 0, 0),
            Comf(f, d) => bo(f, d, K::ComfW, K::ComfF),
            Decf(f, d) => bo(f, d, K::DecfW, K::DecfF),
            Decfsz(f, d) => bo(f, d, K::DecfszW, K::DecfszF),
            Incf(f, d) => bo(f, d, K::IncfW, K::IncfF),
            Incfsz(f, d) => bo(f, d, K::IncfszW, K::IncfszF),
            Iorwf(f, d) => bo(f, d, K::IorwfW, K::IorwfF),
            Movf(f, Dest::W) if indf(f, &RMAP) => op(K::MovfWIndf, 0, 0),
            Movf(f, d) => bo(f, d, K::MovfW, K::MovfF),
            Movwf(f) if indf(f, &WMAP) => op(K::MovwfIndf, 0, 0),
            Movwf(f) => wr(f).map_or(slow, |m| op(K::Movwf, 0, m)),
            Nop => op(K::Nop, 0, 0),
            Rlf(f, d) => bo(f, d, K::RlfW, K::RlfF),
            Rrf(f, d) => bo(f, d, K::RrfW, K::RrfF),
            Subwf(f, d) => bo(f, d, K::SubwfW, K::SubwfF),
            Swapf(f, d) => bo(f, d, K::SwapfW, K::SwapfF),
            Xorwf(f, d) => bo(f, d, K::XorwfW, K::XorwfF),
            Bcf(f, b) | Bsf(f, b) | Btfsc(f, b) | Btfss(f, b) if status(f) => {
                let mask = 1u8 << (b & 7);
                let z = mask == Z;
                match (i, z) {
                    (Bcf(..), true) => op(K::BcfZ, 0, 0),
                    (Bsf(..), true) => op(K::BsfZ, 0, 0),
                    (Btfsc(..), true) => op(K::BtfscZ, 0, 0),
                    (Btfss(..), true) => op(K::BtfssZ, 0, 0),
                    (Bcf(..), _) => op(K::BcfStatus, mask & 0xE7, 0),
                    (Bsf(..), _) => op(K::BsfStatus, mask & 0xE7, 0),
                    (Btfsc(..), _) => op(K::BtfscStatus, mask, 0),
                    _ => op(K::BtfssStatus, mask, 0),
                }
            }
            Bcf(f, b) => modify(K::Bcf, f, 1 << (b & 7)),
            Bsf(f, b) => modify(K::Bsf, f, 1 << (b & 7)),
            Btfsc(f, b) => read(K::Btfsc, f, 1 << (b & 7)),
            Btfss(f, b) => read(K::Btfss, f, 1 << (b & 7)),
            Addlw(k) => op(K::Addlw, k, 0),
            Andlw(k) => op(K::Andlw, k, 0),
            Call(k) => op(K::Call, 0, k & 0x7FF),
            Clrwdt => op(K::Clrwdt, 0, 0),
            Goto(k) => op(K::Goto, 0, k & 0x7FF),
            Iorlw(k) => op(K::Iorlw, k, 0),
            Movlw(k) => op(K::Movlw, k, 0),
            Retfie => op(K::Retfie, 0, 0),
            Retlw(k) => op(K::Retlw, k, 0),
            Return => op(K::Return, 0, 0),
            Sleep => op(K::Sleep, 0, 0),
            Sublw(k) => op(K::Sublw, k, 0),
            Xorlw(k) => op(K::Xorlw, k, 0),
        }
    }

    pub(super) fn is_fused(self) -> bool {
        self.kind as u8 >= PAIRS[0].2 as u8
    }

    /// The op that executes `self` and then `next` (the instruction after it) in one
    /// dispatch, if there is one.
    pub(super) fn fuse(self, next: Op) -> Option<Op> {
        // the second instruction must see the bank the first one leaves
        if matches!(self.kind, Kind::BcfStatus | Kind::BsfStatus) && self.b & 0x60 != 0 {
            return None;
        }
        let &(_, _, kind) = PAIRS
            .iter()
            .find(|&&(first, second, _)| (first, second) == (self.kind, next.kind))?;
        Some(Op {
            kind,
            b: self.b,
            a: self.a,
            a2: next.a,
            b2: next.b,
        })
    }
}
