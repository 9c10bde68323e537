// page.js: the carom page. It writes a scene file from the controls (or takes
// one the user opens), runs it in the WebAssembly engine (carom.js), draws the
// disks with WebGL 2 and the statistics with plots.js.
'use strict';

const DT = 0.01;                  // the page's time step; not a parameter
const FRAMES_PER_SECOND = 60;     // the display rate a throw's velocity assumes
const BACKGROUND = [17, 20, 24];  // #111418
const PLOT_INTERVAL_MS = 250;     // plots refresh a few times a second, not every frame
const MEASURE_INTERVAL_MS = 500;  // one pressure window
const HISTORY_MS = 60000;         // the plots show the last minute
const SPEED_BINS = 40;

// ---------------------------------------------------------------- parameters

// Every control: its URL parameter, element id, type, allowed values, default,
// and whether changing it rebuilds the scene.
const PARAMS = [
  { name: 'n', id: 'particles', type: 'int', min: 1, max: 200000, def: 4000, rebuild: true },
  { name: 'packing', id: 'packing', type: 'real', min: 0.01, max: 0.7, def: 0.5, rebuild: true },
  { name: 'mix', id: 'mix', type: 'real', min: 0, max: 1, def: 0, rebuild: true },
  { name: 'radius_b', id: 'radius-b', type: 'real', min: 0.1, max: 10, def: 2, rebuild: true },
  { name: 'mass_b', id: 'mass-b', type: 'real', min: 0.1, max: 100, def: 4, rebuild: true },
  { name: 'gravity', id: 'gravity', type: 'real', min: 0, max: 100, def: 0 },
  { name: 'boundary', id: 'boundary', type: 'choice', choices: ['walls', 'periodic'], def: 'walls', rebuild: true },
  { name: 'scheme', id: 'scheme', type: 'choice', choices: ['pairwise', 'simultaneous', 'events'], def: 'pairwise', rebuild: true },
  { name: 'seed', id: 'seed', type: 'int', min: 0, max: 4294967295, def: 1, rebuild: true },
  { name: 'speed', id: 'steps-per-frame', type: 'int', min: 1, max: 50, def: 1 },
  { name: 'color', id: 'color', type: 'choice', choices: ['speed', 'mass', 'id'], def: 'speed' },
];

const $ = (id) => document.getElementById(id);
const defaults = () => Object.fromEntries(PARAMS.map((p) => [p.name, p.def]));

// A parameter's value read from text, or a message naming it, the bad value and what is allowed.
function parseParam(spec, text) {
  const allowed = spec.type === 'choice' ? spec.choices.join(', ') : `${spec.min} to ${spec.max}`;
  const fail = (problem) => ({ error: `${spec.name}=${text}: ${problem}; allowed: ${allowed}` });
  if (spec.type === 'choice') return spec.choices.includes(text) ? { value: text } : fail('unknown choice');
  if (spec.type === 'int' && !/^\s*[+-]?\d+\s*$/.test(text)) return fail('not a whole number');
  const value = Number(text);
  if (text.trim() === '' || !Number.isFinite(value)) return fail('not a number');
  if (value < spec.min || value > spec.max) return fail('out of range');
  return { value };
}

// The URL's parameters over the defaults; a bad one keeps its default and adds a message.
function paramsFromUrl(search) {
  const params = defaults(), errors = [];
  for (const [key, text] of new URLSearchParams(search)) {
    const spec = PARAMS.find((p) => p.name === key);
    const parsed = spec ? parseParam(spec, text)
      : { error: `${key}=${text}: unknown parameter; allowed: ${PARAMS.map((p) => p.name).join(', ')}` };
    if (parsed.error) errors.push(parsed.error);
    else params[key] = parsed.value;
  }
  return { params, errors };
}

function readControls() {
  const params = {}, errors = [];
  for (const spec of PARAMS) {
    const parsed = parseParam(spec, $(spec.id).value);
    if (parsed.error) errors.push(parsed.error);
    else params[spec.name] = parsed.value;
  }
  return { params, errors };
}

function writeControls(params) {
  for (const spec of PARAMS) $(spec.id).value = params[spec.name];
  $('speed-value').value = params.speed;
}

// ---------------------------------------------------------------- scene files

const real = (x) => (Number.isInteger(x) ? x.toFixed(1) : String(x));  // TOML floats need a point

