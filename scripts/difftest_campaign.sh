#!/bin/sh
# A long differential-testing campaign: `plcc difftest` over COUNT seeds from FIRST,
# in JOBS parallel slices, on TARGETS (default: plcc's, every machine of the target
# registry that runs here, the C one under UBSan; plain vmasm runs in the
# addressing mode each seed picks; `-` for the default with a LANGUAGE). Reproducers of any
# finding go to OUT; each slice's summary line goes to OUT/log.txt. LANGUAGE is st
# (random ST programs, the default), xml (random PLCopen projects with LD and FBD
# bodies; reproducers are .xml files) or sfc (random sequential function charts,
# each under the three --sfc profiles).
#
#   scripts/difftest_campaign.sh [FIRST] [COUNT] [JOBS] [OUT] [TARGETS] [LANGUAGE]
#   scripts/difftest_campaign.sh 1 100000 2 difftest-out
#   scripts/difftest_campaign.sh 1 20000 2 out-vm interp,host,vmasm
#   scripts/difftest_campaign.sh 1 20000 2 out-xml interp,host,vmasm,pic16f876a xml
#   scripts/difftest_campaign.sh 1 3000 2 out-sfc interp,host,vmasm,pic16f876a sfc
#   scripts/difftest_campaign.sh 1 3000 2 out-sfc - sfc
set -eu
first=${1:-1}
count=${2:-10000}
jobs=${3:-2}
out=${4:-difftest-out}
targets=${5:--}
language=${6:-st}
cd "$(dirname "$0")/.."
cargo build --release --quiet
plcc="${CARGO_TARGET_DIR:-target}/release/plcc"
mkdir -p "$out"
per=$(( (count + jobs - 1) / jobs ))
i=0
while [ "$i" -lt "$jobs" ]; do
    start=$(( first + i * per ))
    n=$per
    if [ $(( start + n )) -gt $(( first + count )) ]; then n=$(( first + count - start )); fi
    if [ "$targets" = - ]; then
        "$plcc" difftest --seed "$start" --count "$n" --out "$out" --lang "$language" \
            > "$out/slice_$i.txt" 2>&1 &
    else
        "$plcc" difftest --seed "$start" --count "$n" --targets "$targets" --out "$out" \
            --lang "$language" > "$out/slice_$i.txt" 2>&1 &
    fi
    i=$(( i + 1 ))
done
wait
status=0
for f in "$out"/slice_*.txt; do
    tail -n 1 "$f" | tee -a "$out/log.txt"
    if grep -q '^seed ' "$f"; then status=1; grep '^seed ' "$f"; fi
done
exit $status
