// The haptex viewer page: the whole cloth as a shaded mesh, the fingers as capsules at the
// device's pose, the local patch highlighted, a force arrow per finger, the contact state (I-IX),
// each finger's 6 x 4 pin amplitudes and the services' loop health. Live, it is a client of the
// viewer's Foxglove WebSocket server; in replay (`haptex view RUN`) it reads the run's MCAP file
// and offers play, pause and a timeline. window.haptexViewer exposes what is shown, for tests.

import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { decodeClothPositions } from "./cloth_positions.js";
import { connectLive } from "./foxglove_client.js";
import { readMcap } from "./mcap_file.js";
import { makeDecoder } from "./proto_decoder.js";

const STATE_NAMES = ["-", "I", "II", "III", "IV", "V", "VI", "VII", "VIII", "IX"];
const FINGERS = { 1: "thumb", 2: "index" };
const ARROW_M_PER_N = 0.02;  // a 1 N force is drawn 2 cm long
const SHOWN = new Set(["haptex.v1.ClothFrame", "haptex.v1.FingerStates", "haptex.v1.ForceModel",
                       "haptex.v1.TouchTrace", "haptex.v1.PinFrame", "haptex.v1.Health"]);

const stats = {
  mode: "", status: "starting", framesRendered: 0, fps: 0, clothFrames: 0, clothVertexCount: 0,
  standClamps: 0, patchParticles: 0, patchFramesSeen: 0, pinFrames: 0, pinMax: 0,
  messages: 0, contactStates: { thumb: "-", index: "-" }, forcesN: { thumb: 0, index: 0 },
  peakForceN: { thumb: 0, index: 0 }, stateTicks: { thumb: {}, index: {} }, health: {}, errors: [],
  timeS: 0, durationS: 0, playing: false, renderScale: 1,
};
window.haptexViewer = {
  stats,
  clothVertex: (k) => (cloth.positions ? Array.from(cloth.positions.slice(3 * k, 3 * k + 3)) : null),
  seek: (t) => seek(t),
  // replay: the first moment both fingers pinch (state VIII or IX), shown; -1 when never
  seekToPinch: () => {
    setPlaying(false);
    seek(0);
    const pinched = (s) => s === "VIII" || s === "IX";
    for (let t = 0; t <= stats.durationS; t += 0.02) {
      seek(t);
      if (pinched(stats.contactStates.thumb) && pinched(stats.contactStates.index)) return t;
    }
    return -1;
  },
  play: () => setPlaying(true),
  pause: () => setPlaying(false),
};

// ---- three.js scene (W: z up, y towards the user)
const canvas = document.getElementById("view");
// no multisampling: where the GPU is software (headless, VMs) it costs most of the frame
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
renderer.setPixelRatio(window.devicePixelRatio);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x20242b);
const camera = new THREE.PerspectiveCamera(40, 1, 0.005, 10);
camera.up.set(0, 0, 1);
camera.position.set(0.18, 0.42, -0.02);
const controls = new OrbitControls(camera, canvas);
controls.target.set(0, 0, -0.1);
controls.update();
scene.add(new THREE.HemisphereLight(0xe8eef8, 0x303030, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(0.3, 0.6, 0.5);
scene.add(sun);

const cloth = { mesh: null, positions: null, colors: null, u: 0, v: 0, assembling: null, frame: -1, seen: new Set(),
                patch: null, assemblingPatch: null };
const clothMaterial = new THREE.MeshStandardMaterial({ vertexColors: true, side: THREE.DoubleSide, roughness: 0.9 });
// the stand: a grey clamp on each particle it holds (the scene's fixed particles, from session.json)
let stand = null;

const fingers = {};
for (const name of ["thumb", "index"]) {
  const group = new THREE.Group();
  const body = new THREE.Mesh(new THREE.CapsuleGeometry(0.008, 0.02, 6, 16),
                              new THREE.MeshStandardMaterial({ color: name === "thumb" ? 0xe0a070 : 0x70a0e0 }));
  body.rotation.z = Math.PI / 2;  // three's capsule is along y; the finger frame's long axis is x
  group.add(body);
  group.visible = false;
  scene.add(group);
  const arrow = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 0.01, 0xff4040, 0.006, 0.004);
  arrow.visible = false;
  scene.add(arrow);
  fingers[name] = { group, body, arrow, position: null, radius: 0.008, length: 0.02 };
}

// The share of the screen's pixels drawn: lowered while frames are slow (a software GPU, a busy
// host), raised again when they are fast; the cloth then looks softer, but moves smoothly.
let renderScale = 1;
function adaptRenderScale(fps) {
  const before = renderScale;
  if (fps < 30 && renderScale > 0.25) renderScale = Math.max(0.25, renderScale * 0.7);
  else if (fps > 50 && renderScale < 1) renderScale = Math.min(1, renderScale * 1.25);
  if (renderScale !== before) renderer.setPixelRatio(window.devicePixelRatio * renderScale);
  stats.renderScale = renderScale;
}

function resize() {
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.floor(w * renderer.getPixelRatio()) || canvas.height !== Math.floor(h * renderer.getPixelRatio())) {
    renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(1, h);
    camera.updateProjectionMatrix();
  }
}