// The scene file of `carom run --scene` that the controls describe.
function sceneToml(p) {
  const countB = Math.round(p.n * p.mix);
  const group = (name, count, radius, mass) => (count === 0 ? '' :
    `\n[[group]]\nname = "${name}"\ncount = ${count}\nradius = ${real(radius)}\nmass = ${real(mass)}\ntemperature = 1.0\n`);
  return `# carom scene, written by the web page from its controls
packing = ${real(p.packing)}
boundary = "${p.boundary}"
collisions = "${p.scheme}"
dt = ${real(DT)}
gravity = [0.0, ${real(p.gravity === 0 ? 0 : -p.gravity)}]
seed = ${p.seed}
` + group('A', p.n - countB, 1, 1) + group('B', countB, p.radius_b, p.mass_b);
}

// An opened file's gravity [gx, gy], so the controls and the plots' notes can show it.
function fileGravity(text) {
  const match = /^\s*gravity\s*=\s*\[\s*([^,\]]+),([^\]]+)\]/m.exec(text);
  const g = match ? [Number(match[1]), Number(match[2])] : [0, 0];
  return g.every(Number.isFinite) ? g : [0, 0];
}

// ---------------------------------------------------------------- the disks' view

// The disks' shaders come in two forms (DISK_FORMS): each disk a point sprite,
// one vertex per disk, or an instanced quad where a disk outgrows the
// largest point the device draws. Software WebGL (SwiftShader) spends far
// more on each instance than on each point (bench/webgl_draw.py).
const DISK_VERTEX = `
layout(location = 0) in vec2 position;  // the engine's disk layout, one vertex (or instance) per disk
layout(location = 1) in vec2 velocity;
layout(location = 2) in float mass;
layout(location = 3) in float radius;
uniform vec2 scale, offset;             // world units to clip space
uniform float pixels;                   // drawing-buffer pixels per world unit
uniform int colorBy;                    // 0 speed, 1 mass, 2 id
uniform float speedScale;               // the speed at the top of the ramp
uniform vec2 massRange;
out vec2 local;                         // pixels from the centre
out float radiusPixels;
out vec3 colour;
// viridis at 9 stops and the id hash, as the native viewer (app/viewer/renderer.cpp) has them.
const vec3 stops[9] = vec3[9](vec3(0.267, 0.005, 0.329), vec3(0.283, 0.141, 0.458), vec3(0.254, 0.265, 0.530),
                              vec3(0.207, 0.372, 0.553), vec3(0.164, 0.471, 0.558), vec3(0.128, 0.567, 0.551),
                              vec3(0.135, 0.659, 0.518), vec3(0.478, 0.821, 0.318), vec3(0.993, 0.906, 0.144));
vec3 viridis(float t) {
  float position = clamp(t, 0.0, 1.0) * 8.0;
  int i = min(int(position), 7);
  return mix(stops[i], stops[i + 1], position - float(i));
}
vec3 idColour(uint id) {
  uint h = id * 2654435761u;
  h ^= h >> 15;
  float hue = float(h % 360u) / 60.0;
  float x = 1.0 - abs(mod(hue, 2.0) - 1.0);
  vec3 sectors[6] = vec3[6](vec3(1, x, 0), vec3(x, 1, 0), vec3(0, 1, x), vec3(0, x, 1), vec3(x, 0, 1), vec3(1, 0, x));
  return 0.25 + 0.75 * sectors[int(hue) % 6];
}
void main() {
  radiusPixels = radius * pixels;
#if POINTS
  gl_PointSize = 2.0 * (radiusPixels + 1.0);  // a pixel of room for the smooth edge
  gl_Position = vec4(position * scale + offset, 0.0, 1.0);
  int id = gl_VertexID;
#else
  vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1) * 2.0 - 1.0;
  local = corner * (radiusPixels + 1.0);
  gl_Position = vec4((position + local / pixels) * scale + offset, 0.0, 1.0);
  int id = gl_InstanceID;
#endif
  if (colorBy == 0) colour = viridis(length(velocity) / speedScale);
  else if (colorBy == 1) colour = viridis(massRange.y > massRange.x ? (mass - massRange.x) / (massRange.y - massRange.x) : 0.5);
  else colour = idColour(uint(id));
}`;

