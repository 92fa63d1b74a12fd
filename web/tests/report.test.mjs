// The lab report (docs/report.md) in a real browser: headless Chromium (the Debian package)
// driven by playwright-core, as tests/lab.test.mjs. Writes a small report with the CLI
// (PENDULAB_BIN, default target/release/pendulab) — an animation, wide value tables and the
// p2c15 gain grid — and opens it from file:// at 390, 800 and 1400 px and for print. The
// screenshots and the PDF go to a temporary directory (PENDULAB_REPORT_SHOTS to choose it),
// named in the log.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import { mkdtempSync, mkdirSync, readFileSync, existsSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve, dirname } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";
import { chromium } from "playwright-core";

const root = resolve(dirname(fileURLToPath(import.meta.url)), "../..");
const bin = resolve(root, process.env.PENDULAB_BIN || "target/release/pendulab");
const chromiumPath = process.env.CHROMIUM || "/usr/bin/chromium";
const work = mkdtempSync(join(tmpdir(), "pendulab-report-"));
const shots = process.env.PENDULAB_REPORT_SHOTS ? resolve(process.env.PENDULAB_REPORT_SHOTS) : join(work, "shots");
const out = join(work, "report");
// p2c15: the gain grid (two columns of panels) and an arm animation; p2c13: the widest value
// tables (4×4 matrices beside the book's); p1c322: a figure whose legend had covered data.
// A lab directory (lab init, design lqr, simulate) gives the lab notebook (report --lab),
// checked at 390 px.
const ids = ["p2c15_ex7_adip_oc_gs_servo", "p2c13_ex5_adip_oc_robust_servo", "p1c322_cdip_id_least_square"];
const widths = [390, 800, 1400];
// 9 pt in CSS pixels: the smallest text a figure may show.
const MIN_TEXT_PX = 12;

let browser;

before(async () => {
  assert.ok(existsSync(bin), `no CLI at ${bin}: cargo build -p pendulab --release`);
  mkdirSync(shots, { recursive: true });
  const args = ["report", "--out", out, ...ids.flatMap((id) => ["--only", id])];
  const r = spawnSync(bin, args, { encoding: "utf8", timeout: 120000 });
  assert.equal(r.status, 0, `pendulab ${args.join(" ")}: ${r.stderr}`);
  browser = await chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: [
      "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
    ],
  });
  console.log(`report screenshots: ${shots}`);
});

after(async () => {
  if (browser) await browser.close();
});

/** A page at `width` px showing the report, its console errors and network requests collected. */
async function open(width) {
  const page = await browser.newPage({ viewport: { width, height: 900 } });
  const errors = [];
  const requests = [];
  page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("request", (r) => requests.push(r.url()));
  await page.goto(pathToFileURL(join(out, "index.html")).href);
  // Load every (lazy) image now and wait for all of them.
  await page.evaluate(async () => {
    const imgs = [...document.images];
    imgs.forEach((i) => { i.loading = "eager"; });
    await Promise.all(imgs.map((i) => (i.complete ? Promise.resolve() : new Promise((ok) => {
      i.addEventListener("load", ok, { once: true });
      i.addEventListener("error", ok, { once: true });
    }))));
  });
  return { page, errors, requests };
}

/** Smallest `font-size` in an SVG file of the report. */
function smallestFont(relPath) {
  const svg = readFileSync(join(out, decodeURIComponent(relPath)), "utf8");
  const sizes = [...svg.matchAll(/font-size="([0-9.]+)(px)?"/g)].map((m) => Number(m[1]));
  return sizes.length ? Math.min(...sizes) : Infinity;
}

