// bakeshop view: the preview's shaders over WebGL2, drawing the bake's own texels (served by
// bakeshop.preview.server). No library. The view comes from the URL's query (scene, width,
// height, yaw, pitch, distance, fov, ev = number | auto, operator, sky_level, sun_light, ui), so
// a screenshot of a URL is a reproducible picture; dragging orbits, the wheel zooms, the panel
// changes the exposure, the tone curve, the sky's level and the sun light, and keeps the URL
// in step.
"use strict";

const OPERATORS = { none: 0, reinhard: 1, aces: 2 };
const KINDS = { "sun-dim": 0, "shadow-dim": 1, "sh": 2, "ggx": 3 };
const MAX_BALLS = 32;

function fail(message) {
  document.getElementById("message").textContent = message;
  document.title = "bakeshop view: error: " + message;
  throw new Error(message);
}

// -- the camera: bakeshop.preview.scene.Camera in doubles ----------------------------------------
function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function cross(a, b) {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}
function normalize(a) { const n = Math.hypot(a[0], a[1], a[2]); return [a[0] / n, a[1] / n, a[2] / n]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

function eyeOf(c) {
  const y = c.yaw * Math.PI / 180, p = c.pitch * Math.PI / 180;
  return [c.target[0] + c.distance * Math.cos(p) * Math.sin(y),
          c.target[1] + c.distance * Math.sin(p),
          c.target[2] + c.distance * Math.cos(p) * Math.cos(y)];
}

// row-major 4x4 as arrays of rows
function viewProjection(c, aspect) {
  const eye = eyeOf(c);
  const forward = normalize(sub(c.target, eye));
  const right = normalize(cross(forward, [0, 1, 0]));
  const up = cross(right, forward);
  const back = [-forward[0], -forward[1], -forward[2]];
  const view = [
    [right[0], right[1], right[2], -dot(right, eye)],
    [up[0], up[1], up[2], -dot(up, eye)],
    [back[0], back[1], back[2], -dot(back, eye)],
    [0, 0, 0, 1],
  ];
  const f = 1 / Math.tan(c.fov * Math.PI / 360), n = c.near, fa = c.far;
  const proj = [
    [f / aspect, 0, 0, 0],
    [0, f, 0, 0],
    [0, 0, (fa + n) / (n - fa), 2 * fa * n / (n - fa)],
    [0, 0, -1, 0],
  ];
  const out = [];
  for (let i = 0; i < 4; i++) {
    out.push([0, 1, 2, 3].map(j => proj[i].reduce((s, v, k) => s + v * view[k][j], 0)));
  }
  return out;
}

// Gauss-Jordan inverse with partial pivoting (doubles)
function invert(m) {
  const a = m.map((row, i) => row.concat([0, 1, 2, 3].map(j => (i === j ? 1 : 0))));
  for (let col = 0; col < 4; col++) {
    let pivot = col;
    for (let r = col + 1; r < 4; r++) if (Math.abs(a[r][col]) > Math.abs(a[pivot][col])) pivot = r;
    [a[col], a[pivot]] = [a[pivot], a[col]];
    const d = a[col][col];
    for (let k = 0; k < 8; k++) a[col][k] /= d;
    for (let r = 0; r < 4; r++) {
      if (r === col) continue;
      const f = a[r][col];
      for (let k = 0; k < 8; k++) a[r][k] -= f * a[col][k];
    }
  }
  return a.map(row => row.slice(4));
}

function columnMajor(m) {
  const out = new Float32Array(16);
  for (let c = 0; c < 4; c++) for (let r = 0; r < 4; r++) out[c * 4 + r] = m[r][c];
  return out;
}

// -- WebGL ----------------------------------------------------------------------------------------
function compile(gl, type, source) {
  const s = gl.createShader(type);
  gl.shaderSource(s, source);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) fail("shader: " + gl.getShaderInfoLog(s));
  return s;
}

function program(gl, sources) {
  const p = gl.createProgram();
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, sources.vertex));
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, sources.fragment));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) fail("link: " + gl.getProgramInfoLog(p));
  return p;
}

async function blob(name) {
  const response = await fetch("data/" + name + ".f32");
  if (!response.ok) fail("cannot load " + name);
  return new Float32Array(await response.arrayBuffer());
}