const DISK_FRAGMENT = `
precision highp float;
in vec2 local;
in float radiusPixels;
in vec3 colour;
out vec4 fragment;
void main() {
#if POINTS
  float r = length((gl_PointCoord * 2.0 - 1.0) * (radiusPixels + 1.0));
#else
  float r = length(local);
#endif
  // A one-pixel smooth edge; a disk smaller than a pixel fades instead of vanishing.
  float alpha = clamp(radiusPixels + 0.5 - r, 0.0, 1.0);
  if (alpha <= 0.0) discard;
  // A darker rim keeps touching disks apart, where they are big enough to show one.
  float rim = radiusPixels > 3.0 ? 0.35 * smoothstep(radiusPixels - 1.5, radiusPixels, r) : 0.0;
  fragment = vec4(colour * (1.0 - rim), alpha);
}`;

const BOX_VERTEX = `#version 300 es
uniform vec2 scale, offset, box;
void main() {
  vec2 corner = vec2(gl_VertexID == 1 || gl_VertexID == 2, gl_VertexID >= 2);
  gl_Position = vec4(corner * box * scale + offset, 0.0, 1.0);
}`;

const BOX_FRAGMENT = `#version 300 es
precision mediump float;
uniform vec3 colour;
out vec4 fragment;
void main() { fragment = vec4(colour, 1.0); }`;

function compileProgram(gl, vertexSource, fragmentSource) {
  const program = gl.createProgram();
  for (const [type, source] of [[gl.VERTEX_SHADER, vertexSource], [gl.FRAGMENT_SHADER, fragmentSource]]) {
    const shader = gl.createShader(type);
    gl.shaderSource(shader, source);
    gl.compileShader(shader);
    if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(shader));
    gl.attachShader(program, shader);
  }
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  const uniforms = {};
  for (let i = 0; i < gl.getProgramParameter(program, gl.ACTIVE_UNIFORMS); i++) {
    const name = gl.getActiveUniform(program, i).name;
    uniforms[name] = gl.getUniformLocation(program, name);
  }
  return { program, uniforms };
}

const DISK_FORMS = { points: '#version 300 es\n#define POINTS 1\n', quads: '#version 300 es\n#define POINTS 0\n' };

