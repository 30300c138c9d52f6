//! The instruction handlers of the VM: one small function per operation and operand
//! type (generic functions, instantiated by the translator in `mod.rs`).
//!
//! A handler gets the machine state, its decoded instruction and its own index, and
//! returns the index of the next instruction or an [`Exit`].

use super::{Core, Exit, Ins, Step, EXIT};

/// Runs a handler body: its next index, or [`EXIT`] with the reason in `c.exit`.
#[inline(always)]
fn step(c: &mut Core, f: impl FnOnce(&mut Core) -> Step) -> usize {
    match f(c) {
        Ok(k) => k,
        Err(e) => {
            c.exit = e;
            EXIT
        }
    }
}

// ---------------------------------------------------------------------------------
// Values in data memory

/// A value stored little-endian in data memory.
pub(super) trait Val: Copy {
    /// Bytes it takes.
    const SIZE: usize;
    /// Reads the value at `a`, or `None` when it does not fit in `d`.
    fn load(d: &[u8], a: usize) -> Option<Self>;
    /// Writes the value at `a`; false when it does not fit in `d`.
    fn store(self, d: &mut [u8], a: usize) -> bool;
}

macro_rules! val {
    ($($t:ty = $n:literal),*) => {$(
        impl Val for $t {
            const SIZE: usize = $n;
            #[inline(always)]
            #[allow(clippy::int_plus_one)]
            fn load(d: &[u8], a: usize) -> Option<Self> {
                // One comparison (`a` is at most 2^32 - 1, so the sum does not wrap).
                if (a as u64) + $n <= d.len() as u64 {
                    // SAFETY: `a..a + $n` is inside `d`; `[u8; $n]` has alignment 1.
                    Some(<$t>::from_le_bytes(unsafe { *(d.as_ptr().add(a) as *const [u8; $n]) }))
                } else {
                    None
                }
            }
            #[inline(always)]
            #[allow(clippy::int_plus_one)]
            fn store(self, d: &mut [u8], a: usize) -> bool {
                if (a as u64) + $n <= d.len() as u64 {
                    // SAFETY: as in `load`.
                    unsafe { *(d.as_mut_ptr().add(a) as *mut [u8; $n]) = self.to_le_bytes() };
                    true
                } else {
                    false
                }
            }
        }
    )*};
}
val!(
    u8 = 1,
    i8 = 1,
    u16 = 2,
    i16 = 2,
    u32 = 4,
    i32 = 4,
    u64 = 8,
    i64 = 8,
    f32 = 4,
    f64 = 8
);

/// A numeric type with the VM's arithmetic.
pub(super) trait Num: Val + PartialOrd {
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
    fn div(self, o: Self) -> Self;
    fn rem(self, o: Self) -> Self;
    fn neg(self) -> Self;
    fn abs(self) -> Self;
}

macro_rules! int_num {
    ($($t:ty: |$x:ident| $abs:expr),*) => {$(
        impl Num for $t {
            #[inline(always)]
            fn add(self, o: Self) -> Self { self.wrapping_add(o) }
            #[inline(always)]
            fn sub(self, o: Self) -> Self { self.wrapping_sub(o) }
            #[inline(always)]
            fn mul(self, o: Self) -> Self { self.wrapping_mul(o) }
            #[inline(always)]
            fn div(self, o: Self) -> Self { if o == 0 { 0 } else { self.wrapping_div(o) } }
            #[inline(always)]
            fn rem(self, o: Self) -> Self { if o == 0 { 0 } else { self.wrapping_rem(o) } }
            #[inline(always)]
            fn neg(self) -> Self { self.wrapping_neg() }
            #[inline(always)]
            fn abs(self) -> Self { let $x = self; $abs }
        }
    )*};
}
int_num!(
    i8: |x| x.wrapping_abs(), i16: |x| x.wrapping_abs(), i32: |x| x.wrapping_abs(),
    i64: |x| x.wrapping_abs(), u8: |x| x, u16: |x| x, u32: |x| x, u64: |x| x
);

macro_rules! float_num {
    ($($t:ty),*) => {$(
        impl Num for $t {
            #[inline(always)]
            fn add(self, o: Self) -> Self { self + o }
            #[inline(always)]
            fn sub(self, o: Self) -> Self { self - o }
            #[inline(always)]
            fn mul(self, o: Self) -> Self { self * o }
            #[inline(always)]
            fn div(self, o: Self) -> Self { self / o }
            #[inline(always)]
            fn rem(self, o: Self) -> Self { self % o }
            #[inline(always)]
            fn neg(self) -> Self { -self }
            #[inline(always)]
            fn abs(self) -> Self { <$t>::abs(self) }
        }
    )*};
}
float_num!(f32, f64);