function buildCloth(u, v) {
  if (cloth.mesh) { scene.remove(cloth.mesh); cloth.mesh.geometry.dispose(); }
  const n = u * v;
  const geometry = new THREE.BufferGeometry();
  cloth.positions = new Float32Array(3 * n);
  cloth.colors = new Float32Array(3 * n);
  geometry.setAttribute("position", new THREE.BufferAttribute(cloth.positions, 3));
  geometry.setAttribute("color", new THREE.BufferAttribute(cloth.colors, 3));
  const index = [];
  for (let j = 0; j + 1 < v; ++j) {
    for (let i = 0; i + 1 < u; ++i) {
      const a = i + u * j, b = a + 1, c = a + u, d = c + 1;  // particle id = i_u + u * i_v
      index.push(a, c, b, b, c, d);
    }
  }
  geometry.setIndex(index);
  cloth.mesh = new THREE.Mesh(geometry, clothMaterial);
  scene.add(cloth.mesh);
  cloth.u = u;
  cloth.v = v;
  stats.clothVertexCount = n;
}

// ---- what each message changes
function onClothFrame(m) {
  const u = m.particles_u, v = m.particles_v;
  if (!u || !v || u * v > 1 << 20 || m.chunk_index >= m.chunk_count) return;
  if (u !== cloth.u || v !== cloth.v) buildCloth(u, v);
  if (m.frame_index !== cloth.frame) {
    cloth.frame = m.frame_index;
    cloth.seen = new Set();  // chunk indices: a 401 x 401 cloth comes in 42 chunks
    cloth.assembling = cloth.assembling && cloth.assembling.length === 3 * u * v ? cloth.assembling : new Float32Array(3 * u * v);
  }
  if (decodeClothPositions(m, cloth.assembling, 3 * m.first_particle) < 0) return;
  cloth.assemblingPatch = { u0: m.patch_u_begin ?? 0, u1: m.patch_u_end ?? 0, v0: m.patch_v_begin ?? 0, v1: m.patch_v_end ?? 0 };
  cloth.seen.add(m.chunk_index);
  if (cloth.seen.size === m.chunk_count) showCloth(cloth.assembling);
}

function showCloth(positions) {
  cloth.positions.set(positions);
  cloth.patch = cloth.assemblingPatch;
  placeStand();
  colourPatch();
  cloth.mesh.geometry.attributes.position.needsUpdate = true;
  cloth.mesh.geometry.computeVertexNormals();
  ++stats.clothFrames;
}

