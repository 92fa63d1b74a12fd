// The loader of the pendulab browser lab (docs/web.md, "Interface"): instantiates the
// WebAssembly module built from crates/web and wraps its C ABI (crates/web/src/ffi.rs) in a
// small object. No generated glue; numbers go through one f64
// buffer in its linear memory, text through a byte buffer.
//
// The module's bytes come from `pendulab_web.wasm.js` (the .wasm as base64, written by
// tools/build-web), so the page also works from file://, where fetch() of a .wasm is refused.
"use strict";

(function () {
  const IO_LEN = 16384;
  const RECORD = 6; // [t, q0, q1, q0', q1', u]  (crates/web/src/lab.rs, RECORD)
  const STATE = 16; // the state block of pl_advance (crates/web/src/ffi.rs, STATE)
  const DESIGN_LEN = 44; // the design block, up to DESIGN_LMI (crates/web/src/ffi.rs)
  const METHODS = { lqr: 0, servo: 1, place: 2, lmi: 3 }; // pl_design's method numbers

  function decodeBase64(text) {
    const bin = atob(text);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return bytes;
  }

  async function load(bytes) {
    const module = await WebAssembly.compile(bytes || decodeBase64(window.PENDULAB_WASM));
    // tools/build-web's module imports nothing; a plain cargo build carries getrandom's unused
    // wasm-bindgen imports (docs/web.md, "Randomness"), answered here by functions that throw.
    const imports = {};
    for (const imp of WebAssembly.Module.imports(module)) {
      (imports[imp.module] = imports[imp.module] || {})[imp.name] = () => {
        throw new Error(`${imp.module}.${imp.name} is not available in the lab`);
      };
    }
    const instance = await WebAssembly.instantiate(module, imports);
    const x = instance.exports;
    const mem = () => x.memory.buffer;
    // The number buffer's address is fixed for the module's life (crates/web/src/ffi.rs,
    // pl_io); its view is made again only when the memory has grown, which detaches the old
    // buffer and leaves the view empty (a length test: reading `memory.buffer` on every call
    // costs an engine call).
    const ioAt = x.pl_io();
    let ioView = new Float64Array(mem(), ioAt, IO_LEN);
    const io = () => {
      if (ioView.length === 0) ioView = new Float64Array(mem(), ioAt, IO_LEN);
      return ioView;
    };
    const utf8 = new TextDecoder();
    const textOut = () => utf8.decode(new Uint8Array(mem(), x.pl_text_out(), x.pl_text_out_len()));
    const check = (rc) => {
      if (rc < 0) throw new Error(textOut());
      return rc;
    };

    // A design's result of order n: one Float64Array laid out as the number buffer's design
    // block (crates/web/src/ffi.rs, DESIGN_GAIN … DESIGN_LMI), and views of it made once: the
    // gain (n), the closed-loop poles (n pairs re, im, flat), the linearisation's A (16,
    // row-major), B (4) and open-loop poles (4 pairs re, im, flat).
    const designOutput = (n) => {
      const all = new Float64Array(DESIGN_LEN);
      return {
        all, gain: all.subarray(0, n), poles: all.subarray(6, 6 + 2 * n),
        a: all.subarray(16, 32), b: all.subarray(32, 36), open: all.subarray(36, 44),
      };
    };
    const designs = {};

    const lab = {
      exports: x,
      init(kind) { check(x.pl_init(kind === "arm" ? 1 : 0)); },
      loadPlant(text) {
        const bytes = new TextEncoder().encode(text);
        new Uint8Array(mem(), x.pl_text_in(bytes.length), bytes.length).set(bytes);
        check(x.pl_load_plant());
      },
      // method: "lqr" (q: 4), "servo" (q: 5), "place" (poles: [[re, im] x 4]), "lmi" (q: 4
      // or 5, r, alpha: the LMI guaranteed-cost LQ design with decay rate alpha, solved by
      // pendulab-lmi's dense interior-point method; 5 weights: the integral servo).
      // The result of a design other than the LMI one is one of two objects (n = 4, 5) that
      // each design of that order fills in place, so that a slider move allocates nothing: it
      // is the lab's current design, overwritten by the next one (copy what you keep). A
      // design that fails leaves it as it was. One plain loop into one typed array, no array
      // builtins: a move runs this after a frame or more of other work, with the engine's
      // caches cold, where filling a dozen small arrays cost about 5 µs more (docs/web.md,
      // "Redesign time").
      design(method, args) {
        const b = io();
        const m = METHODS[method];
        if (m === undefined) throw new Error(`unknown design method ${method}`);
        if (m === 2) {
          const p = args.poles;
          for (let i = 0; i < p.length; i++) { b[2 * i] = p[i][0]; b[2 * i + 1] = p[i][1]; }
        } else {
          const q = args.q;
          for (let i = 0; i < q.length; i++) b[i] = q[i];
        }
        if (m === 3) { b[5] = args.q.length; b[6] = args.alpha; }
        check(x.pl_design(m, m === 2 ? 0 : args.r));
        const o = io();
        const n = o[5];
        const d = m === 3 ? designOutput(n) : (designs[n] ||= designOutput(n));
        const all = d.all;
        for (let i = 0; i < DESIGN_LEN; i++) all[i] = o[i];
        if (m === 3) {
          // The certificate (crates/web/src/ffi.rs, DESIGN_LMI) and its sentence.
          d.lmi = {
            status: o[44] === 1 ? "solved" : "solved (reduced accuracy)", iterations: o[45],
            constraints: o[46], minSlack: o[47], traceX: o[48], inRegion: o[49] === 1, text: textOut(),
          };
        }
        return d;
      },
      mode(swingUp) { check(x.pl_mode(swingUp ? 1 : 0)); },
      reset(q0, q1) { check(x.pl_reset(q0, q1)); },
      poke(dq0, dq1) { check(x.pl_poke(dq0, dq1)); },
      hold(q1) { check(x.pl_hold(q1 === null ? 0 : q1, q1 === null ? 0 : 1)); },
      reference(r) { check(x.pl_reference(r)); },
      effect(which, on) { check(x.pl_effect(which, on ? 1 : 0)); },
      delay(samples) { check(x.pl_delay(samples)); },
      // Runs `samples` samples; calls onRecord(t, q0, q1, v0, v1, u) for every `every`-th.
      advance(samples, every, onRecord) {
        const n = check(x.pl_advance(samples, every));
        const o = io();
        if (onRecord) {
          for (let i = 0; i < n; i++) {
            const k = STATE + RECORD * i;
            onRecord(o[k], o[k + 1], o[k + 2], o[k + 3], o[k + 4], o[k + 5]);
          }
        }
        return {
          t: o[0], x: [o[1], o[2], o[3], o[4]], u: o[5], angle: o[6],
          pose: [[o[7], o[8]], [o[9], o[10]]],
        };
      },
      // kind: "initial" (pendulum at `amplitude` rad) or "step" (reference to `amplitude`).
      response(kind, amplitude, duration, every) {
        const n = check(x.pl_response(kind === "initial" ? 0 : 1, amplitude, duration, every));
        const o = io();
        const t = [], q0 = [], q1 = [], u = [];
        for (let i = 0; i < n; i++) {
          t.push(o[4 * i]); q0.push(o[4 * i + 1]); q1.push(o[4 * i + 2]); u.push(o[4 * i + 3]);
        }
        return { t, q0, q1, u };
      },
      // The gain-scheduled servo of `file` (a controller file) beside the constant LQ servo of
      // weights q (5), r on the arm, both following `steps` ([[t, value rad], ...]) for
      // `duration` s (crates/web/src/compare.rs); every `every`-th sample.
      compare(file, q, r, steps, duration, every) {
        const bytes = new TextEncoder().encode(file);
        new Uint8Array(mem(), x.pl_text_in(bytes.length), bytes.length).set(bytes);
        const b = io();
        q.forEach((v, i) => { b[i] = v; });
        b[5] = r; b[6] = steps.length;
        steps.forEach(([t, v], i) => { b[7 + 2 * i] = t; b[8 + 2 * i] = v; });
        const n = check(x.pl_compare(duration, every));
        const o = io();
        const out = { t: [], r: [], gs: { q0: [], q1: [], u: [] }, lq: { q0: [], q1: [], u: [] } };
        for (let i = 0; i < n; i++) {
          const k = 8 * i;
          out.t.push(o[k]); out.r.push(o[k + 1]);
          out.gs.q0.push(o[k + 2]); out.gs.q1.push(o[k + 3]); out.gs.u.push(o[k + 4]);
          out.lq.q0.push(o[k + 5]); out.lq.q1.push(o[k + 6]); out.lq.u.push(o[k + 7]);
        }
        return out;
      },
      controllerToml() { check(x.pl_controller_toml()); return textOut(); },
      plantToml() { check(x.pl_plant_toml()); return textOut(); },
    };
    return lab;
  }

  window.PendulabLab = { load, EFFECTS: {
    quantization: 0, pseudoDifferentiator: 1, saturation: 2, dac: 3,
    driveFriction: 4, pivotFriction: 5, noise: 6,
  } };
})();