for (const width of widths) {
  test(`at ${width} px: no horizontal overflow, every image loads, the contents link stays, fonts`, async () => {
    const { page, errors, requests } = await open(width);
    try {
      const m = await page.evaluate(() => ({
        scrollWidth: document.documentElement.scrollWidth,
        innerWidth: window.innerWidth,
        images: [...document.images].map((i) => ({
          src: i.getAttribute("src"), natural: i.naturalWidth, shown: i.getBoundingClientRect().width,
        })),
        players: [...document.querySelectorAll(".player svg")].map((s) => ({
          natural: s.viewBox.baseVal.width, shown: s.getBoundingClientRect().width,
          font: Math.min(...[...s.querySelectorAll("[font-size]")].map((e) => parseFloat(e.getAttribute("font-size")))),
        })),
        articles: document.querySelectorAll("article.example").length,
      }));
      assert.ok(m.scrollWidth <= m.innerWidth, `page ${m.scrollWidth} px wide in a ${m.innerWidth} px window`);
      assert.equal(m.articles, ids.length);
      assert.ok(m.images.length >= 4, `${m.images.length} images`);
      for (const i of m.images) assert.ok(i.natural > 0, `${i.src} did not load`);
      assert.ok(m.players.length >= 1, "no animation player");
      // Nothing outside the report directory is fetched: no network, no absolute path.
      for (const u of requests) {
        assert.ok(u.startsWith(pathToFileURL(out).href), `request outside the report: ${u}`);
      }
      // A wide table scrolls inside its card, not the page.
      const tables = await page.evaluate(() => [...document.querySelectorAll(".scroll")].map((d) => ({
        inside: d.getBoundingClientRect().right <= document.documentElement.clientWidth + 0.5,
        scrolls: d.scrollWidth > d.clientWidth,
      })));
      assert.ok(tables.every((t) => t.inside), "a table sticks out of the page");
      if (width === 390) assert.ok(tables.some((t) => t.scrolls), "no table needed to scroll at 390 px");
      // At every width each figure is shown at its own size (scrolling sideways inside its
      // card when the screen is narrower): its text stays ≥ 9 pt = 12 CSS px, from the SVG's
      // font sizes times the rendered scale.
      for (const i of m.images.filter((i) => i.src.endsWith(".svg"))) {
        const px = smallestFont(i.src) * (i.shown / i.natural);
        assert.ok(px >= MIN_TEXT_PX - 1e-6, `${i.src}: text ${px.toFixed(1)} px (${i.shown}/${i.natural})`);
      }
      for (const p of m.players) {
        assert.ok(Math.abs(p.shown - p.natural) < 0.5, `animation shown at ${p.shown} of ${p.natural} px`);
        if (Number.isFinite(p.font)) assert.ok(p.font * (p.shown / p.natural) >= MIN_TEXT_PX - 1e-6, `animation text ${p.font} px`);
      }
      // A figure wider than the screen scrolls inside its frame, which stays inside the page,
      // and its caption says so.
      const frames = await page.evaluate(() => [...document.querySelectorAll(".figscroll")].map((d) => ({
        inside: d.getBoundingClientRect().right <= document.documentElement.clientWidth + 0.5,
        scrolls: d.scrollWidth > d.clientWidth + 0.5,
        hint: getComputedStyle(d.closest("figure").querySelector(".fighint")).display !== "none",
      })));
      assert.ok(frames.length >= 4, `${frames.length} figure frames`);
      assert.ok(frames.every((f) => f.inside), "a figure frame sticks out of the page");
      if (width < 1076) assert.ok(frames.some((f) => f.scrolls), `no figure scrolls at ${width} px`);
      for (const f of frames.filter((f) => f.scrolls)) assert.ok(f.hint, "a scrolling figure without its hint");
      await page.screenshot({ path: join(shots, `report-${width}.png`), fullPage: true });
      // The sticky contents link: visible after scrolling to the end, and it leads back.
      await page.evaluate(() => window.scrollTo(0, document.documentElement.scrollHeight));
      await page.waitForTimeout(100);
      const up = page.locator(".topbar a.up");
      assert.ok(await up.isVisible());
      const box = await up.boundingBox();
      assert.ok(box && box.y >= 0 && box.y + box.height <= 900, `contents link at ${JSON.stringify(box)}`);
      assert.ok(await page.evaluate(() => window.scrollY) > 1000);
      await page.screenshot({ path: join(shots, `report-${width}-end.png`) });
      await up.click();
      await page.waitForTimeout(200);
      const toc = await page.evaluate(() => document.getElementById("contents").getBoundingClientRect().top);
      assert.ok(toc >= 0 && toc < 120, `contents at ${toc} px after the click`);
      assert.deepEqual(errors, []);
    } finally {
      await page.close();
    }
  });
}

