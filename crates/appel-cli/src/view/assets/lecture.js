// The lecture page: asks the server (Appel's lecture2d module) for a scene, a structure's build
// steps and a ray's traversal, and draws them. No structure is computed here.
"use strict";
(() => {
  const $ = (id) => document.getElementById(id);
  const canvas = $("world"), ctx = canvas.getContext("2d");
  const state = { data: null, ready: false, ray: null, requests: 0 };
  window.appelLecture = state;  // read by the browser tests
  const params = new URLSearchParams(location.search);

  // World [0,100]^2 with y up onto the canvas with a margin.
  const M = 20, S = (canvas.width - 2 * M) / 100;
  const toPx = (p) => [M + p.x * S, canvas.height - M - p.y * S];
  const toWorld = (x, y) => ({ x: (x - M) / S, y: (canvas.height - M - y) / S });

  function fill(id, names, value) {
    const s = $(id);
    if (s.options.length === 0) for (const n of names) { const o = document.createElement("option"); o.textContent = n; s.appendChild(o); }
    if (value) s.value = value;
  }
  for (const k of ["n", "seed", "c"]) if (params.has(k)) $(k).value = params.get(k);
  if (params.has("check")) $("check").checked = params.get("check") !== "0";
  if (params.has("ray")) { const [a, b, c, d] = params.get("ray").split(",").map(Number); state.ray = [{ x: a, y: b }, { x: c, y: d }]; }

  async function load() {
    state.ready = false;
    const q = new URLSearchParams({
      scene: $("scene").value || params.get("scene") || "figures", n: $("n").value, seed: $("seed").value,
      structure: $("structure").value || params.get("structure") || "grid", c: $("c").value, check: $("check").checked ? "1" : "0",
    });
    if (state.ray) q.set("ray", [state.ray[0].x, state.ray[0].y, state.ray[1].x, state.ray[1].y].map((v) => v.toFixed(3)).join(","));
    state.requests += 1;
    const r = await fetch("/api/lecture?" + q);
    if (!r.ok) { $("log").textContent = await r.text(); return; }
    const d = await r.json();
    state.data = d;
    fill("scene", d.scenes, q.get("scene"));
    fill("structure", d.structures, d.structure);
    $("build").max = d.steps.length; $("build").value = d.steps.length;
    const n = d.trace ? d.trace.steps.length : 0;
    $("step").max = n; $("step").value = n;
    table(d);
    draw();
    state.ready = true;
  }

  function path(poly) {
    ctx.beginPath();
    poly.forEach((p, i) => { const [x, y] = toPx(p); i ? ctx.lineTo(x, y) : ctx.moveTo(x, y); });
    ctx.closePath();
  }
  function shape(o) {
    ctx.beginPath();
    if (o.kind === "circle") { const [x, y] = toPx(o.c); ctx.arc(x, y, o.r * S, 0, 2 * Math.PI); }
    else if (o.kind === "segment") { ctx.moveTo(...toPx(o.a)); ctx.lineTo(...toPx(o.b)); }
    else { ctx.moveTo(...toPx(o.a)); ctx.lineTo(...toPx(o.b)); ctx.lineTo(...toPx(o.c)); ctx.closePath(); }
  }

  function draw() {
    const d = state.data;
    if (!d) return;
    ctx.fillStyle = "#111"; ctx.fillRect(0, 0, canvas.width, canvas.height);
    ctx.strokeStyle = "#444"; ctx.lineWidth = 1;
    path([{ x: 0, y: 0 }, { x: 100, y: 0 }, { x: 100, y: 100 }, { x: 0, y: 100 }]); ctx.stroke();
    // The build up to the chosen step: splits as lines, the current node outlined.
    const nb = Number($("build").value);
    for (let i = 0; i < nb; i++) {
      const s = d.steps[i];
      if (s.split) { ctx.strokeStyle = `hsl(${200 - Math.min(s.depth, 10) * 15}, 70%, 55%)`; ctx.lineWidth = 1.2; ctx.beginPath(); ctx.moveTo(...toPx(s.split[0])); ctx.lineTo(...toPx(s.split[1])); ctx.stroke(); }
      if (d.structure.startsWith("bvh") && s.leaf) { ctx.strokeStyle = "#5a8"; ctx.lineWidth = 1; path(s.region); ctx.stroke(); }
    }
    const cur = nb > 0 ? d.steps[nb - 1] : null;
    if (cur) { ctx.strokeStyle = "#ff0"; ctx.lineWidth = 2; path(cur.region); ctx.stroke(); }
    $("build_n").textContent = `${nb}/${d.steps.length}`;
    sah(cur);
    // The traversal up to the chosen step.
    const tested = new Map();
    const ns = Number($("step").value);
    const steps = d.trace ? d.trace.steps.slice(0, ns) : [];
    const visits = steps.filter((s) => s.step === "visit");
    visits.forEach((s, i) => {
      ctx.fillStyle = i === visits.length - 1 ? "rgba(255,220,0,0.35)" : "rgba(255,220,0,0.12)";
      path(s.region); ctx.fill();
    });
    for (const s of steps) {
      if (s.step === "test") tested.set(s.object, s.t == null ? "miss" : "hit");
      if (s.step === "mailbox") tested.set(s.object, "mailbox");
    }
    d.objects.forEach((o, i) => {
      const t = tested.get(i);
      ctx.strokeStyle = t === "hit" ? "#f80" : t === "miss" ? "#c6c" : t === "mailbox" ? "#4af" : "#ccc";
      ctx.lineWidth = t ? 2.5 : 1.5;
      shape(o); ctx.stroke();
    });
    if (state.ray) {
      const [a, b] = state.ray;
      const dir = { x: b.x - a.x, y: b.y - a.y }, len = Math.hypot(dir.x, dir.y) || 1;
      const at = (t) => ({ x: a.x + dir.x / len * t, y: a.y + dir.y / len * t });
      ctx.strokeStyle = "#fff"; ctx.lineWidth = 1; ctx.setLineDash([4, 4]);
      ctx.beginPath(); ctx.moveTo(...toPx(a)); ctx.lineTo(...toPx(at(200))); ctx.stroke(); ctx.setLineDash([]);
      // The slab interval of the current cell or node, thick.
      const v = visits[visits.length - 1];
      if (v) { ctx.strokeStyle = "#ff0"; ctx.lineWidth = 4; ctx.beginPath(); ctx.moveTo(...toPx(at(v.t_enter))); ctx.lineTo(...toPx(at(Math.min(v.t_exit, 200)))); ctx.stroke(); }
      ctx.fillStyle = "#fff"; ctx.beginPath(); ctx.arc(...toPx(a), 4, 0, 2 * Math.PI); ctx.fill();
      const done = d.trace && ns === d.trace.steps.length;
      if (done && d.trace.hit) { ctx.fillStyle = "#0f0"; ctx.beginPath(); ctx.arc(...toPx(at(d.trace.hit[1])), 5, 0, 2 * Math.PI); ctx.fill(); }
      if (done && d.brute_force_hit && (!d.trace.hit || d.trace.hit[0] !== d.brute_force_hit[0])) {
        ctx.strokeStyle = "#f44"; ctx.lineWidth = 2; ctx.beginPath(); ctx.arc(...toPx(at(d.brute_force_hit[1])), 8, 0, 2 * Math.PI); ctx.stroke();
      }
    }
    log(d, ns);
  }

  function sah(step) {
    const c = $("sah"), g = c.getContext("2d");
    g.fillStyle = "#1a1a1a"; g.fillRect(0, 0, c.width, c.height);
    g.fillStyle = "#889"; g.font = "11px sans-serif";
    if (!step || !step.sah || step.sah.costs.length === 0) { g.fillText("SAH cost curve: choose a step of an SAH split", 6, 16); return; }
    const s = step.sah, lo = Math.min(...s.costs, s.leaf_cost) * 0.95, hi = Math.max(...s.costs, s.leaf_cost) * 1.02;
    const x0 = s.positions[0], x1 = s.positions[s.positions.length - 1];
    const X = (p) => 8 + (c.width - 16) * (x1 > x0 ? (p - x0) / (x1 - x0) : 0.5), Y = (v) => c.height - 8 - (c.height - 24) * (v - lo) / (hi - lo || 1);
    g.strokeStyle = "#666"; g.beginPath(); g.moveTo(8, Y(s.leaf_cost)); g.lineTo(c.width - 8, Y(s.leaf_cost)); g.stroke();
    g.strokeStyle = "#4af"; g.beginPath();
    s.positions.forEach((p, i) => (i ? g.lineTo(X(p), Y(s.costs[i])) : g.moveTo(X(p), Y(s.costs[i]))));
    g.stroke();
    g.fillStyle = "#ff0"; g.beginPath(); g.arc(X(s.positions[s.chosen]), Y(s.costs[s.chosen]), 4, 0, 2 * Math.PI); g.fill();
    g.fillStyle = "#889"; g.fillText(`SAH cost along ${"xy"[s.axis]} (grey: leaf ${s.leaf_cost})`, 6, 12);
  }

  function log(d, ns) {
    const el = $("log");
    $("step_n").textContent = d.trace ? `${ns}/${d.trace.steps.length}` : "";
    if (!d.trace) { el.textContent = "Drag on the scene to cast a ray."; return; }
    const f = (t) => (t === Infinity || t > 1e30 ? "inf" : t.toFixed(2));
    el.innerHTML = d.trace.steps.map((s, i) => {
      let text;
      if (s.step === "visit") text = `visit ${d.structure === "grid" ? "cell" : "node"} ${s.id}: t in [${f(s.t_enter)}, ${f(s.t_exit)}]`;
      else if (s.step === "test") text = `  test object ${s.object}: ${s.t == null ? "miss" : "hit at t=" + f(s.t)}`;
      else if (s.step === "mailbox") text = `  object ${s.object}: already tested (mailbox)`;
      else if (s.step === "early_exit") text = `early exit: nearest hit t=${f(s.t)}`;
      else text = `  PITFALL: hit of object ${s.object} at t=${f(s.t)} lies beyond the cell (exit ${f(s.t_exit)})`;
      return `<div style="${i === ns - 1 ? "background:#443" : i >= ns ? "opacity:0.4" : ""}">${text}</div>`;
    }).join("");
  }

  function table(d) {
    const tb = document.querySelector("#compare tbody");
    tb.innerHTML = d.compare.map((c) => `<tr class="${c.correct ? "" : "wrong"}"><td>${c.structure}</td><td>${c.counters.visited}</td><td>${c.counters.tests}</td><td>${c.counters.mailbox_hits}</td><td>${c.hit ? c.hit[0] : "-"}${c.correct ? "" : " (wrong)"}</td><td>${c.mean_tests.toFixed(1)}</td></tr>`).join("");
  }

  let drag = null;
  canvas.addEventListener("pointerdown", (e) => {
    const r = canvas.getBoundingClientRect();
    drag = toWorld((e.clientX - r.left) * canvas.width / r.width, (e.clientY - r.top) * canvas.height / r.height);
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const r = canvas.getBoundingClientRect();
    const p = toWorld((e.clientX - r.left) * canvas.width / r.width, (e.clientY - r.top) * canvas.height / r.height);
    if (Math.hypot(p.x - drag.x, p.y - drag.y) > 0.5) { state.ray = [drag, p]; if (state.data) { state.data.trace = null; draw(); } }
  });
  canvas.addEventListener("pointerup", () => { if (drag && state.ray) load(); drag = null; });
  for (const id of ["scene", "n", "seed", "structure", "c", "check"]) $(id).addEventListener("change", load);
  $("build").addEventListener("input", draw);
  $("step").addEventListener("input", draw);
  $("prev").addEventListener("click", () => { $("step").value = Number($("step").value) - 1; draw(); });
  $("next").addEventListener("click", () => { $("step").value = Number($("step").value) + 1; draw(); });
  let playing = null;
  $("play").addEventListener("click", () => {
    clearInterval(playing);
    $("build").value = 0; $("step").value = 0;
    playing = setInterval(() => {
      const b = $("build");
      if (Number(b.value) >= Number(b.max)) { clearInterval(playing); $("step").value = $("step").max; draw(); return; }
      b.value = Number(b.value) + 1; draw();
    }, 120);
  });
  load();
})();
