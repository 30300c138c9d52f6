#!/usr/bin/env python3
"""Flash and RAM of the shared/bench programs' C on the ATmega2560 (OpenPLC's Arduino
Mega target), printed as the table of BENCHMARKS.md.

usage: bench/avr_sizes.py

Method: `plcc --target c PROG.st` writes the file set and `--emit headers` plcc's own
headers; avr-gcc (Debian's gcc-avr 5.4 with avr-libc) builds Config0.c and Res0.c
with a small `main` (the runtime's clock and debug switch, cold start, then a scan
every 10 ms of the clock, forever: the same `main` as tests/e2e.rs c_builds_for_avr)
with `-mmcu=atmega2560 -Os -std=c99 -ffunction-sections -fdata-sections
-Wl,--gc-sections -Wall -Wextra -Werror` and `-lm`. `avr-size -A` gives the
sections: flash is .text + .data (the initial values are stored in flash), RAM is
.data + .bss (static data; the stack comes on top). A program whose RAM the linker
refuses for the chip's 8 KB is linked again with room enough to measure it.

Needs ../shared/bench (skips with a notice otherwise), avr-gcc, avr-libc and a
release build of plcc (`cargo build --release`, done here; CARGO_TARGET_DIR is
honoured).
"""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared", "bench")
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
PLCC = os.path.join(TARGET, "release", "plcc")

MAIN = r"""#include "iec_std_lib.h"
TIME __CURRENT_TIME;
BOOL __DEBUG;
void config_init__(void);
void config_run__(unsigned long tick);
int main(void) {
    unsigned long tick = 0;
    config_init__();
    for (;;) {
        __CURRENT_TIME.tv_nsec += 10000000;
        if (__CURRENT_TIME.tv_nsec >= 1000000000) {
            __CURRENT_TIME.tv_nsec -= 1000000000;
            __CURRENT_TIME.tv_sec += 1;
        }
        config_run__(tick++);
    }
}
"""

FLAGS = ["-mmcu=atmega2560", "-Os", "-std=c99", "-ffunction-sections", "-fdata-sections",
         "-Wl,--gc-sections", "-Wall", "-Wextra", "-Werror"]
RAM, FLASH = 8192, 262144


def run(cmd, **kw):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def sections(elf):
    out = run(["avr-size", "-A", elf]).stdout
    size = {}
    for line in out.splitlines():
        w = line.split()
        if len(w) >= 2 and w[0] in (".text", ".data", ".bss"):
            size[w[0]] = int(w[1])
    return size.get(".text", 0), size.get(".data", 0), size.get(".bss", 0)


def build(name, tmp):
    d = os.path.join(tmp, name)
    os.makedirs(d)
    src = os.path.join(SHARED, name + ".st")
    for extra in ([], ["--emit", "headers"]):
        r = run([PLCC, "--target", "c", *extra, src, "-o", d])
        if r.returncode != 0:
            sys.exit(f"plcc failed on {name}:\n{r.stderr}")
    with open(os.path.join(d, "avr_main.c"), "w") as f:
        f.write(MAIN)
    elf = os.path.join(d, "prog.elf")
    cmd = ["avr-gcc", *FLAGS, "Config0.c", "Res0.c", "avr_main.c", "-o", elf, "-lm"]
    r = run(cmd, cwd=d)
    fits = r.returncode == 0
    if not fits:
        if "not within region" not in r.stderr and "overflowed" not in r.stderr:
            sys.exit(f"avr-gcc failed on {name}:\n{r.stderr}")
        r = run(cmd + ["-Wl,--defsym=__DATA_REGION_LENGTH__=0xfe00",
                       "-Wl,--defsym=__TEXT_REGION_LENGTH__=0x1000000"], cwd=d)
        if r.returncode != 0:
            sys.exit(f"avr-gcc failed on {name} even with room enough:\n{r.stderr}")
    text, data, bss = sections(elf)
    flash, ram = text + data, data + bss
    return flash, ram, fits and ram <= RAM and flash <= FLASH


def main():
    if not os.path.isdir(SHARED):
        print("notice: ../shared/bench not found; nothing to measure")
        return
    if run(["avr-gcc", "--version"]).returncode != 0:
        sys.exit("avr-gcc is not installed (apt-get install gcc-avr avr-libc)")
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    version = run(["avr-gcc", "--version"]).stdout.splitlines()[0]
    print(f"ATmega2560 ({version}, -Os): flash = .text + .data, RAM = .data + .bss\n")
    print("| program | flash bytes | of 256 KB | RAM bytes | of 8 KB | fits |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("lcg", "control", "sieve"):
            flash, ram, fits = build(name, tmp)
            print(f"| {name} | {flash:,} | {100 * flash / FLASH:.1f}% | {ram:,} | "
                  f"{100 * ram / RAM:.1f}% | {'yes' if fits else 'no'} |")


if __name__ == "__main__":
    main()
