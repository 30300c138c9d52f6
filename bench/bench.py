#!/usr/bin/env python3
"""plcc benchmarks: compile throughput and JIT time per scan, printed as tables.

usage: bench/bench.py [--quick] [--only compile|scan|oscat|scaling|pic16]

(a) Compile throughput on ../shared/bench/gen_synth.py output (1,000 and 2,000 POUs):
    `plcc check` (parse, check, lower to IR) and the whole path to JIT code
    (`plcc run --scans 0`: parse, check, lower, verify, optimise, Cranelift, load).
    For a program this large that is the tiered JIT's quick code (each function
    optimised, Cranelift's fast settings; the whole-program passes and the optimised
    code follow on a thread of their own, ARCHITECTURE.md, "Tiers"). "optimised" is
    the same run with `-s tier=full`: the optimised code before the first scan.
    Wall time of the whole process, median of N runs, lines/s = lines / median.
(b) Time per scan of the JIT on lcg.st, control.st and sieve.st against ref.c built
    with `gcc -O2`: `plcc run --timing` times the scan loop alone (no compilation),
    ref.c times its own loop; checksums must be equal. Both sides run interleaved, N
    sets each, and the ratio is taken per set (the machine is noisy: compare ratios).

    The same scans on plcc's CPDev VM (`--target vmasm`, the XCP image as the VM
    runs it) give the VM/JIT ratio, interleaved in the same sets.

(c) OSCAT BASIC 3.33 (../shared/corpus/libs/oscat_basic_333, the ISO-8859-1 original
    and the UTF-8 copy) in the CODESYS dialect: `plcc check` and the whole path to
    native code (`plcc --target host -o x.o`: parse, check, lower, verify, optimise,
    Cranelift, object file; the library has no PROGRAM to run and its pointers are
    unchecked, so the JIT would not run it). MB/s and lines/s of the median.

(d) Compile scaling: gen_synth programs from about 10k to 1M lines, `plcc check`, the
    path to JIT code and to the optimised code (`-s tier=full`), the better of two
    runs each (the large ones take seconds), with the peak
    resident memory of each process (wait4's ru_maxrss). Prints the table and writes
    docs/img/compile-scaling.svg (time against lines, both axes logarithmic).

(e) PIC16F876A: bench/pic16/run.py, printed as it prints it: each program of
    bench/pic16 built by plcc and by SDCC's pic14 port and run in gpsim (code words
    of the whole image, cycles per scan, every variable compared after 6 scans), then
    simulated cycles per second of plcc's simulator against gpsim on the same HEX.
    The geometric means are then set against the aims (words <= 0.45x SDCC's, the
    simulator >= 12x gpsim). Needs gputils, gpsim and SDCC's pic14 port
    (../shared/tools/install-pic16-tools.sh); skips with a notice otherwise.

Needs ../shared/bench (skips with a notice otherwise), python3, gcc, and a release
build (`cargo build --release`, done here).
"""
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared", "bench")
PLCC = os.path.join(ROOT, "target", "release", "plcc")


def run(cmd, **kw):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def wall(cmd, n):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        r = run(cmd)
        times.append(time.perf_counter() - t0)
        if r.returncode != 0:
            sys.exit(f"failed: {' '.join(cmd)}\n{r.stderr[-2000:]}")
    return statistics.median(times)


def compile_bench(tmp, reps):
    print("\n(a) compile throughput (median of %d whole-process runs)\n" % reps)
    print(f"{'program':<22} {'lines':>8} {'check s':>9} {'check lines/s':>14} {'to JIT s':>9} {'to JIT lines/s':>15}"
          f" {'optimised s':>12} {'lines/s':>9}")
    rows = []
    for n in (1000, 2000):
        src = os.path.join(tmp, f"synth{n}.st")
        with open(src, "w") as f:
            subprocess.run([sys.executable, os.path.join(SHARED, "gen_synth.py"), str(n)], stdout=f, check=True)
        lines = sum(1 for _ in open(src))
        t_check = wall([PLCC, "check", src], reps)
        t_jit = wall([PLCC, "run", src, "--scans", "0"], reps)
        t_full = wall([PLCC, "run", src, "--scans", "0", "-s", "tier=full"], reps)
        rows.append((n, lines, t_check, t_jit))
        print(f"{'gen_synth ' + str(n) + ' POUs':<22} {lines:>8} {t_check:>9.3f} {lines / t_check:>14,.0f} {t_jit:>9.3f} {lines / t_jit:>15,.0f}"
              f" {t_full:>12.3f} {lines / t_full:>9,.0f}")
    if len(rows) == 2:
        (_, l1, c1, j1), (_, l2, c2, j2) = rows
        print(f"\ngrowth from {l1} to {l2} lines ({l2 / l1:.2f}x): check {c2 / c1:.2f}x, to JIT {j2 / j1:.2f}x (linear = {l2 / l1:.2f}x)")