/// An unsigned integer type for the bitwise operations.
pub(super) trait Bits:
    Val
    + std::ops::BitAnd<Output = Self>
    + std::ops::BitOr<Output = Self>
    + std::ops::BitXor<Output = Self>
    + std::ops::Not<Output = Self>
{
    const ZERO: Self;
    const BITS: u32;
    fn shl(self, n: u32) -> Self;
    fn shr(self, n: u32) -> Self;
    fn rotl(self, n: u32) -> Self;
    fn rotr(self, n: u32) -> Self;
}

macro_rules! bits {
    ($($t:ty),*) => {$(
        impl Bits for $t {
            const ZERO: Self = 0;
            const BITS: u32 = <$t>::BITS;
            #[inline(always)]
            fn shl(self, n: u32) -> Self { self << n }
            #[inline(always)]
            fn shr(self, n: u32) -> Self { self >> n }
            #[inline(always)]
            fn rotl(self, n: u32) -> Self { self.rotate_left(n) }
            #[inline(always)]
            fn rotr(self, n: u32) -> Self { self.rotate_right(n) }
        }
    )*};
}
bits!(u8, u16, u32, u64);

/// An address-sized pointer value (WORD in the 16-bit mode, DWORD in the 32-bit ones).
pub(super) trait Ptr: Val {
    fn from_addr(a: u32) -> Self;
    fn addr(self) -> u32;
}

impl Ptr for u16 {
    #[inline(always)]
    fn from_addr(a: u32) -> Self {
        a as u16
    }
    #[inline(always)]
    fn addr(self) -> u32 {
        self as u32
    }
}

impl Ptr for u32 {
    #[inline(always)]
    fn from_addr(a: u32) -> Self {
        a
    }
    #[inline(always)]
    fn addr(self) -> u32 {
        self
    }
}

// ---------------------------------------------------------------------------------
// Operations as types (so that one generic handler serves every operation)

/// A binary operation on one type.
pub(super) trait Op2<T> {
    fn f(a: T, b: T) -> T;
}

/// A unary operation from `A` to `R`.
pub(super) trait Op1<A, R> {
    fn f(a: A) -> R;
}

/// A comparison.
pub(super) trait Rel {
    fn t<T: PartialOrd>(a: T, b: T) -> bool;
}

/// A shift or rotation by an INT count.
pub(super) trait Shift {
    fn f<T: Bits>(v: T, n: i16) -> T;
}

macro_rules! num_op2 {
    ($($name:ident: $m:ident),*) => {$(
        pub(super) struct $name;
        impl<T: Num> Op2<T> for $name {
            #[inline(always)]
            fn f(a: T, b: T) -> T { a.$m(b) }
        }
    )*};
}
num_op2!(Add: add, Sub: sub, Mul: mul, Div: div, Rem: rem);

macro_rules! bit_op2 {
    ($($name:ident: $op:tt),*) => {$(
        pub(super) struct $name;
        impl<T: Bits> Op2<T> for $name {
            #[inline(always)]
            fn f(a: T, b: T) -> T { a $op b }
        }
    )*};
}
bit_op2!(And: &, Or: |, Xor: ^);

pub(super) struct Max;
impl<T: Val + PartialOrd> Op2<T> for Max {
    #[inline(always)]
    fn f(a: T, b: T) -> T {
        if b > a {
            b
        } else {
            a
        }
    }
}

pub(super) struct Min;
impl<T: Val + PartialOrd> Op2<T> for Min {
    #[inline(always)]
    fn f(a: T, b: T) -> T {
        if b < a {
            b
        } else {
            a
        }
    }
}

macro_rules! rel {
    ($($name:ident: $op:tt),*) => {$(
        pub(super) struct $name;
        impl Rel for $name {
            #[inline(always)]
            fn t<T: PartialOrd>(a: T, b: T) -> bool { a $op b }
        }
    )*};
}
rel!(Gt: >, Ge: >=, Eq: ==, Le: <=, Lt: <, Ne: !=);

pub(super) struct Neg;
impl<T: Num> Op1<T, T> for Neg {
    #[inline(always)]
    fn f(a: T) -> T {
        a.neg()
    }
}

pub(super) struct Abs;
impl<T: Num> Op1<T, T> for Abs {
    #[inline(always)]
    fn f(a: T) -> T {
        a.abs()
    }
}

pub(super) struct Not;
impl<T: Bits> Op1<T, T> for Not {
    #[inline(always)]
    fn f(a: T) -> T {
        !a
    }
}

macro_rules! op1 {
    ($($name:ident { $($a:ty => $r:ty: |$x:ident| $e:expr;)+ })*) => {$(
        pub(super) struct $name;
        $(impl Op1<$a, $r> for $name {
            #[inline(always)]
            fn f($x: $a) -> $r { $e }
        })+
    )*};
}