// The WebGL 2 view of the box: the disks read straight from the engine's floats.
// The disks' own smooth edges make multisampling unneeded (and costly in software).
function createView(canvas) {
  const gl = canvas.getContext('webgl2', { preserveDrawingBuffer: true, antialias: false, alpha: false });
  if (!gl) throw new Error('this page needs WebGL 2, which this browser does not offer');
  const forms = {};
  for (const [form, head] of Object.entries(DISK_FORMS)) forms[form] = compileProgram(gl, head + DISK_VERTEX, head + DISK_FRAGMENT);
  const largestPoint = gl.getParameter(gl.ALIASED_POINT_SIZE_RANGE)[1];
  const box = compileProgram(gl, BOX_VERTEX, BOX_FRAGMENT);
  const buffer = gl.createBuffer();
  const vao = gl.createVertexArray();
  gl.bindVertexArray(vao);
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  // x, y, vx, vy, mass, radius: 24 bytes a disk.
  for (const [location, size, offset] of [[0, 2, 0], [1, 2, 8], [2, 1, 16], [3, 1, 20]]) {
    gl.enableVertexAttribArray(location);
    gl.vertexAttribPointer(location, size, gl.FLOAT, false, 24, offset);
  }
  gl.bindVertexArray(null);
  gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
  let uploaded = 0;  // floats in the buffer
  let world = { width: 1, height: 1, periodic: false };

  // Drawing-buffer pixels per world unit, and where the box's corner (0, 0) lands: centred, with a margin.
  function layout() {
    const margin = 6 * (window.devicePixelRatio || 1);
    const k = Math.min((canvas.width - 2 * margin) / world.width, (canvas.height - 2 * margin) / world.height);
    return { k, x0: (canvas.width - k * world.width) / 2, y0: (canvas.height - k * world.height) / 2 };
  }

  return {
    gl,
    setWorld(w) { world = w; },
    upload(floats) {
      gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
      if (floats.length === uploaded) gl.bufferSubData(gl.ARRAY_BUFFER, 0, floats);
      else gl.bufferData(gl.ARRAY_BUFFER, floats, gl.DYNAMIC_DRAW);
      uploaded = floats.length;
    },
    draw({ colorBy, speedScale, massMin, massMax, radiusMax }) {
      const { k, x0, y0 } = layout();
      const scale = [(2 * k) / canvas.width, (2 * k) / canvas.height];
      const offset = [(2 * x0) / canvas.width - 1, (2 * y0) / canvas.height - 1];
      gl.viewport(0, 0, canvas.width, canvas.height);
      gl.disable(gl.SCISSOR_TEST);
      gl.clearColor(...BACKGROUND.map((c) => c / 255), 1);
      gl.clear(gl.COLOR_BUFFER_BIT);

      gl.useProgram(box.program);
      gl.uniform2fv(box.uniforms.scale, scale);
      gl.uniform2fv(box.uniforms.offset, offset);
      gl.uniform2f(box.uniforms.box, world.width, world.height);
      // Walls are solid; a periodic edge is only a seam, so it is drawn fainter.
      gl.uniform3fv(box.uniforms.colour, world.periodic ? [0.3, 0.34, 0.4] : [0.62, 0.67, 0.74]);
      gl.drawArrays(gl.LINE_LOOP, 0, 4);

      // Disks crossing a periodic edge are cut there rather than spilling into the margin.
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(Math.floor(x0) - 1, Math.floor(y0) - 1, Math.ceil(k * world.width) + 2, Math.ceil(k * world.height) + 2);
      gl.enable(gl.BLEND);
      const points = 2 * (radiusMax * k + 1) <= largestPoint;
      const disks = points ? forms.points : forms.quads;
      gl.useProgram(disks.program);
      gl.uniform2fv(disks.uniforms.scale, scale);
      gl.uniform2fv(disks.uniforms.offset, offset);
      gl.uniform1f(disks.uniforms.pixels, k);
      gl.uniform1i(disks.uniforms.colorBy, ['speed', 'mass', 'id'].indexOf(colorBy));
      gl.uniform1f(disks.uniforms.speedScale, speedScale);
      gl.uniform2f(disks.uniforms.massRange, massMin, massMax);
      gl.bindVertexArray(vao);
      for (const location of [0, 1, 2, 3]) gl.vertexAttribDivisor(location, points ? 0 : 1);
      if (points) gl.drawArrays(gl.POINTS, 0, uploaded / 6);
      else gl.drawArraysInstanced(gl.TRIANGLE_STRIP, 0, 4, uploaded / 6);
      gl.bindVertexArray(null);
      gl.disable(gl.BLEND);
    },
    // Waits until the drawing is done: a pixel read back has to wait for it, where gl.finish() need not.
    finish() {
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    },
    worldToCanvas(x, y) {
      const { k, x0, y0 } = layout();
      return [x0 + k * x, canvas.height - (y0 + k * y)];
    },
    // From a pointer event to world units, and the world units of a CSS pixel.
    eventToWorld(event) {
      const { k, x0, y0 } = layout();
      const rect = canvas.getBoundingClientRect();
      const px = ((event.clientX - rect.left) * canvas.width) / rect.width;
      const py = ((event.clientY - rect.top) * canvas.height) / rect.height;
      return { x: (px - x0) / k, y: (canvas.height - py - y0) / k, cssPixel: canvas.width / rect.width / k };
    },
  };
}

// ---------------------------------------------------------------- statistics

// What the colours, the drawing and the equation of state need from the
// disks: the mass range, the largest radius, the area fraction η = Σπr²/(W·H) and the rms speed.
function sceneFigures(disks, width, height) {
  let massMin = Infinity, massMax = -Infinity, radiusMax = 0, area = 0, v2 = 0;
  for (let i = 0; i < disks.length; i += 6) {
    massMin = Math.min(massMin, disks[i + 4]);
    massMax = Math.max(massMax, disks[i + 4]);
    radiusMax = Math.max(radiusMax, disks[i + 5]);
    area += Math.PI * disks[i + 5] ** 2;
    v2 += disks[i + 2] ** 2 + disks[i + 3] ** 2;
  }
  return { massMin, massMax, radiusMax, eta: area / (width * height), rmsSpeed: Math.sqrt((v2 * 6) / disks.length) };
}

// The speed histogram (a density), the rms speed and the 2D Maxwell–Boltzmann
// curve at temperature kT for the disks' masses: (1/N) Σ_i rayleighPdf(v, kT/m_i).
function speedDistribution(M, disks, kT, massMin) {
  const n = disks.length / 6;
  const top = kT > 0 ? 4 * Math.sqrt(kT / massMin) : 1;  // the lightest disks' tail ends well within
  const width = top / SPEED_BINS;
  const heights = new Array(SPEED_BINS).fill(0);
  const count = (map, key, k = 1) => map.set(key, (map.get(key) || 0) + k);
  let masses = new Map(), v2 = 0;
  for (let i = 0; i < disks.length; i += 6) {
    const speed = Math.hypot(disks[i + 2], disks[i + 3]);
    v2 += speed * speed;
    const bin = Math.floor(speed / width);
    if (bin < SPEED_BINS) heights[bin] += 1 / (n * width);
    count(masses, disks[i + 4]);
  }
  // A polydisperse file has a mass per disk: two significant digits keep the curve cheap and true enough.
  if (masses.size > 32) {
    const grouped = new Map();
    for (const [m, k] of masses) count(grouped, Number(m.toPrecision(2)), k);
    masses = grouped;
  }
  const xs = [], ys = [];
  for (let j = 0; kT > 0 && j <= 100; j++) {
    const v = (top * j) / 100;
    let density = 0;
    for (const [m, k] of masses) density += (k / n) * M.rayleighPdf(v, kT / m);
    xs.push(v);
    ys.push(density);
  }
  return { edges: heights.map((_, i) => i * width).concat(top), heights, xs, ys, rmsSpeed: Math.sqrt(v2 / n) };
}