def oscat_bench(tmp, reps):
    lib = os.path.join(ROOT, "..", "shared", "corpus", "libs", "oscat_basic_333")
    if not os.path.isdir(lib):
        print("notice: the OSCAT library is not in ../shared; skipping (c)")
        return
    print("\n(c) OSCAT BASIC 3.33, --dialect codesys (median of %d whole-process runs)\n" % reps)
    print(f"{'file':<26} {'MB':>6} {'lines':>7} {'check s':>8} {'MB/s':>6} {'lines/s':>10} {'to code s':>10} {'MB/s':>6} {'lines/s':>10}")
    for name in ("OSCAT_BASIC_333.TXT", "OSCAT_BASIC_333.utf8.st"):
        src = os.path.join(lib, name)
        size = os.path.getsize(src) / 1e6
        with open(src, "rb") as f:
            lines = f.read().count(b"\n")
        common = ["--dialect", "codesys", "--lang", "st"]
        t_check = wall([PLCC, "check", *common, src], reps)
        t_code = wall([PLCC, *common, "--target", "host", src, "-o", os.path.join(tmp, "oscat.o")], reps)
        print(f"{name:<26} {size:>6.2f} {lines:>7} {t_check:>8.3f} {size / t_check:>6.1f} {lines / t_check:>10,.0f} "
              f"{t_code:>10.3f} {size / t_code:>6.1f} {lines / t_code:>10,.0f}")


PER_SCAN = re.compile(r"([0-9.]+) us per scan")
REF_PER_SCAN = re.compile(r"in-process: ([0-9.]+) us/scan")


def checksums_plcc(out, names):
    vals = dict(re.findall(r"^(\w+) = (\S+)$", out, re.M))
    return {k: vals.get(k) for k in names}


def checksums_ref(out):
    return dict(re.findall(r"(\w+)=(\S+)", out))


def scan_bench(tmp, sets):
    print(f"\n(b) JIT time per scan vs C (gcc -O2) and the VM, {sets} interleaved sets, median\n")
    ref = os.path.join(tmp, "ref")
    r = run(["gcc", "-O2", "-o", ref, os.path.join(SHARED, "ref.c")])
    if r.returncode != 0:
        print("notice: gcc failed; skipping the per-scan benchmark\n" + r.stderr)
        return
    cases = [("lcg", 100, ["scans", "x", "acc", "hi", "lo"]),
             ("control", 20000, ["scan", "qsum", "cvsum", "alarms"]),
             ("sieve", 2000, ["scans", "total", "count", "last"])]
    print(f"{'program':<10} {'scans':>7} {'plcc us/scan':>13} {'C us/scan':>10} {'ratio':>7}  "
          f"{'VM us/scan':>11} {'VM/JIT':>7}  checksums")
    for name, scans, keys in cases:
        st = os.path.join(SHARED, name + ".st")
        p_times, c_times, v_times, ratios, vm_ratios = [], [], [], [], []
        same = True
        for _ in range(sets):
            rp = run([PLCC, "run", st, "--scans", str(scans), "--cycle-ms", "1", "--timing"])
            rc = run([ref, name, str(scans)])
            rv = run([PLCC, "run", st, "--target", "vmasm", "--scans", str(scans), "--cycle-ms", "1", "--timing"])
            if rp.returncode != 0 or rc.returncode != 0 or rv.returncode != 0:
                sys.exit(f"{name} failed:\n{rp.stderr}\n{rc.stderr}\n{rv.stderr}")
            tp = float(PER_SCAN.search(rp.stderr).group(1))
            tc = float(REF_PER_SCAN.search(rc.stderr).group(1))
            tv = float(PER_SCAN.search(rv.stderr).group(1))
            p_times.append(tp)
            c_times.append(tc)
            v_times.append(tv)
            ratios.append(tp / tc)
            vm_ratios.append(tv / tp)
            mine = checksums_plcc(rp.stdout, keys)
            theirs = checksums_ref(rc.stdout)
            vm = checksums_plcc(rv.stdout, keys)
            same = same and all(mine[k] == theirs.get(k) == vm[k] for k in keys)
        print(f"{name:<10} {scans:>7} {statistics.median(p_times):>13.3f} {statistics.median(c_times):>10.3f} "
              f"{statistics.median(ratios):>6.2f}x  {statistics.median(v_times):>11.3f} {statistics.median(vm_ratios):>6.1f}x  "
              f"{'equal' if same else 'DIFFER'}")