// one cube texture: levels[m] holds the six faces of level m, rows in order (OpenGL faces)
function cubeTexture(gl, sizes, levels) {
  const tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_CUBE_MAP, tex);
  sizes.forEach((s, m) => {
    for (let face = 0; face < 6; face++) {
      const texels = levels[m].subarray(face * s * s * 4, (face + 1) * s * s * 4);
      gl.texImage2D(gl.TEXTURE_CUBE_MAP_POSITIVE_X + face, m, gl.RGBA32F, s, s, 0, gl.RGBA,
                    gl.FLOAT, texels);
    }
  });
  gl.texParameteri(gl.TEXTURE_CUBE_MAP, gl.TEXTURE_BASE_LEVEL, 0);
  gl.texParameteri(gl.TEXTURE_CUBE_MAP, gl.TEXTURE_MAX_LEVEL, sizes.length - 1);
  gl.texParameteri(gl.TEXTURE_CUBE_MAP, gl.TEXTURE_MIN_FILTER,
                   sizes.length > 1 ? gl.LINEAR_MIPMAP_LINEAR : gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_CUBE_MAP, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  for (const wrap of [gl.TEXTURE_WRAP_S, gl.TEXTURE_WRAP_T, gl.TEXTURE_WRAP_R]) {
    gl.texParameteri(gl.TEXTURE_CUBE_MAP, wrap, gl.CLAMP_TO_EDGE);
  }
  return tex;
}

function texture2d(gl, shape, texels, repeatS) {
  const tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, tex);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, shape[1], shape[0], 0, gl.RGBA, gl.FLOAT, texels);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, repeatS ? gl.REPEAT : gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  return tex;
}

// -- the view --------------------------------------------------------------------------------------
function readState(bake) {
  const q = new URLSearchParams(location.search);
  const num = (key, fallback) => (q.has(key) && isFinite(parseFloat(q.get(key))) ? parseFloat(q.get(key)) : fallback);
  const scene = q.get("scene") === "sky" ? "sky" : "balls";
  const base = bake.cameras[scene];
  const evText = q.get("ev") || "auto";
  return {
    scene,
    width: Math.round(num("width", window.innerWidth || 1280)),
    height: Math.round(num("height", window.innerHeight || 720)),
    camera: {
      target: base.target, yaw: num("yaw", base.yaw), pitch: num("pitch", base.pitch),
      distance: num("distance", base.distance), fov: num("fov", base.fov),
      near: base.near, far: base.far,
    },
    ev: evText === "auto" ? "auto" : num("ev", 0),
    operator: q.get("operator") in OPERATORS ? q.get("operator") : "aces",
    skyLevel: num("sky_level", -1),
    sunLight: q.get("sun_light") === "1",
    ui: q.get("ui") !== "0",
  };
}

function writeState(s) {
  const q = new URLSearchParams({
    scene: s.scene, width: s.width, height: s.height, yaw: s.camera.yaw.toFixed(2),
    pitch: s.camera.pitch.toFixed(2), distance: s.camera.distance.toFixed(3), fov: s.camera.fov,
    ev: s.ev === "auto" ? "auto" : s.ev, operator: s.operator, sky_level: s.skyLevel,
    sun_light: s.sunLight ? 1 : 0,
  });
  history.replaceState(null, "", "?" + q.toString());
}

