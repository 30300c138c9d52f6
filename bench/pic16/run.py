#!/usr/bin/python3
"""plcc's PIC16F876A code beside SDCC's on the same logic.

For every pair NAME.st / NAME.c in this directory:
  * plcc --target pic16f876a NAME.st -> NAME.asm, run in gpsim through pic16-run
    (--break plc_scan_end --hits N --measure plc_scan): code words (whole image) and
    cycles of one scan (median of the plc_scan -> plc_scan intervals);
  * SDCC (through pic16-run) on NAME.c (--break scan --hits N+1 --measure scan, i.e.
    call to call of scan() in main's loop): the same figures;
  * the values of every variable of the ST program after the same N scans, on the PIC
    from both compilers, and on the host from `plcc run --scans N` and gcc NAME.c
    -DNSCANS=N. Any difference is reported loudly (and the exit status is 1).
Then a Markdown table with the ratios plcc/SDCC and their geometric means, a row for
the hand-written /work/shared/tools/samples/banks.asm, the body-only sizes, and the
static share of bank selects in the code.

Then, with plcc's simulator (the `sim_hex_speed` example of backends/pic16, built in
release mode): the share of *executed* instructions that are bank selects in plcc's
code (every instruction of the first 2M cycles, stepped one by one), and simulated
cycles per second of plcc's simulator and of gpsim on the same HEX (100M cycles each,
run free; gpsim's time is pic16-run's wall_s, which excludes building).

Usage: bench/pic16/run.py [--plcc PATH] [--only NAME[,NAME...]] [--scans N] [--keep DIR]
                          [--ram-fill BYTE] [--no-host] [-j JOBS] [--no-sim]
Stdlib only. Takes a few seconds.
"""
import argparse
import concurrent.futures
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
PIC16_RUN = "/work/shared/tools/pic16-run"
HAND_ASM = "/work/shared/tools/samples/banks.asm"

# IEC type -> (bytes, signed); BOOL is a bit in plcc's layout and a uint8_t in C.
TYPES = {
    "SINT": (1, True), "USINT": (1, False), "BYTE": (1, False), "CHAR": (1, False),
    "INT": (2, True), "UINT": (2, False), "WORD": (2, False),
    "DINT": (4, True), "UDINT": (4, False), "DWORD": (4, False),
    "BOOL": (1, False),
}

# bcf/bsf STATUS,RP0 / STATUS,RP1 as 14-bit words
BANK_SELECT_WORDS = {0x1283, 0x1683, 0x1303, 0x1703}


class BenchError(Exception):
    pass


def run(cmd, cwd=None, timeout=60, check=True):
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True, timeout=timeout)
    if check and p.returncode != 0:
        raise BenchError("%s failed (exit %d):\n%s%s" % (" ".join(cmd), p.returncode,
                                                          p.stdout[-3000:], p.stderr[-3000:]))
    return p


def pic16_run(args, allowed=(0,)):
    p = run([PIC16_RUN] + args + ["--json", "-q"], check=False)
    if p.returncode not in allowed:
        raise BenchError("pic16-run %s: exit %d\n%s%s" % (" ".join(args), p.returncode,
                                                          p.stdout[-3000:], p.stderr[-3000:]))
    try:
        return json.loads(p.stdout)
    except ValueError:
        raise BenchError("pic16-run %s: no JSON:\n%s%s" % (" ".join(args), p.stdout[-2000:],
                                                           p.stderr[-2000:]))


def parse_listing_vars(asm_text):
    """The variables of program `main` from plcc's EQU lines:
    `main_x EQU 0x2D ; main.x : BOOL (bit 3)`, `main_a_0 EQU 0x2E ; main.a[0] : INT`.
    Returns [(iec_name, asm_symbol, type, bit or None)]."""
    out = []
    rx = re.compile(r"^(\w+)\s+EQU\s+(0x[0-9A-Fa-f]+)\s*;\s*main\.(\S+)\s*:\s*(\w+)"
                    r"(?:\s*\(bit\s+(\d+)\))?")
    for line in asm_text.splitlines():
        m = rx.match(line)
        if m:
            sym, _addr, name, ty, bit = m.groups()
            out.append((name, sym, ty.upper(), int(bit) if bit is not None else None))
    return out