def measured(cmd):
    """Wall time and peak resident memory (bytes) of one run of `cmd`."""
    with tempfile.TemporaryFile() as err:
        t0 = time.perf_counter()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err)
        _, status, usage = os.wait4(p.pid, 0)
        t = time.perf_counter() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        if p.returncode != 0:
            err.seek(0)
            sys.exit(f"failed: {' '.join(cmd)}\n{err.read().decode(errors='replace')[-2000:]}")
    return t, usage.ru_maxrss * 1024


SCALING_POUS = (170, 850, 1700, 4250, 8500, 17000)


def scaling_bench(tmp, quick):
    pous = SCALING_POUS[:4] if quick else SCALING_POUS
    print("\n(d) compile scaling (the better of two whole-process runs each; peak resident memory)\n")
    print(f"{'POUs':>6} {'lines':>9} {'check s':>8} {'lines/s':>10} {'MB':>6} {'B/line':>7} "
          f"{'to JIT s':>9} {'lines/s':>9} {'MB':>6} {'B/line':>7} "
          f"{'optimised s':>12} {'lines/s':>9} {'MB':>6} {'B/line':>7}")
    rows = []
    for n in pous:
        src = os.path.join(tmp, f"scale{n}.st")
        with open(src, "w") as f:
            subprocess.run([sys.executable, os.path.join(SHARED, "gen_synth.py"), str(n)], stdout=f, check=True)
        lines = sum(1 for _ in open(src))
        # The better of two runs (the first also warms the file cache).
        (tc, mc), (tj, mj), (tf, mf) = (
            min(measured(cmd) for _ in range(2))
            for cmd in ([PLCC, "check", src], [PLCC, "run", src, "--scans", "0"],
                        [PLCC, "run", src, "--scans", "0", "-s", "tier=full"]))
        os.remove(src)
        rows.append((lines, tc, tj, tf))
        print(f"{n:>6} {lines:>9,} {tc:>8.3f} {lines / tc:>10,.0f} {mc / 1e6:>6.0f} {mc / lines:>7.0f} "
              f"{tj:>9.3f} {lines / tj:>9,.0f} {mj / 1e6:>6.0f} {mj / lines:>7.0f} "
              f"{tf:>12.3f} {lines / tf:>9,.0f} {mf / 1e6:>6.0f} {mf / lines:>7.0f}")
    (l0, c0, j0, f0), (l1, c1, j1, f1) = rows[0], rows[-1]
    print(f"\nfrom {l0:,} to {l1:,} lines ({l1 / l0:.0f}x): check {c1 / c0:.0f}x, to JIT {j1 / j0:.0f}x, "
          f"to optimised code {f1 / f0:.0f}x")
    out = os.path.join(ROOT, "docs", "img", "compile-scaling.svg")
    with open(out, "w") as f:
        f.write(scaling_svg(rows))
    print(f"wrote {os.path.relpath(out, ROOT)}")