function placeStand() {
  const fixed = (session.fixed_particles ?? []).filter((k) => Number.isInteger(k) && k >= 0 && k < cloth.u * cloth.v);
  if (!stand) {
    stand = new THREE.InstancedMesh(new THREE.BoxGeometry(0.006, 0.006, 0.006),
                                    new THREE.MeshStandardMaterial({ color: 0x8a8f98 }), Math.max(1, fixed.length));
    stand.count = 0;
    stand.frustumCulled = false;  // its bounds are the one box's at the origin, not the clamps'
    scene.add(stand);
  }
  const place = new THREE.Matrix4();
  stand.count = Math.min(fixed.length, stand.instanceMatrix.count);
  for (let i = 0; i < stand.count; ++i) {
    const k = fixed[i];
    stand.setMatrixAt(i, place.makeTranslation(cloth.positions[3 * k], cloth.positions[3 * k + 1], cloth.positions[3 * k + 2]));
  }
  stand.instanceMatrix.needsUpdate = true;
  stats.standClamps = stand.count;
}

// The local patch: the grid rectangle global_sim cut at the frame's step (ClothFrame's patch_*).
function colourPatch() {
  const c = cloth.colors, r = cloth.patch ?? { u0: 0, u1: 0, v0: 0, v1: 0 };
  let inPatchCount = 0;
  for (let k = 0; k < c.length / 3; ++k) {
    const i = k % cloth.u, j = Math.floor(k / cloth.u);
    const inPatch = i >= r.u0 && i < r.u1 && j >= r.v0 && j < r.v1;
    inPatchCount += inPatch;
    c[3 * k] = inPatch ? 0.85 : 0.22;
    c[3 * k + 1] = inPatch ? 0.62 : 0.3;
    c[3 * k + 2] = inPatch ? 0.25 : 0.52;  // denim blue, the patch amber
  }
  stats.patchParticles = inPatchCount;
  stats.patchFramesSeen += inPatchCount > 0;
  cloth.mesh.geometry.attributes.color.needsUpdate = true;
}

function onFingerStates(m) {
  for (const s of m.fingers) {
    const name = FINGERS[s.finger];
    if (!name) continue;
    const f = fingers[name];
    const p = s.position_w_m || {};
    f.position = new THREE.Vector3(p.x || 0, p.y || 0, p.z || 0);
    f.group.position.copy(f.position);
    const q = s.orientation_wf || { w: 1 };
    f.group.quaternion.set(q.x || 0, q.y || 0, q.z || 0, q.w ?? 1).normalize();
    f.group.visible = true;
    f.arrow.position.copy(f.position);
  }
}

function onForceModel(m) {
  for (const fm of m.fingers) {
    const name = FINGERS[fm.finger];
    if (!name) continue;
    const force = fm.f0_w_n || {};
    const v = new THREE.Vector3(force.x || 0, force.y || 0, force.z || 0);
    const magnitude = v.length();
    stats.forcesN[name] = magnitude;
    stats.peakForceN[name] = Math.max(stats.peakForceN[name], magnitude);
    const state = STATE_NAMES[fm.contact_state] ?? "-";
    stats.contactStates[name] = state;
    stats.stateTicks[name][state] = (stats.stateTicks[name][state] || 0) + 1;
    const arrow = fingers[name].arrow;
    arrow.visible = magnitude > 1e-3 && fingers[name].group.visible;
    if (arrow.visible) {
      arrow.setDirection(v.clone().normalize());
      const length = Math.max(0.004, magnitude * ARROW_M_PER_N);
      arrow.setLength(length, Math.min(0.008, 0.4 * length), Math.min(0.005, 0.25 * length));
    }
  }
}

function onPinFrame(m) {
  ++stats.pinFrames;
  for (const fp of m.fingers) {
    const name = FINGERS[fp.finger];
    if (!name) continue;
    drawPins(name, fp.amplitude_40hz, fp.amplitude_320hz);
    for (const a of [...fp.amplitude_40hz, ...fp.amplitude_320hz]) stats.pinMax = Math.max(stats.pinMax, a);
  }
}

