// The browser lab in a real browser (docs/web.md, "Tests"): headless Chromium (the Debian
// package) driven by playwright-core. Needs the site built by tools/build-web (PENDULAB_SITE,
// default site/) and the CLI (PENDULAB_BIN, default target/release/pendulab). Prints the
// measured figures as one JSON line (`web-perf: {...}`) and writes the screenshots to
// target/web/ (PENDULAB_SHOTS).
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { spawn, spawnSync, execFileSync } from "node:child_process";
import { mkdtempSync, writeFileSync, readFileSync, mkdirSync, existsSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve, dirname } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";
import { chromium } from "playwright-core";

const root = resolve(dirname(fileURLToPath(import.meta.url)), "../..");
const site = resolve(root, process.env.PENDULAB_SITE || "site");
const bin = resolve(root, process.env.PENDULAB_BIN || "target/release/pendulab");
const shots = resolve(root, process.env.PENDULAB_SHOTS || "target/web");
const chromiumPath = process.env.CHROMIUM || "/usr/bin/chromium";
const work = mkdtempSync(join(tmpdir(), "pendulab-web-"));
const perf = {};

let context, page;
const consoleErrors = [];

before(async () => {
  assert.ok(existsSync(join(site, "index.html")), `no site at ${site}: run tools/build-web first`);
  assert.ok(existsSync(bin), `no CLI at ${bin}: cargo build -p pendulab --release`);
  context = await chromium.launchPersistentContext(mkdtempSync(join(tmpdir(), "pendulab-chromium-")), {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: 1400, height: 1000 },
    args: [
      "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
    ],
  });
  page = context.pages()[0] || (await context.newPage());
  page.on("console", (m) => { if (m.type() === "error") consoleErrors.push(m.text()); });
  page.on("pageerror", (e) => consoleErrors.push(String(e)));
  await page.goto(pathToFileURL(join(site, "index.html")).href);
  await page.waitForFunction(() => window.pendulab && window.pendulab.ready, null, { timeout: 20000 });
});

after(async () => {
  console.log("web-perf: " + JSON.stringify(perf));
  if (context) await context.close();
});

test("the page loads from file:// with no console errors", async () => {
  await page.waitForTimeout(1000);
  assert.deepEqual(consoleErrors, []);
  // The book's LQR at start: K = [3.16228, 13.47175, 4.48137, 2.26289] (IP Toolbox
  // cdip_lqr_sim.m, u = +K x, 5 decimals); the page shows the library's −K.
  const gain = JSON.parse(await page.locator("#gain").getAttribute("data-gain"));
  [3.16228, 13.47175, 4.48137, 2.26289].forEach((k, i) => assert.ok(Math.abs(gain[i] + k) <= 5e-6, `K = ${gain}`));
});

test("the cart balances for 10 s after a poke of 5°", async () => {
  await page.click("#reset");
  await page.waitForTimeout(500);
  const t0 = await page.evaluate(() => window.pendulab.snapshot().t);
  await page.click("#poke-right");
  // The simulation follows the wall clock: wait until 10 s of simulated time have passed.
  await page.waitForFunction((t) => window.pendulab.snapshot().t >= t + 10.2, t0, { timeout: 30000 });
  const r = await page.evaluate((t) => {
    const rows = window.pendulab.csv().trim().split("\n").slice(1).map((l) => l.split(",").map(Number));
    const after = rows.filter((row) => row[0] >= t);
    return {
      n: after.length,
      maxTheta: Math.max(...after.map((row) => Math.abs(row[2]))),
      maxZ: Math.max(...after.map((row) => Math.abs(row[1]))),
      last: window.pendulab.snapshot(),
      stats: window.pendulab.frameStats(),
    };
  }, t0);
  assert.ok(r.n >= 10000, `${r.n} samples`);
  assert.ok(r.maxTheta < 5.5 * Math.PI / 180, `θ reached ${r.maxTheta} rad`);
  assert.ok(r.maxZ < 0.4, `z reached ${r.maxZ} m`);
  assert.ok(Math.abs(r.last.angle) < 0.5 * Math.PI / 180, `θ = ${r.last.angle} rad at the end`);
  const median = (a) => { const s = a.slice().sort((x, y) => x - y); return s[Math.floor(s.length / 2)]; };
  perf.frame_work_ms_median = median(r.stats.workMs);
  perf.frame_interval_ms_median = median(r.stats.intervalMs);
  perf.frames = r.stats.workMs.length;
  assert.ok(perf.frame_work_ms_median <= 16.7, `median frame ${perf.frame_work_ms_median} ms`);
  assert.deepEqual(consoleErrors, []);
});