// ---------------------------------------------------------------- the page

let M, sim, view, plots;
const page = {
  params: defaults(),   // the running scene's parameters, as the controls show them
  text: '',             // the running scene's TOML
  fileName: null,       // the opened file's name, null for a scene from the controls
  gravityOn: false,
  paused: false,
  needsDraw: true,
  e0: 0,                // the total energy when the scene started or was last edited
  figures: null,        // sceneFigures of the running scene
  history: null,        // { energy, drift, z }: samples for the plots
  grab: null,           // the disk held by the pointer
  timing: { step: 0, draw: 0, fps: 0 },
};

function showMessage(text, kind = 'error') {
  $('message').textContent = text;
  $('message').className = text ? kind : '';
}

// The total energy's relative change since the scene started or was last edited. NaN in
// a periodic box under gravity, where -Σ m g·x jumps as disks wrap and is no potential energy.
const driftRelative = () => (sim.periodic() && page.gravityOn ? NaN :
  page.e0 ? (sim.observables().total - page.e0) / Math.abs(page.e0) : 0);

// After an edit (a grab, a burst, a gravity change) the drift counts from the new energy.
function resetDrift() {
  page.e0 = sim.observables().total;
  if (page.history) page.history.drift = [];
}

function refreshFigures() {
  page.figures = sceneFigures(sim.disks(), sim.width(), sim.height());
}

// Makes `text` the running scene; on failure shows why and leaves the running one as it was.
function loadScene(text, name) {
  const error = sim.load(text, name);
  if (error) {
    showMessage(error);
    return error;
  }
  showMessage('');
  page.text = text;
  page.grab = null;
  page.history = { energy: [], drift: [], z: [] };
  view.setWorld({ width: sim.width(), height: sim.height(), periodic: sim.periodic() });
  refreshFigures();
  resetDrift();
  fitCanvas();
  page.needsDraw = true;
  return '';
}

function loadParams(params) {
  const error = loadScene(sceneToml(params), 'controls');
  if (error) {
    writeControls(page.params);
    return error;
  }
  page.params = params;
  page.fileName = null;
  page.gravityOn = params.gravity !== 0;
  return '';
}

function loadFile(text, name) {
  const error = loadScene(text, name);
  if (error) return error;
  page.fileName = name;
  // The controls take the file's scheme, boundary and gravity, so that params() and the next rebuild start from them.
  const g = fileGravity(text);
  page.gravityOn = g[0] !== 0 || g[1] !== 0;
  page.params = { ...page.params, scheme: sim.scheme(), boundary: sim.periodic() ? 'periodic' : 'walls',
                  gravity: Math.min(100, Math.max(0, -g[1])) };
  writeControls(page.params);
  return '';
}

// The canvas as large as its column allows, keeping the box's aspect; its drawing buffer in device pixels.
function fitCanvas() {
  const canvas = $('view');
  const margin = 12;  // CSS pixels around the box, as in the view's layout
  const aspect = sim.width() / sim.height();
  const maxHeight = Math.max(240, window.innerHeight - 120);
  const width = Math.floor(Math.min(canvas.parentElement.clientWidth, (maxHeight - margin) * aspect + margin));
  const height = Math.floor((width - margin) / aspect + margin);
  canvas.style.width = `${width}px`;
  canvas.style.height = `${height}px`;
  const ratio = window.devicePixelRatio || 1;
  if (canvas.width !== Math.round(width * ratio) || canvas.height !== Math.round(height * ratio)) {
    canvas.width = Math.round(width * ratio);
    canvas.height = Math.round(height * ratio);
    page.needsDraw = true;
  }
}

