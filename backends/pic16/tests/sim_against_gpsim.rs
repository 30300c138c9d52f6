//! The simulator against the reference tools: programs assembled by gpasm, loaded from
//! their .hex, run to a label, and compared with gpsim (through
//! `shared/tools/pic16-run`): cycles at the break, W, and every general-purpose RAM
//! byte. Skips (and passes) when gpasm/gpsim or `../shared` are missing.

use plcc_pic16::sim::{Pic16, Stop};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `shared/tools`, if the reference tools can run here.
fn tools() -> Option<PathBuf> {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    if !shared.is_dir() {
        eprintln!("skipping: {} not found", shared.display());
        return None;
    }
    for tool in ["gpasm", "gpvc", "gpsim"] {
        let ok = Command::new(tool)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success());
        if !ok {
            eprintln!("skipping: {tool} not installed");
            return None;
        }
    }
    Some(shared.join("tools"))
}

/// A scratch directory, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let d = std::env::temp_dir().join(format!("plcc-pic16-sim-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        TempDir(d)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// An assembled program: its words and symbol table.
struct Built {
    words: Vec<u16>,
    syms: HashMap<String, u16>,
}

impl Built {
    fn sym(&self, name: &str) -> u16 {
        *self
            .syms
            .get(name)
            .unwrap_or_else(|| panic!("no symbol `{name}`"))
    }
}

/// Assembles `dir/name.asm` with gpasm and reads back the .hex and `gpvc -s` symbols.
fn assemble(dir: &Path, name: &str) -> Built {
    let out = Command::new("gpasm")
        .args(["-o", &format!("{name}.hex"), &format!("{name}.asm")])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "gpasm failed on {name}.asm:\n{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let hex = std::fs::read_to_string(dir.join(format!("{name}.hex"))).unwrap();
    let words = Pic16::load_hex(&hex).unwrap();
    let out = Command::new("gpvc")
        .args(["-s", &format!("{name}.cod")])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "gpvc failed");
    let mut syms = HashMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        // "done = 5f, type = address"
        let Some((name, rest)) = line.split_once(" = ") else {
            continue;
        };
        let Some((val, _)) = rest.split_once(',') else {
            continue;
        };
        if let Ok(v) = u16::from_str_radix(val.trim(), 16) {
            syms.insert(name.trim().to_string(), v);
        }
    }
    Built { words, syms }
}

/// Runs `words` in the simulator from reset to `stop`.
fn simulate(words: &[u16], stop: u16, budget: u64) -> Pic16 {
    let mut p = Pic16::new(words);
    let r = p.run_until(&[stop], budget).unwrap();
    assert_eq!(r, Stop::Breakpoint(stop), "did not reach 0x{stop:04X}");
    p
}

#[test]
fn banks_sample_gives_the_documented_baseline() {
    let Some(tools) = tools() else { return };
    let dir = TempDir::new("banks");
    std::fs::copy(tools.join("samples/banks.asm"), dir.0.join("banks.asm")).unwrap();
    let b = assemble(&dir.0, "banks");
    let used = b.words.iter().filter(|&&w| w != 0x3FFF).count();
    assert_eq!(used, 93, "code words");
    let p = simulate(&b.words, b.sym("done"), 100_000);
    assert_eq!(p.cycles(), 1846);
    let le = |name: &str, n: u16| -> u64 {
        let a = b.sym(name);
        (0..n).map(|i| u64::from(p.read(a + i)) << (8 * i)).sum()
    };
    assert_eq!(le("scan_cnt", 1), 5);
    assert_eq!(le("cnt16_lo", 2), 259);
    assert_eq!(le("sum16_lo", 2), 465);
    assert_eq!(le("prod_lo", 2), 30000);
    assert_eq!(le("diff_lo", 2), 29535);
    assert_eq!(le("acc16_lo", 2), 0x5B04);
    assert_eq!(le("arr", 4), 2762187425);
    assert_eq!(p.max_stack_depth(), 0);

    // one scan is 367 cycles, from scan_start to scan_end 360
    let mut p = Pic16::new(&b.words);
    let (start, end) = (b.sym("scan_start"), b.sym("scan_end"));
    assert_eq!(p.run_until(&[start], 1000), Ok(Stop::Breakpoint(start)));
    assert_eq!(p.cycles(), 12);
    assert_eq!(p.run_until(&[end], 1000), Ok(Stop::Breakpoint(end)));
    assert_eq!(p.cycles(), 12 + 360);
    assert_eq!(p.run_until(&[start], 1000), Ok(Stop::Breakpoint(start)));
    assert_eq!(p.cycles(), 12 + 367);
}

