#!/usr/bin/env node
// Times the browser lab's redesign (docs/web.md, "Redesign time") in Node's V8, the engine of
// Chromium, on the module `tools/build-web` writes: the cart's LQR (n = 4) and the servo (n = 5)
// through the page's own entry `pl_design`, after the same warm-up the page runs at load.
//
// Usage: node tools/bench/web_redesign.mjs [SITE] [--rounds N]   (SITE default: site)
//
// Three figures per method, each a median over N rounds (default 60), as one JSON line:
// - `tight_us`: a call inside a loop of 200 back-to-back calls (the computation, warm);
// - `after_wait_us`: the first call after a 30 ms pause (what a slider move meets: the last
//   move was a frame or more ago, and on a shared machine other processes ran meanwhile);
// - `repeat_us`: the same call again at once (same inputs moved by 1e-3, so it is a new design).
// The gap between `after_wait_us` and `repeat_us` is the cost of running the design's code and
// data from cold caches, branch predictors and TLBs, not of the computation.
import { readFileSync } from "node:fs";
import { join, resolve } from "node:path";

const args = process.argv.slice(2);
const roundsAt = args.indexOf("--rounds");
const rounds = roundsAt >= 0 ? Number(args[roundsAt + 1]) : 60;
const site = resolve(args.find((a, i) => !a.startsWith("--") && args[i - 1] !== "--rounds") || "site");
if (!(Number.isInteger(rounds) && rounds > 0)) {
  console.error("web_redesign: --rounds must be a positive integer");
  process.exit(2);
}

let bytes;
try {
  bytes = readFileSync(join(site, "pendulab_web.wasm"));
} catch (e) {
  console.error(`web_redesign: ${join(site, "pendulab_web.wasm")}: ${e.code || e.message} (build the site with tools/build-web)`);
  process.exit(2);
}
const module = await WebAssembly.compile(bytes);
const imports = {};
for (const imp of WebAssembly.Module.imports(module)) {
  (imports[imp.module] ||= {})[imp.name] = () => {
    throw new Error(`${imp.module}.${imp.name} is not available`);
  };
}
const x = (await WebAssembly.instantiate(module, imports)).exports;
const io = () => new Float64Array(x.memory.buffer, x.pl_io(), 16384);
const check = (rc) => {
  if (rc < 0) throw new Error(`pendulab_web returned ${rc}`);
};
check(x.pl_init(0));

// The page's calls (web/src/lab.js `design`): weights into the number buffer, then pl_design.
const methods = {
  lqr: (s) => {
    io().set([10 * s, 10, 0, 0]);
    check(x.pl_design(0, 1));
  },
  servo: (s) => {
    io().set([1 * s, 5, 0, 0, 100]);
    check(x.pl_design(1, 1));
  },
};
// The page's warm-up at load (web/src/app.js): 300 designs of each method in a row.
for (const design of [methods.lqr, methods.servo]) {
  for (let i = 0; i < 300; i++) design(1 + 1e-3 * i);
}

const median = (a) => {
  const s = [...a].sort((p, q) => p - q);
  return s[Math.floor(s.length / 2)];
};
const sleep = (ms) => new Promise((ok) => setTimeout(ok, ms));
const result = { rounds, node: process.version };
for (const [name, design] of Object.entries(methods)) {
  const tight = [];
  const afterWait = [];
  const repeat = [];
  for (let r = 0; r < rounds; r++) {
    const s = 1 + 0.01 * (r % 50);
    let t = performance.now();
    for (let i = 0; i < 200; i++) design(s + 1e-5 * i);
    tight.push(((performance.now() - t) / 200) * 1000);
    await sleep(30);
    t = performance.now();
    design(s);
    afterWait.push((performance.now() - t) * 1000);
    t = performance.now();
    design(s + 1e-3);
    repeat.push((performance.now() - t) * 1000);
  }
  result[name] = {
    tight_us: +median(tight).toFixed(2),
    after_wait_us: +median(afterWait).toFixed(2),
    repeat_us: +median(repeat).toFixed(2),
  };
}
console.log(JSON.stringify(result));
