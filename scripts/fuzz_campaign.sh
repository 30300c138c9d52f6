#!/usr/bin/env bash
# Coverage-guided fuzzing of plcc's front ends with AFL++ (afl.rs), seeded from
# ../shared/corpus and the project's own programs. Method and log: TESTING.md.
#
# usage: scripts/fuzz_campaign.sh TARGET [EXECS] [OUT]
#   TARGET: st | il | stl | ld     EXECS: executions to run (default 10000000)
#   OUT: output directory (default fuzz/out/TARGET); crashes and hangs land in
#   OUT/default/crashes and OUT/default/hangs.
# Needs cargo-afl (cargo install cargo-afl), whose own AFL++ runs the campaign.
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?usage: scripts/fuzz_campaign.sh st|il|stl|ld [EXECS] [OUT]}
execs=${2:-10000000}
out=$(realpath -m "${3:-fuzz/out/$target}")
(cd fuzz && cargo afl build --release --quiet)
seeds=$PWD/fuzz/seeds/$target
rm -rf "$seeds"
mkdir -p "$seeds"
add() { # files no larger than 10 kB, the inputs' limit
    for f in "$@"; do
        [ -f "$f" ] && [ "$(stat -c %s "$f")" -le 10240 ] && cp "$f" "$seeds/$(echo "$f" | tr '/' '_')"
    done
    true
}
case $target in
    st) add ../shared/corpus/st/*.st tests/programs/st/*/*.st tests/bad/*.st
        add $(ls ../shared/corpus/bulk/ironplc_e2e/*.st 2>/dev/null | head -100) ;;
    il) add ../shared/corpus/il/*.il tests/programs/il/*.il tests/programs/*/*.il tests/bad/*.il ;;
    stl) add tests/programs/stl/*.stl tests/bad/*.stl ;;
    ld) add tests/programs/ld/*.xml tests/bad/*.xml examples/*.xml ;;
    *) echo "unknown target $target" >&2; exit 2 ;;
esac
echo "$(ls "$seeds" | wc -l) seeds for $target"
mkdir -p "$(dirname "$out")"
export AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1
# -t 1000: an input running over 1 s is a hang; -G 10240: inputs of at most 10 kB.
(cd fuzz && cargo afl fuzz -m none -i "$seeds" -o "$out" -t 1000 -G 10240 -E "$execs" -- "target/release/$target")
echo "crashes: $(ls "$out/default/crashes" 2>/dev/null | grep -vc README || true)"
echo "hangs:   $(ls "$out/default/hangs" 2>/dev/null | wc -l)"