// ---- our own programs, compared with gpsim byte for byte ---------------------------

const HEADER: &str = "        LIST    P=16F876A, R=DEC
        #include <p16f876a.inc>
        __CONFIG _HS_OSC & _WDT_OFF & _PWRTE_ON & _BODEN_OFF & _LVP_OFF & _CP_OFF
        ERRORLEVEL -302, -306
";

/// Flags of every arithmetic and logic instruction on edge cases (recorded as
/// STATUS, W and the file register, through FSR into banks 0, 1 and 2), then a
/// checksum of ADDWF/SUBWF/SUBLW/ADDLW/RRF results and flags over all 65536 operand
/// pairs. (`CLRF STATUS` runs with C = DC = 0: gpsim clears them, where the data sheet
/// says they are kept, which the simulator does; see its unit tests.)
const FLAGS_ASM: &str = "
        CBLOCK  0x70
        x
        savw
        a
        b
        chk_lo
        chk_hi
        ENDC

REC     MACRO
        movwf   savw
        swapf   STATUS, W
        movwf   INDF
        incf    FSR, F
        movf    savw, W
        movwf   INDF
        incf    FSR, F
        movf    x, W
        movwf   INDF
        incf    FSR, F
        ENDM

TF      MACRO   op, va, vw, d
        movlw   va
        movwf   x
        movlw   vw
        bcf     STATUS, C
        op      x, d
        REC
        ENDM

TFC     MACRO   op, va, vw, d
        movlw   va
        movwf   x
        movlw   vw
        bsf     STATUS, C
        op      x, d
        REC
        ENDM

TL      MACRO   op, vw, k
        movlw   vw
        op      k
        REC
        ENDM

TSK     MACRO   op, va, d
        movlw   va
        movwf   x
        movlw   0x11
        op      x, d
        movlw   0x22
        REC
        ENDM

        ORG     0
        goto    main
        ORG     4
        retfie

