#!/usr/bin/env python3
"""Hover latency of `plcc lsp` on OSCAT BASIC (30k lines of ST), printed as the
table of BENCHMARKS.md.

usage: bench/lsp_hover.py [--hovers N] [--plcc PATH]

Method: OSCAT_BASIC_333.utf8.st from ../shared/corpus/libs is copied alone into a
fresh folder (the server builds a document's folder). The script starts
`plcc lsp` (release build), sends `initialize`, opens the file with `didOpen` and
waits for its diagnostics: that time is the load (reading, the whole build, the
index). Then it asks N hovers (200 by default) one after another, each at a name
of the file: the names are every identifier-like word of the text, N of them taken
at even steps from first to last (some fall in comments, where the answer is
null). Each hover is timed from the moment the request is written to the moment
its response is read, in this script (so the pipe and JSON both ways are in it).
The table gives the load, and the hovers' min, median, p99 and max, with how many
had an answer; then one `semanticTokens/full` of the whole file, timed the same way. Nothing else talks to the server meanwhile. The aim (issue 23): a
hover answered in under 50 ms once loaded.

Needs python3 and a release build of plcc (`cargo build --release --bin plcc`,
done here unless `--plcc PATH` names a binary; CARGO_TARGET_DIR is honoured).
"""
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
OSCAT = os.path.join(ROOT, "..", "shared", "corpus", "libs", "oscat_basic_333",
                     "OSCAT_BASIC_333.utf8.st")


KEYWORDS = set("""
PROGRAM END_PROGRAM FUNCTION END_FUNCTION FUNCTION_BLOCK END_FUNCTION_BLOCK VAR
VAR_INPUT VAR_OUTPUT VAR_IN_OUT VAR_TEMP VAR_GLOBAL VAR_EXTERNAL VAR_CONFIG END_VAR
CONSTANT RETAIN PERSISTENT TYPE END_TYPE STRUCT END_STRUCT ARRAY OF AT IF THEN ELSIF
ELSE END_IF CASE END_CASE FOR TO BY DO END_FOR WHILE END_WHILE REPEAT UNTIL
END_REPEAT EXIT RETURN AND OR XOR NOT MOD TRUE FALSE BOOL BYTE WORD DWORD LWORD SINT
INT DINT LINT USINT UINT UDINT ULINT REAL LREAL TIME DATE TOD DT TIME_OF_DAY
DATE_AND_TIME STRING WSTRING POINTER REF_TO REFERENCE""".split())


def arg(name, default, conv):
    if name in sys.argv:
        return conv(sys.argv[sys.argv.index(name) + 1])
    return default


class Server:
    def __init__(self, plcc, cwd):
        self.p = subprocess.Popen([plcc, "lsp"], cwd=cwd, stdin=subprocess.PIPE,
                                  stdout=subprocess.PIPE)
        self.next_id = 1

    def send(self, msg):
        body = json.dumps(msg).encode()
        self.p.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
        self.p.stdin.flush()

    def read(self):
        length = None
        while True:
            line = self.p.stdout.readline()
            if not line:
                raise SystemExit("plcc lsp ended")
            line = line.strip()
            if not line:
                break
            if line.lower().startswith(b"content-length:"):
                length = int(line.split(b":")[1])
        return json.loads(self.p.stdout.read(length))

    def request(self, method, params):
        rid = self.next_id
        self.next_id += 1
        self.send({"jsonrpc": "2.0", "id": rid, "method": method, "params": params})
        while True:
            m = self.read()
            if m.get("id") == rid and "method" not in m:
                return m

    def notify(self, method, params):
        self.send({"jsonrpc": "2.0", "method": method, "params": params})


def main():
    hovers = arg("--hovers", 200, int)
    plcc = arg("--plcc", None, str)
    if not os.path.exists(OSCAT):
        raise SystemExit(f"{OSCAT} is missing: this benchmark needs ../shared")
    if plcc is None:
        subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "plcc"],
                       cwd=ROOT, check=True)
        plcc = os.path.join(TARGET, "release", "plcc")
    plcc = os.path.abspath(plcc)
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "oscat.st")
        shutil.copy(OSCAT, path)
        text = open(path, encoding="utf-8").read()
        lines = text.split("\n")
        # Comments and strings blanked (line breaks kept), then the words that are
        # no keyword: the names.
        masked = re.sub(r"\(\*.*?\*\)|//[^\n]*|'[^'\n]*'|\"[^\"\n]*\"",
                        lambda m: re.sub(r"[^\n]", " ", m.group()), text, flags=re.S)
        names = []
        for n, line in enumerate(masked.split("\n")):
            for m in re.finditer(r"[A-Za-z_][A-Za-z0-9_]*", line):
                if m.group().upper() in KEYWORDS or re.match(r"[A-Z]+#", line[m.start():]):
                    continue
                col16 = len(lines[n][:m.start()].encode("utf-16-le")) // 2
                names.append((n, col16 + 1))
        step = max(1, len(names) // hovers)
        picks = names[::step][:hovers]
        uri = "file://" + path
        s = Server(plcc, d)
        s.request("initialize", {"processId": None, "rootUri": "file://" + d,
                                 "capabilities": {}})
        s.notify("initialized", {})
        t0 = time.perf_counter()
        s.notify("textDocument/didOpen", {"textDocument": {
            "uri": uri, "languageId": "iecst", "version": 1, "text": text}})
        while True:
            m = s.read()
            if m.get("method") == "textDocument/publishDiagnostics" \
                    and m["params"]["uri"] == uri:
                break
        load = time.perf_counter() - t0
        times = []
        answered = 0
        for (line, col) in picks:
            t = time.perf_counter()
            r = s.request("textDocument/hover", {
                "textDocument": {"uri": uri},
                "position": {"line": line, "character": col}})
            times.append(time.perf_counter() - t)
            if r.get("result"):
                answered += 1
        t = time.perf_counter()
        r = s.request("textDocument/semanticTokens/full", {"textDocument": {"uri": uri}})
        tokens_ms = (time.perf_counter() - t) * 1000
        tokens = len(r["result"]["data"]) // 5
        s.request("shutdown", None)
        s.notify("exit", None)
        s.p.wait(timeout=10)
    ms = sorted(t * 1000 for t in times)
    p99 = ms[min(len(ms) - 1, int(len(ms) * 0.99))]
    print(f"plcc lsp on OSCAT BASIC 3.33 ({len(lines)} lines), {len(ms)} hovers, "
          f"{answered} answered")
    print()
    print("| load (didOpen to diagnostics) | hover min | median | p99 | max "
          "| semantic tokens of the file |")
    print("|---|---|---|---|---|---|")
    print(f"| {load * 1000:.0f} ms | {ms[0]:.2f} ms | {statistics.median(ms):.2f} ms "
          f"| {p99:.2f} ms | {ms[-1]:.2f} ms | {tokens_ms:.0f} ms ({tokens} tokens) |")
    print()
    print("aim: every hover under 50 ms:", "met" if ms[-1] < 50 else "NOT met")


if __name__ == "__main__":
    main()