async function main() {
  const response = await fetch("bake.json");
  if (!response.ok) fail("cannot load bake.json");
  const bake = await response.json();
  const state = readState(bake);
  const canvas = document.getElementById("view");
  canvas.width = state.width;
  canvas.height = state.height;
  canvas.style.width = state.width + "px";
  canvas.style.height = state.height + "px";
  const gl = canvas.getContext("webgl2", {
    antialias: false, alpha: false, depth: false, preserveDrawingBuffer: true,
  });
  if (!gl) fail("this browser has no WebGL2");
  if (!gl.getExtension("OES_texture_float_linear")) fail("no OES_texture_float_linear");

  const specular = await Promise.all(bake.specular.map((_, m) => blob("specular" + m)));
  const textures = {
    uEnvCube: cubeTexture(gl, [bake.cube], [await blob("cube")]),
    uSpecular: cubeTexture(gl, bake.specular, specular),
    uSunDim: texture2d(gl, bake.sun_dim, await blob("sun_dim"), true),
    uShadowDim: texture2d(gl, bake.shadow_dim, await blob("shadow_dim"), true),
    uDfg: texture2d(gl, bake.dfg, await blob("dfg"), false),
  };
  const prog = program(gl, bake.programs.balls);
  const vao = gl.createVertexArray();
  const u = name => gl.getUniformLocation(prog, name);

  const geometry = new Float32Array(MAX_BALLS * 4);
  const material = new Float32Array(MAX_BALLS * 4);
  const colour = new Float32Array(MAX_BALLS * 4);
  bake.balls.forEach((b, i) => {
    geometry.set([...b.centre, b.radius], i * 4);
    material.set([KINDS[b.kind], b.roughness, b.metalness, 0], i * 4);
    colour.set([...b.colour, 0], i * 4);
  });
  const sun = bake.sun || { direction: [0, 0, 0], irradiance: [0, 0, 0], radius: 0 };
  if (bake.sun) {
    const d = sun.direction;
    const elevation = Math.asin(d[1]) * 180 / Math.PI;
    const azimuth = Math.atan2(d[0], -d[2]) * 180 / Math.PI;
    document.getElementById("sun-info").textContent =
      `sun: elevation ${elevation.toFixed(1)}°, ${azimuth.toFixed(1)}° from -Z towards +X`;
  }

  function draw() {
    const s = state;
    gl.viewport(0, 0, s.width, s.height);
    gl.useProgram(prog);
    Object.entries(textures).forEach(([name, tex], unit) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(name === "uEnvCube" || name === "uSpecular" ? gl.TEXTURE_CUBE_MAP : gl.TEXTURE_2D, tex);
      gl.uniform1i(u(name), unit);
    });
    const vp = viewProjection(s.camera, s.width / s.height);
    gl.uniformMatrix4fv(u("uInvViewProj"), false, columnMajor(invert(vp)));
    gl.uniform1i(u("uMode"), 0);
    gl.uniform1i(u("uBallCount"), s.scene === "balls" ? bake.balls.length : 0);
    gl.uniform4fv(u("uBalls"), geometry);
    gl.uniform4fv(u("uBallMaterial"), material);
    gl.uniform4fv(u("uBallColor"), colour);
    gl.uniform1i(u("uSunLight"), s.sunLight ? 1 : 0);
    gl.uniform1i(u("uDisplay"), 1);
    gl.uniform1f(u("uExposure"), s.ev === "auto" ? bake.exposure : s.ev);
    gl.uniform1i(u("uOperator"), OPERATORS[s.operator]);
    gl.uniform1f(u("uSpecularLevels"), bake.specular.length);
    gl.uniform3fv(u("uSh"), new Float32Array(bake.sh.flat()));
    gl.uniform3fv(u("uSunDirection"), new Float32Array(sun.direction));
    gl.uniform3fv(u("uSunIrradiance"), new Float32Array(sun.irradiance));
    gl.uniform1f(u("uSunRadius"), sun.radius);
    gl.uniform1f(u("uSkyLevel"), s.skyLevel);
    gl.bindVertexArray(vao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.finish();
    document.title = "bakeshop view: ready";
    document.body.dataset.ready = "1";
  }

  // -- controls -----------------------------------------------------------------------------------
  const panel = document.getElementById("panel");
  panel.style.display = state.ui ? "block" : "none";
  const el = id => document.getElementById(id);
  function syncPanel() {
    el("scene").value = state.scene;
    el("ev").value = state.ev === "auto" ? bake.exposure : state.ev;
    el("ev-value").textContent = state.ev === "auto"
      ? `auto (${bake.exposure.toFixed(2)} EV)` : `${Number(state.ev).toFixed(2)} EV`;
    el("operator").value = state.operator;
    el("sky-level").max = bake.specular.length - 1;
    el("sky-level").value = state.skyLevel;
    el("sky-value").textContent = state.skyLevel < 0 ? "environment" : `level ${state.skyLevel}`;
    el("sun-light").checked = state.sunLight;
  }
  function changed() { syncPanel(); writeState(state); draw(); }
  el("scene").onchange = e => {
    state.scene = e.target.value;
    const c = bake.cameras[state.scene];
    Object.assign(state.camera, { target: c.target, yaw: c.yaw, pitch: c.pitch,
                                  distance: c.distance, fov: c.fov, near: c.near, far: c.far });
    changed();
  };
  el("ev").oninput = e => { state.ev = parseFloat(e.target.value); changed(); };
  el("ev-auto").onclick = () => { state.ev = "auto"; changed(); };
  el("operator").onchange = e => { state.operator = e.target.value; changed(); };
  el("sky-level").oninput = e => { state.skyLevel = parseFloat(e.target.value); changed(); };
  el("sun-light").onchange = e => { state.sunLight = e.target.checked; changed(); };
  let drag = null;
  canvas.addEventListener("pointerdown", e => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener("pointerup", () => { drag = null; });
  canvas.addEventListener("pointermove", e => {
    if (!drag) return;
    state.camera.yaw -= (e.clientX - drag[0]) * 0.3;
    state.camera.pitch = Math.max(-89, Math.min(89, state.camera.pitch + (e.clientY - drag[1]) * 0.3));
    drag = [e.clientX, e.clientY];
    changed();
  });
  canvas.addEventListener("wheel", e => {
    e.preventDefault();
    state.camera.distance = Math.max(0.1, state.camera.distance * Math.exp(e.deltaY * 0.001));
    changed();
  }, { passive: false });
  syncPanel();
  draw();
}

main().catch(e => {
  if (!document.title.startsWith("bakeshop view: error")) fail(String(e));
});
