// The page of the pendulab browser lab: the rig drawn and run in real time, the design panel,
// the live plots and the exports. All numbers come from the WebAssembly module (lab.js).
"use strict";

(async function () {
  const $ = (id) => document.getElementById(id);
  const status = (text, error) => {
    $("status").textContent = text;
    $("status").classList.toggle("error", !!error);
  };
  const DEG = Math.PI / 180;
  const TS = 1e-3; // the rigs' sample time [s] (docs/model.md §3)
  const HISTORY = 120000; // samples kept for the CSV (2 min at 1 kHz)
  const WINDOW = 10; // s shown in the live plots

  // The book's weights (docs/rig/examples: cart_lqr, arm_lqr, cart_lq_servo) and the poles
  // the placement panel starts from.
  const DEFAULTS = {
    cart: { lqr: [10, 10, 0, 0], servo: [1, 5, 0, 0, 100], r: 1, poles: [[-3, 2], [-3, -2], [-6, 0], [-7, 0]], ref: 0.1, unit: "m" },
    arm: { lqr: [5, 10, 0.1, 0.1], servo: [5, 10, 0.1, 0.1, 20], r: 1, poles: [[-4, 2], [-4, -2], [-7, 0], [-8, 0]], ref: 0.5, unit: "rad" },
  };
  const Q_LABELS = ["q₁ (q₀)", "q₂ (θ)", "q₃ (q̇₀)", "q₄ (θ̇)", "q₅ (∫e)"];

  let lab;
  try {
    lab = await window.PendulabLab.load();
  } catch (e) {
    status("The WebAssembly module did not load: " + e.message, true);
    throw e;
  }

  const state = {
    plant: "cart", method: "lqr", q: [], r: 1, alpha: 1, poles: [], design: null, lmiMs: [],
    paused: false, responseDirty: true, lastDesignUs: [], frameMs: [], intervalMs: [],
    simStart: 0, wallStart: 0,
    hist: { t: new Float64Array(HISTORY), q0: new Float64Array(HISTORY), q1: new Float64Array(HISTORY),
            v0: new Float64Array(HISTORY), v1: new Float64Array(HISTORY), u: new Float64Array(HISTORY), n: 0, head: 0 },
    snap: null, dragging: false,
  };

  // --- slider scale: position −4 means 0, else q = 10^position ---------------------------
  const toWeight = (p) => (p <= -4 ? 0 : Math.pow(10, p));
  const toPos = (q) => (q <= 0 ? -4 : Math.max(-3.95, Math.min(4, Math.log10(q))));
  const show = (v) => (v === 0 ? "0" : v >= 1000 || v < 0.01 ? v.toExponential(2) : String(+v.toPrecision(3)));

  function slider(id, label, value, onInput) {
    const wrap = document.createElement("div");
    wrap.className = "slider";
    wrap.innerHTML = `<label for="${id}">${label}</label><input id="${id}" type="range" min="-4" max="4" step="0.05"><output for="${id}"></output>`;
    const input = wrap.querySelector("input"), out = wrap.querySelector("output");
    input.value = toPos(value);
    const shown = (q) => { out.textContent = show(q); input.setAttribute("aria-valuetext", show(q)); };
    const update = () => { const q = toWeight(+input.value); shown(q); return q; };
    shown(value); // the weight in use (the slider's position is its nearest step)
    input.addEventListener("input", () => onInput(update()));
    return wrap;
  }

  function buildWeights() {
    const box = $("weights");
    box.innerHTML = "";
    $("poles-input").hidden = state.method !== "place";
    box.hidden = state.method === "place";
    if (state.method === "place") return buildPoles();
    state.q.forEach((v, i) => box.appendChild(slider(`q${i}`, Q_LABELS[i], v, (q) => { state.q[i] = q; redesign(); })));
    box.appendChild(slider("r", "R", state.r, (r) => { if (r > 0) { state.r = r; redesign(); } }));
    $("lmi-panel").hidden = !isLmi();
    if (isLmi()) {
      // The decay rate α of the pole region Re λ < −α (linear, 0 … 10 1/s).
      const wrap = document.createElement("div");
      wrap.className = "slider";
      wrap.innerHTML = `<label for="alpha">α [1/s]</label><input id="alpha" type="range" min="0" max="10" step="0.25"><output for="alpha"></output>`;
      const input = wrap.querySelector("input"), out = wrap.querySelector("output");
      input.value = state.alpha; out.textContent = String(state.alpha);
      input.addEventListener("input", () => { state.alpha = +input.value; out.textContent = String(state.alpha); redesign(); });
      box.appendChild(wrap);
    }
  }

  const isLmi = () => state.method === "lmi" || state.method === "lmi-servo";
  const servoWeights = () => state.method === "servo" || state.method === "lmi-servo";

  function buildPoles() {
    const box = $("poles-input");
    box.innerHTML = "<p class=\"small\">Closed-loop poles [1/s]: two real, one complex pair (re ± im).</p>";
    const mk = (id, label, v, set) => {
      const l = document.createElement("label");
      l.innerHTML = `${label} <input id="${id}" type="number" step="0.5" value="${v}">`;
      l.querySelector("input").addEventListener("input", (e) => { const x = parseFloat(e.target.value); if (isFinite(x)) { set(x); redesign(); } });
      return l;
    };
    const row = document.createElement("div");
    row.className = "row";
    const p = state.poles;
    row.appendChild(mk("pole-re", "pair re", p[0][0], (x) => { p[0][0] = x; p[1][0] = x; }));
    row.appendChild(mk("pole-im", "± im", Math.abs(p[0][1]), (x) => { p[0][1] = x; p[1][1] = -x; }));
    row.appendChild(mk("pole-3", "real", p[2][0], (x) => { p[2][0] = x; }));
    row.appendChild(mk("pole-4", "real", p[3][0], (x) => { p[3][0] = x; }));
    box.appendChild(row);
  }

  // --- design ------------------------------------------------------------------------------
  // [re, im] pairs of a flat array of poles (a design's `poles`, `open`: web/src/lab.js).
  const pairs = (flat) => Array.from({ length: flat.length / 2 }, (_, i) => [flat[2 * i], flat[2 * i + 1]]);

  function redesign() {
    const t0 = performance.now();
    try {
      const d = state.method === "place"
        ? lab.design("place", { poles: state.poles })
        : isLmi() ? lab.design("lmi", { q: state.q, r: state.r, alpha: state.alpha })
        : lab.design(state.method, { q: state.q, r: state.r });
      const us = (performance.now() - t0) * 1000;
      if (isLmi()) {
        state.lmiMs.push(us / 1000);
        if (state.lmiMs.length > 200) state.lmiMs.shift();
        $("lmi-cert").textContent = d.lmi.text;
        $("lmi-time").textContent = `${(us / 1000).toFixed(1)} ms (median ${median(state.lmiMs).toFixed(1)} ms of ${state.lmiMs.length}), in WebAssembly`;
      } else {
        state.lastDesignUs.push(us);
        if (state.lastDesignUs.length > 1000) state.lastDesignUs.shift();
      }
      state.design = d;
      state.responseDirty = true;
      const g = $("gain");
      const gain = Array.from(d.gain);
      g.textContent = "[" + gain.map((v) => v.toFixed(4)).join(", ") + "]";
      g.dataset.gain = JSON.stringify(gain);
      $("poles").textContent = pairs(d.poles).map(([re, im]) => im === 0 ? re.toFixed(3) : `${re.toFixed(3)}${im >= 0 ? "+" : "−"}${Math.abs(im).toFixed(3)}i`).join(", ");
      // Outside a cross-origin-isolated page (e.g. file://) the browser's timer resolves 100 µs.
      if (!isLmi()) $("redesign-time").textContent = `${median(state.lastDesignUs).toFixed(1)} µs (median of ${state.lastDesignUs.length})${window.crossOriginIsolated ? "" : ", timer resolution 100 µs"}`;
      window.PendulabPlot.poleMap($("polemap"), pairs(d.open), pairs(d.poles));
      status("");
    } catch (e) {
      status(e.message, true);
      if (isLmi()) $("lmi-cert").textContent = e.message;
    }
  }

  function drawResponse() {
    if (!state.design) return;
    const kind = $("response-kind").value;
    const d = DEFAULTS[state.plant];
    try {
      const r = kind === "initial" ? lab.response("initial", 5 * DEG, 4, 10) : lab.response("step", d.ref, 6, 10);
      const panels = [
        { title: kind === "initial" ? `predicted: θ [°] from 5°` : `predicted: q₀ [${d.unit}] to ${d.ref}`,
          series: kind === "initial" ? [{ t: r.t, y: r.q1.map((v) => v / DEG) }] : [{ t: r.t, y: r.q0 }] },
        { title: "u [V]", series: [{ t: r.t, y: r.u, color: "#8250df" }] },
      ];
      window.PendulabPlot.stacked($("response"), 0.62, 0, r.t[r.t.length - 1] || 1, panels);
    } catch (e) {
      status("response: " + e.message, true);
    }
    state.responseDirty = false;
  }

  // --- the rig -----------------------------------------------------------------------------
  function restart() {
    const up = $("mode").value !== "swing-up";
    lab.mode(!up);
    lab.reset(0, up ? 0 : Math.PI + 0.01); // a slight nudge: from rest exactly hanging, energy pumping has nothing to pump
    state.hist.n = 0; state.hist.head = 0;
    state.simStart = 0; state.wallStart = performance.now();
  }

  function choosePlant(kind, keepPlant) {
    state.plant = kind;
    const d = DEFAULTS[kind];
    if (!keepPlant) lab.init(kind);
    state.q = (servoWeights() ? d.servo : d.lqr).slice();
    state.r = d.r;
    state.poles = d.poles.map((p) => p.slice());
    $("ref-unit").textContent = `[${d.unit}]`;
    $("reference").value = d.ref;
    for (const el of document.querySelectorAll("[data-effect]")) lab.effect(window.PendulabLab.EFFECTS[el.dataset.effect], el.checked);
    lab.delay(+$("delay").value);
    buildWeights();
    redesign();
    restart();
    $("plant-text").value = lab.plantToml();
  }

  function record(t, q0, q1, v0, v1, u) {
    const h = state.hist, i = h.head;
    h.t[i] = t; h.q0[i] = q0; h.q1[i] = q1; h.v0[i] = v0; h.v1[i] = v1; h.u[i] = u;
    h.head = (i + 1) % HISTORY;
    if (h.n < HISTORY) h.n++;
  }

  // Samples in time order from `from` (s) on, every `every`-th.
  function history(from, every) {
    const h = state.hist, out = { t: [], q0: [], q1: [], u: [] };
    const start = (h.head - h.n + HISTORY) % HISTORY;
    for (let k = 0; k < h.n; k += every) {
      const i = (start + k) % HISTORY;
      if (h.t[i] < from) continue;
      out.t.push(h.t[i]); out.q0.push(h.q0[i]); out.q1.push(h.q1[i]); out.u.push(h.u[i]);
    }
    return out;
  }

  // The drawing scale: metres to CSS pixels, origin at the drive's pivot.
  function geometry(w, h) {
    if (state.plant === "cart") {
      const s = Math.min(w / 1.1, h / 0.62);
      return { s, ox: w / 2, oy: h * 0.8 };
    }
    const s = Math.min(w / 1.25, h / 1.2);
    return { s, ox: w / 2, oy: h * 0.55 };
  }

  function drawRig(snap) {
    const cv = $("rig");
    const { ctx, w, h } = window.PendulabPlot.fit(cv, 0.6);
    const { s, ox, oy } = geometry(w, h);
    const P = ([x, y]) => [ox + x * s, oy - y * s];
    ctx.lineCap = "round";
    if (state.plant === "cart") {
      ctx.fillStyle = "#e9edf3"; ctx.fillRect(ox - 0.5 * s, oy + 14, s, 6); // the rail, ±0.5 m
      ctx.fillStyle = "#b42318";
      for (const z of [-0.4, 0.4]) ctx.fillRect(ox + z * s - 1, oy + 8, 2, 16); // travel limits
      ctx.fillStyle = "#5b6677"; ctx.font = "11px system-ui"; ctx.fillText("travel ±0.4 m", ox - 34, oy + 38);
      const [px, py] = P(snap.pose[0]);
      ctx.fillStyle = "#1c2330"; ctx.fillRect(px - 0.07 * s, py - 10, 0.14 * s, 24);
      if (Math.abs(state.ref) > 0) { ctx.strokeStyle = "#1a7f37"; ctx.setLineDash([4, 4]); ctx.beginPath(); ctx.moveTo(ox + state.ref * s, oy + 26); ctx.lineTo(ox + state.ref * s, oy - 0.45 * s); ctx.stroke(); ctx.setLineDash([]); }
      line(ctx, P(snap.pose[0]), P(snap.pose[1]), "#1f6feb", 6);
    } else {
      ctx.fillStyle = "#1c2330"; ctx.beginPath(); ctx.arc(ox, oy, 8, 0, 2 * Math.PI); ctx.fill();
      line(ctx, [ox, oy], P(snap.pose[0]), "#1c2330", 8);
      line(ctx, P(snap.pose[0]), P(snap.pose[1]), "#1f6feb", 6);
    }
    const [tx, ty] = P(snap.pose[1]);
    ctx.fillStyle = state.dragging ? "#d1242f" : "#1f6feb"; ctx.beginPath(); ctx.arc(tx, ty, 9, 0, 2 * Math.PI); ctx.fill();
    ctx.fillStyle = "#1c2330"; ctx.font = "12px system-ui";
    ctx.fillText(`t = ${snap.t.toFixed(2)} s   θ = ${(snap.angle / DEG).toFixed(1)}°   ${state.plant === "cart" ? "z" : "θ₁"} = ${snap.x[0].toFixed(3)}   v = ${snap.u.toFixed(2)} V`, 8, 16);
  }

  function line(ctx, a, b, color, width) {
    ctx.strokeStyle = color; ctx.lineWidth = width;
    ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
  }

  function drawPlots(now) {
    const h = history(now - WINDOW, 10);
    const unit = DEFAULTS[state.plant].unit;
    window.PendulabPlot.stacked($("plots"), innerWidth > 760 ? 0.26 : 0.9, Math.max(0, now - WINDOW), Math.max(WINDOW, now), [
      { title: `${state.plant === "cart" ? "z" : "θ₁"} [${unit}]`, series: [{ t: h.t, y: h.q0 }] },
      { title: "θ [°]", series: [{ t: h.t, y: h.q1.map((v) => v / DEG), color: "#d1242f" }] },
      { title: "v [V]", series: [{ t: h.t, y: h.u, color: "#8250df" }] },
    ]);
  }

  function median(a) {
    if (!a.length) return NaN;
    const s = Float64Array.from(a).sort();
    return s.length % 2 ? s[(s.length - 1) / 2] : 0.5 * (s[s.length / 2 - 1] + s[s.length / 2]);
  }

  // --- the frame loop: the simulated time follows the wall clock at 1 kHz ------------------
  let lastFrame = 0, simDebt = 0;
  function frame(now) {
    const t0 = performance.now();
    if (lastFrame) state.intervalMs.push(now - lastFrame);
    const dt = lastFrame ? Math.min((now - lastFrame) / 1000, 0.1) : 0;
    lastFrame = now;
    let snap = state.snap;
    if (!state.paused) {
      simDebt += dt / TS;
      const n = Math.floor(simDebt);
      simDebt -= n;
      try {
        snap = lab.advance(n, 1, record);
      } catch (e) {
        status(e.message + " — reset to go on", true);
        state.paused = true;
      }
    }
    if (!snap) snap = lab.advance(0, 1, null);
    state.snap = snap;
    drawRig(snap);
    drawPlots(snap.t);
    if (state.responseDirty) drawResponse();
    const ms = performance.now() - t0;
    state.frameMs.push(ms);
    if (state.frameMs.length > 600) state.frameMs.shift();
    if (state.intervalMs.length > 600) state.intervalMs.shift();
    if (state.frameMs.length % 30 === 0) {
      $("perf").textContent = `frame work ${median(state.frameMs).toFixed(2)} ms (median), frame interval ${median(state.intervalMs).toFixed(1)} ms, 1 kHz physics`;
    }
    requestAnimationFrame(frame);
  }

  // --- controls ----------------------------------------------------------------------------
  state.ref = 0;
  $("plant").addEventListener("change", (e) => choosePlant(e.target.value));
  $("mode").addEventListener("change", () => restart());
  $("reset").addEventListener("click", () => { state.paused = false; $("pause").setAttribute("aria-pressed", "false"); $("pause").textContent = "Pause"; state.ref = 0; restart(); });
  $("pause").addEventListener("click", (e) => {
    state.paused = !state.paused;
    e.target.setAttribute("aria-pressed", String(state.paused));
    e.target.textContent = state.paused ? "Run" : "Pause";
  });
  $("poke-left").addEventListener("click", () => lab.poke(0, -5 * DEG));
  $("poke-right").addEventListener("click", () => lab.poke(0, 5 * DEG));
  $("ref-step").addEventListener("click", () => {
    const r = parseFloat($("reference").value);
    try { lab.reference(r); state.ref = r; } catch (e) { status(e.message, true); }
  });
  $("ref-zero").addEventListener("click", () => { lab.reference(0); state.ref = 0; });
  for (const el of document.querySelectorAll("[data-effect]")) {
    el.addEventListener("change", () => { try { lab.effect(window.PendulabLab.EFFECTS[el.dataset.effect], el.checked); state.responseDirty = true; } catch (e) { status(e.message, true); } });
  }
  $("delay").addEventListener("change", (e) => { lab.delay(+e.target.value); state.responseDirty = true; });
  for (const el of document.querySelectorAll("input[name=method]")) {
    el.addEventListener("change", () => {
      state.method = el.value;
      const d = DEFAULTS[state.plant];
      state.q = (servoWeights() ? d.servo : d.lqr).slice();
      buildWeights();
      redesign();
    });
  }
  $("response-kind").addEventListener("change", () => { state.responseDirty = true; });

  function download(name, type, text) {
    const a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([text], { type }));
    a.download = name;
    document.body.appendChild(a); a.click(); a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }
  function csv() {
    const h = state.hist, start = (h.head - h.n + HISTORY) % HISTORY;
    const head = state.plant === "cart" ? "t,z,theta,z_dot,theta_dot,v" : "t,theta1,theta2,theta1_dot,theta2_dot,v";
    const rows = [head];
    for (let k = 0; k < h.n; k++) {
      const i = (start + k) % HISTORY;
      rows.push(`${h.t[i]},${h.q0[i]},${h.q1[i]},${h.v0[i]},${h.v1[i]},${h.u[i]}`);
    }
    return rows.join("\n") + "\n";
  }
  $("export-toml").addEventListener("click", () => {
    const text = lab.controllerToml();
    $("toml-out").value = text;
    download(`${state.plant}_controller.toml`, "application/toml", text);
  });
  $("export-csv").addEventListener("click", () => download(`${state.plant}_run.csv`, "text/csv", csv()));
  $("plant-load").addEventListener("click", () => {
    try {
      lab.loadPlant($("plant-text").value);
      const kind = /kind\s*=\s*"arm"/.test($("plant-text").value) ? "arm" : "cart";
      $("plant").value = kind;
      choosePlant(kind, true);
      status("plant loaded");
    } catch (e) { status(e.message, true); }
  });
  $("plant-book").addEventListener("click", () => choosePlant(state.plant));

  // Drag the pendulum: pointer down near its tip holds it; the angle follows the pointer.
  const rig = $("rig");
  rig.tabIndex = 0;
  const pointerAngle = (ev) => {
    const r = rig.getBoundingClientRect();
    const { s, ox, oy } = geometry(r.width, r.height);
    const pivot = state.snap.pose[0];
    const px = ev.clientX - r.left - (ox + pivot[0] * s), py = (oy - pivot[1] * s) - (ev.clientY - r.top);
    return Math.atan2(px, py);
  };
  rig.addEventListener("pointerdown", (ev) => {
    if (!state.snap) return;
    state.dragging = true;
    rig.setPointerCapture(ev.pointerId);
    lab.hold(pointerAngle(ev));
  });
  rig.addEventListener("pointermove", (ev) => { if (state.dragging) lab.hold(pointerAngle(ev)); });
  const release = () => { if (state.dragging) { state.dragging = false; lab.hold(null); } };
  rig.addEventListener("pointerup", release);
  rig.addEventListener("pointercancel", release);
  rig.addEventListener("keydown", (ev) => {
    if (ev.key === "ArrowLeft") { lab.poke(0, -5 * DEG); ev.preventDefault(); }
    if (ev.key === "ArrowRight") { lab.poke(0, 5 * DEG); ev.preventDefault(); }
  });

  // --- the gain-scheduled arm servo beside the constant LQ servo (crates/web/src/compare.rs) --
  // The schedule's controller file and its weights come from gain_schedule.js (tools/build-web).
  function compareServos() {
    const gs = window.PENDULAB_GAIN_SCHEDULE;
    if (!gs) { $("gs-summary").textContent = "No schedule in this build (tools/build-web writes gain_schedule.js)."; return null; }
    if (state.plant !== "arm") { $("plant").value = "arm"; choosePlant("arm"); }
    const amp = +$("gs-amplitude").value * DEG;
    const t0 = performance.now();
    try {
      const r = lab.compare(gs.file, gs.q, gs.r, [[0.5, amp], [6.5, 0]], 12, 10);
      const ms = performance.now() - t0;
      const deg = (a) => a.map((v) => v / DEG);
      // Shown within ±m degrees: once a pendulum falls its arm spins away.
      const clip = (a, m) => a.map((v) => Math.max(-m, Math.min(m, v)));
      const GS = "#1f6feb", LQ = "#d4760a";
      window.PendulabPlot.stacked($("gs-plot"), innerWidth > 760 ? 0.33 : 0.9, 0, 12, [
        { title: "θ₁ [°] (within ±120°): reference (grey), gain-scheduled (blue), constant LQ (orange)", series: [
          { t: r.t, y: deg(r.r), color: "#8c959f" }, { t: r.t, y: clip(deg(r.gs.q0), 120), color: GS }, { t: r.t, y: clip(deg(r.lq.q0), 120), color: LQ }] },
        { title: "θ₂ [°] (within ±45°)", series: [{ t: r.t, y: clip(deg(r.gs.q1), 45), color: GS },
          { t: r.t, y: clip(deg(r.lq.q1), 45), color: LQ }] },
        { title: "v [V]", series: [{ t: r.t, y: r.gs.u, color: GS }, { t: r.t, y: r.lq.u, color: LQ }] },
      ]);
      const maxAbs = (a) => Math.max(...a.map(Math.abs)) / DEG;
      const fell = (a) => maxAbs(a) > 90;
      const at = r.t.findIndex((t) => t >= 6.4);
      const err = (a) => Math.abs(a[at] - amp) / DEG;
      const says = (name, run) => fell(run.q1) ? `${name}: the pendulum falls (|θ₂| > 90°)`
        : `${name}: |θ₁ − r| = ${err(run.q0).toFixed(1)}° at 6.4 s, max |θ₂| = ${maxAbs(run.q1).toFixed(1)}°`;
      $("gs-summary").textContent = `${says("gain-scheduled", r.gs)}; ${says("constant LQ", r.lq)}. Both runs (2 × 12 s at 1 kHz) took ${ms.toFixed(0)} ms.`;
      state.compare = { r, ms };
      return r;
    } catch (e) {
      $("gs-summary").textContent = e.message;
      status("comparison: " + e.message, true);
      return null;
    }
  }
  $("gs-run").addEventListener("click", () => compareServos());

  // The hooks the browser tests read (web/tests): the lab object and the page's numbers.
  window.pendulab = {
    lab,
    weights: () => ({ method: state.method, q: state.q.slice(), r: state.r }),
    // The current design with plain arrays (poles as [re, im] pairs): lab.js's result is
    // typed arrays, overwritten by the next design.
    design: () => state.design && {
      gain: Array.from(state.design.gain), poles: pairs(state.design.poles),
      a: Array.from(state.design.a), b: Array.from(state.design.b), open: pairs(state.design.open),
      lmi: state.design.lmi,
    },
    snapshot: () => state.snap,
    frameStats: () => ({ workMs: state.frameMs.slice(), intervalMs: state.intervalMs.slice() }),
    redesignUs: () => state.lastDesignUs.slice(),
    lmiMs: () => state.lmiMs.slice(),
    comparison: () => state.compare || null,
    csv,
    ready: true,
  };

  // Warm-up (docs/web.md, "Redesign time"): the engine compiles a WebAssembly function
  // lazily at its first call with its baseline compiler and recompiles it optimised only once
  // it is hot, so the first slider moves would run unoptimised code. A few hundred designs of
  // each slider method at load, in a row as a slider gives them (each starts from the last
  // one's gain: the path of a move), make the redesign path hot before anyone moves a slider.
  lab.init("cart");
  for (const [method, q] of [["lqr", [10, 10, 0, 0]], ["servo", [1, 5, 0, 0, 100]]]) {
    for (let i = 0; i < 300; i++) lab.design(method, { q, r: 1 + 1e-3 * i });
  }
  choosePlant("cart");
  requestAnimationFrame(frame);
})();