op1! {
    NotBool { u8 => u8: |x| (x == 0) as u8; }
    Sqrt { f32 => f32: |x| x.sqrt(); f64 => f64: |x| x.sqrt(); }
    Ln { f32 => f32: |x| x.ln(); f64 => f64: |x| x.ln(); }
    Log { f32 => f32: |x| x.log10(); f64 => f64: |x| x.log10(); }
    Exp { f32 => f32: |x| x.exp(); f64 => f64: |x| x.exp(); }
    Sin { f32 => f32: |x| x.sin(); f64 => f64: |x| x.sin(); }
    Cos { f32 => f32: |x| x.cos(); f64 => f64: |x| x.cos(); }
    Tan { f32 => f32: |x| x.tan(); f64 => f64: |x| x.tan(); }
    Asin { f32 => f32: |x| x.asin(); f64 => f64: |x| x.asin(); }
    Acos { f32 => f32: |x| x.acos(); f64 => f64: |x| x.acos(); }
    Atan { f32 => f32: |x| x.atan(); f64 => f64: |x| x.atan(); }
    Trunc { f32 => i32: |x| x as i32; f64 => i64: |x| x as i64; }
    Round { f32 => i32: |x| x.round() as i32; f64 => i64: |x| x.round() as i64; }
    // CONV (group 19)
    IntToReal { i16 => f32: |x| x as f32; }
    DintToReal { i32 => f32: |x| x as f32; }
    Bits32 { u32 => u32: |x| x; }
    TimeToReal { u32 => f32: |x| x as f32; }
    RealToTime { f32 => u32: |x| x as u32; }
    BcdByteToInt { u8 => i16: |x| from_bcd(x as u32, 2) as i16; }
    BcdWordToInt { u16 => i16: |x| from_bcd(x as u32, 4) as i16; }
    IntToBcdByte { i16 => u8: |x| to_bcd(x, 2) as u8; }
    IntToBcdWord { i16 => u16: |x| to_bcd(x, 4) as u16; }
    RealToInt { f32 => i16: |x| x as i16; }
    IntToBool { i16 => u8: |x| (x as u8 != 0) as u8; }
    IntToDint { i16 => i32: |x| x as i32; }
    RealToLreal { f32 => f64: |x| x as f64; }
    LrealToReal { f64 => f32: |x| x as f32; }
    LintToLreal { i64 => f64: |x| x as f64; }
    DwordToReal { u32 => f32: |x| x as f32; }
    RealToDword { f32 => u32: |x| x as u32; }
}

/// The value of the `digits` low BCD digits of `x` (nibbles above 9 count as their
/// binary value).
fn from_bcd(x: u32, digits: u32) -> u32 {
    (0..digits)
        .rev()
        .fold(0, |acc, d| acc * 10 + (x >> (4 * d) & 0xF))
}

/// The `digits` low decimal digits of `|x|` in BCD.
fn to_bcd(x: i16, digits: u32) -> u32 {
    let mut v = x.unsigned_abs() as u32;
    let mut out = 0;
    for d in 0..digits {
        out |= (v % 10) << (4 * d);
        v /= 10;
    }
    out
}

pub(super) struct Shl;
impl Shift for Shl {
    #[inline(always)]
    fn f<T: Bits>(v: T, n: i16) -> T {
        if (0..T::BITS as i16).contains(&n) {
            v.shl(n as u32)
        } else {
            T::ZERO
        }
    }
}

pub(super) struct Shr;
impl Shift for Shr {
    #[inline(always)]
    fn f<T: Bits>(v: T, n: i16) -> T {
        if (0..T::BITS as i16).contains(&n) {
            v.shr(n as u32)
        } else {
            T::ZERO
        }
    }
}

pub(super) struct Rol;
impl Shift for Rol {
    #[inline(always)]
    fn f<T: Bits>(v: T, n: i16) -> T {
        v.rotl((n as i32).rem_euclid(T::BITS as i32) as u32)
    }
}

pub(super) struct Ror;
impl Shift for Ror {
    #[inline(always)]
    fn f<T: Bits>(v: T, n: i16) -> T {
        v.rotr((n as i32).rem_euclid(T::BITS as i32) as u32)
    }
}

// ---------------------------------------------------------------------------------
// Generic handlers. Operand fields: `a`, `b`, `c`, `d` in encoding order unless noted.

/// An instruction the C VM of the checked port might get wrong: runs [`super::ub`]'s
/// check on its operands first (`e` indexes the real handler and the opcode).
pub(super) fn checked(c: &mut Core, i: &Ins, k: usize) -> usize {
    let (h, op) = c.checked[i.e as usize];
    let Some(rules) = c.checks else {
        return h(c, i, k);
    };
    match super::ub::check(c, &rules, op, i) {
        Ok(None) => h(c, i, k),
        Ok(Some(why)) => {
            c.exit = c.fault(format!(
                "{op:04X}: undefined or misread in the C VM of this port: {why}"
            ));
            EXIT
        }
        Err(e) => {
            c.exit = e;
            EXIT
        }
    }
}