function setPaused(paused) {
  page.paused = paused;
  $('pause').textContent = paused ? 'Play' : 'Pause';
  $('pause').setAttribute('aria-pressed', String(paused));
  $('step').disabled = !paused;
}

// One frame: `steps` steps, the disks uploaded, then drawn. Returns [stepMs, drawMs].
function runFrame(steps, finish) {
  const t0 = performance.now();
  if (steps > 0) {
    const error = sim.step(steps);
    if (error) {
      showMessage(error);
      setPaused(true);
    }
  }
  view.upload(sim.disks());
  const t1 = performance.now();
  const f = page.figures;
  view.draw({ colorBy: page.params.color, speedScale: 2.5 * f.rmsSpeed || 1, massMin: f.massMin, massMax: f.massMax,
              radiusMax: f.radiusMax });
  if (finish) view.finish();
  page.needsDraw = false;
  return [t1 - t0, performance.now() - t1];
}

// ---------------------------------------------------------------- the pointer

function onPointerDown(event) {
  if (event.button !== 0) return;
  const { x, y, cssPixel } = view.eventToWorld(event);
  // The disk under the pointer (a few pixels' slack for tiny disks), the most deeply hit one.
  const disks = sim.disks();
  let id = -1, best = 3 * cssPixel;
  for (let i = 0; i < disks.length; i += 6) {
    const gap = Math.hypot(disks[i] - x, disks[i + 1] - y) - disks[i + 5];
    if (gap < best) [id, best] = [i / 6, gap];
  }
  if (id >= 0) {
    $('view').setPointerCapture(event.pointerId);
    page.grab = { id, radius: disks[id * 6 + 5], x, y, lastX: x, lastY: y, lastTime: performance.now(), vx: 0, vy: 0 };
    return;
  }
  const error = sim.burst(x, y, 12, 1, 1, 3);
  if (error) return showMessage(error);
  refreshFigures();
  resetDrift();
  page.needsDraw = true;
}

// The held disk follows the pointer and moves with its velocity, so that letting go throws it.
function holdGrabbedDisk(now) {
  const grab = page.grab;
  const seconds = (now - grab.lastTime) / 1000;
  if (seconds > 0) {  // smoothed over a few frames, so a throw follows the last flick
    grab.vx = 0.7 * grab.vx + (0.3 * (grab.x - grab.lastX)) / seconds;
    grab.vy = 0.7 * grab.vy + (0.3 * (grab.y - grab.lastY)) / seconds;
  }
  Object.assign(grab, { lastX: grab.x, lastY: grab.y, lastTime: now });
  // World units per real second into world units per simulated time, at the page's pace
  // (an opened file may have its own dt: the steps so far tell it).
  const o = sim.observables(), dt = o.steps > 0 ? o.time / o.steps : DT;
  const pace = page.paused ? 0 : page.params.speed * dt * FRAMES_PER_SECOND;
  let vx = pace ? grab.vx / pace : 0, vy = pace ? grab.vy / pace : 0;
  // At most half a radius a step, so the disk cannot jump through its neighbours.
  const cap = (0.5 * grab.radius) / dt, speed = Math.hypot(vx, vy);
  if (speed > cap) [vx, vy] = [(vx * cap) / speed, (vy * cap) / speed];
  const clamp = (v, high) => Math.min(Math.max(v, grab.radius), high - grab.radius);
  const error = sim.setDisk(grab.id, clamp(grab.x, sim.width()), clamp(grab.y, sim.height()), vx, vy);
  if (error) {
    showMessage(error);
    page.grab = null;
  }
  resetDrift();
  page.needsDraw = true;
}

function bindPointer(canvas) {
  canvas.addEventListener('pointerdown', onPointerDown);
  canvas.addEventListener('pointermove', (event) => {
    if (!page.grab) return;
    const { x, y } = view.eventToWorld(event);
    Object.assign(page.grab, { x, y });
  });
  const release = () => {
    if (!page.grab) return;
    page.grab = null;
    resetDrift();
  };
  canvas.addEventListener('pointerup', release);
  canvas.addEventListener('pointercancel', release);
}

// ---------------------------------------------------------------- controls