test("moving the Q slider gives the gain of `pendulab lqr` (1e-9)", async () => {
  const slider = page.locator("#q1");
  await slider.focus();
  for (let i = 0; i < 12; i++) await page.keyboard.press("ArrowRight");
  const { weights, design } = await page.evaluate(() => ({ weights: window.pendulab.weights(), design: window.pendulab.design() }));
  assert.equal(weights.method, "lqr");
  assert.ok(Math.abs(weights.q[1] - Math.pow(10, 1.6)) < 1e-9 * weights.q[1], `q = ${weights.q}`);
  const rows = (m, n) => Array.from({ length: m.length / n }, (_, i) => m.slice(i * n, i * n + n).map(String).join(", ")).join("\n") + "\n";
  const diag = (q) => q.map((v, i) => q.map((_, j) => (i === j ? String(v) : "0")).join(", ")).join("\n") + "\n";
  writeFileSync(join(work, "A.txt"), rows(design.a, 4));
  writeFileSync(join(work, "B.txt"), rows(design.b, 1));
  writeFileSync(join(work, "Q.txt"), diag(weights.q));
  writeFileSync(join(work, "R.txt"), String(weights.r) + "\n");
  const out = JSON.parse(execFileSync(bin, ["lqr", "--a", join(work, "A.txt"), "--b", join(work, "B.txt"),
    "--q", join(work, "Q.txt"), "--r", join(work, "R.txt"), "--json"]).toString());
  const native = out.gain[0];
  const shown = JSON.parse(await page.locator("#gain").getAttribute("data-gain"));
  assert.equal(shown.length, 4);
  for (let i = 0; i < 4; i++) {
    assert.ok(Math.abs(shown[i] - native[i]) <= 1e-9 * Math.max(1, Math.abs(native[i])), `K[${i}]: ${shown[i]} vs ${native[i]}`);
  }
  // Redesign time in WebAssembly: LQR (n = 4) and the servo (n = 5), per call.
  perf.redesign_us = await page.evaluate(() => {
    const lab = window.pendulab.lab;
    const time = (f) => { const n = 2000; f(); const t = performance.now(); for (let i = 0; i < n; i++) f(); return ((performance.now() - t) / n) * 1000; };
    const lqr = time(() => lab.design("lqr", { q: [10, 10, 0, 0], r: 1 }));
    const servo = time(() => lab.design("servo", { q: [1, 5, 0, 0, 100], r: 1 }));
    lab.design("lqr", { q: window.pendulab.weights().q, r: window.pendulab.weights().r });
    return { lqr, servo };
  });
  assert.deepEqual(consoleErrors, []);
});

test("the exported controller file runs in `pendulab rig run` against `pendulab rig emulate`", async () => {
  await page.click("#export-toml");
  const toml = await page.locator("#toml-out").inputValue();
  assert.match(toml, /^# Designed in the pendulab browser lab/);
  assert.match(toml, /kind = "state-feedback"/);
  const file = join(work, "controller.toml");
  writeFileSync(file, toml);
  const emu = spawn(bin, ["rig", "emulate", "--plant", "cart", "--listen", "127.0.0.1:0", "--theta0-deg", "3", "--duration", "30"], { stdio: ["ignore", "pipe", "inherit"] });
  try {
    const addr = await new Promise((ok, fail) => {
      let buf = "";
      emu.stdout.on("data", (d) => {
        buf += d;
        const m = buf.match(/listening on (\S+)/);
        if (m) ok(m[1]);
      });
      emu.on("exit", (c) => fail(new Error(`emulator exited ${c}`)));
    });
    const log = join(work, "run.csv");
    // The watchdog at its widest (0.5 s): a loaded machine can starve the emulator's thread.
    const run = spawnSync(bin, ["rig", "run", "--connect", addr, "--controller", file, "--log", log, "--duration", "3",
      "--watchdog-periods", "500"]);
    const out = run.stdout.toString();
    assert.equal(run.status, 0, out + run.stderr.toString());
    assert.match(out, /stop: completed/);
    const lines = readFileSync(log, "utf8").trim().split("\n");
    const head = lines[0].split(",");
    const ti = head.indexOf("theta");
    assert.ok(ti >= 0, head.join(","));
    const last = lines[lines.length - 1].split(",").map(Number);
    assert.ok(lines.length > 2900, `${lines.length} rows`);
    assert.ok(Math.abs(last[ti]) < 2 * Math.PI / 180, `θ = ${last[ti]} rad after 3 s`);
  } finally {
    emu.kill("SIGINT");
  }
});

test("screenshots at 390 px and 1400 px", async () => {
  mkdirSync(shots, { recursive: true });
  await page.setViewportSize({ width: 1400, height: 1000 });
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.waitForTimeout(800);
  await page.screenshot({ path: join(shots, "lab-1400.png"), fullPage: true });
  await page.setViewportSize({ width: 390, height: 844 });
  await page.waitForTimeout(800);
  await page.screenshot({ path: join(shots, "lab-390.png"), fullPage: true });
  // Readable at phone width: nothing wider than the screen.
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth);
  assert.ok(overflow <= 390, `page is ${overflow} px wide at 390 px`);
  assert.deepEqual(consoleErrors, []);
});