/// An integer type whose value fits an `i64` (u64 reinterpreted).
pub(super) trait Int: Val {
    fn wide(self) -> i64;
}

macro_rules! int_wide {
    ($($t:ty),*) => {$(
        impl Int for $t {
            #[inline(always)]
            fn wide(self) -> i64 { self as i64 }
        }
    )*};
}
int_wide!(i8, i16, i32, i64, u8, u16, u32, u64);

/// A checked DIV or MOD (`O`) of `T`: with a divisor other than 0 and -1, which
/// [`super::ub::check`] accepts for every type but LINT (never given here), it runs the
/// operation directly; otherwise through [`checked`].
pub(super) fn checked_div<T: Int, O: Op2<T>>(c: &mut Core, i: &Ins, k: usize) -> usize {
    let (a, b) = (c.at(i.b), c.at(i.c));
    if let (Some(x), Some(y)) = (T::load(&c.data, a), T::load(&c.data, b)) {
        let w = y.wide();
        if w != 0 && w != -1 {
            return step(c, |c| c.st(i.a, O::f(x, y)).map(|()| k + 1));
        }
    }
    checked(c, i, k)
}

/// The exact `i64` result of an ADD, SUB or MUL of operands of at most 32 bits.
pub(super) trait Wide {
    fn w(a: i64, b: i64) -> i64;
}

impl Wide for Add {
    #[inline(always)]
    fn w(a: i64, b: i64) -> i64 {
        a + b
    }
}

impl Wide for Sub {
    #[inline(always)]
    fn w(a: i64, b: i64) -> i64 {
        a - b
    }
}

impl Wide for Mul {
    #[inline(always)]
    fn w(a: i64, b: i64) -> i64 {
        a * b
    }
}

/// A checked ADD, SUB or MUL of a `T` of at most 32 bits (not LINT): a result within
/// the narrowest C type [`super::ub::check`] may compute it in (16 bits below 4 bytes,
/// else 32) cannot overflow, so the operation runs directly; otherwise through
/// [`checked`].
pub(super) fn checked_arith<T: Int, O: Op2<T> + Wide>(c: &mut Core, i: &Ins, k: usize) -> usize {
    let (a, b) = (c.at(i.b), c.at(i.c));
    if let (Some(x), Some(y)) = (T::load(&c.data, a), T::load(&c.data, b)) {
        let r = O::w(x.wide(), y.wide());
        let fits = if T::SIZE < 4 {
            r == r as i16 as i64
        } else {
            r == r as i32 as i64
        };
        if fits {
            return step(c, |c| c.st(i.a, O::f(x, y)).map(|()| k + 1));
        }
    }
    checked(c, i, k)
}

/// NOP.
pub(super) fn nop(_: &mut Core, _: &Ins, k: usize) -> usize {
    k + 1
}

/// `dst := op(x, y)`.
pub(super) fn bin<T: Val, O: Op2<T>>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let x: T = c.ld(i.b)?;
        let y: T = c.ld(i.c)?;
        c.st(i.a, O::f(x, y))?;
        Ok(k + 1)
    })
}

/// Variadic: `dst := op(op(x0, x1), …)`; `a` dst, `b` the offset of the source
/// addresses in the operand pool, `c` their number (at least 2).
pub(super) fn fold<T: Val, O: Op2<T>>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let (off, n) = (i.b as usize, i.c as usize);
        let mut acc: T = c.ld(c.pool[off])?;
        for j in off + 1..off + n {
            let y: T = c.ld(c.pool[j])?;
            acc = O::f(acc, y);
        }
        c.st(i.a, acc)?;
        Ok(k + 1)
    })
}

/// `dst := op(x)`.
pub(super) fn un<A: Val, R: Val, O: Op1<A, R>>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let x: A = c.ld(i.b)?;
        c.st(i.a, O::f(x))?;
        Ok(k + 1)
    })
}

/// `dst := op(x)` on one type.
pub(super) fn un1<T: Val, O: Op1<T, T>>(c: &mut Core, i: &Ins, k: usize) -> usize {
    un::<T, T, O>(c, i, k)
}

/// `dst := x rel y` (BOOL).
pub(super) fn rel<T: Val + PartialOrd, R: Rel>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let x: T = c.ld(i.b)?;
        let y: T = c.ld(i.c)?;
        c.st(i.a, R::t(x, y) as u8)?;
        Ok(k + 1)
    })
}