main:   bcf     STATUS, IRP
        movlw   0x20
        movwf   FSR
        TF      addwf, 0x0F, 0x01, W
        TF      addwf, 0xFF, 0x01, F
        TF      addwf, 0x80, 0x80, W
        TF      addwf, 0x12, 0x34, F
        TF      addwf, 0x08, 0x08, W
        TF      addwf, 0x00, 0x00, F
        TF      subwf, 5, 3, W
        TF      subwf, 3, 5, F
        TF      subwf, 5, 5, W
        TF      subwf, 0x10, 0x01, F
        TF      subwf, 0, 0, W
        TF      subwf, 0, 0x80, F
        TF      subwf, 0x80, 0x01, W
        TF      andwf, 0xF0, 0x0F, W
        TF      andwf, 0xF0, 0x3C, F
        TF      iorwf, 0, 0, F
        TF      iorwf, 0x50, 0x05, W
        TF      xorwf, 0xAA, 0xAA, F
        TF      xorwf, 0xAA, 0x55, W
        TF      comf, 0xFF, 0, F
        TF      comf, 0x0F, 0, W
        TF      decf, 1, 0, F
        TF      decf, 0, 0, W
        TF      incf, 0xFF, 0, F
        TF      incf, 0x7F, 0, W
        TF      movf, 0, 0x12, F

        movlw   0xA0
        movwf   FSR
        TF      movf, 0x34, 0, W
        TF      rlf, 0x80, 0, W
        TFC     rlf, 0x41, 0, F
        TF      rrf, 0x01, 0, F
        TFC     rrf, 0x82, 0, W
        TF      swapf, 0xA5, 0, F
        TF      swapf, 0x3C, 0, W
        TL      addlw, 0xFF, 1
        TL      addlw, 0x08, 8
        TL      addlw, 0x80, 0x80
        TL      sublw, 3, 5
        TL      sublw, 5, 3
        TL      sublw, 5, 5
        TL      sublw, 1, 0x10
        TL      sublw, 0, 0
        TL      sublw, 1, 0
        TL      andlw, 0xF0, 0x0F
        TL      iorlw, 0, 0
        TL      xorlw, 0xFF, 0xFF
        TF      addwf, 0x0F, 0x0F, W
        TF      addwf, 0xF8, 0x08, F
        movlw   0x55
        clrw
        REC
        movlw   0x03
        addlw   0x01
        clrf    STATUS
        REC
        movlw   0x07
        movwf   STATUS
        REC
        movlw   0x22
        addwf   STATUS, F
        REC
        bcf     STATUS, RP0
        bcf     STATUS, RP1
        clrwdt
        REC

        bsf     STATUS, IRP
        movlw   0x10
        movwf   FSR
        TSK     decfsz, 1, F
        TSK     decfsz, 2, F
        TSK     decfsz, 1, W
        TSK     decfsz, 0, W
        TSK     incfsz, 0xFF, F
        TSK     incfsz, 0xFE, F
        TSK     incfsz, 0xFF, W
        TSK     btfsc, 0x01, 0
        TSK     btfsc, 0x01, 1
        TSK     btfss, 0x80, 7
        TSK     btfss, 0x80, 6
        bcf     STATUS, IRP

        clrf    chk_lo
        clrf    chk_hi
        clrf    a
outer:  clrf    b
inner:  movf    b, W
        addwf   a, W
        call    mix
        movf    b, W
        subwf   a, W
        call    mix
        movf    b, W
        sublw   0x5A
        call    mix
        movf    a, W
        addlw   0xA7
        call    mix
        movf    b, W
        movwf   x
        rrf     x, W
        call    mix
        incfsz  b, F
        goto    inner
        incfsz  a, F
        goto    outer
done:   goto    done

mix:    movwf   savw
        swapf   STATUS, W
        andlw   0x70
        xorwf   chk_hi, F
        movf    savw, W
        addwf   chk_lo, F
        btfsc   STATUS, C
        incf    chk_hi, F
        rlf     chk_lo, F
        rlf     chk_hi, F
        btfsc   STATUS, C
        bsf     chk_lo, 0
        return
        END
";

/// Computed jumps through PCL (with PCLATH, wrapping inside a 256-word block, through
/// INDF), far CALL/GOTO into pages 1–3, reading PCL, 7 nested calls, a table loop.
const PCL_ASM: &str = "
        CBLOCK  0x20
        r_t0
        r_wrap
        r_far
        r_far2
        r_pcl
        r_pg3
        r_ind
        r_nest
        r_depth
        r_sum
        cnt
        ENDC

        ORG     0
        goto    main
        ORG     4
        retfie

table0: addwf   PCL, F
        retlw   10
        retlw   11
        retlw   12
        retlw   13

main:   clrf    PCLATH
        movlw   2
        call    table0
        movwf   r_t0
        movlw   HIGH tabw
        movwf   PCLATH
        movlw   3
        call    tabw
        movwf   r_wrap
        movlw   HIGH far1
        movwf   PCLATH
        call    far1
        movwf   r_far
        movlw   HIGH far2
        movwf   PCLATH
        goto    far2
back2:  movwf   r_far2
        movf    PCL, W
        movwf   r_pcl
        movlw   0x1F
        movwf   PCLATH
        movlw   0x40
        movwf   PCL
back3:  movwf   r_pg3
        clrf    PCLATH
        movlw   PCL
        movwf   FSR
        movlw   LOW back4
        movwf   INDF
        movlw   0xEE
        movwf   r_ind
back4:  movlw   0x44
        addwf   r_ind, F
        clrf    r_depth
        call    n1
        movwf   r_nest
        clrf    r_sum
        movlw   4
        movwf   cnt
