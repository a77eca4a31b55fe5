// crslab serve: the scopes. Four panels (Simulink_PlotVar1..4, motor angles, commanded torques, applied
// torques), and in a world with fixtures a fifth, the egg's force as its scale shows it (with the contest's
// band); a rolling window of simulated time, pause (the window stops following the run) and zoom (the
// wheel widens or narrows the window; with the run paused, shift + wheel moves it in time).
"use strict";

window.CrsScopes = (function () {
  const COLUMNS = 13; // the order of crslab/sinks/page_stream.py's SCOPE_SIGNALS (then WORLD_SCOPE_SIGNALS)
  const PANELS = [
    { title: "Simulink_PlotVar1..4", unit: "lab units", cols: [0, 1, 2, 3],
      names: ["PlotVar1", "PlotVar2", "PlotVar3", "PlotVar4"] },
    { title: "motor angles", unit: "rad", cols: [4, 5, 6], names: ["theta1motor", "theta2motor", "theta3motor"] },
    { title: "torques commanded by lab()", unit: "command units", cols: [7, 8, 9], names: ["tau1", "tau2", "tau3"] },
    { title: "torques applied", unit: "command units", cols: [10, 11, 12],
      names: ["tau1 applied", "tau2 applied", "tau3 applied"] },
  ];
  const EGG_PANEL = { title: "the egg's force, as its scale shows it", unit: "g", cols: [13], names: ["scale"],
    band: true };
  const COLORS = ["#0b63b6", "#d0531f", "#1e7a34", "#7b3fa0"];
  const MAX_ROWS = 120000; // ten minutes of simulated time at a row every 5 ms
  const TITLE_H = 16; // px: the title's band; the traces are drawn below it
  const BOTTOM_H = 14; // px: the time labels' band

  // The value range a panel shows for data from lo to hi: never narrower than a thousandth of the
  // values' size (at least 1e-3), so that float noise of 1e-5 on a steady signal draws a flat line,
  // not steps across the whole panel; padded by 8 % each side.
  function shownRange(lo, hi) {
    if (!(hi >= lo)) { lo = -1; hi = 1; }
    const minSpan = Math.max(1e-3, 1e-3 * Math.max(Math.abs(lo), Math.abs(hi)));
    if (hi - lo < minSpan) { const mid = (lo + hi) / 2; lo = mid - minSpan / 2; hi = mid + minSpan / 2; }
    const pad = (hi - lo) * 0.08;
    return [lo - pad, hi + pad];
  }
  // A value label that fits the 50 px left of the traces: 3 significant digits, or an exponent.
  function label(v) {
    const a = Math.abs(v);
    return a !== 0 && (a >= 1e4 || a < 1e-2) ? v.toExponential(1) : String(Number(v.toPrecision(3)));
  }

  function Scopes(host) {
    this.host = host;
    this.panels = [];
    this.canvases = [];
    PANELS.forEach((p) => this.addPanel(p));
    this.band = null;
    this.clear();
    this.windowS = 5;
    this.paused = false;
    this.endTick = 0;
    this.dirty = true;
  }

  Scopes.prototype.addPanel = function (p) {
    const c = document.createElement("canvas");
    c.setAttribute("aria-label", `${p.title} (${p.unit})`);
    if (p === EGG_PANEL) c.dataset.testid = "scope-egg";
    this.host.appendChild(c);
    c.addEventListener("wheel", (e) => this.wheel(e), { passive: false });
    this.panels.push(p);
    this.canvases.push(c);
  };

  // The contest's band [low, high] drawn over the egg's scope (null: none).
  Scopes.prototype.setBand = function (band) { this.band = band; this.dirty = true; };

  Scopes.prototype.clear = function () {
    if (this.panels.length > PANELS.length) { // the egg's panel goes with its run
      this.canvases.pop().remove();
      this.panels.pop();
    }
    this.columns = COLUMNS;
    this.data = new Float32Array(MAX_ROWS * COLUMNS);
    this.tick0 = 0; // tick of row 0
    this.every = 1; // ticks from one row to the next (the server sends a row every 5 ms)
    this.rows = 0;
    this.endTick = 0;
    this.dirty = true;
  };

  // One chunk's rows (row i is tick tick0 + i * every), from the server's base64 float32 block.
  Scopes.prototype.add = function (scope) {
    const bytes = Uint8Array.from(atob(scope.data), (c) => c.charCodeAt(0));
    const rows = new Float32Array(bytes.buffer);
    const n = scope.rows;
    if (this.rows === 0) {
      this.tick0 = scope.tick0;
      this.every = scope.every || 1;
      const columns = scope.columns || COLUMNS;
      if (columns !== this.columns) { this.columns = columns; this.data = new Float32Array(MAX_ROWS * columns); }
      if (columns > COLUMNS && this.panels.length === PANELS.length) this.addPanel(EGG_PANEL);
    }
    const width = this.columns;
    if (this.rows + n > MAX_ROWS) { // drop the oldest half
      const keep = Math.floor(MAX_ROWS / 2);
      this.data.copyWithin(0, (this.rows - keep) * width, this.rows * width);
      this.tick0 += (this.rows - keep) * this.every;
      this.rows = keep;
    }
    this.data.set(rows.subarray(0, n * width), this.rows * width);
    this.rows += n;
    this.dirty = true;
  };

  // Follow the run up to `tick` (the playout's current tick).
  Scopes.prototype.follow = function (tick) {
    if (!this.paused && tick !== this.endTick) { this.endTick = tick; this.dirty = true; }
  };

  Scopes.prototype.wheel = function (e) {
    e.preventDefault();
    if (e.shiftKey && this.paused) {
      this.endTick += Math.sign(e.deltaY) * this.windowS * 100;
    } else {
      this.windowS = Math.min(120, Math.max(0.05, this.windowS * (e.deltaY > 0 ? 1.25 : 0.8)));
    }
    this.dirty = true;
  };

  Scopes.prototype.draw = function () {
    if (!this.dirty) return;
    this.dirty = false;
    const span = Math.round(this.windowS * 1000);
    const end = this.endTick;
    const start = end - span;
    this.panels.forEach((panel, k) => this.drawPanel(this.canvases[k], panel, start, end));
  };

  Scopes.prototype.drawPanel = function (canvas, panel, start, end) {
    const w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== w) canvas.width = w;
    if (canvas.height !== h) canvas.height = h;
    const g = canvas.getContext("2d");
    g.clearRect(0, 0, w, h);
    const e = this.every;
    const first = Math.max(0, Math.ceil((start - this.tick0) / e));
    const last = Math.min(this.rows, Math.ceil((end - this.tick0) / e));
    const width = this.columns;
    const band = panel.band && this.band ? this.band : null;
    let lo = band ? band[0] : Infinity, hi = band ? band[1] : -Infinity;
    for (let r = first; r < last; r++) {
      for (const c of panel.cols) {
        const v = this.data[r * width + c];
        if (v < lo) lo = v;
        if (v > hi) hi = v;
      }
    }
    [lo, hi] = shownRange(lo, hi);
    const left = 52;
    const x = (tick) => left + ((tick - start) / (end - start)) * (w - left - 4);
    const y = (v) => h - BOTTOM_H - ((v - lo) / (hi - lo)) * (h - BOTTOM_H - TITLE_H - 2);
    g.font = "11px system-ui, sans-serif";
    g.fillStyle = "#5b6670";
    g.fillText(`${panel.title} (${panel.unit})`, left, 11, w - left - 100);
    g.fillText(label(hi), 2, TITLE_H + 10, left - 4); // below the title's band, within the left margin
    g.fillText(label(lo), 2, h - BOTTOM_H - 2, left - 4);
    g.save();
    g.beginPath();
    g.rect(left, TITLE_H, w - left, h - TITLE_H - BOTTOM_H + 2);
    g.clip(); // the traces stay in their band
    g.fillText(`${(start / 1000).toFixed(2)} s`, left, h - 2);
    g.fillText(`${(end / 1000).toFixed(2)} s`, w - 60, h - 2);
    const step = Math.max(1, Math.floor((last - first) / (w - left))); // at most a few points per pixel
    panel.cols.forEach((c, i) => {
      g.strokeStyle = COLORS[i];
      g.beginPath();
      for (let r = first; r < last; r += step) {
        // min and max of each pixel column, so a spike narrower than a pixel still shows
        let mn = Infinity, mx = -Infinity;
        for (let q = r; q < Math.min(last, r + step); q++) {
          const v = this.data[q * width + c];
          if (v < mn) mn = v;
          if (v > mx) mx = v;
        }
        const px = x(this.tick0 + r * e);
        if (r === first) g.moveTo(px, y(mn)); else g.lineTo(px, y(mn));
        if (mx !== mn) g.lineTo(px, y(mx));
      }
      g.stroke();
    });
    if (band) { // the contest's band, dashed
      g.strokeStyle = "#1e7a34";
      g.setLineDash([4, 4]);
      for (const v of band) { g.beginPath(); g.moveTo(left, y(v)); g.lineTo(w, y(v)); g.stroke(); }
      g.setLineDash([]);
    }
    g.restore();
    panel.cols.forEach((c, i) => {
      g.fillStyle = COLORS[i];
      g.fillText(panel.names[i], w - 90, 11 + 12 * i);
    });
  };

  return { Scopes, PANELS, EGG_PANEL, shownRange, label, TITLE_H };
})();
