#!/usr/bin/env bash
# Instructions per RK4 step of `bench sim-rk4`'s headline loop (the fixed-size kernel's
# FMA-compiled loop over the cart pendulum with the anchored sine/cosine), counted by callgrind
# on a small harness built against the crates of a given checkout, so that two checkouts (e.g.
# a worktree of an older commit and this one) are measured by the same harness.
#
# Usage: tools/bench/callgrind_rk4.sh [-r RUNS] [-t ROUNDS] REPO_DIR...
#
#   REPO_DIR  a pendulab checkout (its crates/lti, crates/sim, crates/plants and Cargo.lock);
#             the harness takes `CartPendulum::with_trig` where the checkout has no
#             `plants::cart::fast::FastCart` (before the fast paths moved behind `sim::fast`)
#   -r RUNS   recorded 10 s runs after the first one (default 10)
#   -t ROUNDS also time the harnesses natively, alternating between the checkouts ROUNDS times
#             (1000 runs each time); prints each one's fastest and median ns per step over the
#             rounds (each round's figure: its fastest run) — instructions are not cycles: the
#             loop is bound by the latency of the state → command → step chain
#
# The harness runs the sim-rk4 loop (book cart, LQR with Q = diag(10, 10, 0, 0), R = 1, ZOH
# 1 kHz, RK4 1 ms, 10 s from θ₀ = 15°, every sample recorded, storage recycled) 1 + RUNS times;
# callgrind collects only inside the loop function (`--toggle-collect=*run_fused*`). Printed
# per checkout: the loop's own instructions per step (the FMA loop alone, its callees apart),
# the same with its callees (recording's matrix checks, storage, libm fallbacks), the
# multiply–add path taken and the final state (bit-identity across checkouts). The harness is
# built offline with the checkout's own Cargo.lock and release profile (opt-level 3) in
# ${HC_TARGET:-/tmp}/callgrind-rk4-<hash>. Needs valgrind and callgrind_annotate.
set -euo pipefail

runs=10
rounds=0
while getopts "r:t:" opt; do
    case "$opt" in
        r) runs="$OPTARG" ;;
        t) rounds="$OPTARG" ;;
        *) sed -n '7,16p' "$0"; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
[ "$#" -ge 1 ] || { sed -n '7,16p' "$0"; exit 2; }

# The harness's folder for a checkout.
harness_dir() {
    local hash
    hash="$(printf '%s' "$(cd "$1" && pwd)" | cksum | cut -d' ' -f1)"
    printf '%s\n' "${HC_TARGET:-/tmp}/callgrind-rk4-$hash"
}

measure() {
    local repo
    repo="$(cd "$1" && pwd)"
    local dir
    dir="$(harness_dir "$repo")"
    mkdir -p "$dir/src"
    local plant
    if [ -f "$repo/crates/plants/src/cart/fast.rs" ]; then
        plant='pendulab_plants::cart::fast::FastCart::new(book, pendulab_sim::fast::Trig::Anchored)'
    else
        plant='book.with_trig(pendulab_sim::lanes::Trig::Anchored)'
    fi
    cat >"$dir/Cargo.toml" <<EOF
[package]
name = "callgrind-rk4"
version = "0.0.0"
edition = "2024"
publish = false

[dependencies]
pendulab-lti = { path = "$repo/crates/lti" }
pendulab-sim = { path = "$repo/crates/sim" }
pendulab-plants = { path = "$repo/crates/plants" }

[profile.release]
opt-level = 3
debug = false

[workspace]
EOF
    cat >"$dir/src/main.rs" <<EOF
use pendulab_lti::Mat;
use pendulab_plants::{CartEquilibrium, CartPendulum};
use pendulab_sim::controllers::StaticStateFeedback;
use pendulab_sim::{Integrator, Record, SampledLoop, SampledOptions};
use std::hint::black_box;

fn main() {
    let runs: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).expect("RUNS");
    let book = CartPendulum::book();
    let sys = book.linearize(CartEquilibrium::upright()).expect("linearisation");
    let mut q = Mat::zeros(4, 4);
    q[(0, 0)] = 10.0;
    q[(1, 1)] = 10.0;
    let k = pendulab_lti::design::lqr(&sys, &q, &Mat::identity(1, 1), None).expect("lqr").gain;
    let options = SampledOptions {
        ts: 1e-3,
        t_final: 10.0,
        integrator: Integrator::Rk4 { dt: 1e-3 },
        record: Record::EverySample,
        ..Default::default()
    };
    let lp = SampledLoop::new($plant, StaticStateFeedback::new(k).expect("gain"), options)
        .expect("loop");
    let mut fast = lp.fixed::<4>().expect("fixed kernel");
    let x0 = [0.0, 15f64.to_radians(), 0.0, 0.0];
    let mut last = fast.run(&x0).expect("run");
    let mut times = Vec::with_capacity(runs);
    for _ in 0..runs {
        let start = std::time::Instant::now();
        last = fast.run_recycling(black_box(&x0), &mut (), last).expect("run");
        times.push(start.elapsed().as_secs_f64());
    }
    let d = &last.diagnostics;
    times.sort_by(f64::total_cmp);
    let per_step = |s: f64| s * 1e9 / d.integration.accepted_steps as f64;
    println!(
        "path {:?} steps/run {} final_state {:?} ns/step min {:.3} median {:.3}",
        fast.multiply_add(),
        d.integration.accepted_steps,
        d.final_state,
        per_step(times.first().copied().unwrap_or(f64::NAN)),
        per_step(times.get(times.len() / 2).copied().unwrap_or(f64::NAN)),
    );
}
EOF
    cp "$repo/Cargo.lock" "$dir/Cargo.lock"
    (cd "$dir" && CARGO_TARGET_DIR="$dir/target" cargo build --release --offline --quiet)
    local out="$dir/callgrind.out"
    local line
    line="$(valgrind --tool=callgrind --toggle-collect='*run_fused*' --callgrind-out-file="$out" \
        "$dir/target/release/callgrind-rk4" "$runs" 2>/dev/null)"
    local steps_per_run
    steps_per_run="$(sed -E 's/.*steps\/run ([0-9]+).*/\1/' <<<"$line")"
    local self incl
    self="$(callgrind_annotate "$out" 2>/dev/null | awk '/run_fused/ { gsub(",", "", $1); print $1; exit }')"
    incl="$(callgrind_annotate --inclusive=yes "$out" 2>/dev/null | awk '/run_fused/ { gsub(",", "", $1); print $1; exit }')"
    awk -v r="$1" -v s="$self" -v i="$incl" -v n="$(( (runs + 1) * steps_per_run ))" -v l="$line" \
        'BEGIN { printf "%s: %.1f instructions/step in the loop, %.1f with its callees (%d steps); %s\n",
                 r, s / n, i / n, n, l }'
}

for repo in "$@"; do
    measure "$repo"
done

if [ "$rounds" -gt 0 ]; then
    declare -A figs=()
    for ((r = 1; r <= rounds; r++)); do
        for repo in "$@"; do
            line="$("$(harness_dir "$repo")/target/release/callgrind-rk4" 1000)"
            figs[$repo]+="$(sed -E 's/.*ns\/step min ([0-9.]+).*/\1/' <<<"$line") "
        done
    done
    for repo in "$@"; do
        printf '%s\n' ${figs[$repo]} | sort -g | awk -v r="$repo" '{ v[NR] = $1 } END {
            m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
            printf "%s: %.3f ns/step fastest, %.3f median of %d alternated rounds\n", r, v[1], m, NR
        }'
    done
fi