sumlp:  decf    cnt, W
        call    table0
        addwf   r_sum, F
        decfsz  cnt, F
        goto    sumlp
done:   goto    done

n1:     incf    r_depth, F
        call    n2
        addlw   1
        return
n2:     incf    r_depth, F
        call    n3
        addlw   2
        return
n3:     incf    r_depth, F
        call    n4
        addlw   3
        return
n4:     incf    r_depth, F
        call    n5
        addlw   4
        return
n5:     incf    r_depth, F
        call    n6
        addlw   5
        return
n6:     incf    r_depth, F
        call    n7
        addlw   6
        return
n7:     incf    r_depth, F
        retlw   0x70

        ORG     0x101
        retlw   0x99
        ORG     0x1FD
tabw:   addwf   PCL, F
        retlw   1
        retlw   2

        ORG     0x800
far1:   retlw   0x55

        ORG     0x1000
far2:   movlw   0x66
        clrf    PCLATH
        goto    back2

        ORG     0x1F40
        movlw   0x77
        clrf    PCLATH
        goto    back3
        END
";

/// Indirect addressing across the four banks (FSR + IRP), direct access with RP1:RP0,
/// the common-RAM mirrors, INDF at FSR = 0, FSR pointing at itself, at STATUS and at
/// TRISB.
const INDIRECT_ASM: &str = "
        CBLOCK  0x70
        i
        v
        s_lo
        s_hi
        t1
        t2
        t3
        t4
        t5
        t6
        t7
        ENDC

        ORG     0
        goto    main
        ORG     4
        retfie

main:   movlw   1
        movwf   v
        bcf     STATUS, IRP
        movlw   0x28
        call    fill8
        movlw   0xA8
        call    fill8
        bsf     STATUS, IRP
        movlw   0x28
        call    fill8
        movlw   0xA8
        call    fill8
        clrf    s_lo
        clrf    s_hi
        bcf     STATUS, IRP
        movlw   0x28
        call    sum8
        movlw   0xA8
        call    sum8
        bsf     STATUS, IRP
        movlw   0x28
        call    sum8
        movlw   0xA8
        call    sum8
        bcf     STATUS, IRP
        bsf     STATUS, RP1
        movf    0x2A, W
        bcf     STATUS, RP1
        movwf   0x21
        bsf     STATUS, RP0
        bsf     STATUS, RP1
        movf    0x2F, W
        movwf   t1
        movlw   0x5C
        movwf   0x73
        bcf     STATUS, RP0
        bcf     STATUS, RP1
        movf    0x73, W
        movwf   t2
        clrf    FSR
        movlw   0x99
        movwf   INDF
        movf    INDF, W
        movwf   t3
        movlw   0x80
        movwf   FSR
        movf    INDF, W
        movwf   t4
        movlw   FSR
        movwf   FSR
        incf    INDF, F
        incf    INDF, F
        movf    FSR, W
        movwf   t5
        movlw   0x86
        movwf   FSR
        movlw   0x0F
        movwf   INDF
        movlw   0x83
        movwf   FSR
        movf    INDF, W
        movwf   t6
        movlw   0x78
        movwf   STATUS
        movf    0x06, W
        movwf   t7
        movlw   0xBB
        movwf   0x30
        clrf    STATUS
        movlw   0x3C
        movwf   0x30
done:   goto    done

fill8:  movwf   FSR
        movlw   8
        movwf   i
f8lp:   movf    v, W
        movwf   INDF
        movlw   3
        addwf   v, F
        incf    FSR, F
        decfsz  i, F
        goto    f8lp
        return

sum8:   movwf   FSR
        movlw   8
        movwf   i
s8lp:   movf    INDF, W
        addwf   s_lo, F
        btfsc   STATUS, C
        incf    s_hi, F
        incf    FSR, F
        decfsz  i, F
        goto    s8lp
        return
        END
";