/// `dst := shift(v, n)`, n an INT.
pub(super) fn shift<T: Bits, S: Shift>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let v: T = c.ld(i.b)?;
        let n: i16 = c.ld(i.c)?;
        c.st(i.a, S::f(v, n))?;
        Ok(k + 1)
    })
}

/// EXPT with a float result: `exp(log(x) * y)` computed in double, as the C VMs do.
macro_rules! expt_f {
    ($($name:ident: $b:ty, $e:ty);*) => {$(
        pub(super) fn $name(c: &mut Core, i: &Ins, k: usize) -> usize {
            step(c, |c| {
                let x: $b = c.ld(i.b)?;
                let y: $e = c.ld(i.c)?;
                c.st(i.a, ((x as f64).ln() * y as f64).exp() as $b)?;
                Ok(k + 1)
            })
        }
    )*};
}
expt_f!(expt_rs: f32, i8; expt_ri: f32, i16; expt_rd: f32, i32; expt_rr: f32, f32;
        expt_ll: f64, f64);

/// EXPT with an integer base and a SINT exponent, written as a DINT: the C VMs'
/// square-and-multiply, with the running square held in the base's own type.
macro_rules! expt_i {
    ($($name:ident: $t:ty);*) => {$(
        pub(super) fn $name(c: &mut Core, i: &Ins, k: usize) -> usize {
            step(c, |c| {
                let mut b: $t = c.ld(i.b)?;
                let mut e: i8 = c.ld(i.c)?;
                let mut r: i32 = 1;
                while e > 0 {
                    if e & 1 != 0 {
                        r = r.wrapping_mul(b as i32);
                    }
                    e >>= 1;
                    b = b.wrapping_mul(b);
                }
                c.st(i.a, r)?;
                Ok(k + 1)
            })
        }
    )*};
}
expt_i!(expt_ss: i8; expt_is: i16; expt_ds: i32);

/// `SEL dst, g, in0, in1`.
pub(super) fn sel<T: Val>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let g: u8 = c.ld(i.b)?;
        let v: T = c.ld(if g != 0 { i.d } else { i.c })?;
        c.st(i.a, v)?;
        Ok(k + 1)
    })
}

/// `LIMIT dst, mn, in, mx` = MIN(MAX(in, mn), mx).
pub(super) fn limit<T: Val + PartialOrd>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let mn: T = c.ld(i.b)?;
        let x: T = c.ld(i.c)?;
        let mx: T = c.ld(i.d)?;
        let v = if x < mn { mn } else { x };
        c.st(i.a, if v > mx { mx } else { v })?;
        Ok(k + 1)
    })
}

/// `MUX dst, K, in0, …`: `a` dst, `b` K, `c` the offset of the inputs in the operand
/// pool, `d` their number. K out of range leaves dst unchanged.
pub(super) fn mux<T: Val>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let sel: i16 = c.ld(i.b)?;
        if sel >= 0 && (sel as u32) < i.d {
            let v: T = c.ld(c.pool[i.c as usize + sel as usize])?;
            c.st(i.a, v)?;
        }
        Ok(k + 1)
    })
}

/// MMV, bit 7 clear: local dst, absolute src; `c` the byte count.
pub(super) fn mmv_in(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let d = c.at(i.a);
        let s = c.abs(i.b);
        c.copy(d, s, i.c as usize)?;
        Ok(k + 1)
    })
}

/// MMV, bit 7 set: absolute dst, local src.
pub(super) fn mmv_out(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let d = c.abs(i.a);
        let s = c.at(i.b);
        c.copy(d, s, i.c as usize)?;
        Ok(k + 1)
    })
}

// ---------------------------------------------------------------------------------
// SYSCTRL

/// JMP.
pub(super) fn jmp(_: &mut Core, i: &Ins, _: usize) -> usize {
    i.a as usize
}

/// JNZ cond, label.
pub(super) fn jnz(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let v: u8 = c.ld(i.a)?;
        Ok(if v != 0 { i.b as usize } else { k + 1 })
    })
}

/// JZ cond, label.
pub(super) fn jz(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let v: u8 = c.ld(i.a)?;
        Ok(if v == 0 { i.b as usize } else { k + 1 })
    })
}

/// CALF / CALB area, code: DPTR += area.
pub(super) fn call(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        c.push(k + 1)?;
        c.dptr = c.dptr.wrapping_add(i.a) & c.mask;
        Ok(i.b as usize)
    })
}

/// RETURN / RETFB.
pub(super) fn ret(c: &mut Core, _: &Ins, _: usize) -> usize {
    step(c, |c| c.pop())
}

/// TRML label.
pub(super) fn trml(c: &mut Core, i: &Ins, _: usize) -> usize {
    step(c, |c| {
        c.trml = i.a as usize;
        Err(Exit::Trml)
    })
}