function bindControls() {
  $('controls').addEventListener('submit', (event) => event.preventDefault());
  for (const spec of PARAMS) {
    $(spec.id).addEventListener(spec.name === 'speed' ? 'input' : 'change', () => onControl(spec));
  }
  $('pause').addEventListener('click', () => setPaused(!page.paused));
  $('step').addEventListener('click', () => {
    const error = sim.step(1);
    if (error) showMessage(error);
    page.needsDraw = true;
  });
  $('reset').addEventListener('click', () => {
    const { params, errors } = readControls();
    if (errors.length) {
      showMessage(errors.join('\n'));
      writeControls(page.params);
    } else {
      loadParams(params);
    }
  });
  $('share').addEventListener('click', share);
  $('save-scene').addEventListener('click', () => {
    const link = document.createElement('a');
    link.href = URL.createObjectURL(new Blob([page.text], { type: 'application/toml' }));
    link.download = page.fileName || 'carom-scene.toml';
    link.click();
    setTimeout(() => URL.revokeObjectURL(link.href), 1000);
  });
  $('scene-file').addEventListener('change', (event) => {
    const file = event.target.files[0];
    if (!file) return;
    const reader = new FileReader();
    reader.onload = () => loadFile(String(reader.result), file.name);
    reader.onerror = () => showMessage(`${file.name}: could not be read`);
    reader.readAsText(file);
    event.target.value = '';  // so the same file can be opened again
  });
}

function onControl(spec) {
  const text = $(spec.id).value;
  if (text === '') return;  // being retyped (or not a number): the running scene stays
  const parsed = parseParam(spec, text);
  if (parsed.error) {
    showMessage(parsed.error);
    writeControls(page.params);
    return;
  }
  const params = { ...page.params, [spec.name]: parsed.value };
  if (spec.rebuild) {
    loadParams(params);
    return;
  }
  if (spec.name === 'gravity') {
    const error = sim.setGravity(0, params.gravity === 0 ? 0 : -params.gravity);
    if (error) {
      showMessage(error);
      writeControls(page.params);
      return;
    }
    page.gravityOn = params.gravity !== 0;
    if (page.fileName === null) page.text = sceneToml(params);
    resetDrift();
  }
  page.params = params;
  $('speed-value').value = params.speed;
  page.needsDraw = true;
}

function share() {
  const query = new URLSearchParams(Object.entries(page.params).map(([k, v]) => [k, String(v)]));
  history.replaceState(null, '', `?${query}`);
  const link = document.createElement('a');
  link.href = link.textContent = location.href;
  $('message').className = 'info';
  $('message').replaceChildren('Link to these settings: ', link,
    page.fileName ? ' (it holds the controls, not the opened file)' : '');
}

// ---------------------------------------------------------------- plots and status

function createPlots() {
  return {
    speeds: new Plot($('plot-speeds'), { xLabel: 'speed |v|', yLabel: 'probability density' }),
    energy: new Plot($('plot-energy'), { xLabel: 'simulated time t', yLabel: 'energy', includeZero: true }),
    drift: new Plot($('plot-drift'), { xLabel: 'simulated time t', yLabel: 'ΔE/|E₀|', empty: 'since the last edit' }),
    z: new Plot($('plot-z'), { xLabel: 'simulated time t', yLabel: 'Z = PA/NkT' }),
  };
}

const column = (samples, key) => samples.map((s) => s[key]);