test("the lab notebook at 390 px: the report's responsive layout, no horizontal overflow", async () => {
  const lab = join(work, "lab");
  for (const args of [
    ["lab", "init", lab, "--plant", "cart"],
    ["design", "lqr", "--lab", lab, "--q", "10 10 0 0", "--r", "1"],
    ["simulate", "--lab", lab, "--controller", join(lab, "designs", "lqr.toml")],
    ["report", "--lab", lab],
  ]) {
    const r = spawnSync(bin, args, { encoding: "utf8", timeout: 120000 });
    assert.equal(r.status, 0, `pendulab ${args.join(" ")}: ${r.stderr}`);
  }
  const page = await browser.newPage({ viewport: { width: 390, height: 900 } });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  try {
    await page.goto(pathToFileURL(join(lab, "report", "index.html")).href);
    const m = await page.evaluate(() => ({
      scrollWidth: document.documentElement.scrollWidth,
      innerWidth: window.innerWidth,
      viewport: !!document.querySelector('meta[name="viewport"]'),
      tables: [...document.querySelectorAll("table")].map((t) => !!t.closest(".scroll")),
      frames: [...document.querySelectorAll(".figscroll")].map((d) => d.getBoundingClientRect().right <= document.documentElement.clientWidth + 0.5),
      images: [...document.images].map((i) => ({ src: i.getAttribute("src"), natural: i.naturalWidth, shown: i.getBoundingClientRect().width })),
    }));
    assert.ok(m.viewport, "no viewport meta");
    assert.ok(m.scrollWidth <= m.innerWidth, `notebook ${m.scrollWidth} px wide in a ${m.innerWidth} px window`);
    assert.ok(m.tables.length >= 1 && m.tables.every(Boolean), "a table outside a scrolling card");
    assert.ok(m.frames.length >= 1 && m.frames.every(Boolean), "a figure frame sticks out of the page");
    for (const i of m.images) assert.ok(i.natural > 0, `${i.src} did not load`);
    await page.screenshot({ path: join(shots, "lab-notebook-390.png"), fullPage: true });
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});

test("the animation pauses, plays and follows its time scrubber, by keyboard", async () => {
  const { page, errors } = await open(800);
  try {
    const player = page.locator(".player").first();
    await player.scrollIntoViewIfNeeded();
    const button = player.locator("button");
    const range = player.locator('input[type="range"]');
    assert.ok(await button.isVisible(), "no pause button");
    assert.ok(await range.isVisible(), "no scrubber");
    const paused = () => player.evaluate((p) => p.querySelector("svg").animationsPaused());
    assert.equal(await paused(), false);
    // Space on the focused button pauses, again plays.
    await button.focus();
    await page.keyboard.press("Space");
    assert.equal(await paused(), true);
    assert.equal(await button.textContent(), "Play");
    await page.keyboard.press("Space");
    assert.equal(await paused(), false);
    // Tab reaches the scrubber; Home goes to t = 0 and pauses; PageUp steps forward.
    await page.keyboard.press("Tab");
    assert.ok(await range.evaluate((r) => r === document.activeElement), "Tab does not reach the scrubber");
    // Where the moving parts are: the boxes of the elements under each animateTransform.
    const frame = () => player.evaluate((p) => {
      const svg = p.querySelector("svg");
      return {
        t: svg.getCurrentTime(),
        boxes: [...svg.querySelectorAll("animateTransform")].map((a) => {
          const r = a.parentElement.getBoundingClientRect();
          return [r.x, r.y, r.width, r.height].map((v) => Math.round(v * 10) / 10);
        }),
      };
    });
    await page.keyboard.press("Home");
    assert.equal(await paused(), true);
    const start = await frame();
    assert.ok(Math.abs(start.t) < 1e-6, `t = ${start.t} at Home`);
    await page.screenshot({ path: join(shots, "report-animation-start.png"), clip: await player.boundingBox() });
    for (let k = 0; k < 3; k++) await page.keyboard.press("PageUp");
    const later = await frame();
    const value = Number(await range.inputValue());
    assert.ok(value > 0, `scrubber at ${value}`);
    assert.ok(Math.abs(later.t - value) < 0.011, `clock ${later.t} s, scrubber ${value} s`);
    assert.notDeepEqual(later.boxes, start.boxes, "the frame did not move");
    assert.equal(await player.locator("output").textContent(), `${value.toFixed(2)} s`);
    await page.screenshot({ path: join(shots, "report-animation-later.png"), clip: await player.boundingBox() });
    // Still paused: the frame stays.
    await page.waitForTimeout(300);
    assert.deepEqual((await frame()).boxes, later.boxes);
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});

test("print: no bar or controls, one example per page, figures whole", async () => {
  const { page, errors } = await open(800);
  try {
    await page.emulateMedia({ media: "print" });
    const css = await page.evaluate(() => ({
      bar: getComputedStyle(document.querySelector(".topbar")).display,
      controls: [...document.querySelectorAll(".controls")].map((c) => getComputedStyle(c).display),
      article: getComputedStyle(document.querySelector("article.example + article.example") || document.querySelector("article.example")).breakBefore,
      figure: getComputedStyle(document.querySelector("figure")).breakInside,
    }));
    assert.equal(css.bar, "none");
    assert.ok(css.controls.every((d) => d === "none"), JSON.stringify(css.controls));
    assert.equal(css.figure, "avoid");
    await page.screenshot({ path: join(shots, "report-print.png"), fullPage: true });
    const pdf = await page.pdf({ format: "A4", printBackground: true });
    writeFileSync(join(shots, "report.pdf"), pdf);
    // Contents, then each example on its own page(s).
    const pages = (pdf.toString("latin1").match(/\/Type\s*\/Page[^s]/g) || []).length;
    assert.ok(pages >= 1 + ids.length, `${pages} PDF pages for ${ids.length} examples`);
    assert.deepEqual(errors, []);
  } finally {
    await page.close();
  }
});