/// MCD / MCD4A: `a` dst, `b` the offset of the bytes in the byte pool, `c` their number.
pub(super) fn mcd(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let d = c.at(i.a);
        let n = i.c as usize;
        let r = c.range(d, n)?;
        let off = i.b as usize;
        c.data[r].copy_from_slice(&c.bytes[off..off + n]);
        Ok(k + 1)
    })
}

/// MEMCP / MEMCP4A of 1, 2, 4 or 8 bytes: a load, then a store (memmove semantics).
pub(super) fn mov<T: Val>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let v: T = c.ld(i.b)?;
        c.st(i.a, v)?;
        Ok(k + 1)
    })
}

/// MCD / MCD4A of 1, 2, 4 or 8 bytes: the value is `b` (low half) and `c` (high half).
pub(super) fn imm<T: Val>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let b = (i.c as u64) << 32 | i.b as u64;
        let v = T::load(&b.to_le_bytes(), 0).ok_or(Exit::Fault)?;
        c.st(i.a, v)?;
        Ok(k + 1)
    })
}

/// MEMCP / MEMCP4A dst, src, count (memmove).
pub(super) fn memcp(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let d = c.at(i.a);
        let s = c.at(i.b);
        c.copy(d, s, i.c as usize)?;
        Ok(k + 1)
    })
}

/// FPAT / FPAT4A dst, byte, count (memset).
pub(super) fn fpat(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let d = c.at(i.a);
        let r = c.range(d, i.c as usize)?;
        c.data[r].fill(i.b as u8);
        Ok(k + 1)
    })
}

/// CUR_TIME dst.
pub(super) fn cur_time(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let t = c.clock;
        c.st(i.a, t)?;
        Ok(k + 1)
    })
}

/// TASK_CYCLE dst (TIME).
pub(super) fn task_cycle(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let t = c.cycle;
        c.st(i.a, t)?;
        Ok(k + 1)
    })
}

/// GET_STATUS_WORD1 dst.
pub(super) fn status_word(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let s = c.status;
        c.st(i.a, s)?;
        Ok(k + 1)
    })
}

/// GET_VMACH_VERSION dst.
pub(super) fn version(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        c.st(i.a, super::VMACH_VERSION)?;
        Ok(k + 1)
    })
}

/// The local address and size of element `idx` (an INT variable at `c`) of size
/// `size` (an INT variable at `d`) of the array at `b`.
fn element(c: &mut Core, i: &Ins) -> Result<(usize, usize), Exit> {
    let idx: i16 = c.ld(i.c)?;
    let size: i16 = c.ld(i.d)?;
    if size < 0 {
        return Err(c.fault(format!("negative element size {size}")));
    }
    let off = (idx as i32).wrapping_mul(size as i32) as u32;
    Ok((c.at(i.b.wrapping_add(off)), size as usize))
}

/// AURD dst, base, idx, size.
pub(super) fn aurd(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let (s, n) = element(c, i)?;
        let d = c.at(i.a);
        c.copy(d, s, n)?;
        Ok(k + 1)
    })
}

/// AUWR src, base, idx, size.
pub(super) fn auwr(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let (d, n) = element(c, i)?;
        let s = c.at(i.a);
        c.copy(d, s, n)?;
        Ok(k + 1)
    })
}

/// The direction of an array access.
pub(super) trait Access {
    /// Moves a `T` between the variable at local `var` and the element at local `elem`.
    fn f<T: Val>(c: &mut Core, var: u32, elem: u32) -> Result<(), Exit>;
}

/// AxRD: var := element.
pub(super) struct Rd;
impl Access for Rd {
    #[inline(always)]
    fn f<T: Val>(c: &mut Core, var: u32, elem: u32) -> Result<(), Exit> {
        let v: T = c.ld(elem)?;
        c.st(var, v)
    }
}

/// AxWR: element := var.
pub(super) struct Wr;
impl Access for Wr {
    #[inline(always)]
    fn f<T: Val>(c: &mut Core, var: u32, elem: u32) -> Result<(), Exit> {
        let v: T = c.ld(var)?;
        c.st(elem, v)
    }
}

/// The local address of element `idx` of `T`s at `base`.
#[inline(always)]
pub(super) fn elem_addr<T: Val>(base: u32, idx: i16) -> u32 {
    base.wrapping_add((idx as i32).wrapping_mul(T::SIZE as i32) as u32)
}

/// AORD/ATRD/AFRD/AQRD var, base, idx (var := base[idx]) and AOWR/ATWR/AFWR/AQWR
/// (base[idx] := var); idx is an INT variable.
pub(super) fn acc<T: Val, A: Access>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let idx: i16 = c.ld(i.c)?;
        A::f::<T>(c, i.a, elem_addr::<T>(i.b, idx))?;
        Ok(k + 1)
    })
}