/// Timer1 + CCP1 special event trigger interrupt (CCPR1 = 250, 1:2: a tick every 500
/// cycles) counting 40 ticks while the main loop counts iterations, sampling TMR1L in
/// the ISR; then TMR1 overflow interrupts with TMR1H reloaded in the ISR. That phase
/// runs at 1:1: with a prescaler, gpsim 0.31 moves TMR1L back after a TMR1H write
/// (it restarts the count from `now - TMR1L` cycles, ignoring the prescaler), where the
/// chip keeps TMR1L and clears the prescaler, as the simulator does.
const TICK_ASM: &str = "
        CBLOCK  0x70
        w_save
        s_save
        p_save
        ticks_lo
        ticks_hi
        loops_lo
        loops_hi
        idx
        ovf_cnt
        ENDC
samples EQU     0x20

        ORG     0
        goto    main
        ORG     4
isr:    movwf   w_save
        swapf   STATUS, W
        clrf    STATUS
        movwf   s_save
        movf    PCLATH, W
        movwf   p_save
        clrf    PCLATH
        btfss   PIR1, CCP1IF
        goto    isr_t1
        bcf     PIR1, CCP1IF
        incf    ticks_lo, F
        btfsc   STATUS, Z
        incf    ticks_hi, F
        movf    idx, W
        andlw   0x3F
        addlw   samples
        movwf   FSR
        movf    TMR1L, W
        movwf   INDF
        incf    idx, F
isr_t1: btfss   PIR1, TMR1IF
        goto    isr_out
        bcf     PIR1, TMR1IF
        movlw   0xFC
        movwf   TMR1H
        incf    ovf_cnt, F
        movf    idx, W
        andlw   0x3F
        addlw   samples
        movwf   FSR
        movf    TMR1L, W
        movwf   INDF
        incf    idx, F
isr_out:
        movf    p_save, W
        movwf   PCLATH
        swapf   s_save, W
        movwf   STATUS
        swapf   w_save, F
        swapf   w_save, W
        retfie

main:   movlw   250
        movwf   CCPR1L
        clrf    CCPR1H
        movlw   0x0B
        movwf   CCP1CON
        clrf    TMR1L
        clrf    TMR1H
        bsf     STATUS, RP0
        bsf     PIE1, CCP1IE
        bcf     STATUS, RP0
        clrf    PIR1
        movlw   0xC0
        movwf   INTCON
        movlw   0x11
        movwf   T1CON
loop:   incf    loops_lo, F
        btfsc   STATUS, Z
        incf    loops_hi, F
        movf    ticks_lo, W
        xorlw   40
        btfss   STATUS, Z
        goto    loop

        clrf    CCP1CON
        bsf     STATUS, RP0
        bcf     PIE1, CCP1IE
        bsf     PIE1, TMR1IE
        bcf     STATUS, RP0
        movlw   0x01
        movwf   T1CON
        movlw   0xFC
        movwf   TMR1H
        clrf    TMR1L
loop2:  incf    loops_lo, F
        btfsc   STATUS, Z
        incf    loops_hi, F
        nop
        movf    ovf_cnt, W
        xorlw   5
        btfss   STATUS, Z
        goto    loop2
done:   goto    done
        END
";

/// Timer0 interrupts: no prescaler with TMR0 reloaded in the ISR, then 1:8 (OPTION
/// written once, then TMR0), counting overflows and sampling TMR0.
const TIMER0_ASM: &str = "
        CBLOCK  0x70
        w_save
        s_save
        cnt
        idx
        loops
        ENDC
samples EQU     0x20

        ORG     0
        goto    main
        ORG     4
        movwf   w_save
        swapf   STATUS, W
        clrf    STATUS
        movwf   s_save
        bcf     INTCON, T0IF
        movlw   156
        addwf   TMR0, F
        incf    cnt, F
        movf    idx, W
        andlw   0x3F
        addlw   samples
        movwf   FSR
        movf    TMR0, W
        movwf   INDF
        incf    idx, F
        swapf   s_save, W
        movwf   STATUS
        swapf   w_save, F
        swapf   w_save, W
        retfie