def parse_plc_values(text):
    """`name = value` lines of `plcc run` (and of the C programs on the host)."""
    vals = {}
    for line in text.splitlines():
        if " = " not in line:
            continue
        name, val = line.split(" = ", 1)
        name, val = name.strip().lower(), val.strip()
        if val == "TRUE":
            v = 1
        elif val == "FALSE":
            v = 0
        else:
            m = re.fullmatch(r"(?:[A-Za-z_]+#)?(-?)(16#|8#|2#)?([0-9A-Fa-f_]+)", val)
            if not m:
                vals[name] = val
                continue
            sign, base, digits = m.groups()
            b = {"16#": 16, "8#": 8, "2#": 2}.get(base, 10)
            v = int(digits.replace("_", ""), b) * (-1 if sign else 1)
        vals[name] = v
    return vals


def to_signed(v, size):
    bits = 8 * size
    v &= (1 << bits) - 1
    return v - (1 << bits) if v >> (bits - 1) else v


def hex_words(path):
    """Program words (below 0x2000) of an Intel HEX file."""
    mem = {}
    upper = 0
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line.startswith(":"):
                continue
            data = bytes.fromhex(line[1:])
            n, addr, typ = data[0], (data[1] << 8) | data[2], data[3]
            if typ == 4:
                upper = (data[4] << 8) | data[5]
            elif typ == 0:
                base = (upper << 16) | addr
                for k in range(n):
                    mem[base + k] = data[4 + k]
    words = {}
    for a in mem:
        if a % 2 == 0 and a // 2 < 0x2000:
            words[a // 2] = mem[a] | (mem.get(a + 1, 0) << 8)
    return words


PIC14_OPS = set("""addwf andwf clrf clrw comf decf decfsz incf incfsz iorwf movf movwf nop
rlf rrf subwf swapf xorwf bcf bsf btfsc btfss addlw andlw call clrwdt goto iorlw movlw
retfie retlw return sleep sublw xorlw""".split())


def plcc_sections(asm_text):
    """Instruction counts and bank selects per `; ---- TITLE ----` section of plcc's .asm."""
    secs = {}
    cur = "header"
    for line in asm_text.splitlines():
        m = re.match(r"^; ---- (.*?) ----", line)
        if m:
            cur = m.group(1)
            continue
        if not line[:1].isspace():
            continue
        parts = line.split(";", 1)[0].split()
        if not parts or parts[0].lower() not in PIC14_OPS:
            continue
        s = secs.setdefault(cur, [0, 0])
        s[0] += 1
        if parts[0].lower() in ("bcf", "bsf") and len(parts) > 1 and \
                re.fullmatch(r"STATUS,\s*(RP0|RP1|5|6)", parts[1].replace(" ", ""), re.I):
            s[1] += 1
    return secs


def sdcc_scan_words(map_path, name):
    """Size of SDCC's scan() code section from the gplink map."""
    rx = re.compile(r"^\s*S_\w*__scan\s+code\s+0x[0-9a-f]+\s+program\s+(0x[0-9a-f]+)", re.I)
    with open(map_path) as f:
        for line in f:
            m = rx.match(line)
            if m:
                return int(m.group(1), 16) // 2
    return None


def median(xs):
    return statistics.median(xs) if xs else float("nan")


def bench_one(name, opts, work):
    st = os.path.join(HERE, name + ".st")
    c = os.path.join(HERE, name + ".c")
    n = opts.scans
    wdir = os.path.join(work, name)
    os.makedirs(wdir, exist_ok=True)
    res = {"name": name, "problems": []}

    # ---- plcc -> PIC
    asm = os.path.join(wdir, name + ".asm")
    run([opts.plcc, "--target", "pic16f876a", st, "-o", asm])
    with open(asm) as f:
        asm_text = f.read()
    variables = parse_listing_vars(asm_text)
    if not variables:
        raise BenchError("%s: no `main.` variables in the EQU lines of %s" % (name, asm))
    st_specs, c_specs = [], []
    for iec, sym, ty, bit in variables:
        if ty not in TYPES:
            res["problems"].append("variable %s : %s not compared (type)" % (iec, ty))
            continue
        size, signed = TYPES[ty]
        suffix = ":%d%s" % (size, "s" if signed else "")
        st_specs.append(sym + suffix)
        m = re.fullmatch(r"(\w+)\[(\d+)\]", iec)
        if m:
            c_specs.append("%s+%d%s" % (m.group(1), int(m.group(2)) * size, suffix))
        else:
            c_specs.append(iec + suffix)
    keep_st = os.path.join(wdir, "st")
    fill = ["--ram-fill", opts.ram_fill] if opts.ram_fill else []
    js = pic16_run([asm, "--break", "plc_scan_end", "--hits", str(n), "--measure", "plc_scan",
                    "--keep", keep_st] + fill + ["--ram"] + st_specs)
    if js["status"] != "break":
        raise BenchError("%s (plcc): status %s" % (name, js["status"]))
    st_int = js["measures"].get("plc_scan->plc_scan", [])
    res["plcc_words"] = js["code_words"]
    res["plcc_all"] = st_int
    st_pic = {}
    for (iec, sym, ty, bit), spec in zip([v for v in variables if v[2] in TYPES], st_specs):
        v = js["values"][spec.split(":")[0]]
        if bit is not None:
            v = (v >> bit) & 1
        elif TYPES[ty][1]:
            v = to_signed(v, TYPES[ty][0])
        st_pic[iec.lower()] = v
    secs = plcc_sections(asm_text)
    res["plcc_body"] = secs.get("program `main`", [0, 0])[0]
    res["plcc_body_bs"] = secs.get("program `main`", [0, 0])[1]
    res["plcc_helpers"] = sum(v[0] for k, v in secs.items()
                              if not re.match(r"(header|reset|interrupt|cold start|program |init )", k))
    words = hex_words(os.path.join(keep_st, name + ".hex"))
    res["plcc_bs"] = sum(1 for w in words.values() if w in BANK_SELECT_WORDS)
    res["plcc_hexwords"] = len(words)

    # ---- SDCC -> PIC
    keep_c = os.path.join(wdir, "c")
    jc = pic16_run([c, "--break", "scan", "--hits", str(n + 1), "--measure", "scan",
                    "--keep", keep_c, "--ram"] + c_specs)
    if jc["status"] != "break":
        raise BenchError("%s (SDCC): status %s" % (name, jc["status"]))
    c_int = jc["measures"].get("scan->scan", [])
    res["sdcc_words"] = jc["code_words"]
    res["sdcc_all"] = c_int
    c_pic = {}
    for (iec, sym, ty, bit), spec in zip([v for v in variables if v[2] in TYPES], c_specs):
        v = jc["values"][spec.split(":")[0]]
        if ty == "BOOL":
            v = 1 if v else 0
        elif TYPES[ty][1]:
            v = to_signed(v, TYPES[ty][0])
        c_pic[iec.lower()] = v
    res["sdcc_body"] = sdcc_scan_words(os.path.join(keep_c, name + ".map"), name)
    cwords = hex_words(os.path.join(keep_c, name + ".hex"))
    res["sdcc_bs"] = sum(1 for w in cwords.values() if w in BANK_SELECT_WORDS)
    res["sdcc_hexwords"] = len(cwords)

    # The same scans on both sides: plcc's intervals are scans 1..N-1 (the break is at the
    # end of scan N), SDCC's are scans 1..N; compare scans 1..N-1.
    k = min(len(st_int), len(c_int))
    res["plcc_cycles"] = median(st_int[:k])
    res["sdcc_cycles"] = median(c_int[:k])

    # ---- host references
    host = {}
    if not opts.no_host:
        p = run([opts.plcc, "run", st, "--scans", str(n)])
        host["plcc run"] = parse_plc_values(p.stdout)
        if shutil.which("gcc"):
            exe = os.path.join(wdir, name + ".host")
            run(["gcc", "-O1", "-DNSCANS=%d" % n, "-o", exe, c])
            host["gcc"] = parse_plc_values(run([exe]).stdout)

    # ---- compare
    sources = [("plcc/PIC", st_pic), ("SDCC/PIC", c_pic)] + list(host.items())
    mism = []
    for iec in st_pic:
        vals = [(src, d.get(iec, "<missing>")) for src, d in sources]
        if len(set(str(v) for _, v in vals)) > 1:
            mism.append("%s: %s" % (iec, ", ".join("%s=%s" % sv for sv in vals)))
    res["mismatches"] = mism
    res["values"] = st_pic
    return res


def fmt_ratio(r):
    return "%.2f" % r if r == r else "n/a"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--plcc", default=os.path.join(ROOT, "target", "release", "plcc"))
    ap.add_argument("--only", help="NAME or NAME,NAME,... (default: every NAME.st here)")
    ap.add_argument("--scans", type=int, default=6,
                    help="scans to run before comparing values (default 6: --hits 6)")
    ap.add_argument("--keep", help="keep the build files in this directory")
    ap.add_argument("--ram-fill", metavar="BYTE",
                    help="pre-fill the PIC's RAM with BYTE for plcc's code (catches reads of "
                         "uninitialised RAM; SDCC's side is left at gpsim's zeros)")
    ap.add_argument("--no-host", action="store_true", help="skip `plcc run` and gcc")
    ap.add_argument("-j", "--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--no-sim", action="store_true",
                    help="skip the executed bank selects and the simulator speed")
    opts = ap.parse_args()
    opts.plcc = os.path.abspath(opts.plcc)
    if opts.scans < 2:
        ap.error("--scans must be at least 2")
    if not os.access(opts.plcc, os.X_OK):
        sys.exit("run.py: no plcc at %s (cargo build --release, or --plcc PATH)" % opts.plcc)

    names = sorted(f[:-3] for f in os.listdir(HERE)
                   if f.endswith(".st") and os.path.exists(os.path.join(HERE, f[:-3] + ".c")))
    if opts.only:
        want = [w.strip() for w in opts.only.split(",") if w.strip()]
        unknown = [w for w in want if w not in names]
        if unknown:
            sys.exit("run.py: no pair %s (have: %s)" % (", ".join(unknown), ", ".join(names)))
        names = [x for x in names if x in want]

    work = opts.keep or tempfile.mkdtemp(prefix="pic16bench.")
    os.makedirs(work, exist_ok=True)
    results, errors = {}, {}
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, opts.jobs)) as ex:
            futs = {ex.submit(bench_one, nm, opts, work): nm for nm in names}
            hand = ex.submit(pic16_run, [HAND_ASM, "--break", "done", "--measure", "scan_start"])
            for fu in concurrent.futures.as_completed(futs):
                nm = futs[fu]
                try:
                    results[nm] = fu.result()
                except (BenchError, subprocess.TimeoutExpired, KeyError) as e:
                    errors[nm] = str(e)
            try:
                hj = hand.result()
                hand_words = hj["code_words"]
                hand_cycles = median(hj["measures"]["scan_start->scan_start"])
            except (BenchError, KeyError) as e:
                hand_words = hand_cycles = None
                errors["banks.asm"] = str(e)
    finally:
        if not opts.keep:
            shutil.rmtree(work, ignore_errors=True)

    n = opts.scans
    print("## plcc vs SDCC on the PIC16F876A (%d scans, gpsim through pic16-run)\n" % n)
    print("| program | plcc words | SDCC words | ratio | plcc cycles/scan | SDCC cycles/scan | ratio |")
    print("|---|---|---|---|---|---|---|")
    wr, cr = [], []
    for nm in names:
        if nm not in results:
            print("| %s | ERROR | | | | | |" % nm)
            continue
        r = results[nm]
        rw = r["plcc_words"] / r["sdcc_words"]
        rc = r["plcc_cycles"] / r["sdcc_cycles"]
        wr.append(rw)
        cr.append(rc)
        flag = " **VALUES DIFFER**" if r["mismatches"] else ""
        print("| %s%s | %d | %d | %s | %g | %g | %s |" % (
            nm, flag, r["plcc_words"], r["sdcc_words"], fmt_ratio(rw),
            r["plcc_cycles"], r["sdcc_cycles"], fmt_ratio(rc)))
    if wr:
        gw = math.exp(sum(map(math.log, wr)) / len(wr))
        gc = math.exp(sum(map(math.log, cr)) / len(cr))
        print("| **geometric mean** (%d programs) | | | **%.2f** | | | **%.2f** |" % (len(wr), gw, gc))
    if hand_words is not None and "banks" in results:
        r = results["banks"]
        print("| banks: plcc vs hand-written banks.asm (in the SDCC columns; not in the means) "
              "| %d | %d | %s | %g | %g | %s |" % (
                  r["plcc_words"], hand_words, fmt_ratio(r["plcc_words"] / hand_words),
                  r["plcc_cycles"], hand_cycles, fmt_ratio(r["plcc_cycles"] / hand_cycles)))
    elif hand_words is not None:
        print("| banks.asm (hand-written) | | %d | | | %g | |" % (hand_words, hand_cycles))
    print()
    print("Targets: words ratio <= 0.70, cycles ratio <= 0.50. Words = the whole image (below "
          "0x2000, config word excluded), runtime included on both sides (plcc: reset, 1 ms "
          "timer ISR, cold start, init; SDCC: startup/idata copy, libsdcc helpers). "
          "Cycles/scan = median over scans 1..%d of plc_scan->plc_scan (plcc: includes "
          "sampling the clock, and the timer ISR whenever it fires, about every 5000 cycles) "
          "and call-to-call of scan() in SDCC's main loop." % (n - 1))
    print()

    print("### Code of the scan alone, and bank selects (static)\n")
    print("| program | plcc program body | SDCC scan() | ratio | plcc helpers | "
          "plcc bank selects (whole image) | in program body | SDCC bank selects (whole image) "
          "| plcc cycles, all scans | SDCC cycles, all scans |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    tot = [0, 0, 0, 0]
    for nm in names:
        if nm not in results:
            continue
        r = results[nm]
        sb = r["sdcc_body"]
        tot[0] += r["plcc_bs"]
        tot[1] += r["plcc_hexwords"]
        tot[2] += r["plcc_body_bs"]
        tot[3] += r["plcc_body"]
        print("| %s | %d | %s | %s | %d | %d/%d (%.1f%%) | %d/%d (%.1f%%) | %d/%d (%.1f%%) | %s | %s |" % (
            nm, r["plcc_body"], sb if sb is not None else "?",
            fmt_ratio(r["plcc_body"] / sb) if sb else "n/a", r["plcc_helpers"],
            r["plcc_bs"], r["plcc_hexwords"], 100.0 * r["plcc_bs"] / max(1, r["plcc_hexwords"]),
            r["plcc_body_bs"], r["plcc_body"], 100.0 * r["plcc_body_bs"] / max(1, r["plcc_body"]),
            r["sdcc_bs"], r["sdcc_hexwords"], 100.0 * r["sdcc_bs"] / max(1, r["sdcc_hexwords"]),
            " ".join(map(str, r["plcc_all"])), " ".join(map(str, r["sdcc_all"]))))
    if tot[1]:
        print()
        print("Bank selects in plcc's code, counted **statically** (bcf/bsf STATUS,RP0|RP1 words "
              "in the .hex; gpsim gives no per-instruction execution counts): %d of %d words "
              "(%.1f%%) in all images, %d of %d (%.1f%%) in the program bodies." % (
                  tot[0], tot[1], 100.0 * tot[0] / tot[1], tot[2], tot[3],
                  100.0 * tot[2] / max(1, tot[3])))
    print()

    if not opts.no_sim:
        sim_section(names, opts)

    bad = 0
    for nm in names:
        if nm in results:
            r = results[nm]
            for p in r["problems"]:
                print("note: %s: %s" % (nm, p))
            if r["mismatches"]:
                bad += 1
                print("!!!! VALUE MISMATCH in %s after %d scans:" % (nm, n))
                for m in r["mismatches"]:
                    print("!!!!   " + m)
    for nm, e in errors.items():
        bad += 1
        print("!!!! ERROR in %s: %s" % (nm, e))
    if not bad:
        print("All variables equal after %d scans: plcc on the PIC, SDCC on the PIC%s." % (
            n, "" if opts.no_host else ", `plcc run` and gcc on the host"))
    return 1 if bad else 0


def sim_section(names, opts):
    """Executed bank selects (plcc's simulator, stepped) and simulator speed vs gpsim."""
    run(["cargo", "build", "--release", "-q", "-p", "plcc-pic16", "--example", "sim_hex_speed"],
        cwd=ROOT, timeout=600)
    tool = os.path.join(ROOT, "target", "release", "examples", "sim_hex_speed")
    work = tempfile.mkdtemp(prefix="pic16sim.")
    try:
        print("### Executed bank selects and simulator speed\n")
        print("| program | executed instructions | bank selects | share | plcc sim Mcycles/s "
              "| gpsim Mcycles/s | ratio |")
        print("|---|---|---|---|---|---|---|")
        tot_sel = tot_ex = 0
        ratios = []
        for nm in names:
            hexp = os.path.join(work, nm + ".hex")
            run([opts.plcc, "--target", "pic16f876a", "--emit", "hex",
                 os.path.join(HERE, nm + ".st"), "-o", hexp])
            out = run([tool, hexp, "1e8", "2e6"], timeout=300).stdout
            vals = dict(l.split(" = ", 1) for l in out.splitlines() if " = " in l)
            sel, ex = (int(x) for x in vals["bank_selects"].split(" of "))
            ours = float(vals["cycles_per_s"]) / 1e6
            asm = os.path.join(work, nm + ".asm")
            run([opts.plcc, "--target", "pic16f876a", os.path.join(HERE, nm + ".st"), "-o", asm])
            gj = pic16_run([asm, "--cycles", "1e8"])
            theirs = gj["cycles"] / gj["wall_s"] / 1e6
            tot_sel += sel
            tot_ex += ex
            ratios.append(ours / theirs)
            print("| %s | %d | %d | %.2f%% | %.0f | %.0f | %.1f |" % (
                nm, ex, sel, 100.0 * sel / max(1, ex), ours, theirs, ours / theirs))
        if ratios:
            g = math.exp(sum(map(math.log, ratios)) / len(ratios))
            print("| **all** | %d | %d | **%.2f%%** | | | **%.1f** (geometric mean) |" % (
                tot_ex, tot_sel, 100.0 * tot_sel / max(1, tot_ex), g))
        print()
        print("Targets: bank selects at most 5% of executed instructions; plcc's simulator at "
              "least 10x gpsim in simulated cycles per second.")
        print()
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
