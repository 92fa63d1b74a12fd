// Canvas drawing of the lab's figures: time series panels and the pole map. Layout only; the
// numbers come from the WebAssembly module (docs/web.md, "Charts").
"use strict";

(function () {
  const COLORS = ["#1f6feb", "#d1242f", "#1a7f37", "#8250df"];

  // Sizes the canvas's backing store to its CSS box × devicePixelRatio; returns the context
  // scaled to CSS pixels and the box.
  function fit(canvas, aspect) {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(100, canvas.clientWidth || canvas.width);
    const h = Math.round(aspect ? w * aspect : canvas.clientHeight || canvas.height);
    if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
      canvas.width = Math.round(w * dpr);
      canvas.height = Math.round(h * dpr);
    }
    const ctx = canvas.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);
    return { ctx, w, h };
  }

  function niceTicks(lo, hi, count) {
    const span = hi - lo || 1;
    const step0 = span / count;
    const mag = Math.pow(10, Math.floor(Math.log10(step0)));
    const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= step0) || step0;
    const ticks = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-12; v += step) ticks.push(Math.abs(v) < 1e-12 ? 0 : v);
    return ticks;
  }

  function fmt(v) {
    const a = Math.abs(v);
    if (a === 0) return "0";
    if (a >= 100 || a < 0.01) return v.toExponential(0);
    return String(+v.toPrecision(3));
  }

  // One panel: `series` = [{ t: [], y: [], color, label }], x from t0 to t1.
  function panel(ctx, box, t0, t1, series, title) {
    const { x, y, w, h } = box;
    const left = x + 44, right = x + w - 8, top = y + 16, bottom = y + h - 18;
    let lo = Infinity, hi = -Infinity;
    for (const s of series) for (const v of s.y) { if (v < lo) lo = v; if (v > hi) hi = v; }
    if (!isFinite(lo)) { lo = -1; hi = 1; }
    const pad = Math.max((hi - lo) * 0.1, 1e-3);
    lo -= pad; hi += pad;
    const X = (t) => left + ((t - t0) / (t1 - t0 || 1)) * (right - left);
    const Y = (v) => bottom - ((v - lo) / (hi - lo)) * (bottom - top);
    ctx.font = "11px system-ui, sans-serif";
    ctx.strokeStyle = "#e3e7ee"; ctx.fillStyle = "#5b6677"; ctx.lineWidth = 1;
    for (const v of niceTicks(lo, hi, 3)) {
      ctx.beginPath(); ctx.moveTo(left, Y(v)); ctx.lineTo(right, Y(v)); ctx.stroke();
      ctx.fillText(fmt(v), x + 2, Y(v) + 4);
    }
    for (const t of niceTicks(t0, t1, 5)) ctx.fillText(fmt(t), X(t) - 6, bottom + 13);
    ctx.strokeStyle = "#b8c0cc"; ctx.strokeRect(left, top, right - left, bottom - top);
    ctx.fillStyle = "#1c2330"; ctx.fillText(title, left + 4, top - 4);
    series.forEach((s, i) => {
      ctx.strokeStyle = s.color || COLORS[i % COLORS.length]; ctx.lineWidth = 1.5;
      ctx.beginPath();
      let first = true;
      for (let k = 0; k < s.t.length; k++) {
        if (s.t[k] < t0) continue;
        const px = X(s.t[k]), py = Y(s.y[k]);
        if (first) { ctx.moveTo(px, py); first = false; } else ctx.lineTo(px, py);
      }
      ctx.stroke();
      if (s.label) { ctx.fillStyle = ctx.strokeStyle; ctx.fillText(s.label, right - 70 - 60 * i, top - 4); }
    });
  }

  // Stacked panels sharing the time axis: panels = [{ title, series }].
  function stacked(canvas, aspect, t0, t1, panels) {
    const { ctx, w, h } = fit(canvas, aspect);
    const wide = w > 700 && panels.length > 1;
    const n = panels.length;
    panels.forEach((p, i) => {
      const box = wide
        ? { x: (i * w) / n, y: 0, w: w / n, h }
        : { x: 0, y: (i * h) / n, w, h: h / n };
      panel(ctx, box, t0, t1, p.series, p.title);
    });
  }

  // The s-plane: open-loop poles as circles, closed-loop ones as crosses ([re, im] pairs).
  function poleMap(canvas, open, closed) {
    const { ctx, w, h } = fit(canvas, 0.62);
    const all = open.concat(closed);
    const reach = Math.max(1, ...all.map(([re, im]) => Math.max(Math.abs(re), Math.abs(im)))) * 1.15;
    const cx = w * 0.62, cy = h / 2, sc = Math.min((w * 0.58) / reach, (h * 0.45) / reach);
    ctx.font = "11px system-ui, sans-serif";
    ctx.fillStyle = "#fff4f4"; ctx.fillRect(cx, 0, w - cx, h);
    ctx.strokeStyle = "#b8c0cc"; ctx.lineWidth = 1;
    ctx.beginPath(); ctx.moveTo(0, cy); ctx.lineTo(w, cy); ctx.moveTo(cx, 0); ctx.lineTo(cx, h); ctx.stroke();
    ctx.fillStyle = "#5b6677";
    for (const v of niceTicks(-reach, reach * 0.6, 4)) {
      if (v === 0) continue;
      const px = cx + v * sc;
      if (px < 8 || px > w - 8) continue;
      ctx.fillText(fmt(v), px - 8, cy + 13);
    }
    ctx.fillText("Re [1/s]", w - 52, cy - 6);
    ctx.fillText("Im", cx + 4, 12);
    ctx.strokeStyle = "#5b6677"; ctx.lineWidth = 1.5;
    for (const [re, im] of open) { ctx.beginPath(); ctx.arc(cx + re * sc, cy - im * sc, 5, 0, 2 * Math.PI); ctx.stroke(); }
    ctx.strokeStyle = "#d1242f"; ctx.lineWidth = 2;
    for (const [re, im] of closed) {
      const px = cx + re * sc, py = cy - im * sc;
      ctx.beginPath(); ctx.moveTo(px - 5, py - 5); ctx.lineTo(px + 5, py + 5); ctx.moveTo(px - 5, py + 5); ctx.lineTo(px + 5, py - 5); ctx.stroke();
    }
    ctx.fillStyle = "#5b6677"; ctx.fillText("○ open loop   × closed loop", 6, h - 6);
  }

  window.PendulabPlot = { fit, stacked, poleMap, COLORS };
})();