/// AORD var, base, idx followed by `JZ` (`Z`) or `JNZ` (not `Z`) on `var`: `a`, `b`,
/// `c` as the AORD, `d` the jump's target. Only the AORD can fault.
pub(super) fn acc_j<const Z: bool>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let idx: i16 = c.ld(i.c)?;
        let v: u8 = c.ld(elem_addr::<u8>(i.b, idx))?;
        c.st(i.a, v)?;
        c.extra += 1;
        Ok(if (v == 0) == Z { i.d as usize } else { k + 2 })
    })
}

/// CEAC idx, low, span: idx -= low; outside 0..=span sets ARRAYBOUND and stops the
/// VM, as every CPDev runtime but iOS's does (`VMP_Debug(6)`).
pub(super) fn ceac(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let idx: i16 = c.ld(i.a)?;
        let low: i16 = c.ld(i.b)?;
        let span: i16 = c.ld(i.c)?;
        let v = idx.wrapping_sub(low);
        c.st(i.a, v)?;
        if v < 0 || v > span {
            return Err(c.ceac_stop(idx));
        }
        Ok(k + 1)
    })
}

// ---------------------------------------------------------------------------------
// POINTERS

/// DPSTO dst.
pub(super) fn dpsto<P: Ptr>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let p = P::from_addr(c.dptr);
        c.st(i.a, p)?;
        Ok(k + 1)
    })
}

/// DPRDL dst, ptr, count: local dst := count bytes at the absolute address in ptr.
pub(super) fn dprdl<P: Ptr>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let p: P = c.ld(i.b)?;
        let s = c.abs(p.addr());
        let d = c.at(i.a);
        c.copy(d, s, i.c as usize)?;
        Ok(k + 1)
    })
}

/// DPWRL src, ptr, count: count bytes at the absolute address in ptr := local src.
pub(super) fn dpwrl<P: Ptr>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let p: P = c.ld(i.b)?;
        let d = c.abs(p.addr());
        let s = c.at(i.a);
        c.copy(d, s, i.c as usize)?;
        Ok(k + 1)
    })
}

/// CALBR ptr, code: call with DPTR := the absolute address in ptr.
pub(super) fn calbr<P: Ptr>(c: &mut Core, i: &Ins, k: usize) -> usize {
    step(c, |c| {
        let p: P = c.ld(i.a)?;
        c.push(k + 1)?;
        c.dptr = p.addr() & c.mask;
        Ok(i.b as usize)
    })
}

// ---------------------------------------------------------------------------------
// Pseudo-instructions of the translator

/// Bytes that do not decode (or a PC outside the code): `a` indexes the message.
pub(super) fn invalid(c: &mut Core, i: &Ins, _: usize) -> usize {
    step(c, |c| {
        let m = c.msgs[i.a as usize].clone();
        Err(c.fault(m))
    })
}

/// A breakpoint patched in by `run(stop_at)`.
pub(super) fn stop(c: &mut Core, _: &Ins, _: usize) -> usize {
    c.exit = Exit::Stop;
    EXIT
}

/// A fall-through to an instruction laid out elsewhere (overlapping instructions);
/// not counted as executed.
pub(super) fn goto(c: &mut Core, i: &Ins, _: usize) -> usize {
    c.extra = c.extra.wrapping_sub(1);
    i.a as usize
}

// ---------------------------------------------------------------------------------
// Superinstructions: one handler runs a sequence of consecutive entries exactly as
// their own handlers would (same loads and stores in the same order), counts them in
// `Core::extra`, and on a fault names the faulting one through `Core::skip`.

/// The end of a superinstruction that stands for `count` entries beyond its first:
/// on success they are counted; on a fault, only the `done` entries before the
/// faulting one are, and `Core::skip` names it.
fn fused_end(c: &mut Core, r: Step, done: u64, count: u64) -> usize {
    match r {
        Ok(next) => {
            c.extra += count;
            next
        }
        Err(e) => {
            c.extra += done;
            c.skip = done as usize;
            c.exit = e;
            EXIT
        }
    }
}

/// A comparison followed by `JZ` (`Z`) or `JNZ` (not `Z`) on its result: `a` dst (=
/// the jump's cond), `b` x, `c` y (as the comparison), `d` the jump's target.
pub(super) fn rel_j<T: Val + PartialOrd, R: Rel, const Z: bool>(
    c: &mut Core,
    i: &Ins,
    k: usize,
) -> usize {
    step(c, |c| {
        let x: T = c.ld(i.b)?;
        let y: T = c.ld(i.c)?;
        let r = R::t(x, y);
        c.st(i.a, r as u8)?;
        c.extra += 1;
        Ok(if r != Z { i.d as usize } else { k + 2 })
    })
}

