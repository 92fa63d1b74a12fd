#!/usr/bin/env bash
# Alternates two builds of `pendulab` on the same workloads in one session, so that both see the
# same host load, and summarises each side's headline figure.
#
# Usage: tools/bench/alternate.sh [-n ROUNDS] [-s SECONDS] [-o OUT.jsonl] OLD_BIN NEW_BIN [WORKLOAD...]
#
#   OLD_BIN, NEW_BIN  two `pendulab` binaries (e.g. a worktree of the previous commit built with
#                     `cargo build --release -p pendulab`, and this one)
#   WORKLOAD          `pendulab bench` workloads (default: sim-rk4 cartpole-step sim-batch)
#   -n ROUNDS         invocations per binary and workload (default 5), in the order
#                     old, new, old, new, ... for each workload
#   -s SECONDS        `--seconds` passed to `pendulab bench` (default 1)
#   -o OUT.jsonl      also keep every JSON line, tagged with its side and round
#
# Each invocation is `BIN bench WORKLOAD --json --seconds SECONDS`; its `figure` (the workload's
# headline, larger is faster) is one sample. Per workload and side the script prints the fastest
# and the median sample, and the ratios new/old of both. Needs jq.
set -euo pipefail

rounds=5
seconds=1
out=""
while getopts "n:s:o:" opt; do
    case "$opt" in
        n) rounds="$OPTARG" ;;
        s) seconds="$OPTARG" ;;
        o) out="$OPTARG" ;;
        *) sed -n '4,17p' "$0"; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
if [ "$#" -lt 2 ]; then
    sed -n '4,17p' "$0"
    exit 2
fi
old="$1"
new="$2"
shift 2
workloads=("$@")
if [ "${#workloads[@]}" -eq 0 ]; then
    workloads=(sim-rk4 cartpole-step sim-batch)
fi
command -v jq >/dev/null || { echo "alternate.sh: needs jq" >&2; exit 2; }
for bin in "$old" "$new"; do
    [ -x "$bin" ] || { echo "alternate.sh: not an executable: $bin" >&2; exit 2; }
done
[ -z "$out" ] || : >"$out"

# Prints "fastest median" of the numbers on stdin.
summary() {
    sort -g | awk '{ v[NR] = $1 } END {
        m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
        printf "%.6g %.6g\n", v[NR], m
    }'
}

printf '%-14s %-4s %s\n' workload side "figures (rounds in order)"
for w in "${workloads[@]}"; do
    declare -a figs_old=() figs_new=()
    unit=""
    for ((r = 1; r <= rounds; r++)); do
        for side in old new; do
            bin="$old"
            [ "$side" = new ] && bin="$new"
            line="$("$bin" bench "$w" --json --seconds "$seconds")"
            fig="$(jq -r '.figure' <<<"$line")"
            unit="$(jq -r '.unit' <<<"$line")"
            if [ "$side" = old ]; then figs_old+=("$fig"); else figs_new+=("$fig"); fi
            [ -z "$out" ] || jq -c --arg side "$side" --argjson round "$r" \
                '{side: $side, round: $round} + .' <<<"$line" >>"$out"
        done
    done
    printf '%-14s %-4s %s\n' "$w" old "${figs_old[*]}"
    printf '%-14s %-4s %s\n' "$w" new "${figs_new[*]}"
    read -r old_fast old_med < <(printf '%s\n' "${figs_old[@]}" | summary)
    read -r new_fast new_med < <(printf '%s\n' "${figs_new[@]}" | summary)
    awk -v w="$w" -v u="$unit" -v of="$old_fast" -v om="$old_med" -v nf="$new_fast" -v nm="$new_med" \
        'BEGIN { printf "%-14s fastest old %.4g new %.4g (new/old %.3f); median old %.4g new %.4g (new/old %.3f) %s\n",
                 w, of, nf, nf / of, om, nm, nm / om, u }'
done