def scaling_svg(rows):
    """Time against lines on log-log axes, one line per path, as a small SVG."""
    import math
    w, h, left, bottom, top, right = 660, 400, 70, 50, 20, 170
    xs = [r[0] for r in rows]
    ys = [t for r in rows for t in r[1:]]
    x0, x1 = math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs)))
    y0, y1 = math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys)))
    px = lambda x: left + (math.log10(x) - x0) / (x1 - x0) * (w - left - right)
    py = lambda y: h - bottom - (math.log10(y) - y0) / (y1 - y0) * (h - bottom - top)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>']
    for e in range(x0, x1 + 1):
        x = px(10 ** e)
        out.append(f'<line x1="{x:.1f}" y1="{top}" x2="{x:.1f}" y2="{h - bottom}" stroke="#ddd"/>')
        out.append(f'<text x="{x:.1f}" y="{h - bottom + 16}" text-anchor="middle">{10 ** e:,}</text>')
    for e in range(y0, y1 + 1):
        y = py(10 ** e)
        out.append(f'<line x1="{left}" y1="{y:.1f}" x2="{w - right}" y2="{y:.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">{10.0 ** e:g} s</text>')
    out.append(f'<text x="{(left + w - right) / 2}" y="{h - 10}" text-anchor="middle">lines of ST (gen_synth)</text>')
    paths = [("plcc check", "#1f77b4"), ("to JIT code", "#d62728"), ("to optimised code", "#2ca02c")]
    for k, (label, colour) in enumerate(paths):
        pts = " ".join(f"{px(r[0]):.1f},{py(r[1 + k]):.1f}" for r in rows)
        out.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for r in rows:
            out.append(f'<circle cx="{px(r[0]):.1f}" cy="{py(r[1 + k]):.1f}" r="3" fill="{colour}"/>')
        ly = top + 20 + 20 * k
        out.append(f'<line x1="{w - right + 10}" y1="{ly}" x2="{w - right + 30}" y2="{ly}" stroke="{colour}" stroke-width="2"/>')
        out.append(f'<text x="{w - right + 36}" y="{ly + 4}">{label}</text>')
    out.append("</svg>\n")
    return "\n".join(out)


def pic16_bench():
    print("\n(e) PIC16F876A against SDCC and gpsim (bench/pic16/run.py)\n")
    missing = [t for t in ("gpasm", "gpsim") if shutil.which(t) is None]
    if missing:
        print(f"notice: {', '.join(missing)} not found (../shared/tools/install-pic16-tools.sh); "
              "the PIC16 was not measured")
        return
    r = run([sys.executable, os.path.join(ROOT, "bench", "pic16", "run.py"), "--plcc", PLCC])
    print(r.stdout)
    if r.returncode != 0:
        print(f"notice: bench/pic16/run.py failed (exit {r.returncode}): the PIC16 figures "
              f"above are incomplete\n{r.stderr[-2000:]}")
        return
    words = re.search(r"\*\*geometric mean\*\* \(\d+ programs\) \| \| \| \*\*([\d.]+)\*\*", r.stdout)
    sim = re.search(r"\*\*([\d.]+)\*\* \(geometric mean\)", r.stdout)
    if words:
        w = float(words.group(1))
        print(f"code words against SDCC's (geometric mean): {w:.2f}x (aim <= 0.45x: "
              f"{'met' if w <= 0.45 else 'NOT met'})")
    if sim:
        v = float(sim.group(1))
        print(f"plcc's simulator against gpsim (geometric mean): {v:.1f}x (aim >= 12x: "
              f"{'met' if v >= 12 else 'NOT met'})")


def main():
    if "--help" in sys.argv or "-h" in sys.argv:
        print(__doc__)
        return
    if not os.path.isdir(SHARED):
        print("notice: ../shared/bench not found; nothing to measure")
        return
    quick = "--quick" in sys.argv
    only = sys.argv[sys.argv.index("--only") + 1] if "--only" in sys.argv else None
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    with tempfile.TemporaryDirectory() as tmp:
        if only in (None, "compile"):
            compile_bench(tmp, 3 if quick else 7)
        if only in (None, "scan"):
            scan_bench(tmp, 3 if quick else 9)
        if only in (None, "oscat"):
            oscat_bench(tmp, 3 if quick else 7)
        if only in (None, "scaling"):
            scaling_bench(tmp, quick)
    if only in (None, "pic16"):
        pic16_bench()


if __name__ == "__main__":
    main()
