// crslab serve: the page. Logs in, holds the lab in a CodeMirror editor, talks to the server over one
// WebSocket (crslab/serve/page_messages.py), and plays what a run streams at the time the board sent it:
// Tera Term (xterm.js), the arm in 3D, the scopes, the watched variables.
"use strict";

(function () {
  const V = window.CrsVendor;
  const $ = (id) => document.getElementById(id);
  const state = { ws: null, session: null, running: false, speed: 1, labName: "lab1.c", user: null,
    playout: [], notes: [], end: null, origin: null, lastTick: 0, shownTick: 0, pendingCr: false, armShapes: null, arm: null,
    scopes: null, term: null, editor: null, watched: [] };

  // -- the editor -------------------------------------------------------------------------------------
  function makeEditor(text) {
    state.editor = new V.EditorView({
      state: V.EditorState.create({ doc: text, extensions: [V.basicSetup, V.cpp(), V.lintGutter(),
        V.keymap.of([V.indentWithTab]), V.EditorView.updateListener.of((u) => { if (u.docChanged) saveLocal(); })] }),
      parent: $("editor-host"),
    });
    state.editor.contentDOM.setAttribute("data-testid", "editor");
    state.editor.contentDOM.setAttribute("aria-label", "the lab file");
  }
  const labText = () => state.editor.state.doc.toString();
  function setLab(name, text) {
    state.labName = name;
    $("lab-name").textContent = name;
    state.editor.dispatch({ changes: { from: 0, to: state.editor.state.doc.length, insert: text } });
    mark([]);
  }
  function saveLocal() {
    try { localStorage.setItem(`crslab:${state.user}:lab`, JSON.stringify({ name: state.labName, text: labText() })); }
    catch (e) { /* private mode: nothing kept */ }
  }
  // Compiler messages as markers at their lines.
  function mark(diagnostics) {
    const doc = state.editor.state.doc;
    const marks = diagnostics.filter((d) => d.line >= 1 && d.line <= doc.lines).map((d) => {
      const line = doc.line(d.line);
      return { from: line.from, to: Math.max(line.from, line.to), severity: d.severity, message: d.message };
    });
    state.editor.dispatch(V.setDiagnostics(state.editor.state, marks));
  }

  // -- talking to the server ----------------------------------------------------------------------------
  function send(msg) {
    if (state.ws && state.ws.readyState === WebSocket.OPEN) state.ws.send(JSON.stringify(msg));
    else diagnose("not connected to the server: reload the page", true);
  }
  function connect() {
    const ws = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`);
    state.ws = ws;
    ws.onopen = () => setConnection("connected", "good");
    ws.onclose = (e) => {
      setConnection(`disconnected${e.reason ? ": " + e.reason : ""}`, "bad");
      setRunning(false);
    };
    ws.onmessage = (e) => receive(JSON.parse(e.data));
  }
  function setConnection(text, cls) {
    const c = $("connection");
    c.textContent = text;
    c.className = `badge ${cls}`;
  }
  function diagnose(text, bad) {
    const d = $("diagnosis");
    d.textContent = text;
    d.className = bad === undefined ? "" : bad ? "bad" : "good";
  }
  function note(text) {
    const line = document.createElement("div");
    line.textContent = text;
    $("events").appendChild(line);
    $("events").scrollTop = $("events").scrollHeight;
    return line;
  }
  // The build's warnings (the C89 habits the board's compiler builds), one line each as crslab sim
  // says them, above the run's events; a new build replaces them.
  function buildWarnings(diagnostics) {
    $("events").querySelectorAll(".build-warning").forEach((e) => e.remove());
    for (const d of diagnostics.filter((x) => x.severity === "warning")) {
      note(`warning: ${d.message}`).classList.add("build-warning");
    }
  }
  const at = (tick) => `t = ${(tick / 1000).toFixed(3)} s`;

  function receive(m) {
    switch (m.type) {
      case "hello": state.session = m.session; break;
      case "built":
        mark(m.diagnostics);
        if (!m.ok) {
          const first = m.diagnostics.find((d) => d.severity === "error");
          diagnose(first ? `${m.message}: line ${first.line}: ${first.message}` : m.message, true);
        } else {
          buildWarnings(m.diagnostics);
          if (!state.running) diagnose(m.message, false);
        }
        if (m.watched) setWatched(m.watched.map((w) => w.name));
        break;
      case "building": diagnose(m.message, false); break;
      case "started": started(m); break;
      case "chunk":
        if (m.frames) m.frames = unpackRows(m.frames);
        state.playout.push(m);
        state.lastTick = m.tick;
        if (state.speed === null) drain(Infinity);
        break;
      case "expectation": // said once, when judged (the scenario's own list leaves expectations out)
        queueNote(m.tick, m.met ? `${at(m.tick)}: expect ${m.what}: met`
          : `${at(m.tick)}: expect ${m.what}: FAILED: ${m.lines.map((l) => l.replace(/^t = [\d.]+ s: /, "")).join("; ")}`);
        break;
      case "note": // the server's word on the run (it goes on slower than real time)
        queueNote(m.tick, `${at(m.tick)}: ${m.text}`);
        break;
      case "motor_board":
        queueNote(m.tick, `${at(m.tick)}: motor board ${m.off ? `cut every output (joint ${m.joint})` : "outputs back"}`);
        break;
      case "scorecard": state.card = m; break; // shown with the run's end (showEnd)
      case "ended": ended(m); break;
      case "vars": varsReply(m); break;
      case "checked":
        $("check-report").textContent = m.report;
        diagnose(m.ok ? "check: the run matches the golden file" : `check: ${m.report.split("\n")[0]}`, !m.ok);
        break;
      case "error": diagnose(m.message, true); break;
      default: break;
    }
  }
  // A chunk's packed rows ({columns, rows, data: base64 little-endian float64}) as arrays of numbers.
  function unpackRows(p) {
    const bytes = Uint8Array.from(atob(p.data), (c) => c.charCodeAt(0));
    const values = new Float64Array(bytes.buffer);
    const rows = [];
    for (let i = 0; i < p.rows; i++) rows.push(Array.from(values.subarray(i * p.columns, (i + 1) * p.columns)));
    return rows;
  }
  function queueNote(tick, text) {
    state.notes.push({ tick, text });
    state.notes.sort((a, b) => a.tick - b.tick);
  }

  // -- a run ----------------------------------------------------------------------------------------
  function runOptions() {
    const speed = $("speed").value;
    const duration = parseFloat($("duration").value);
    const scenarioChoice = $("scenario").value;
    let scenario = { name: scenarioChoice };
    if (scenarioChoice === "__file__") scenario = { file: state.scenarioFile };
    return {
      type: "run", lab: { name: state.labName, text: labText() }, scenario,
      speed: speed === "fast" ? null : Number(speed),
      offsets: $("use-offsets").checked ? [Number($("offset2").value), Number($("offset3").value)] : null,
      no_startup_delay: $("no-startup-delay").checked,
      duration: duration > 0 ? duration : null,
      record: { csv: $("record-csv").checked, rrd: $("record-rrd").checked },
      world: $("world").value || "none",
      contest: $("contest").checked,
    };
  }
  function run() {
    const msg = runOptions();
    if (msg.scenario.file === undefined && msg.scenario.name === "__file__") {
      diagnose("choose a scenario file first", true);
      return;
    }
    state.speed = msg.speed;
    resetRun();
    diagnose(`building ${state.labName}…`);
    setRunning(true);
    send(msg);
  }
  function resetRun() {
    state.term.reset();
    $("terminal").textContent = "";
    state.pendingCr = false;
    state.playout = [];
    state.notes = [];
    state.end = null;
    state.origin = null;
    state.lastTick = 0;
    state.shownTick = 0;
    $("events").textContent = "";
    $("var-reply").textContent = "";
    $("var-reply").className = "";
    $("var-table").replaceChildren();
    $("joint-angles").textContent = "DH angles: -";
    $("check-report").textContent = "";
    $("sim-time").textContent = at(0);
    if (state.arm && state.restFrame) state.arm.pose(state.restFrame);
    state.scopes.clear();
    state.scopes.setBand(null);
    state.card = null;
    $("scorecard").textContent = "";
    $("scorecard-panel").hidden = true;
    ["transcript", "csv", "rrd"].forEach((k) => $(`dl-${k}`).classList.add("disabled"));
  }
  function started(m) {
    diagnose(`running ${state.labName} on ${m.scenario}`);
    for (const e of m.events) if (!e.text.startsWith("expect ")) queueNote(e.tick, `${at(e.tick)}: ${e.text}`);
    for (const n of m.notes) note(n);
    if (m.contest) { // the contest: where the arm rests, and the egg's band on its scope
      note(m.contest.rest.replace(/^rest +/, "the arm rests at "));
      state.scopes.setBand(m.contest.band_g);
    }
    setWatched(m.watched);
  }
  function ended(m) {
    state.end = m;
    // the clock reaches the tick the run ended at (a crash at 7.100 s is not shown as 7.000 s)
    if (m.end_tick !== undefined) state.lastTick = Math.max(state.lastTick, m.end_tick);
    if (state.speed === null || m.end_tick === undefined) drain(Infinity);
    setRunning(false);
  }
  function showEnd(m) {
    const fails = (m.failed_expectations || []).map((l) => `\nexpectation failed: ${l}`).join("");
    const notes = (m.notes || []).map((l) => `\n${l}`).join("");
    if (m.status === "ok") diagnose(`run finished at ${at(m.end_tick)}${notes}`, false);
    else if (m.status === "build-error" && !m.bad_input) { /* the build's own message stays */ }
    else diagnose(`${m.status}: ${m.message}${fails}${notes}`, true);
    if (state.card) { // the contest's card, once the run's end is shown
      $("scorecard").textContent = state.card.lines.join("\n");
      $("scorecard-panel").hidden = false;
      state.card = null;
    }
    for (const kind of m.downloads || []) {
      const a = $(`dl-${kind}`);
      a.href = `/api/download/${kind}?session=${encodeURIComponent(state.session)}`;
      a.classList.remove("disabled");
    }
  }
  function setRunning(on) {
    state.running = on;
    $("run").disabled = on;
    $("build").disabled = on;
    $("stop").disabled = !on;
  }

  // Play what arrived at the time the board sent it: tick k is shown k ms (/ speed) after the run began.
  function currentTick() {
    if (state.speed === null) return Infinity;
    const now = performance.now();
    const first = state.playout[0];
    if (state.origin === null && first) state.origin = now - first.first / state.speed;
    if (state.origin === null) return 0;
    return (now - state.origin) * state.speed;
  }
  function drain(upTo) {
    while (state.playout.length) {
      const m = state.playout[0];
      playChunk(m, upTo);
      if (m.serial.length || (m.frames && m.frames.length)) break; // the rest of it is not due yet
      state.playout.shift();
    }
    // a note is due once the run has reached its tick (as fast as possible too: never ahead of it)
    const reached = Math.min(upTo, state.playout.length ? state.shownTick : state.lastTick);
    while (state.notes.length && state.notes[0].tick <= reached) note(state.notes.shift().text);
    if (state.end && !state.playout.length && (state.end.end_tick === undefined || state.end.end_tick <= upTo)) {
      // only what the run reached: after a crash at 7.1 s a release planned at 23 s never happened
      const last = state.end.end_tick === undefined ? state.lastTick : state.end.end_tick;
      while (state.notes.length && state.notes[0].tick <= last) note(state.notes.shift().text);
      state.notes = [];
      const m = state.end;
      state.end = null;
      showEnd(m);
    }
  }
  function playChunk(m, upTo) {
    if (m.scope && !m.scopeAdded) { state.scopes.add(m.scope); m.scopeAdded = true; }
    let bytes = "";
    while (m.serial.length && m.serial[0][0] <= upTo) bytes += m.serial.shift()[1];
    if (bytes) writeSerial(bytes);
    let frame = null;
    while (m.frames && m.frames.length && m.frames[0][0] <= upTo) frame = m.frames.shift();
    if (frame) showFrame(frame);
    state.shownTick = Math.min(upTo, m.tick);
  }
  function writeSerial(text) {
    const bytes = Uint8Array.from(text, (c) => c.charCodeAt(0));
    state.term.write(bytes);
    // what Tera Term shows: "\n\r" (and "\r\n") is one line end, also when split between two chunks
    let t = text;
    if (state.pendingCr && t.startsWith("\r")) t = t.slice(1);
    if (t.length) state.pendingCr = t.endsWith("\n");
    $("terminal").appendChild(document.createTextNode(t.replaceAll("\n\r", "\n").replaceAll("\r\n", "\n")));
  }
  function showFrame(f) {
    if (state.arm) state.arm.pose(f);
    const deg = (r) => (r * 180 / Math.PI).toFixed(2);
    if (!state.restFrame) state.restFrame = f;
    $("joint-angles").textContent = `the arm's DH angles (true): ${deg(f[1])} ${deg(f[2])} ${deg(f[3])} deg; ` +
      `the lab's motor angles (what lab() reads, offset-dependent): ${deg(f[4])} ${deg(f[5])} ${deg(f[6])} deg`;
    const s = $("arm-state");
    if (f[8]) { s.textContent = "motor board: every output cut"; s.className = "badge bad"; }
    else if (f[7]) { s.textContent = "outside the safety envelope: the hold controller has the arm"; s.className = "badge bad"; }
    else { s.textContent = "inside the safety envelope"; s.className = "badge good"; }
  }
  function frameLoop() {
    const tick = currentTick();
    drain(tick);
    const shown = state.speed === null ? state.lastTick : Math.min(tick, state.lastTick);
    $("sim-time").textContent = at(Math.max(0, Math.floor(shown)));
    state.scopes.follow(Math.floor(shown));
    state.scopes.draw();
    if (state.arm) state.arm.render();
    requestAnimationFrame(frameLoop);
  }

  // -- watched variables --------------------------------------------------------------------------
  function setWatched(names) {
    state.watched = names;
    $("var-names").replaceChildren(...names.map((n) => Object.assign(document.createElement("option"), { value: n })));
  }
  function varTarget() {
    const m = /^\s*([A-Za-z_]\w*)\s*(?:\[\s*(\d+)\s*\])?\s*$/.exec($("var-name").value);
    if (!m) { $("var-reply").textContent = "a variable: NAME or NAME[i]"; return null; }
    return { name: m[1], index: m[2] === undefined ? null : Number(m[2]) };
  }
  function varsReply(m) {
    $("var-reply").textContent = m.reply;
    $("var-reply").className = m.ok ? "" : "error";
    if (m.ok && m.cmd === "list") {
      const rows = Object.entries(m.values || {}).map(([k, v]) => `<tr><td>${k}</td><td>${v}</td></tr>`);
      $("var-table").innerHTML = "";
      for (const [k, v] of Object.entries(m.values || {})) {
        const tr = document.createElement("tr");
        tr.append(Object.assign(document.createElement("td"), { textContent: k }),
          Object.assign(document.createElement("td"), { textContent: v }));
        $("var-table").appendChild(tr);
      }
      void rows;
    }
  }

  // The generation a lab was written for: the first whose header it includes (crslab/generations.py).
  function showGeneration(text) {
    for (const [name, header] of Object.entries(state.generations)) {
      const include = new RegExp(`^[ \\t]*#[ \\t]*include[ \\t]*["<]${header.replace(/[.]/g, "\\.")}[">]`, "m");
      if (include.test(text)) { $("gen-choice").value = name; return; }
    }
  }

  // -- files ----------------------------------------------------------------------------------------
  function readFile(input) {
    return new Promise((resolve) => {
      const f = input.files[0];
      if (!f) return resolve(null);
      f.text().then((text) => resolve({ name: f.name, text }));
    });
  }
  function download(name, text) {
    const a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([text], { type: "text/x-c" }));
    a.download = name;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }

  // -- start ----------------------------------------------------------------------------------------
  async function loadTemplate() {
    const r = await fetch(`/api/template?lab=${$("lab-choice").value}&gen=${$("gen-choice").value}`);
    const t = await r.json();
    setLab(t.name, t.text);
  }
  async function startBench(me) {
    state.user = me.user;
    $("who").textContent = `${me.user}`;
    $("logout").hidden = !me.login;
    $("admin-link").hidden = !me.admin;
    $("login").hidden = true;
    $("bench").hidden = false;
    for (const [key, title] of Object.entries(me.labs)) {
      $("lab-choice").appendChild(Object.assign(document.createElement("option"), { value: key, textContent: title }));
    }
    state.generations = me.generation_headers || {};
    for (const [name, title] of Object.entries(me.generations)) {
      $("gen-choice").appendChild(Object.assign(document.createElement("option"), { value: name, textContent: title }));
    }
    if (me.default_generation) $("gen-choice").value = me.default_generation; // crslab new's default
    const [scenarios, shapes, worlds] = await Promise.all([fetch("/api/scenarios").then((r) => r.json()),
      fetch("/api/arm").then((r) => r.json()), fetch("/api/worlds").then((r) => r.json())]);
    for (const w of worlds) {
      $("world").appendChild(Object.assign(document.createElement("option"),
        { value: w.name, textContent: w.name, title: w.description }));
    }
    for (const s of scenarios) {
      $("scenario").appendChild(Object.assign(document.createElement("option"),
        { value: s.name, textContent: `${s.name} (${s.end_s} s)`, title: s.description }));
    }
    $("scenario").appendChild(Object.assign(document.createElement("option"),
      { value: "__file__", textContent: "the uploaded file", disabled: true, id: "scenario-file-option" }));
    let saved = null;
    try { saved = JSON.parse(localStorage.getItem(`crslab:${state.user}:lab`) || "null"); } catch (e) { saved = null; }
    makeEditor(saved ? saved.text : "");
    if (saved) { state.labName = saved.name; $("lab-name").textContent = saved.name; showGeneration(saved.text); }
    else await loadTemplate();
    state.term = new V.Terminal({ convertEol: false, scrollback: 5000, fontSize: 13, rows: 14 });
    state.term.open($("xterm"));
    state.scopes = new window.CrsScopes.Scopes($("scopes"));
    const showArm = (armShapes) => {
      try {
        if (state.arm) state.arm.dispose();
        state.arm = new window.CrsArm.ArmView($("arm-view"), armShapes, (hand) => {
          if (!state.running) return;
          send(hand ? { type: "hand", ...hand } : { type: "release" });
        });
        state.arm.onWorld = (force, grams, broken) => {  // the egg's force, as the scale shows it
          $("world-readout").textContent =
            `egg ${force.toFixed(2)} N · scale ${grams.toFixed(0)} g${broken ? " · the egg is broken" : ""}`;
        };
        $("world-readout").textContent = "";
      } catch (e) {
        $("arm-view").textContent = `no 3D view in this browser (${e.message})`;
      }
    };
    showArm(shapes);
    $("world").onchange = async () => {  // the 3D view draws the chosen world's fixtures
      showArm(await fetch(`/api/arm?world=${encodeURIComponent($("world").value)}`).then((r) => r.json()));
    };
    $("contest").onchange = () => { // the contest is run in a world with its fixtures, hands off
      const contest = $("contest").checked;
      $("scenario").disabled = contest;
      if (contest && $("world").value === "none") { $("world").value = "contest"; $("world").onchange(); }
    };
    wire();
    connect();
    requestAnimationFrame(frameLoop);
  }
  function wire() {
    $("run").onclick = run;
    $("stop").onclick = () => send({ type: "stop" });
    $("build").onclick = () => { diagnose(`building ${state.labName}…`); send({ type: "build", lab: { name: state.labName, text: labText() } }); };
    $("speed").onchange = () => {
      if (!state.running) return;
      const v = $("speed").value;
      state.speed = v === "fast" ? null : Number(v);
      state.origin = null;
      send({ type: "speed", speed: state.speed });
    };
    $("new-lab").onclick = () => { if (confirm("Replace the editor's lab with the template?")) loadTemplate(); };
    $("lab-file").onchange = async () => {
      const f = await readFile($("lab-file"));
      if (f) { setLab(f.name, f.text); showGeneration(f.text); }
      $("lab-file").value = "";
    };
    $("save-lab").onclick = () => download(state.labName, labText());
    $("scenario-file").onchange = async () => {
      const f = await readFile($("scenario-file"));
      if (!f) return;
      state.scenarioFile = f;
      const opt = $("scenario-file-option");
      opt.disabled = false;
      opt.textContent = f.name;
      $("scenario").value = "__file__";
    };
    $("golden-file").onchange = async () => {
      const f = await readFile($("golden-file"));
      $("golden-file").value = "";
      if (!f) return;
      resetRun(); // what the panels showed was the previous run's
      $("check-report").textContent = `checking ${state.labName} against ${f.name}…`;
      send({ type: "check", lab: { name: state.labName, text: labText() }, golden: f });
    };
    $("var-list").onclick = () => send({ type: "vars", cmd: "list" });
    $("var-get").onclick = () => { const t = varTarget(); if (t) send({ type: "vars", cmd: "get", ...t }); };
    $("var-set").onclick = () => {
      const t = varTarget();
      const value = Number($("var-value").value);
      if (!t) return;
      if ($("var-value").value.trim() === "" || !Number.isFinite(value)) { $("var-reply").textContent = "a value: a number"; return; }
      send({ type: "vars", cmd: "set", ...t, value });
    };
    $("scope-pause").onclick = () => {
      state.scopes.paused = !state.scopes.paused;
      $("scope-pause").textContent = state.scopes.paused ? "follow" : "pause";
      state.scopes.dirty = true;
    };
    $("scope-window").onchange = () => { state.scopes.windowS = Number($("scope-window").value); state.scopes.dirty = true; };
    $("logout").onclick = async () => { await fetch("/api/logout", { method: "POST" }); location.reload(); };
  }
  async function main() {
    const r = await fetch("/api/me");
    const me = await r.json();
    if (r.ok) return startBench(me);
    if (!me.login) { $("no-login").hidden = false; return; }
    $("login").hidden = false;
    $("login-form").onsubmit = async (e) => {
      e.preventDefault();
      const res = await fetch("/api/login", { method: "POST", headers: { "Content-Type": "application/json" },
        body: JSON.stringify({ name: document.querySelector("[data-testid=login-name]").value,
          password: document.querySelector("[data-testid=login-password]").value }) });
      const body = await res.json();
      if (!res.ok) { $("login-error").textContent = body.error; return; }
      const again = await fetch("/api/me");
      startBench(await again.json());
    };
  }
  document.addEventListener("DOMContentLoaded", main);
})();
