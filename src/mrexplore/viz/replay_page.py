"""The page of ``replay.html``: HTML, style and script, all inline.

Kept as Python strings (not package data files) so that every install has them.
:func:`mrexplore.viz.replay.replay_html` fills ``/*STYLE*/``, ``/*SCRIPT*/`` and
``/*DATA*/`` (the JSON document of :func:`mrexplore.viz.replay.replay_data`).
"""

from __future__ import annotations

PAGE_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>mrexplore replay</title>
<style>/*STYLE*/</style>
</head>
<body>
<header>
  <h1 id="title">mrexplore replay</h1>
  <p id="subtitle"></p>
</header>
<div id="controls">
  <button id="play" type="button" title="play / pause (space)" disabled>&#9654; Play</button>
  <input id="slider" type="range" min="0" max="0" value="0" step="1" aria-label="tick" disabled>
  <label>speed
    <select id="speed" title="ticks per second"></select>
  </label>
  <span class="toggles">
    <label><input id="show-links" type="checkbox" checked> links</label>
    <label><input id="show-targets" type="checkbox" checked> targets</label>
    <label><input id="show-trails" type="checkbox" checked> trails</label>
    <label><input id="show-believed" type="checkbox" checked> believed positions</label>
    <label><input id="show-beliefs" type="checkbox"> robot beliefs</label>
  </span>
</div>
<div id="readouts">
  <span>tick <b id="tick">0</b> / <span id="last-tick">0</span></span>
  <span>coverage <b id="coverage">0.0%</b></span>
  <span>bytes sent <b id="bytes">0</b></span>
  <span>sub-networks <b id="subnetworks">-</b></span>
  <span>failed <b id="failed">0</b></span>
  <span id="localisation-box" hidden>localisation error mean / max
    <b id="localisation">-</b> cells</span>
</div>
<p id="status">Loading the run&hellip;</p>
<main id="stage">
  <div id="map-box"><canvas id="map"></canvas></div>
  <div id="beliefs" hidden></div>
</main>
<section id="charts"></section>
<footer>
  <div id="legend"></div>
  <p id="credit"></p>
  <p class="small">Written by <span id="generator">mrexplore</span>. Links are those in
  force during the tick, coloured like the lowest-id robot of their sub-network; a ring
  is a robot's current target; a crossed-out robot has failed; a hollow square joined
  to a robot is the cell it believes it is on (runs with odometry drift). A belief panel
  shows a cell from the tick the robot first knew it, with the value it held at the
  end (the run keeps only its final belief). Space: play/pause,
  arrows: step, click a curve: jump; <code>#tick=250&amp;beliefs=1</code> after the file
  name opens the replay at that tick with the robots' beliefs shown.</p>