// A loop's measured rate: its ticks since the service's previous Health over the uptime between.
function onHealth(m) {
  const before = stats.health[m.service];
  const measuredHz = (l) => {
    const was = before?.loops.find((b) => b.name === l.name);
    const dt = (m.uptime_s ?? 0) - (before?.uptime_s ?? 0);
    return was && dt > 0 && l.ticks >= was.ticks ? (l.ticks - was.ticks) / dt : null;
  };
  stats.health[m.service] = {
    state: m.state, uptime_s: m.uptime_s ?? 0,
    loops: m.loops.map((l) => ({ name: l.name, hz: l.target_rate_hz, measured_hz: measuredHz(l), ticks: l.ticks,
                                 overruns: l.overruns, p99_us: l.period_p99_us })),
    latencies: m.latencies.map((l) => ({ name: l.name, p50_us: l.p50_us, p99_us: l.p99_us })),
    last_error: m.last_error,
  };
}

function handle(schemaName, message) {
  ++stats.messages;
  switch (schemaName) {
    case "haptex.v1.ClothFrame": onClothFrame(message); break;
    case "haptex.v1.FingerStates": onFingerStates(message); break;
    case "haptex.v1.ForceModel": onForceModel(message); break;
    case "haptex.v1.PinFrame": onPinFrame(message); break;
    case "haptex.v1.Health": onHealth(message); break;
    default: break;
  }
}

// ---- panels
function drawPins(name, a40, a320) {
  for (const [channel, amplitudes] of [["40", a40], ["320", a320]]) {
    const c = document.getElementById(`pins-${name}-${channel}`);
    if (!c || amplitudes.length !== 24) continue;
    const g = c.getContext("2d");
    const cell = c.width / 4;
    for (let k = 0; k < 24; ++k) {
      const a = Math.max(0, Math.min(1, amplitudes[k]));
      g.fillStyle = `rgb(${Math.round(40 + 215 * a)}, ${Math.round(40 + 120 * a)}, ${Math.round(60 * (1 - a))})`;
      g.fillRect((k % 4) * cell, Math.floor(k / 4) * cell, cell - 1, cell - 1);  // row k / 4, column k % 4
    }
  }
}

function updatePanels() {
  for (const name of ["thumb", "index"]) {
    document.getElementById(`state-${name}`).textContent = stats.contactStates[name];
    document.getElementById(`force-${name}`).textContent = stats.forcesN[name].toFixed(2);
  }
  document.getElementById("fps").textContent = stats.fps.toFixed(0);
  document.getElementById("status").textContent = stats.status;
  const rows = [];
  for (const [service, h] of Object.entries(stats.health)) {
    for (const l of h.loops) {
      const rate = l.measured_hz === null ? "-" : l.measured_hz.toFixed(0);
      rows.push(`<tr><td>${escapeHtml(service)}</td><td>${escapeHtml(l.name)}</td><td>${rate} / ${l.hz.toFixed(0)}</td>` +
                `<td>${l.overruns}</td><td>${(l.p99_us / 1000).toFixed(2)}</td></tr>`);
    }
  }
  document.getElementById("health").innerHTML = rows.join("");
  const latencies = [];
  for (const [service, h] of Object.entries(stats.health)) {
    for (const l of h.latencies) {
      if (l.p99_us > 0) latencies.push(`<tr><td>${escapeHtml(service)}</td><td>${escapeHtml(l.name)}</td>` +
                                       `<td>${(l.p50_us / 1000).toFixed(2)}</td><td>${(l.p99_us / 1000).toFixed(2)}</td></tr>`);
    }
  }
  document.getElementById("latencies").innerHTML = latencies.join("");
  if (stats.mode === "replay") {
    document.getElementById("time").textContent = `${stats.timeS.toFixed(2)} / ${stats.durationS.toFixed(2)} s`;
    const slider = document.getElementById("timeline");
    if (document.activeElement !== slider) slider.value = String(stats.timeS);
  }
}

function escapeHtml(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" })[c]);
}

// ---- replay: the whole run in memory, shown at the timeline's time
const replay = { messages: [], start: 0n, next: 0, playing: false, lastWallMs: 0 };