main:   bsf     STATUS, RP0
        movlw   0x88
        movwf   OPTION_REG
        bcf     STATUS, RP0
        movlw   0xA0
        movwf   INTCON
loop:   incf    loops, F
        movf    cnt, W
        xorlw   20
        btfss   STATUS, Z
        goto    loop
        bsf     STATUS, RP0
        movlw   0x82
        movwf   OPTION_REG
        bcf     STATUS, RP0
        clrf    TMR0
loop2:  incf    loops, F
        movf    cnt, W
        xorlw   30
        btfss   STATUS, Z
        goto    loop2
done:   goto    done
        END
";

/// The general-purpose RAM ranges, as pic16-run's `--dump` wants them.
const GPR_DUMP: &str = "0x20-0x7f,0xa0-0xef,0x110-0x16f,0x190-0x1ef";
const GPR: [(u16, u16); 4] = [(0x20, 0x7F), (0xA0, 0xEF), (0x110, 0x16F), (0x190, 0x1EF)];

/// Assembles `src`, runs it to `done` in gpsim (pic16-run) and in the simulator, and
/// compares the cycle count, W and all general-purpose RAM. Returns the simulator.
fn compare_with_gpsim(tools: &Path, name: &str, src: &str, budget: u64) -> Option<Pic16> {
    let dir = TempDir::new(name);
    let asm = dir.0.join(format!("{name}.asm"));
    std::fs::write(&asm, format!("{HEADER}{src}")).unwrap();
    let b = assemble(&dir.0, name);
    let done = b.sym("done");
    let p = simulate(&b.words, done, budget);

    let out = Command::new(tools.join("pic16-run"))
        .arg(&asm)
        .args(["--break", "done", "--cycles", &budget.to_string()])
        .args(["--dump", GPR_DUMP, "--json", "-q"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        panic!(
            "pic16-run failed on {name} ({}):\n{text}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let j = Json::parse(&text).unwrap_or_else(|e| panic!("bad JSON from pic16-run ({e}):\n{text}"));
    assert_eq!(
        j.get("status").and_then(Json::as_str),
        Some("break"),
        "{name}"
    );
    let gp_cycles = j.get("cycles").and_then(Json::as_u64).unwrap();
    let gp_pc = j.get("pc").and_then(Json::as_u64).unwrap();
    let gp_w = j.get("w").and_then(Json::as_u64).unwrap();
    let ram = j.get("ram").unwrap();
    let mut diffs = Vec::new();
    for (lo, hi) in GPR {
        for a in lo..=hi {
            let key = format!("0x{a:03x}");
            let want = ram.get(&key).and_then(Json::as_u64).unwrap();
            if u64::from(p.read(a)) != want {
                diffs.push(format!("{key}: sim {:#04x}, gpsim {want:#04x}", p.read(a)));
            }
        }
    }
    assert!(
        diffs.is_empty(),
        "{name}: RAM differs from gpsim:\n{}",
        diffs.join("\n")
    );
    assert_eq!(
        (u64::from(p.pc()), u64::from(p.w())),
        (gp_pc, gp_w),
        "{name}: PC, W"
    );
    assert_eq!(p.cycles(), gp_cycles, "{name}: cycles at `done`");
    eprintln!(
        "{name}: {gp_cycles} cycles, {} RAM bytes equal to gpsim",
        368
    );
    Some(p)
}

#[test]
fn arithmetic_flags_agree_with_gpsim() {
    let Some(tools) = tools() else { return };
    let p = compare_with_gpsim(&tools, "flags", FLAGS_ASM, 20_000_000).unwrap();
    // spot checks of the recorded edge cases: (swapped STATUS, W, f) triples from 0x20
    let rec = |i: u16| {
        let a = 0x20 + 3 * i;
        (p.read(a).rotate_left(4) & 7, p.read(a + 1), p.read(a + 2))
    };
    assert_eq!(rec(0), (0b010, 0x10, 0x0F), "0x0F + 0x01: DC");
    assert_eq!(rec(1), (0b111, 0x01, 0x00), "0xFF + 0x01 -> f: C DC Z");
    assert_eq!(rec(7), (0b000, 0x05, 0xFE), "3 - 5 -> f: borrow");
    assert_eq!(rec(8), (0b111, 0x00, 0x05), "5 - 5: C DC Z");
}

#[test]
fn computed_jumps_and_paging_agree_with_gpsim() {
    let Some(tools) = tools() else { return };
    let p = compare_with_gpsim(&tools, "pcl", PCL_ASM, 100_000).unwrap();
    let got: Vec<u8> = (0x20..0x2A).map(|a| p.read(a)).collect();
    // r_t0 r_wrap r_far r_far2 r_pcl r_pg3 r_ind r_nest r_depth r_sum
    assert_eq!(&got[..4], &[12, 0x99, 0x55, 0x66]);
    assert_eq!(&got[5..], &[0x77, 0x44, 0x70 + 21, 7, 46]);
    assert_eq!(p.max_stack_depth(), 7);
}

#[test]
fn indirect_addressing_agrees_with_gpsim() {
    let Some(tools) = tools() else { return };
    let p = compare_with_gpsim(&tools, "indirect", INDIRECT_ASM, 100_000).unwrap();
    // 32 values 1, 4, 7, ...: sum = 32 + 3 * 496 = 0x5F0; s_hi (0x73) was then
    // overwritten through its mirror 0x1F3
    assert_eq!((p.read(0x72), p.read(0x73)), (0xF0, 0x5C));
    assert_eq!(p.read(0x1B0), 0xBB, "MOVWF STATUS selected bank 3");
    assert_eq!(
        p.read(0x7A),
        0x0F,
        "TRISB written through INDF, read at 0x186"
    );
    assert_eq!(p.read(0x30), 0x3C);
}

#[test]
fn timer1_ccp1_interrupts_agree_with_gpsim() {
    let Some(tools) = tools() else { return };
    let p = compare_with_gpsim(&tools, "tick", TICK_ASM, 2_000_000).unwrap();
    assert_eq!((p.read(0x73), p.read(0x78)), (40, 5), "ticks, overflows");
}

#[test]
fn timer0_interrupts_agree_with_gpsim() {
    let Some(tools) = tools() else { return };
    let p = compare_with_gpsim(&tools, "timer0", TIMER0_ASM, 2_000_000).unwrap();
    assert_eq!(p.read(0x72), 30);
}

// ---- a small JSON reader for pic16-run --json ---------------------------------------

#[derive(Debug, Clone, PartialEq)]
enum Json {
    Null,
    Bool(bool),
    Num(f64),
    Str(String),
    Arr(Vec<Json>),
    Obj(Vec<(String, Json)>),
}

impl Json {
    fn parse(text: &str) -> Result<Json, String> {
        let mut p = JsonParser {
            s: text.as_bytes(),
            i: 0,
        };
        let v = p.value()?;
        p.ws();
        if p.i != p.s.len() {
            return Err(format!("trailing characters at {}", p.i));
        }
        Ok(v)
    }

    fn get(&self, key: &str) -> Option<&Json> {
        match self {
            Json::Obj(kv) => kv.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    fn as_u64(&self) -> Option<u64> {
        match *self {
            Json::Num(n) if n >= 0.0 && n.fract() == 0.0 => Some(n as u64),
            _ => None,
        }
    }

    fn as_str(&self) -> Option<&str> {
        match self {
            Json::Str(s) => Some(s),
            _ => None,
        }
    }
}

struct JsonParser<'a> {
    s: &'a [u8],
    i: usize,
}

impl JsonParser<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }

    fn eat(&mut self, c: u8) -> Result<(), String> {
        self.ws();
        if self.s.get(self.i) == Some(&c) {
            self.i += 1;
            Ok(())
        } else {
            Err(format!("expected '{}' at {}", c as char, self.i))
        }
    }

    fn value(&mut self) -> Result<Json, String> {
        self.ws();
        match self.s.get(self.i) {
            Some(b'{') => {
                self.i += 1;
                let mut kv = Vec::new();
                self.ws();
                if self.s.get(self.i) == Some(&b'}') {
                    self.i += 1;
                    return Ok(Json::Obj(kv));
                }
                loop {
                    self.ws();
                    let k = self.string()?;
                    self.eat(b':')?;
                    kv.push((k, self.value()?));
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b'}') => {
                            self.i += 1;
                            return Ok(Json::Obj(kv));
                        }
                        _ => return Err(format!("bad object at {}", self.i)),
                    }
                }
            }
            Some(b'[') => {
                self.i += 1;
                let mut v = Vec::new();
                self.ws();
                if self.s.get(self.i) == Some(&b']') {
                    self.i += 1;
                    return Ok(Json::Arr(v));
                }
                loop {
                    v.push(self.value()?);
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b']') => {
                            self.i += 1;
                            return Ok(Json::Arr(v));
                        }
                        _ => return Err(format!("bad array at {}", self.i)),
                    }
                }
            }
            Some(b'"') => Ok(Json::Str(self.string()?)),
            Some(b't') if self.s[self.i..].starts_with(b"true") => {
                self.i += 4;
                Ok(Json::Bool(true))
            }
            Some(b'f') if self.s[self.i..].starts_with(b"false") => {
                self.i += 5;
                Ok(Json::Bool(false))
            }
            Some(b'n') if self.s[self.i..].starts_with(b"null") => {
                self.i += 4;
                Ok(Json::Null)
            }
            Some(_) => {
                let start = self.i;
                while self.i < self.s.len() && b"+-.eE0123456789".contains(&self.s[self.i]) {
                    self.i += 1;
                }
                std::str::from_utf8(&self.s[start..self.i])
                    .ok()
                    .and_then(|t| t.parse().ok())
                    .map(Json::Num)
                    .ok_or_else(|| format!("bad value at {start}"))
            }
            None => Err("unexpected end".into()),
        }
    }

    fn string(&mut self) -> Result<String, String> {
        if self.s.get(self.i) != Some(&b'"') {
            return Err(format!("expected a string at {}", self.i));
        }
        self.i += 1;
        let mut out = String::new();
        loop {
            let c = *self.s.get(self.i).ok_or("unterminated string")?;
            self.i += 1;
            match c {
                b'"' => return Ok(out),
                b'\\' => {
                    let e = *self.s.get(self.i).ok_or("bad escape")?;
                    self.i += 1;
                    match e {
                        b'n' => out.push('\n'),
                        b't' => out.push('\t'),
                        b'r' => out.push('\r'),
                        b'b' => out.push('\u{8}'),
                        b'f' => out.push('\u{c}'),
                        b'u' => {
                            let h = std::str::from_utf8(
                                self.s.get(self.i..self.i + 4).ok_or("bad \\u")?,
                            )
                            .map_err(|e| e.to_string())?;
                            let n = u32::from_str_radix(h, 16).map_err(|e| e.to_string())?;
                            out.push(char::from_u32(n).unwrap_or('\u{FFFD}'));
                            self.i += 4;
                        }
                        other => out.push(other as char),
                    }
                }
                _ => {
                    // copy a UTF-8 run
                    let start = self.i - 1;
                    while self.i < self.s.len() && self.s[self.i] != b'"' && self.s[self.i] != b'\\'
                    {
                        self.i += 1;
                    }
                    out.push_str(&String::from_utf8_lossy(&self.s[start..self.i]));
                }
            }
        }
    }
}

#[test]
fn json_reader() {
    let j = Json::parse(r#"{"a": [1, 2.5, -3], "b": {"c": "x\"y\u0041"}, "d": null, "e": true}"#)
        .unwrap();
    assert_eq!(
        j.get("b").and_then(|b| b.get("c")).and_then(Json::as_str),
        Some("x\"yA")
    );
    assert_eq!(
        j.get("a"),
        Some(&Json::Arr(vec![
            Json::Num(1.0),
            Json::Num(2.5),
            Json::Num(-3.0)
        ]))
    );
    assert_eq!(j.get("d"), Some(&Json::Null));
    assert_eq!(j.get("e"), Some(&Json::Bool(true)));
}