</footer>
<script type="application/json" id="replay-data">/*DATA*/</script>
<script>/*SCRIPT*/</script>
</body>
</html>
"""

STYLE = """
:root { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; color: #222; }
body { margin: 12px 18px; background: #fafafa; }
header h1 { font-size: 1.25rem; margin: 0 0 2px 0; }
header p { margin: 0 0 8px 0; color: #555; font-size: 0.85rem; }
#controls, #readouts { display: flex; flex-wrap: wrap; gap: 6px 16px; align-items: center;
  margin: 4px 0; font-size: 0.9rem; }
#slider { flex: 1 1 320px; min-width: 200px; }
#play { min-width: 6.5em; font-size: 0.95rem; padding: 3px 10px; }
#readouts b { font-variant-numeric: tabular-nums; display: inline-block; min-width: 3.5em; }
#readouts #tick { text-align: right; }
.toggles label { margin-right: 8px; white-space: nowrap; }
#status { color: #a33; font-size: 0.85rem; margin: 4px 0; min-height: 1em; }
#stage { display: flex; flex-wrap: wrap; gap: 12px; align-items: flex-start; }
#map-box { background: #fff; border: 1px solid #ccc; line-height: 0; }
#map { display: block; cursor: crosshair; }
#beliefs { display: grid; gap: 8px; align-content: start; }
#beliefs[hidden] { display: none; }
.panel { font-size: 0.75rem; line-height: 1.2; }
.panel canvas { display: block; border: 3px solid #888; background: #fff; }
#charts { display: flex; flex-wrap: wrap; gap: 12px; margin-top: 10px; }
#charts canvas { background: #fff; border: 1px solid #ddd; cursor: pointer; }
#legend { display: flex; flex-wrap: wrap; gap: 4px 14px; font-size: 0.8rem; margin-top: 10px; }
.chip { display: inline-block; width: 11px; height: 11px; border: 1px solid #333;
  vertical-align: -1px; margin-right: 4px; }
.chip.hollow { width: 9px; height: 9px; border: 2px solid #333; background: transparent; }
#localisation { min-width: 6em; }
footer p { font-size: 0.75rem; color: #666; max-width: 70em; }
.small { font-size: 0.75rem; }
"""

SCRIPT = r"""
"use strict";
(async function main() {
  const $ = (id) => document.getElementById(id);
  const status = $("status");
  const DTYPES = { u1: Uint8Array, i1: Int8Array, u2: Uint16Array, i2: Int16Array,
    u4: Uint32Array, i4: Int32Array, f4: Float32Array, f8: Float64Array };

  function bytesOf(text) {
    const raw = atob(text);
    const out = new Uint8Array(raw.length);
    for (let i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
    return out;
  }
  async function inflate(spec) {
    const packed = new Blob([bytesOf(spec.z)]);
    const stream = packed.stream().pipeThrough(new DecompressionStream("deflate"));
    const buffer = await new Response(stream).arrayBuffer();
    return new DTYPES[spec.dtype](buffer);
  }
  function unpackBits(bytes, count) {
    const out = new Uint8Array(count);
    for (let i = 0; i < count; i++) out[i] = (bytes[i >> 3] >> (7 - (i & 7))) & 1;
    return out;
  }
  function rgba(hex) {  // "#rrggbb" -> 0xAABBGGRR (ImageData is little-endian RGBA)
    const v = parseInt(hex.slice(1), 16);
    return (0xff000000 | ((v & 0xff) << 16) | (v & 0xff00) | ((v >> 16) & 0xff)) >>> 0;
  }
  function lighten(hex, share) {
    const v = parseInt(hex.slice(1), 16);
    const c = [v >> 16, (v >> 8) & 0xff, v & 0xff].map((x) => Math.round(x + (255 - x) * share));
    return `rgb(${c[0]},${c[1]},${c[2]})`;
  }
  function formatBytes(n) {
    if (n < 1e4) return String(Math.round(n));
    const units = [["G", 1e9], ["M", 1e6], ["k", 1e3]];
    for (const [u, f] of units) if (n >= f) return (n / f).toFixed(n >= 100 * f ? 0 : 1) + " " + u;
    return String(n);
  }

  // ------------------------------------------------------------------ data
  let data;
  try {
    data = JSON.parse($("replay-data").textContent);
  } catch (error) {
    status.textContent = "This replay holds no readable run data: " + error;
    return;
  }
  if (typeof DecompressionStream === "undefined") {
    status.textContent = "This browser lacks DecompressionStream; open the replay in a " +
      "current Chromium, Firefox or Safari.";
    return;
  }
  const meta = data.meta;
  const names = Object.keys(data.arrays);
  const decoded = await Promise.all(names.map((name) => inflate(data.arrays[name])));
  const A = {};
  names.forEach((name, i) => { A[name] = decoded[i]; });
  data.arrays = null;  // let the base64 text go

  const H = meta.height, W = meta.width, T = meta.last_tick, N = meta.robots;
  const S = meta.map_stride, HB = Math.ceil(H / S), WB = Math.ceil(W / S);
  const colours = Array.from({ length: N }, (_, i) => meta.colours[i % meta.colours.length]);
  const trailColours = colours.map((c) => lighten(c, 0.45));
  const failTick = meta.fail_tick || new Array(N).fill(-1);
  const alive = (t, i) => failTick[i] < 0 || t < failTick[i];

  // Positions (and targets): first row + per-tick deltas -> absolute, (T+1) x N x 2.
  function integrate(start, deltas) {
    const out = new Int32Array((T + 1) * N * 2);
    for (let k = 0; k < 2 * N; k++) out[k] = start[k >> 1][k & 1];
    for (let k = 2 * N; k < out.length; k++) out[k] = out[k - 2 * N] + deltas[k];
    return out;
  }
  const pos = integrate(meta.start, A.positions);
  const goals = A.goals ? integrate(meta.goal_start, A.goals) : null;
  // Noisy runs: the cell each robot believes it is on, and its localisation error.
  const est = A.estimated_positions ? integrate(meta.estimated_start, A.estimated_positions)
    : null;
  const locError = A.localisation_error || null;

  // Map: cells sorted by the tick they became known; known at t = first start[t+1].
  const occupied = unpackBits(A.truth, HB * WB);
  function sortByTick(firstKnown, offset, count) {
    const counts = new Uint32Array(T + 2);
    for (let i = 0; i < count; i++) {
      const v = firstKnown[offset + i];
      if (v > 0 && v <= T + 1) counts[v - 1]++;
    }
    const start = new Uint32Array(T + 2);
    for (let t = 0; t <= T; t++) start[t + 1] = start[t] + counts[t];
    const fill = start.slice(0, T + 1);
    const order = new Uint32Array(start[T + 1]);
    for (let i = 0; i < count; i++) {
      const v = firstKnown[offset + i];
      if (v > 0 && v <= T + 1) order[fill[v - 1]++] = i;
    }
    return { start, order };
  }
  const team = sortByTick(A.first_known, 0, HB * WB);
  A.first_known = null;
  const MC = meta.map_colours;
  // Colour classes: 0-3 unknown free/wall, known free/wall; 4-5 (belief panels of
  // noisy runs) held free but a wall in truth, held a wall but free in truth.
  const PIX = [rgba(MC.unknown_free), rgba(MC.unknown_occupied),
    rgba(MC.known_free), rgba(MC.known_occupied), rgba(MC.wrong_free || MC.known_free),
    rgba(MC.wrong_occupied || MC.known_occupied)];
  const knownOf = (occ) => occ.map((v) => v + 2);

  // A layer of cells drawn into an ImageData; changed tiles go to its canvas. A cell
  // shows class occ[i] while unknown and kn[i] once known.
  const TILE = 64;
  function cellLayer(width, height, occ, kn) {
    const canvas = document.createElement("canvas");
    canvas.width = width; canvas.height = height;
    const ctx = canvas.getContext("2d");
    const image = ctx.createImageData(width, height);
    const px = new Uint32Array(image.data.buffer);
    for (let i = 0; i < px.length; i++) px[i] = PIX[occ[i]];
    ctx.putImageData(image, 0, 0);
    const tilesX = Math.ceil(width / TILE), tilesY = Math.ceil(height / TILE);
    return { canvas, ctx, image, px, shown: -1, width, height, occ, kn, tilesX, tilesY,
      dirty: new Uint8Array(tilesX * tilesY) };
  }
  // Bring a layer from the tick it shows to tick t, painting only the cells in between.
  function advance(layer, sorted, t) {
    const from = layer.shown, order = sorted.order, start = sorted.start;
    if (from === t) return;
    let a, b;
    if (t > from) { a = start[from + 1]; b = start[t + 1]; }
    else { a = start[t + 1]; b = start[from + 1]; }
    const cls = t > from ? layer.kn : layer.occ;
    const px = layer.px, width = layer.width, dirty = layer.dirty;
    const tilesX = layer.tilesX;
    let any = false;
    for (let k = a; k < b; k++) {
      const i = order[k];
      px[i] = PIX[cls[i]];
      const y = (i / width) | 0;
      dirty[((y / TILE) | 0) * tilesX + (((i - y * width) / TILE) | 0)] = 1;
      any = true;
    }
    layer.shown = t;
    if (!any) return;
    for (let j = 0; j < dirty.length; j++) {
      if (!dirty[j]) continue;
      dirty[j] = 0;
      const x = (j % tilesX) * TILE, y = ((j / tilesX) | 0) * TILE;
      layer.ctx.putImageData(layer.image, 0, 0, x, y,
        Math.min(TILE, layer.width - x), Math.min(TILE, layer.height - y));
    }
  }
  const base = cellLayer(WB, HB, occupied, knownOf(occupied));

  // Links: pair k <-> (a, b), a < b, in the order (0,1), (0,2), ..., (1,2), ...
  const pairA = [], pairB = [];
  for (let a = 0; a < N; a++) for (let b = a + 1; b < N; b++) { pairA.push(a); pairB.push(b); }
  const linkBytes = Math.ceil(pairA.length / 8);
  const hasLinks = !!(A.link_bits && A.component);

  // Belief panels (optional): every robot's first-known ticks, reduced; with a noisy
  // run's final beliefs, the class each cell takes once known (panel_belief).
  const hasBeliefs = !!A.robot_known;
  const beliefColours = !!A.panel_belief;
  let panels = [];
  if (hasBeliefs) {
    const PS = meta.panel_stride, HP = Math.ceil(H / PS), WP = Math.ceil(W / PS);
    const panelOcc = unpackBits(A.panel_truth, HP * WP);
    const panelKnown = knownOf(panelOcc);
    for (let r = 0; r < N; r++) {
      const sorted = sortByTick(A.robot_known, r * HP * WP, HP * WP);
      const kn = beliefColours ? A.panel_belief.subarray(r * HP * WP, (r + 1) * HP * WP)
        : panelKnown;
      panels.push({ sorted, layer: cellLayer(WP, HP, panelOcc, kn), WP, HP, PS });
    }
    A.robot_known = null;
  } else {
    $("show-beliefs").disabled = true;
    $("show-beliefs").parentElement.title = "this run was recorded without robot beliefs " +
      "(mrexplore run --belief-panels)";
  }
  if (!hasLinks) $("show-links").disabled = true;
  if (meta.all_linked) {  // unlimited range: every line would be drawn, showing nothing
    $("show-links").checked = false;
    $("show-links").parentElement.title = "every two robots are linked at every tick";
  }
  if (!goals) $("show-targets").disabled = true;
  if (!est) {
    $("show-believed").disabled = true;
    $("show-believed").parentElement.title = "this run has no odometry drift " +
      "(no estimated_positions in its trace)";
  }
  if (locError) $("localisation-box").hidden = false;

  // ------------------------------------------------------------------ page
  document.title = "mrexplore replay: " + (meta.title || "run");
  $("title").textContent = meta.title || "mrexplore run";
  $("subtitle").textContent = meta.subtitle || "";
  $("credit").textContent = meta.credit ? "Map: " + meta.credit : "";
  $("generator").textContent = "mrexplore " + meta.version;
  $("last-tick").textContent = String(T);
  const slider = $("slider");
  slider.max = String(T);
  const speedSelect = $("speed");
  const speeds = [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000];
  const wanted = T / 20;  // a whole run in about 20 s
  let best = speeds[0];
  for (const s of speeds) if (Math.abs(Math.log(s / wanted)) < Math.abs(Math.log(best / wanted)))
    best = s;
  for (const s of speeds) {
    const option = document.createElement("option");
    option.value = String(s); option.textContent = s + " ticks/s";
    if (s === best) option.selected = true;
    speedSelect.appendChild(option);
  }
  const legend = $("legend");
  const legendItems = [];
  for (let i = 0; i < Math.min(N, 24); i++) legendItems.push([colours[i], "robot " + i]);
  if (N > 24) legendItems.push(["#888888", `... ${N} robots (colours repeat)`]);
  legendItems.push([MC.known_free, "known free"], [MC.known_occupied, "known wall"],
    [MC.unknown_free, "unknown free"], [MC.unknown_occupied, "unknown wall"]);
  if (est) legendItems.push([null, "believed position"]);
  if (beliefColours) legendItems.push([MC.wrong_free, "belief free, truly a wall"],
    [MC.wrong_occupied, "belief wall, truly free"]);
  for (const [colour, label] of legendItems) {
    const item = document.createElement("span");
    const chip = document.createElement("span");
    if (colour === null) chip.className = "chip hollow";
    else { chip.className = "chip"; chip.style.background = colour; }
    item.appendChild(chip); item.appendChild(document.createTextNode(label));
    legend.appendChild(item);
  }

  // ------------------------------------------------------------------ drawing
  const mapCanvas = $("map");
  const ctx = mapCanvas.getContext("2d");
  const trail = document.createElement("canvas");
  const trailCtx = trail.getContext("2d");
  const view = { k: 1, dpr: 1, cssW: 0, cssH: 0, trailTick: -1 };
  const state = { tick: 0, playing: false, last: 0, carry: 0 };

  function layout() {
    const beliefsShown = $("show-beliefs").checked && hasBeliefs;
    const avail = Math.max(240, (document.documentElement.clientWidth || 900) - 48 -
      (beliefsShown ? 340 : 0));
    const maxH = Math.max(240, (window.innerHeight || 800) - 330);
    view.k = Math.min(avail / W, maxH / H, 12);
    view.dpr = window.devicePixelRatio || 1;
    view.cssW = Math.max(1, Math.round(W * view.k));
    view.cssH = Math.max(1, Math.round(H * view.k));
    for (const c of [mapCanvas, trail]) {
      c.width = Math.round(view.cssW * view.dpr); c.height = Math.round(view.cssH * view.dpr);
    }
    mapCanvas.style.width = view.cssW + "px"; mapCanvas.style.height = view.cssH + "px";
    view.trailTick = -1;
    layoutPanels(beliefsShown);
    layoutCharts();
  }
  const cx = (c) => (c + 0.5) * view.k;
  const at = (t, i, axis) => pos[(t * N + i) * 2 + axis];

  function drawTrails(t) {
    const tc = trailCtx;
    let from = view.trailTick;
    if (from < 0 || from > t) {
      tc.setTransform(1, 0, 0, 1, 0, 0);
      tc.clearRect(0, 0, trail.width, trail.height);
      from = 0;
    }
    if (from < t) {
      tc.setTransform(view.dpr, 0, 0, view.dpr, 0, 0);
      tc.lineWidth = Math.max(1.5, Math.min(view.k * 0.5, 4));
      tc.lineJoin = "round"; tc.lineCap = "round";
      for (let i = 0; i < N; i++) {
        tc.strokeStyle = trailColours[i];
        tc.beginPath();
        tc.moveTo(cx(at(from, i, 1)), cx(at(from, i, 0)));
        for (let s = from + 1; s <= t; s++) tc.lineTo(cx(at(s, i, 1)), cx(at(s, i, 0)));
        tc.stroke();
      }
    }
    view.trailTick = t;
    ctx.drawImage(trail, 0, 0, view.cssW, view.cssH);
  }
  function drawLinks(t) {
    const comp = A.component, bits = A.link_bits;
    const leader = new Map();
    for (let i = 0; i < N; i++) {
      const label = comp[t * N + i];
      if (label >= 0 && !leader.has(label)) leader.set(label, i);
    }
    ctx.lineWidth = Math.max(1.5, Math.min(view.k * 0.35, 3));
    for (let p = 0; p < pairA.length; p++) {
      if (!((bits[t * linkBytes + (p >> 3)] >> (7 - (p & 7))) & 1)) continue;
      const a = pairA[p], b = pairB[p];
      ctx.strokeStyle = colours[leader.get(comp[t * N + a]) ?? a];
      ctx.beginPath();
      ctx.moveTo(cx(at(t, a, 1)), cx(at(t, a, 0)));
      ctx.lineTo(cx(at(t, b, 1)), cx(at(t, b, 0)));
      ctx.stroke();
    }
  }
  function robotSide() { return Math.max(7, Math.min(view.k, 16)); }
  function drawTargets(t) {
    const r = robotSide() * 0.7;
    for (let i = 0; i < N; i++) {
      const k = (t * N + i) * 2;
      if (goals[k] < 0 || !alive(t, i)) continue;
      const x = cx(goals[k + 1]), y = cx(goals[k]);
      ctx.beginPath(); ctx.arc(x, y, r, 0, 2 * Math.PI);
      ctx.lineWidth = 4; ctx.strokeStyle = "#141414"; ctx.stroke();
      ctx.lineWidth = 2; ctx.strokeStyle = colours[i]; ctx.stroke();
    }
  }
  function drawRobot(c2d, x, y, side, colour, dead) {
    c2d.fillStyle = "#141414";
    c2d.fillRect(x - side / 2 - 1, y - side / 2 - 1, side + 2, side + 2);
    c2d.fillStyle = colour;
    c2d.fillRect(x - side / 2, y - side / 2, side, side);
    if (dead) {
      c2d.strokeStyle = "#141414"; c2d.lineWidth = Math.max(1.5, side / 5);
      c2d.beginPath();
      c2d.moveTo(x - side / 2, y - side / 2); c2d.lineTo(x + side / 2, y + side / 2);
      c2d.moveTo(x + side / 2, y - side / 2); c2d.lineTo(x - side / 2, y + side / 2);
      c2d.stroke();
    }
  }
  // A robot's believed cell: a hollow square in its colour, a thin line to the robot.
  function drawBelieved(c2d, x, y, bx, by, side, colour) {
    c2d.strokeStyle = colour;
    c2d.lineWidth = 1;
    c2d.beginPath(); c2d.moveTo(x, y); c2d.lineTo(bx, by); c2d.stroke();
    c2d.lineWidth = 2;
    c2d.strokeRect(bx - side / 2, by - side / 2, side, side);
  }
  const estAt = (t, i, axis) => est[(t * N + i) * 2 + axis];
  function believedShown(t, i) {
    return alive(t, i) && (estAt(t, i, 0) !== at(t, i, 0) || estAt(t, i, 1) !== at(t, i, 1));
  }
  function drawMap(t) {
    let clock = performance.now();
    const lap = (name) => {
      const now = performance.now();
      parts[name] = (parts[name] || 0) + now - clock;
      clock = now;
    };
    advance(base, team, t);
    lap("cells");
    ctx.setTransform(view.dpr, 0, 0, view.dpr, 0, 0);
    ctx.imageSmoothingEnabled = view.k * S < 1;
    ctx.drawImage(base.canvas, 0, 0, WB, HB, 0, 0, WB * S * view.k, HB * S * view.k);
    lap("blit");
    if ($("show-trails").checked) drawTrails(t);
    lap("trails");
    if (hasLinks && $("show-links").checked) drawLinks(t);
    const side = robotSide();
    if (est && $("show-believed").checked) {
      for (let i = 0; i < N; i++) {
        if (!believedShown(t, i)) continue;
        drawBelieved(ctx, cx(at(t, i, 1)), cx(at(t, i, 0)), cx(estAt(t, i, 1)),
          cx(estAt(t, i, 0)), side + 2, colours[i]);
      }
    }
    if (goals && $("show-targets").checked) drawTargets(t);
    for (let i = 0; i < N; i++) {
      drawRobot(ctx, cx(at(t, i, 1)), cx(at(t, i, 0)), side, colours[i], !alive(t, i));
    }
    lap("overlays");
  }

  // Belief panels.
  const beliefsBox = $("beliefs");
  function layoutPanels(shown) {
    beliefsBox.hidden = !shown;
    beliefsBox.textContent = "";
    if (!shown) return;
    const columns = Math.ceil(Math.sqrt(N));
    beliefsBox.style.gridTemplateColumns = `repeat(${columns}, auto)`;
    const side = Math.max(90, Math.min(220, (view.cssH - 8 * columns) / columns - 16));
    for (let r = 0; r < N; r++) {
      const p = panels[r];
      const k = side / Math.max(p.WP, p.HP);
      p.cssW = Math.round(p.WP * k); p.cssH = Math.round(p.HP * k); p.k = k;
      const box = document.createElement("div");
      box.className = "panel";
      const caption = document.createElement("div");
      caption.textContent = "robot " + r;
      caption.style.color = colours[r];
      const canvas = document.createElement("canvas");
      canvas.width = Math.round(p.cssW * view.dpr); canvas.height = Math.round(p.cssH * view.dpr);
      canvas.style.width = p.cssW + "px"; canvas.style.height = p.cssH + "px";
      canvas.style.borderColor = colours[r];
      box.appendChild(caption); box.appendChild(canvas);
      beliefsBox.appendChild(box);
      p.canvas = canvas; p.ctx = canvas.getContext("2d"); p.caption = caption;
    }
  }
  function drawPanels(t) {
    for (let r = 0; r < N; r++) {
      const p = panels[r];
      advance(p.layer, p.sorted, t);
      const c2d = p.ctx;
      c2d.setTransform(view.dpr, 0, 0, view.dpr, 0, 0);
      c2d.imageSmoothingEnabled = false;
      c2d.drawImage(p.layer.canvas, 0, 0, p.cssW, p.cssH);
      const scale = p.k / p.PS;
      if (est && $("show-believed").checked && believedShown(t, r)) {
        drawBelieved(c2d, (at(t, r, 1) + 0.5) * scale, (at(t, r, 0) + 0.5) * scale,
          (estAt(t, r, 1) + 0.5) * scale, (estAt(t, r, 0) + 0.5) * scale, 9, colours[r]);
      }
      drawRobot(c2d, (at(t, r, 1) + 0.5) * scale, (at(t, r, 0) + 0.5) * scale, 6, colours[r],
        !alive(t, r));
      p.caption.textContent = "robot " + r + (alive(t, r) ? "" : " (failed)");
    }
  }

  // Charts under the map: value per tick with a cursor at the current tick.
  const charts = [];
  function addChart(id, label, values, format, yMax) {
    const canvas = document.createElement("canvas");
    canvas.id = id;
    $("charts").appendChild(canvas);
    const chart = { canvas, ctx: canvas.getContext("2d"), label, values, format, yMax,
      image: null };
    charts.push(chart);
    const seekFrom = (event) => {
      const rect = canvas.getBoundingClientRect();
      const x = (event.clientX - rect.left - chart.left) / (chart.plotW || 1);
      seek(Math.round(Math.max(0, Math.min(1, x)) * T));
    };
    canvas.addEventListener("mousedown", (event) => { pause(); seekFrom(event); });
    canvas.addEventListener("mousemove", (event) => { if (event.buttons & 1) seekFrom(event); });
  }
  if (A.coverage) addChart("chart-coverage", "coverage", A.coverage,
    (v) => (100 * v).toFixed(1) + "%", 1);
  if (A.bytes) addChart("chart-bytes", "bytes sent (cumulative)", A.bytes, formatBytes, 0);
  const subnetworks = A.subnetworks || null;
  if (subnetworks && N > 1) addChart("chart-subnetworks", "sub-networks", subnetworks,
    (v) => String(v), 0);

  function layoutCharts() {
    const width = Math.max(260, Math.min(view.cssW, 900) / Math.min(charts.length, 2) - 8);
    for (const chart of charts) {
      const cssW = Math.round(width), cssH = 130;
      chart.cssW = cssW; chart.cssH = cssH;
      chart.canvas.width = Math.round(cssW * view.dpr);
      chart.canvas.height = Math.round(cssH * view.dpr);
      chart.canvas.style.width = cssW + "px"; chart.canvas.style.height = cssH + "px";
      chart.left = 8; chart.top = 18; chart.plotW = cssW - 16; chart.plotH = cssH - 34;
      drawChartBase(chart);
    }
  }
  function drawChartBase(chart) {
    const c = chart.ctx, v = chart.values;
    let max = chart.yMax;
    if (!max) { max = 0; for (let i = 0; i < v.length; i++) if (v[i] > max) max = v[i]; }
    chart.max = max || 1;
    c.setTransform(view.dpr, 0, 0, view.dpr, 0, 0);
    c.clearRect(0, 0, chart.cssW, chart.cssH);
    c.fillStyle = "#fff"; c.fillRect(0, 0, chart.cssW, chart.cssH);
    c.strokeStyle = "#ddd"; c.lineWidth = 1;
    c.strokeRect(chart.left, chart.top, chart.plotW, chart.plotH);
    c.fillStyle = "#555"; c.font = "11px system-ui, sans-serif";
    const last = chart.format(v[v.length - 1]), top = chart.format(chart.max);
    const note = last === top || chart.yMax ? "final " + last : "max " + top + ", final " + last;
    c.fillText(chart.label + " (" + note + ")", chart.left, 12);
    c.fillText("0", chart.left, chart.top + chart.plotH + 12);
    const end = "tick " + T;
    c.fillText(end, chart.left + chart.plotW - c.measureText(end).width,
      chart.top + chart.plotH + 12);
    c.strokeStyle = "#1f77b4"; c.lineWidth = 1.5; c.beginPath();
    const n = Math.min(v.length, Math.max(2, Math.round(chart.plotW * 2)));
    for (let j = 0; j < n; j++) {
      const t = Math.round((j / (n - 1)) * T);
      const x = chart.left + (t / Math.max(T, 1)) * chart.plotW;
      const y = chart.top + chart.plotH * (1 - v[t] / chart.max);
      if (j === 0) c.moveTo(x, y); else c.lineTo(x, y);
    }
    c.stroke();
    chart.image = c.getImageData(0, 0, chart.canvas.width, chart.canvas.height);
  }
  function drawCharts(t) {
    for (const chart of charts) {
      const c = chart.ctx;
      c.putImageData(chart.image, 0, 0);
      const x = chart.left + (t / Math.max(T, 1)) * chart.plotW;
      const y = chart.top + chart.plotH * (1 - chart.values[t] / chart.max);
      c.strokeStyle = "#d62728"; c.lineWidth = 1;
      c.beginPath(); c.moveTo(x, chart.top); c.lineTo(x, chart.top + chart.plotH); c.stroke();
      c.fillStyle = "#d62728"; c.beginPath(); c.arc(x, y, 3, 0, 2 * Math.PI); c.fill();
      const text = chart.format(chart.values[t]);
      const w = c.measureText(text).width;
      c.fillText(text, Math.min(x + 5, chart.left + chart.plotW - w), chart.top + 11);
    }
  }

  function readouts(t) {
    $("tick").textContent = String(t);
    $("coverage").textContent = (100 * A.coverage[t]).toFixed(1) + "%";
    $("bytes").textContent = A.bytes ? formatBytes(A.bytes[t]) : "-";
    let groups = "-";
    if (subnetworks) groups = String(subnetworks[t]);
    $("subnetworks").textContent = groups;
    let failed = 0;
    for (let i = 0; i < N; i++) if (!alive(t, i)) failed++;
    $("failed").textContent = String(failed);
    if (locError) {
      let sum = 0, max = 0, live = 0;
      for (let i = 0; i < N; i++) {
        if (!alive(t, i)) continue;
        const e = locError[t * N + i] / 10;  // sent in tenths of a cell
        sum += e; live++; if (e > max) max = e;
      }
      $("localisation").textContent = live ? (sum / live).toFixed(1) + " / " + max.toFixed(1)
        : "-";
    }
    slider.value = String(t);
  }

  const parts = {};  // milliseconds spent per drawing step, summed over frames
  const stats = { frames: 0, totalMs: 0, lastMs: 0, parts };
  function render() {
    const started = performance.now();
    const t = state.tick;
    drawMap(t);
    let clock = performance.now();
    if (hasBeliefs && $("show-beliefs").checked) drawPanels(t);
    parts.panels = (parts.panels || 0) + performance.now() - clock;
    clock = performance.now();
    drawCharts(t);
    readouts(t);
    parts.charts = (parts.charts || 0) + performance.now() - clock;
    stats.lastMs = performance.now() - started;
    stats.frames++; stats.totalMs += stats.lastMs;
  }
  function seek(t) {
    state.tick = Math.max(0, Math.min(T, Math.round(t)));
    render();
  }

  // ------------------------------------------------------------------ playing
  const playButton = $("play");
  function step(now) {
    if (!state.playing) return;
    const elapsed = Math.min(0.25, (now - state.last) / 1000);
    state.last = now;
    state.carry += elapsed * Number(speedSelect.value);
    const ticks = Math.floor(state.carry);
    if (ticks > 0) {
      state.carry -= ticks;
      seek(state.tick + ticks);
    }
    if (state.tick >= T) { pause(); return; }
    requestAnimationFrame(step);
  }
  function play() {
    if (state.playing) return;
    if (state.tick >= T) seek(0);
    state.playing = true; state.last = performance.now(); state.carry = 0;
    playButton.innerHTML = "&#10074;&#10074; Pause";
    requestAnimationFrame(step);
  }
  function pause() {
    state.playing = false;
    playButton.innerHTML = "&#9654; Play";
  }
  playButton.addEventListener("click", () => (state.playing ? pause() : play()));
  slider.addEventListener("input", () => seek(Number(slider.value)));
  for (const id of ["show-links", "show-targets", "show-trails", "show-believed"]) {
    $(id).addEventListener("change", () => render());
  }
  $("show-beliefs").addEventListener("change", () => { layout(); render(); });
  window.addEventListener("resize", () => { layout(); render(); });
  document.addEventListener("keydown", (event) => {
    // Menus answer the keyboard themselves, buttons and checkboxes the space bar.
    const tag = event.target && event.target.tagName;
    if (tag === "SELECT") return;
    const pressable = tag === "BUTTON" || (tag === "INPUT" && event.target.type === "checkbox");
    if (event.key === " " && !pressable) {
      event.preventDefault();
      if (state.playing) pause(); else play();
    } else if (event.target !== slider &&
      (event.key === "ArrowRight" || event.key === "ArrowLeft")) {
      event.preventDefault();
      pause();
      seek(state.tick + (event.key === "ArrowRight" ? 1 : -1) * (event.shiftKey ? 10 : 1));
    }
  });

  // Mean time to draw a frame over `frames` evenly spread ticks (forward, then back).
  function benchmark(frames) {
    const n = Math.max(2, frames | 0);
    for (const key of Object.keys(parts)) delete parts[key];
    const started = performance.now();
    for (let j = 0; j < n; j++) seek(Math.round((j / (n - 1)) * T));
    const forward = (performance.now() - started) / n;
    const back = performance.now();
    for (let j = n - 1; j >= 0; j--) seek(Math.round((j / (n - 1)) * T));
    const backward = (performance.now() - back) / n;
    const perFrame = {};
    for (const [key, ms] of Object.entries(parts)) perFrame[key] = ms / (2 * n);
    return { forwardMs: forward, backwardMs: backward, frames: n, partsMs: perFrame };
  }

  // A link can open the replay at a moment: replay.html#tick=250&beliefs=1&links=0.
  const wish = new URLSearchParams(location.hash.slice(1));
  for (const [key, id] of [["links", "show-links"], ["targets", "show-targets"],
    ["trails", "show-trails"], ["beliefs", "show-beliefs"], ["believed", "show-believed"]]) {
    if (wish.has(key) && !$(id).disabled) $(id).checked = wish.get(key) !== "0";
  }
  if (speeds.includes(Number(wish.get("speed")))) speedSelect.value = wish.get("speed");
  layout();
  seek(Number(wish.get("tick")) || 0);
  playButton.disabled = false;
  slider.disabled = false;
  status.textContent = "";
  window.replay = { seek, play, pause, benchmark, stats, meta,
    get tick() { return state.tick; }, get playing() { return state.playing; } };
  document.body.dataset.ready = "1";
})().catch((error) => {
  document.getElementById("status").textContent = "Could not show this run: " + error;
  document.body.dataset.error = String(error);
});
"""
