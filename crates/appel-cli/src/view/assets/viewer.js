// The viewer page: camera controls send the view to the server over a WebSocket; the server
// answers with frames (previews while moving or while an animation plays, then refined samples),
// each acknowledged once drawn.
"use strict";
(() => {
  const canvas = document.getElementById("view");
  const ctx = canvas.getContext("2d");
  const $ = (id) => document.getElementById(id);
  const state = { frames: 0, fps: 0, last: null, hello: null, scene: null, errors: [], times: [] };
  window.appelViewer = state;  // read by the browser tests

  const cam = { eye: [0, 0, 5], target: [0, 0, 0], up: [0, 1, 0], fov: 40 };
  const add = (a, b) => a.map((x, i) => x + b[i]);
  const sub = (a, b) => a.map((x, i) => x - b[i]);
  const mul = (a, k) => a.map((x) => x * k);
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const norm = (a) => mul(a, 1 / Math.hypot(a[0], a[1], a[2]));
  // Rodrigues' rotation of v about the unit axis k by angle a.
  const rotate = (v, k, a) => add(add(mul(v, Math.cos(a)), mul(cross(k, v), Math.sin(a))), mul(k, dot(k, v) * (1 - Math.cos(a))));

  const ws = new WebSocket(`ws://${location.host}/ws`);
  ws.binaryType = "arraybuffer";
  const send = (m) => { if (ws.readyState === 1) ws.send(JSON.stringify(m)); };
  const sendCamera = (moving) => send({ type: "camera", eye: cam.eye, look_at: cam.target, up: cam.up, fov: cam.fov, moving });

  ws.onopen = () => { $("status").textContent = "connected"; };
  ws.onclose = () => { $("status").textContent = "disconnected"; };
  // Each frame's info comes just before its image. Up to two frames are in flight, so infos
  // wait in order for their images, and images are drawn in order (decoding is asynchronous).
  const infos = [];
  let drawing = Promise.resolve();
  ws.onmessage = (ev) => {
    if (typeof ev.data === "string") {
      const m = JSON.parse(ev.data);
      if (m.type === "hello") hello(m);
      else if (m.type === "scene") sceneInfo(m);
      else if (m.type === "frame") infos.push(m);
      else if (m.type === "error") { state.errors.push(m.message); $("status").textContent = "error: " + m.message; }
      return;
    }
    const info = infos.shift();
    drawing = drawing.then(() => draw(ev.data, info));
  };

  async function draw(buf, info) {
    const head = new DataView(buf, 0, 16);
    const w = head.getUint32(4, true), h = head.getUint32(8, true), format = head.getUint32(12, true);
    const body = new Uint8Array(buf, 16);
    let bitmap;
    if (format === 2 && w === canvas.width && h === canvas.height) {
      // Raw RGBA of the canvas's size: put as it is, with no bitmap to make.
      ctx.putImageData(new ImageData(new Uint8ClampedArray(body.buffer, 16, w * h * 4), w, h), 0, 0);
    } else if (format === 2) {
      bitmap = await createImageBitmap(new ImageData(new Uint8ClampedArray(body.buffer, 16, w * h * 4), w, h));
    } else {
      bitmap = await createImageBitmap(new Blob([body], { type: format === 1 ? "image/png" : "image/jpeg" }));
    }
    if (bitmap) {
      ctx.imageSmoothingEnabled = true;
      ctx.drawImage(bitmap, 0, 0, canvas.width, canvas.height);
      bitmap.close();
    }
    state.frames += 1;
    const now = performance.now();
    state.times.push(now);
    while (state.times.length && now - state.times[0] > 1000) state.times.shift();
    state.fps = state.times.length;
    $("s_fps").textContent = state.fps;
    // Acknowledged once drawn: the server then may send another.
    if (info) { state.last = info; showInfo(info); send({ type: "ack", frame: info.id }); }
  }

  function fill(id, names, value) {
    const s = $(id);
    s.innerHTML = "";
    for (const n of names) { const o = document.createElement("option"); o.textContent = n; s.appendChild(o); }
    s.value = value;
  }

  function hello(m) {
    state.hello = m;
    cam.eye = m.eye; cam.target = m.look_at; cam.up = m.up; cam.fov = m.fov;
    fill("integrator", m.integrators, m.integrator);
    fill("preview", m.previews, "whitted");
    fill("accel", m.accels, m.accel);
    fill("aov", m.aovs, "color");
    fill("format", m.formats, m.format);
    $("spp").value = m.spp;
    $("aperture_radius").value = m.aperture_radius;
    $("focus_distance").value = m.focus_distance;
    const size = `${m.width}x${m.height}`;
    if (![...$("size").options].some((o) => o.value === size)) { const o = document.createElement("option"); o.textContent = size; $("size").appendChild(o); }
    $("size").value = size;
    canvas.width = m.width; canvas.height = m.height;
    const animated = m.frames > 1;
    $("animation").hidden = !animated;
    for (const row of document.querySelectorAll("tr.anim")) row.hidden = !animated;
    $("anim_frame").max = m.frames - 1;
  }

  const fmtBytes = (b) => b == null ? "-" : b > 1e6 ? (b / 1e6).toFixed(1) + " MB" : (b / 1e3).toFixed(1) + " kB";
  function sceneInfo(m) {
    state.scene = m;
    $("s_build").textContent = m.build_ms.toFixed(2) + " ms (" + m.accel + ")";
    $("s_mem").textContent = fmtBytes(m.accel_bytes);
    $("s_rss").textContent = fmtBytes(m.peak_rss_bytes);
    $("s_prims").textContent = m.primitives;
  }
  function showInfo(m) {
    $("s_mrays").textContent = m.mrays_per_s.toFixed(1);
    $("s_spp").textContent = m.preview ? "preview (" + m.integrator + ")" : `${m.spp} / ${m.target_spp}`;
    $("s_frame").textContent = `#${m.id} ${m.width}x${m.height}`;
    $("s_ms").textContent = m.render_ms.toFixed(1) + " / " + m.encode_ms.toFixed(1);
    $("s_bytes").textContent = fmtBytes(m.bytes);
    if (state.hello && state.hello.frames > 1) {
      $("s_anim").textContent = `${m.anim_frame} / ${state.hello.frames - 1}` + (m.playing ? " (playing)" : "");
      if (document.activeElement !== $("anim_frame")) $("anim_frame").value = m.anim_frame;
      $("play").textContent = m.playing ? "Pause" : "Play";
      if (m.step) {
        const s = m.step;
        $("s_refit").textContent = `${s.refit_ms.toFixed(2)} ms (${s.refitted} refitted, ${s.rebuilt} rebuilt; load ${s.load_ms.toFixed(1)} ms)`;
      }
    }
  }

  // Play and pause an animated scene; the slider shows a frame (and playing goes on from it).
  state.playing = false;
  $("play").addEventListener("click", () => {
    state.playing = !state.playing;
    $("play").textContent = state.playing ? "Pause" : "Play";
    send({ type: "play", playing: state.playing });
  });
  $("anim_frame").addEventListener("input", () => send({ type: "seek", frame: Number($("anim_frame").value) }));

  for (const id of ["integrator", "preview", "accel", "aov", "format", "spp", "size", "preview_scale", "aperture_radius", "focus_distance"]) {
    $(id).addEventListener("change", () => {
      const [w, h] = $("size").value.split("x").map(Number);
      canvas.width = w; canvas.height = h;
      send({ type: "settings", integrator: $("integrator").value, preview: $("preview").value, accel: $("accel").value,
        aov: $("aov").value, format: $("format").value, spp: Math.max(1, Number($("spp").value) | 0), width: w, height: h,
        preview_scale: Number($("preview_scale").value), ...lens() });
    });
  }

  // The lens's fields, those that hold a valid number (the server checks them too).
  function lens() {
    const out = {};
    const r = Number($("aperture_radius").value), f = Number($("focus_distance").value);
    if ($("aperture_radius").value !== "" && r >= 0) out.aperture_radius = r;
    if ($("focus_distance").value !== "" && f > 0) out.focus_distance = f;
    return out;
  }

  // Orbit about the target (yaw about the up axis, pitch about the right axis), pan, zoom.
  function orbit(dx, dy) {
    let off = sub(cam.eye, cam.target);
    off = rotate(off, norm(cam.up), -dx * 0.008);
    const right = norm(cross(off, cam.up));
    const turned = rotate(off, right, dy * 0.008);
    // Stop short of the poles, where up and the view direction would align.
    if (Math.abs(dot(norm(turned), norm(cam.up))) < 0.98) off = turned;
    cam.eye = add(cam.target, off);
  }
  function pan(dx, dy) {
    const off = sub(cam.eye, cam.target);
    const dist = Math.hypot(...off);
    const f = norm(mul(off, -1)), r = norm(cross(f, cam.up)), u = cross(r, f);
    const k = dist * 2 * Math.tan(cam.fov * Math.PI / 360) / canvas.clientHeight;
    const move = add(mul(r, -dx * k), mul(u, dy * k));
    cam.eye = add(cam.eye, move); cam.target = add(cam.target, move);
  }
  function zoom(factor) {
    const off = sub(cam.eye, cam.target);
    const dist = Math.hypot(...off);
    if (dist * factor < 1e-3 * (state.hello ? state.hello.scene_size : 1)) return;
    cam.eye = add(cam.target, mul(off, factor));
  }

  const pointers = new Map();
  let pinch = null;
  canvas.addEventListener("contextmenu", (e) => e.preventDefault());
  canvas.addEventListener("pointerdown", (e) => {
    canvas.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY, button: e.button, shift: e.shiftKey });
    canvas.focus();
  });
  canvas.addEventListener("pointermove", (e) => {
    const p = pointers.get(e.pointerId);
    if (!p) return;
    const dx = e.clientX - p.x, dy = e.clientY - p.y;
    p.x = e.clientX; p.y = e.clientY;
    if (pointers.size === 2) {
      const [a, b] = [...pointers.values()];
      const d = Math.hypot(a.x - b.x, a.y - b.y);
      if (pinch) zoom(pinch / Math.max(d, 1));
      pinch = d;
      pan(dx / 2, dy / 2);
    } else if (p.button === 2 || p.shift) pan(dx, dy);
    else orbit(dx, dy);
    sendCamera(true);
  });
  const release = (e) => {
    if (!pointers.delete(e.pointerId)) return;
    pinch = null;
    if (pointers.size === 0) sendCamera(false);
  };
  canvas.addEventListener("pointerup", release);
  canvas.addEventListener("pointercancel", release);
  let wheelTimer = null;
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    zoom(Math.exp(e.deltaY * 0.001));
    sendCamera(true);
    clearTimeout(wheelTimer);
    wheelTimer = setTimeout(() => sendCamera(false), 150);
  }, { passive: false });

  // WASD (and QE for down and up) fly the eye and target together while held.
  const held = new Set();
  let lastTick = 0;
  const keys = { w: [0, 0, 1], s: [0, 0, -1], a: [-1, 0, 0], d: [1, 0, 0], q: [0, -1, 0], e: [0, 1, 0] };
  window.addEventListener("keydown", (e) => {
    const k = e.key.toLowerCase();
    if (!(k in keys) || e.target.tagName === "INPUT") return;
    if (held.size === 0) { lastTick = performance.now(); requestAnimationFrame(fly); }
    held.add(k);
  });
  window.addEventListener("keyup", (e) => { held.delete(e.key.toLowerCase()); if (held.size === 0) sendCamera(false); });
  function fly(now) {
    if (held.size === 0) return;
    const dt = Math.min(0.1, (now - lastTick) / 1000);
    lastTick = now;
    const off = sub(cam.target, cam.eye);
    const f = norm(off), r = norm(cross(f, cam.up)), u = cross(r, f);
    const speed = 0.4 * Math.hypot(...off) * dt;
    let move = [0, 0, 0];
    for (const k of held) { const [x, y, z] = keys[k]; move = add(move, add(add(mul(r, x), mul(u, y)), mul(f, z))); }
    move = mul(move, speed);
    cam.eye = add(cam.eye, move); cam.target = add(cam.target, move);
    sendCamera(true);
    requestAnimationFrame(fly);
  }
})();