function seek(t) {
  const target = Math.max(0, Math.min(stats.durationS, t));
  // replaying from the start rebuilds every panel exactly as the run went (cheap: decoded once)
  if (target < stats.timeS || replay.next === 0) {
    replay.next = 0;
    for (const name of ["thumb", "index"]) {
      stats.peakForceN[name] = 0;
      stats.stateTicks[name] = {};
    }
    stats.pinFrames = stats.pinMax = stats.patchFramesSeen = 0;
  }
  stats.timeS = target;
  const until = replay.start + BigInt(Math.round(target * 1e9));
  while (replay.next < replay.messages.length && replay.messages[replay.next].logTimeNs <= until) {
    const m = replay.messages[replay.next++];
    handle(m.schemaName, m.decoded);
  }
}

function setPlaying(playing) {
  stats.playing = playing;
  replay.lastWallMs = performance.now();
  document.getElementById("play").textContent = playing ? "pause" : "play";
}

async function startReplay() {
  stats.mode = "replay";
  document.getElementById("replay-controls").hidden = false;
  stats.status = "loading the recording";
  const response = await fetch(session.recording);
  if (!response.ok) throw new Error(`the recording ${session.recording}: HTTP ${response.status}`);
  const mcap = readMcap(await response.arrayBuffer());
  const decoders = new Map();
  for (const m of mcap.messages) {
    const channel = mcap.channels.get(m.channelId);
    const schema = channel && mcap.schemas.get(channel.schemaId);
    if (!schema || !SHOWN.has(schema.name)) continue;
    if (!decoders.has(channel.id)) decoders.set(channel.id, makeDecoder(schema.data, schema.name));
    replay.messages.push({ logTimeNs: m.logTimeNs, schemaName: schema.name, decoded: decoders.get(channel.id)(m.data) });
  }
  if (replay.messages.length === 0) throw new Error("the recording has no messages this page shows");
  replay.start = replay.messages[0].logTimeNs;
  stats.durationS = Number(replay.messages[replay.messages.length - 1].logTimeNs - replay.start) * 1e-9;
  const slider = document.getElementById("timeline");
  slider.max = String(stats.durationS);
  slider.oninput = () => seek(Number(slider.value));
  document.getElementById("play").onclick = () => setPlaying(!stats.playing);
  stats.status = `replay of ${session.scene?.name ?? "a run"}: ${replay.messages.length} messages`;
  seek(0);
  setPlaying(true);
}

function startLive() {
  stats.mode = "live";
  const url = `${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/`;
  connectLive(url, {
    wanted: (schemaName) => SHOWN.has(schemaName),
    onMessage: (topic, schemaName, decoded) => handle(schemaName, decoded),
    onStatus: (text) => { stats.status = `live: ${text}`; },
  });
}

// ---- the frame loop
let session = {};
let fpsFrames = 0, fpsSince = performance.now();
function frame(nowMs) {
  if (stats.mode === "replay" && stats.playing) {
    const dt = (nowMs - replay.lastWallMs) * 1e-3;
    replay.lastWallMs = nowMs;
    seek(stats.timeS + dt);
    if (stats.timeS >= stats.durationS) setPlaying(false);
  }
  resize();
  controls.update();
  renderer.render(scene, camera);
  ++stats.framesRendered;
  ++fpsFrames;
  if (nowMs - fpsSince >= 1000) {
    stats.fps = (1000 * fpsFrames) / (nowMs - fpsSince);
    adaptRenderScale(stats.fps);
    fpsFrames = 0;
    fpsSince = nowMs;
    updatePanels();
  }
  requestAnimationFrame(frame);
}

async function main() {
  try {
    session = await (await fetch("/session.json")).json();
    document.getElementById("title").textContent = `haptex: ${session.scene?.name ?? ""}`;
    for (const f of session.scene?.fingers ?? []) {
      const finger = fingers[f.finger];
      if (!finger) continue;
      finger.radius = f.radius_m;
      finger.length = f.length_m;
      finger.body.geometry.dispose();
      finger.body.geometry = new THREE.CapsuleGeometry(f.radius_m, f.length_m, 6, 16);
    }
    if (session.mode === "replay") await startReplay();
    else startLive();
  } catch (e) {
    stats.errors.push(String(e.message ?? e));
    stats.status = `error: ${e.message ?? e}`;
  }
  updatePanels();
  requestAnimationFrame(frame);
}
main();