/// A binary operation followed by `JMP`: `a`, `b`, `c` as the operation, `d` the
/// jump's target.
pub(super) fn bin_jmp<T: Val, O: Op2<T>>(c: &mut Core, i: &Ins, _: usize) -> usize {
    step(c, |c| {
        let x: T = c.ld(i.b)?;
        let y: T = c.ld(i.c)?;
        c.st(i.a, O::f(x, y))?;
        c.extra += 1;
        Ok(i.d as usize)
    })
}

/// `SEL` followed by `JZ`: `a`..`d` as the SEL, `e` JZ's cond, `g` its target.
pub(super) fn sel_jz<T: Val>(c: &mut Core, i: &Ins, k: usize) -> usize {
    let mut done = 0;
    let r = (|| -> Step {
        let g: u8 = c.ld(i.b)?;
        let v: T = c.ld(if g != 0 { i.d } else { i.c })?;
        c.st(i.a, v)?;
        done = 1;
        let z: u8 = c.ld(i.e)?;
        Ok(if z == 0 { i.g as usize } else { k + 2 })
    })();
    fused_end(c, r, done, 1)
}

/// The array-access sequence `MEMCP lac, idx, #2; CEAC lac, low, span; AxRD/AxWR var,
/// base, lac`, and with `J` followed by `JMP`: `a` lac, `b` idx (as the MEMCP, whose
/// handler ignores `c`), `c` low, `d` span, `e` var, `g` base, `h` the JMP's target.
pub(super) fn arr<T: Val, A: Access, const J: bool>(c: &mut Core, i: &Ins, k: usize) -> usize {
    // Fast path: the MEMCP and the CEAC with every operand inside data memory, through
    // one view of it (the same loads and stores in the same order).
    let (lac, idx, low, span) = (c.at(i.a), c.at(i.b), c.at(i.c), c.at(i.d));
    let len = c.data.len();
    if lac.max(idx).max(low).max(span) < len.saturating_sub(1) {
        let d = &mut c.data[..];
        let rd = |d: &[u8], a: usize| i16::from_le_bytes([d[a], d[a + 1]]);
        let v = rd(d, idx);
        d[lac..lac + 2].copy_from_slice(&v.to_le_bytes());
        let (lo, sp) = (rd(d, low), rd(d, span));
        let x = v.wrapping_sub(lo);
        d[lac..lac + 2].copy_from_slice(&x.to_le_bytes());
        if x < 0 || x > sp {
            let e = c.ceac_stop(v);
            return fused_end(c, Err(e), 1, 0);
        }
        let r = A::f::<T>(c, i.e, elem_addr::<T>(i.g, x))
            .map(|()| if J { i.h as usize } else { k + 3 });
        return fused_end(c, r, 2, if J { 3 } else { 2 });
    }
    let mut done = 0;
    let r = (|| -> Step {
        // MEMCP lac, idx, #2
        let v: i16 = c.ld(i.b)?;
        c.st(i.a, v)?;
        done = 1;
        // CEAC lac, low, span (lac reads back v)
        let low: i16 = c.ld(i.c)?;
        let span: i16 = c.ld(i.d)?;
        let x = v.wrapping_sub(low);
        c.st(i.a, x)?;
        if x < 0 || x > span {
            return Err(c.ceac_stop(v));
        }
        done = 2;
        // AxRD / AxWR var, base, lac (lac reads back x)
        A::f::<T>(c, i.e, elem_addr::<T>(i.g, x))?;
        Ok(if J { i.h as usize } else { k + 3 })
    })();
    fused_end(c, r, done, if J { 3 } else { 2 })
}

/// A comparison, a SEL on its result and JZ on it: `a` the comparison's dst (= SEL's
/// selector = JZ's cond), `b` x, `c` y, `d` SEL's dst, `e` in0, `g` in1, `h` JZ's target.
pub(super) fn rel_sel_jz<T: Val + PartialOrd, R: Rel, S: Val>(
    c: &mut Core,
    i: &Ins,
    k: usize,
) -> usize {
    let mut done = 0;
    let r = (|| -> Step {
        let x: T = c.ld(i.b)?;
        let y: T = c.ld(i.c)?;
        let r = R::t(x, y);
        c.st(i.a, r as u8)?;
        done = 1;
        // SEL d, a, e, g (a reads back r)
        let v: S = c.ld(if r { i.g } else { i.e })?;
        c.st(i.d, v)?;
        done = 2;
        // JZ a, h (SEL's dst may overlap a: read it again)
        let z: u8 = c.ld(i.a)?;
        Ok(if z == 0 { i.h as usize } else { k + 3 })
    })();
    fused_end(c, r, done, 2)
}
