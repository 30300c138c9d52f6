#!/usr/bin/env python3
"""Time per scan of the `c` target's C (gcc -O2) against ref.c, printed as the table
of BENCHMARKS.md.

usage: bench/c_speed.py [--quick] [--sets N]

Method: for each program of ../shared/bench (lcg, control, sieve), `plcc --target c`
writes the file set and `--emit headers` plcc's own headers; a driver of our own
(`bench_main.c`: the runtime's clock and debug switch, cold start, then N scans with
the clock at k ms for scan k, as ref.c runs them, timed by CLOCK_MONOTONIC around the
scan loop alone, and the checksum variables printed) is built with them by
`gcc -O2 -std=c99 -ffp-contract=off` (docs/c.md's flags for the IR's bits; without
FMA on x86-64's baseline the contraction changes nothing). ref.c is built with
`gcc -O2`, as its header says, and times its own loop the same way. The two run
interleaved, N sets each (9 by default); the table gives the medians, the median of
the per-set ratios, and the ratio of the fastest runs (on a machine shared with other
work a set is often slowed down; the fastest run of each is the least disturbed).
The checksums must equal ref.c's.

Needs ../shared/bench (skips with a notice otherwise), gcc and a release build of
plcc (`cargo build --release`, done here; CARGO_TARGET_DIR is honoured).
"""
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared", "bench")
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
PLCC = os.path.join(TARGET, "release", "plcc")

# name, scans, the instance's type and its checksum fields (C name, printf format)
CASES = [
    ("lcg", 100, "LCG", [("scans", "SCANS", "%d"), ("x", "X", "%d"), ("acc", "ACC", "%d"),
                         ("hi", "HI", "%d"), ("lo", "LO", "%d")]),
    ("control", 20000, "CONTROL", [("scan", "SCAN", "%d"), ("qsum", "QSUM", "%d"),
                                   ("cvsum", "CVSUM", "%d"), ("alarms", "ALARMS", "%d"),
                                   ("pvsum", "PVSUM", "%.9g")]),
    ("sieve", 2000, "SIEVE", [("scans", "SCANS", "%d"), ("total", "TOTAL", "%d"),
                              ("count", "COUNT", "%d"), ("last", "LAST", "%d")]),
]


def driver(inst, fields):
    prints = " ".join(
        f'printf("{k}={fmt}{" " if i + 1 < len(fields) else chr(92) + "n"}", '
        f'({"double" if fmt.endswith("g") else "int"})RES0__{inst}.{c}.value);'
        for i, (k, c, fmt) in enumerate(fields))
    return f"""#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "iec_std_lib.h"
#include "POUS.h"
TIME __CURRENT_TIME;
BOOL __DEBUG;
void config_init__(void);
void config_run__(unsigned long tick);
int main(int argc, char **argv) {{
    unsigned long n = argc > 1 ? strtoul(argv[1], 0, 10) : 1, k;
    struct timespec t0, t1;
    config_init__();
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (k = 0; k < n; k++) {{
        __CURRENT_TIME.tv_sec = (long)(k / 1000);
        __CURRENT_TIME.tv_nsec = (long)(k % 1000) * 1000000L;
        config_run__(k);
    }}
    clock_gettime(CLOCK_MONOTONIC, &t1);
    {prints}
    fprintf(stderr, "in-process: %.3f us/scan over %lu scans\\n",
            ((t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec)) / 1e3 / (double)n, n);
    return 0;
}}
"""


def run(cmd, **kw):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


PER_SCAN = re.compile(r"in-process: ([0-9.]+) us/scan")


def checksums(out):
    return dict(re.findall(r"(\w+)=(\S+)", out))


def build(name, inst, fields, tmp):
    d = os.path.join(tmp, name)
    os.makedirs(d)
    src = os.path.join(SHARED, name + ".st")
    for extra in ([], ["--emit", "headers"]):
        r = run([PLCC, "--target", "c", *extra, src, "-o", d])
        if r.returncode != 0:
            sys.exit(f"plcc failed on {name}:\n{r.stderr}")
    with open(os.path.join(d, "bench_main.c"), "w") as f:
        f.write(driver(inst, fields))
    exe = os.path.join(d, "prog")
    r = run(["gcc", "-O2", "-std=c99", "-ffp-contract=off", "-I.", "Config0.c", "Res0.c",
             "bench_main.c", "-o", exe, "-lm"], cwd=d)
    if r.returncode != 0:
        sys.exit(f"gcc failed on {name}:\n{r.stderr}")
    return exe


def main():
    if not os.path.isdir(SHARED):
        print("notice: ../shared/bench not found; nothing to measure")
        return
    sets = 3 if "--quick" in sys.argv else 9
    if "--sets" in sys.argv:
        sets = int(sys.argv[sys.argv.index("--sets") + 1])
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    with tempfile.TemporaryDirectory() as tmp:
        ref = os.path.join(tmp, "ref")
        r = run(["gcc", "-O2", "-o", ref, os.path.join(SHARED, "ref.c")])
        if r.returncode != 0:
            sys.exit("gcc failed on ref.c\n" + r.stderr)
        print(f"plcc's C (gcc -O2) vs ref.c (gcc -O2), {sets} interleaved sets, median\n")
        print("| program | scans | plcc C µs/scan | ref.c µs/scan | ratio (median of sets) "
              "| ratio of the fastest | checksums |")
        print("|---|---|---|---|---|---|---|")
        for name, scans, inst, fields in CASES:
            exe = build(name, inst, fields, tmp)
            mine, theirs, ratios = [], [], []
            same = True
            for _ in range(sets):
                rp = run([exe, str(scans)])
                rc = run([ref, name, str(scans)])
                if rp.returncode != 0 or rc.returncode != 0:
                    sys.exit(f"{name} failed:\n{rp.stderr}\n{rc.stderr}")
                tp = float(PER_SCAN.search(rp.stderr).group(1))
                tc = float(PER_SCAN.search(rc.stderr).group(1))
                mine.append(tp)
                theirs.append(tc)
                ratios.append(tp / tc)
                a, b = checksums(rp.stdout), checksums(rc.stdout)
                same = same and all(a[k] == b.get(k) for k, _, _ in fields)
            print(f"| {name} | {scans:,} | {statistics.median(mine):.3f} | "
                  f"{statistics.median(theirs):.3f} | {statistics.median(ratios):.2f}× | "
                  f"{min(mine) / min(theirs):.2f}× | {'equal' if same else 'DIFFER'} |")


if __name__ == "__main__":
    main()