function refreshPlots(now) {
  const o = sim.observables(), h = page.history;
  if (!h.energy.length || o.time !== h.energy[h.energy.length - 1].t) {
    h.energy.push({ real: now, t: o.time, kinetic: o.kinetic, potential: o.potential, total: o.total });
    h.drift.push({ real: now, t: o.time, drift: driftRelative() });
  }
  for (const key of ['energy', 'drift', 'z']) while (h[key].length && now - h[key][0].real > HISTORY_MS) h[key].shift();

  const disks = sim.disks();
  const speeds = speedDistribution(M, disks, o.temperature, page.figures.massMin);
  page.figures.rmsSpeed = speeds.rmsSpeed;
  plots.speeds.draw([
    { kind: 'bars', label: 'speeds', color: '#3d7cc9', edges: speeds.edges, heights: speeds.heights },
    { kind: 'line', label: `Maxwell–Boltzmann at kT = ${o.temperature.toPrecision(3)}`, color: '#c8432b', xs: speeds.xs, ys: speeds.ys },
  ]);
  const t = column(h.energy, 't');
  plots.energy.draw([
    { kind: 'line', label: 'kinetic', color: '#3d7cc9', xs: t, ys: column(h.energy, 'kinetic') },
    { kind: 'line', label: 'potential', color: '#d8902c', xs: t, ys: column(h.energy, 'potential') },
    { kind: 'line', label: 'total', color: '#22272e', xs: t, ys: column(h.energy, 'total') },
  ]);
  plots.drift.draw(h.drift.length < 2 || Number.isNaN(h.drift[h.drift.length - 1].drift) ? [] :
    [{ kind: 'line', color: '#7b3fb0', xs: column(h.drift, 't'), ys: column(h.drift, 'drift') }]);
  const eta = page.figures.eta;
  plots.z.draw(h.z.length ? [
    { kind: 'line', label: 'Z = PA/NkT, measured', color: '#3d7cc9', xs: column(h.z, 't'), ys: column(h.z, 'z') },
    { kind: 'hline', label: `Z, published hard-disk equation of state at η = ${eta.toFixed(3)}`, color: '#c8432b',
      dash: [6, 4], y: M.referenceZ(eta) },
  ] : []);

  const drift = driftRelative();
  $('drift').textContent = Number.isNaN(drift) ? 'drift: none to measure, periodic box under gravity' :
    `drift ${drift >= 0 ? '+' : ''}${drift.toExponential(1)}`;
  $('collisions').textContent = `collisions ${o.collisions.toLocaleString('en-US')}`;
  $('z-note').hidden = !page.gravityOn;
  const { fps, step, draw } = page.timing;
  $('status').textContent = `N = ${(disks.length / 6).toLocaleString('en-US')} · ${sim.scheme()} · ` +
    `${page.paused ? 'paused' : `${fps.toFixed(0)} fps`} · step ${step.toFixed(2)} ms · draw ${draw.toFixed(2)} ms · t = ${o.time.toFixed(2)}`;
}

// One pressure window; a window without simulated time (paused) has no pressure.
function measure(now) {
  const w = sim.takeMeasurements();
  if (w.time > 0) page.history.z.push({ real: now, t: sim.observables().time, z: w.compressibility });
}

// ---------------------------------------------------------------- the loop

let lastFrame = 0, lastPlots = 0, lastMeasure = 0;

function frame(now) {
  requestAnimationFrame(frame);
  if (page.grab) holdGrabbedDisk(now);
  if (!page.paused || page.needsDraw) {
    const [step, draw] = runFrame(page.paused ? 0 : page.params.speed, false);
    if (!page.paused) {  // running averages over about 20 frames
      const t = page.timing, average = (old, value) => (old ? old + 0.05 * (value - old) : value);
      t.step = average(t.step, step);
      t.draw = average(t.draw, draw);
      if (lastFrame) t.fps = average(t.fps, 1000 / (now - lastFrame));
    }
  }
  lastFrame = page.paused ? 0 : now;
  if (now - lastPlots > PLOT_INTERVAL_MS) {
    lastPlots = now;
    refreshPlots(now);
  }
  if (now - lastMeasure > MEASURE_INTERVAL_MS) {
    lastMeasure = now;
    measure(now);
  }
}

const median = (values) => values.slice().sort((a, b) => a - b)[Math.floor(values.length / 2)];

function start(module) {
  M = module;
  sim = new M.Simulation();
  $('version').textContent = `engine ${M.version}`;
  try {
    view = createView($('view'));
  } catch (error) {
    showMessage(String(error.message || error));
    return;
  }
  plots = createPlots();
  const { params, errors } = paramsFromUrl(location.search);
  writeControls(params);
  const error = loadParams(params);
  if (error) {  // the URL's values together make no scene: start from the defaults
    errors.push(error);
    writeControls(defaults());
    loadParams(defaults());
  }
  showMessage(errors.join('\n'));
  setPaused(false);
  bindControls();
  bindPointer($('view'));
  window.addEventListener('resize', fitCanvas);  // the canvas's column changes width only with the window
  runFrame(0, true);

  // The hooks the browser tests use.
  window.caromPage = {
    ready: true,
    sim,
    module: M,
    params: () => ({ ...page.params }),
    sceneText: () => page.text,
    load: (text, name = 'scene.toml') => loadFile(text, name),
    pause: () => setPaused(true),
    play: () => setPaused(false),
    paused: () => page.paused,
    frames(k) {
      const times = Array.from({ length: k }, () => runFrame(page.params.speed, true));
      return { stepMs: median(times.map((t) => t[0])), drawMs: median(times.map((t) => t[1])) };
    },
    timing: () => ({ ...page.timing }),
    worldToCanvas: (x, y) => view.worldToCanvas(x, y),
    background: BACKGROUND.slice(),
    driftRelative,
  };
  requestAnimationFrame(frame);
}

createCarom().then(start, (error) => showMessage(`the engine did not load: ${error}`));
