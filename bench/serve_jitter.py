#!/usr/bin/env python3
"""Scan jitter of `plcc serve`: lateness and execution time of the scans of a small
program run in real time, printed as the table of BENCHMARKS.md.

usage: bench/serve_jitter.py [--seconds S] [--cycle-ms M] [--load N] [--plcc PATH]

Method: `plcc serve` (release build, the JIT, target `host`) runs the small program
below at `--cycle-ms` (10 by default) for S seconds (60 by default), Modbus off, the
HTTP API on a loopback port. The server keeps, for every scan, its lateness (how long
after its deadline, start + n x cycle, it started) and its execution time (latching
the inputs, the program, publishing the outputs), and gives in `GET /api/status` the
minimum, mean and maximum over every scan and the median (p50) and 99th percentile
(p99) over the last 1,000 scans. The script reads the status once every 1,000 cycles
(10 s at 10 ms), so each reading covers its own window of about 1,000 scans; the
table gives min, mean and max over the whole run, the median of the windows' p50
and the largest of their p99, the overruns (scans that ended after the next
deadline), and the scans counted against those the run's length allows; then the
p50 and p99 of every window. Nothing else asks the server anything meanwhile.

`--load N` runs N busy loops (pure Python, at the script's own priority) beside the
server for the whole run, to see the scans on a loaded machine. The script prints
the number of cores and the load average before and after the run.

Needs python3 and a release build of plcc (`cargo build --release --bin plcc`, done
here unless `--plcc PATH` names a binary; CARGO_TARGET_DIR is honoured). Linux only
(the load average, SIGTERM).
"""
import json
import multiprocessing
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))

# A small program: a blinker on a TON, a counter, a moving average over 8 samples
# of an input register, a start/stop latch, and outputs on the Modbus map.
PROGRAM = """\
PROGRAM bench
VAR
  start AT %IX0.0 : BOOL;
  stop AT %IX0.1 : BOOL;
  running AT %QX0.0 : BOOL;
  blink AT %QX0.1 : BOOL;
  level AT %IW0 : INT;
  average AT %QW0 : INT;
  count AT %MD0 : DINT;
  t : TON;
  samples : ARRAY[0..7] OF INT;
  i : INT;
  k : INT;
  acc : DINT;
END_VAR
running := (start OR running) AND NOT stop;
t(IN := NOT t.Q, PT := T#500ms);
IF t.Q THEN
  blink := NOT blink;
END_IF;
samples[k] := level + INT#3 * (k MOD 4);
k := (k + 1) MOD 8;
acc := 0;
FOR i := 0 TO 7 DO
  acc := acc + samples[i];
END_FOR;
average := DINT_TO_INT(acc / 8);
count := count + 1;
END_PROGRAM
"""

WINDOW = 1000  # the scans the server's percentiles are taken over


def arg(name, default, conv):
    if name in sys.argv:
        return conv(sys.argv[sys.argv.index(name) + 1])
    return default


def status(addr):
    with urllib.request.urlopen(f"http://{addr}/api/status", timeout=10) as r:
        return json.load(r)


def busy(stop):
    while not stop.is_set():
        pass


def main():
    seconds = arg("--seconds", 60.0, float)
    cycle_ms = arg("--cycle-ms", 10.0, float)
    load = arg("--load", 0, int)
    plcc = arg("--plcc", None, str)
    if plcc is None:
        subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "plcc"],
                       cwd=ROOT, check=True)
        plcc = os.path.join(TARGET, "release", "plcc")
    window_s = WINDOW * cycle_ms / 1000.0
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "bench.st")
        with open(src, "w") as f:
            f.write(PROGRAM)
        stop_load = multiprocessing.Event()
        hogs = [multiprocessing.Process(target=busy, args=(stop_load,)) for _ in range(load)]
        for h in hogs:
            h.start()
        load_before = os.getloadavg()
        server = subprocess.Popen(
            [plcc, "serve", src, "--cycle-ms", f"{cycle_ms:g}", "--modbus", "none",
             "--http", "127.0.0.1:0"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
            text=True)
        lines = []
        addr = None
        for line in server.stderr:
            lines.append(line.rstrip("\n"))
            m = re.match(r"http: listening on (\S+)", line)
            if m:
                addr = m.group(1)
                break
        if addr is None:
            sys.exit("plcc serve did not start:\n" + "\n".join(lines))
        rest = threading.Thread(target=lambda: lines.extend(l.rstrip("\n") for l in server.stderr))
        rest.start()
        t0 = time.monotonic()
        windows = []
        k = 1
        while True:
            due = min(k * window_s, seconds)
            time.sleep(max(0.0, t0 + due - time.monotonic()))
            st = status(addr)
            windows.append((time.monotonic() - t0, st))
            if due >= seconds:
                break
            k += 1
        elapsed = time.monotonic() - t0
        final = windows[-1][1]
        server.send_signal(signal.SIGTERM)
        server.wait(timeout=30)
        rest.join(timeout=10)
        load_after = os.getloadavg()
        stop_load.set()
        for h in hogs:
            h.join()
    if final["state"] != "running" or server.returncode != 0:
        sys.exit(f"the server did not run to the end ({final['state']}, status "
                 f"{server.returncode}):\n" + "\n".join(lines))
    expected = int(elapsed * 1000 / cycle_ms)
    print(f"plcc serve, target {final['target']}, cycle {cycle_ms:g} ms, {seconds:g} s; "
          f"{os.cpu_count()} cores; load average (1 min) {load_before[0]:.2f} before, "
          f"{load_after[0]:.2f} after; {load} busy loop(s) beside it\n")
    print("| µs | min | p50 | mean | p99 | max |")
    print("|---|---|---|---|---|---|")
    for key, name in [("lateness_us", "lateness"), ("exec_us", "execution")]:
        p50 = statistics.median(w[key]["p50"] for _, w in windows)
        p99 = max(w[key]["p99"] for _, w in windows)
        s = final[key]
        print(f"| {name} | {s['min']} | {p50:g} | {s['mean']:.1f} | {p99} | {s['max']} |")
    print(f"\nscans: {final['scans']:,} of {expected:,} cycles in {elapsed:.1f} s; "
          f"overruns: {final['overruns']}\n")
    print("| window ending at s | lateness p50 | lateness p99 | execution p50 | execution p99 |")
    print("|---|---|---|---|---|")
    for t, w in windows:
        print(f"| {t:.1f} | {w['lateness_us']['p50']} | {w['lateness_us']['p99']} "
              f"| {w['exec_us']['p50']} | {w['exec_us']['p99']} |")
    stats = [l for l in lines if l.startswith("scans: ")]
    if stats:
        print(f"\nthe server's last line: {stats[-1]}")


if __name__ == "__main__":
    main()
