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
  return { target: gl.TEXTURE_CUBE_MAP, tex };
}

function texture2d(gl, shape, texels, options) {
  const o = Object.assign({ repeatS: false, repeatT: false, nearest: false }, options);
  const tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, tex);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, shape[1], shape[0], 0, gl.RGBA, gl.FLOAT, texels);
  const filter = o.nearest ? gl.NEAREST : gl.LINEAR;
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, o.repeatS ? gl.REPEAT : gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, o.repeatT ? gl.REPEAT : gl.CLAMP_TO_EDGE);
  return { target: gl.TEXTURE_2D, tex };
}

// every active uniform of a program: name (without "[0]") -> {location, type}
function uniformTable(gl, prog) {
  const table = {};
  const count = gl.getProgramParameter(prog, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < count; i++) {
    const info = gl.getActiveUniform(prog, i);
    const name = info.name.replace(/\[0\]$/, "");
    table[name] = { location: gl.getUniformLocation(prog, info.name), type: info.type };
  }
  return table;
}

// set uniforms by name from numbers, booleans and flat arrays (names the program lacks skipped)
function setUniforms(gl, table, values) {
  for (const [name, value] of Object.entries(values)) {
    const u = table[name];
    if (!u) continue;
    const v = typeof value === "boolean" ? (value ? 1 : 0) : value;
    switch (u.type) {
      case gl.FLOAT: gl.uniform1f(u.location, v); break;
      case gl.INT: case gl.BOOL: gl.uniform1i(u.location, v); break;
      case gl.FLOAT_VEC3: gl.uniform3fv(u.location, new Float32Array(v)); break;
      case gl.FLOAT_VEC4: gl.uniform4fv(u.location, new Float32Array(v)); break;
      case gl.FLOAT_MAT4: gl.uniformMatrix4fv(u.location, false, new Float32Array(v)); break;
      default: fail("uniform " + name + " of an unexpected type");
    }
  }
}

// bind textures to the sampler uniforms a program has, one unit each
function bindTextures(gl, table, textures) {
  let unit = 0;
  for (const [name, t] of Object.entries(textures)) {
    if (!table[name]) continue;
    gl.activeTexture(gl.TEXTURE0 + unit);
    gl.bindTexture(t.target, t.tex);
    gl.uniform1i(table[name].location, unit);
    unit++;
  }
}

// -- the view --------------------------------------------------------------------------------------
const SCENES = ["sky", "balls", "golf", "water"];

function readState(bake) {
  const q = new URLSearchParams(location.search);
  const num = (key, fallback) => {
    const v = parseFloat(q.get(key));
    return q.has(key) && isFinite(v) ? v : fallback;
  };
  const scene = SCENES.includes(q.get("scene")) ? q.get("scene") : "balls";
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
    diffuse: q.get("diffuse") in bake.diffuse ? q.get("diffuse") : "pair",
    water: q.get("water") !== "0",
    reflection: q.get("reflection") in bake.reflections ? q.get("reflection") : "fresnel",
    time: num("time", 0),
    ui: q.get("ui") !== "0",
  };
}

function writeState(s) {
  const q = new URLSearchParams({
    scene: s.scene, width: s.width, height: s.height, yaw: s.camera.yaw.toFixed(2),
    pitch: s.camera.pitch.toFixed(2), distance: s.camera.distance.toFixed(3), fov: s.camera.fov,
    ev: s.ev === "auto" ? "auto" : s.ev, operator: s.operator, sky_level: s.skyLevel,
    sun_light: s.sunLight ? 1 : 0, diffuse: s.diffuse, water: s.water ? 1 : 0,
    reflection: s.reflection, time: s.time,
  });
  history.replaceState(null, "", "?" + q.toString());
}

// the golf meshes' vertex attributes and their floats (bakeshop.preview.render._ATTRIBUTES)
const ATTRIBUTES = [["aPosition", 3], ["aNormal", 3], ["aAlbedo", 3], ["aUv", 2], ["aCentre", 3],
                    ["aKind", 1]];

// the golf course: its programs, mesh, water textures and the sun's shadow map (drawn once)
async function loadGolf(gl, bake, shared) {
  if (!gl.getExtension("EXT_color_buffer_float")) fail("no EXT_color_buffer_float");
  const g = bake.golf, w = bake.water;
  const programs = {};
  for (const name of ["scene", "shadow", "compose"]) {
    const prog = program(gl, bake.programs[name]);
    programs[name] = { prog, table: uniformTable(gl, prog) };
  }
  const buffer = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.bufferData(gl.ARRAY_BUFFER, await blob("golf"), gl.STATIC_DRAW);
  function meshVao(prog) {
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    let offset = 0;
    for (const [name, size] of ATTRIBUTES) {
      const loc = gl.getAttribLocation(prog, name);
      if (loc >= 0) {
        gl.enableVertexAttribArray(loc);
        gl.vertexAttribPointer(loc, size, gl.FLOAT, false, g.floats * 4, offset * 4);
      }
      offset += size;
    }
    gl.bindVertexArray(null);
    return vao;
  }
  const [frames, n, , comps] = w.normals;
  const normals = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D_ARRAY, normals);
  gl.texImage3D(gl.TEXTURE_2D_ARRAY, 0, comps === 2 ? gl.RG32F : gl.RGB32F, n, n, frames, 0,
                comps === 2 ? gl.RG : gl.RGB, gl.FLOAT, await blob("water_normals"));
  gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_S, gl.REPEAT);
  gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_T, gl.REPEAT);
  const textures = Object.assign({}, shared, {
    uNormals: { target: gl.TEXTURE_2D_ARRAY, tex: normals },
    uEnv: texture2d(gl, w.env, await blob("water_env"), { repeatS: true }),
    uRain: texture2d(gl, w.rain, await blob("water_rain"),
                     { repeatS: true, repeatT: true, nearest: true }),
    uRing: texture2d(gl, w.ring, await blob("water_ring"), {}),
  });
  // the shadow map: depth from the sun, nearest texel, drawn once
  if (bake.sun) {
    const size = g.shadow_size;
    const depth = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, depth);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.DEPTH_COMPONENT24, size, size, 0, gl.DEPTH_COMPONENT,
                  gl.UNSIGNED_INT, null);
    for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST],
                          [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) {
      gl.texParameteri(gl.TEXTURE_2D, k, v);
    }
    const fbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.TEXTURE_2D, depth, 0);
    gl.viewport(0, 0, size, size);
    gl.enable(gl.DEPTH_TEST);
    gl.clear(gl.DEPTH_BUFFER_BIT);
    const p = programs.shadow;
    gl.useProgram(p.prog);
    setUniforms(gl, p.table, { uViewProj: g.uniforms.uShadowViewProj });
    gl.bindVertexArray(meshVao(p.prog));
    gl.drawArrays(gl.TRIANGLES, 0, g.vertices);
    gl.disable(gl.DEPTH_TEST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    textures.uShadowMap = { target: gl.TEXTURE_2D, tex: depth };
  }
  return { programs, textures, sceneVao: meshVao(programs.scene.prog), target: null };
}

// the scene pass's target: colour and world position (RGBA32F, nearest) and a depth buffer
function sceneTarget(gl, width, height) {
  const fbo = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
  const attachments = [];
  for (let i = 0; i < 2; i++) {
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, width, height, 0, gl.RGBA, gl.FLOAT, null);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0 + i, gl.TEXTURE_2D, tex, 0);
    attachments.push({ target: gl.TEXTURE_2D, tex });
  }
  const depth = gl.createRenderbuffer();
  gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
  gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, width, height);
  gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
  gl.drawBuffers([gl.COLOR_ATTACHMENT0, gl.COLOR_ATTACHMENT1]);
  if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) {
    fail("the scene pass's float framebuffer is incomplete");
  }
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  return { fbo, colour: attachments[0], position: attachments[1], width, height };
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
  const shared = {
    uEnvCube: cubeTexture(gl, [bake.cube], [await blob("cube")]),
    uSpecular: cubeTexture(gl, bake.specular, specular),
    uSunDim: texture2d(gl, bake.sun_dim, await blob("sun_dim"), { repeatS: true }),
    uShadowDim: texture2d(gl, bake.shadow_dim, await blob("shadow_dim"), { repeatS: true }),
    uDfg: texture2d(gl, bake.dfg, await blob("dfg"), {}),
  };
  const ballsProg = program(gl, bake.programs.balls);
  const ballsTable = uniformTable(gl, ballsProg);
  const emptyVao = gl.createVertexArray();
  let golf = null;

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

  // the uniforms every program shares (Renderer.uniforms), for the canvas: display on
  function common(s) {
    return {
      uSpecularLevels: bake.specular.length, uSh: bake.sh.flat(),
      uSunDirection: sun.direction, uSunIrradiance: sun.irradiance, uSunRadius: sun.radius,
      uSkyLevel: s.skyLevel, uDisplay: true,
      uExposure: s.ev === "auto" ? bake.exposure : s.ev, uOperator: OPERATORS[s.operator],
    };
  }

  function drawBalls(s, inverse) {
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, s.width, s.height);
    gl.useProgram(ballsProg);
    bindTextures(gl, ballsTable, shared);
    setUniforms(gl, ballsTable, Object.assign(common(s), {
      uInvViewProj: Array.from(columnMajor(inverse)), uMode: 0,
      uBallCount: s.scene === "balls" ? bake.balls.length : 0,
      uBalls: Array.from(geometry), uBallMaterial: Array.from(material),
      uBallColor: Array.from(colour), uSunLight: s.sunLight,
    }));
    gl.bindVertexArray(emptyVao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  function drawGolf(s, vp, inverse) {
    if (!golf.target || golf.target.width !== s.width || golf.target.height !== s.height) {
      golf.target = sceneTarget(gl, s.width, s.height);
    }
    const t = golf.target;
    const scene = golf.programs.scene, compose = golf.programs.compose;
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.fbo);
    gl.viewport(0, 0, s.width, s.height);
    gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
    gl.clearBufferfv(gl.COLOR, 1, [0, 0, 0, 0]);
    gl.clearBufferfv(gl.DEPTH, 0, [1]);
    gl.enable(gl.DEPTH_TEST);
    gl.useProgram(scene.prog);
    bindTextures(gl, scene.table, golf.textures);
    setUniforms(gl, scene.table, Object.assign(common(s), bake.golf.uniforms, {
      uViewProj: Array.from(columnMajor(vp)), uMode: 0, uDiffuse: bake.diffuse[s.diffuse],
    }));
    gl.bindVertexArray(golf.sceneVao);
    gl.drawArrays(gl.TRIANGLES, 0, bake.golf.vertices);
    gl.disable(gl.DEPTH_TEST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.useProgram(compose.prog);
    bindTextures(gl, compose.table, Object.assign({}, golf.textures,
                                                  { uSceneColor: t.colour, uScenePosition: t.position }));
    setUniforms(gl, compose.table, Object.assign(common(s), bake.water.uniforms, {
      uInvViewProj: Array.from(columnMajor(inverse)), uMode: 0, uWater: s.water,
      uReflection: bake.reflections[s.reflection], uTime: s.time,
    }));
    gl.bindVertexArray(emptyVao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  async function draw() {
    const s = state;
    document.body.dataset.ready = "0";
    const vp = viewProjection(s.camera, s.width / s.height);
    const inverse = invert(vp);
    if (s.scene === "golf" || s.scene === "water") {
      if (!golf) golf = await loadGolf(gl, bake, shared);
      drawGolf(s, vp, inverse);
    } else {
      drawBalls(s, inverse);
    }
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
    el("diffuse").value = state.diffuse;
    el("water").checked = state.water;
    el("reflection").value = state.reflection;
    const golfControls = state.scene === "golf" || state.scene === "water";
    el("golf-controls").style.display = golfControls ? "block" : "none";
  }
  function changed() { syncPanel(); writeState(state); draw().catch(e => fail(String(e))); }
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
  el("diffuse").onchange = e => { state.diffuse = e.target.value; changed(); };
  el("water").onchange = e => { state.water = e.target.checked; changed(); };
  el("reflection").onchange = e => { state.reflection = e.target.value; changed(); };
  let drag = null;
  canvas.addEventListener("pointerdown", e => {
    drag = [e.clientX, e.clientY];
    canvas.setPointerCapture(e.pointerId);
  });
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
  await draw();
  // ?frames=N: draw the view N more times and record the mean frame time (ms; each frame read
  // back one pixel, which waits for the GPU process to finish drawing it)
  const frames = Math.round(Number(new URLSearchParams(location.search).get("frames") || 0));
  if (frames > 0) {
    const pixel = new Uint8Array(4);
    const start = performance.now();
    for (let i = 0; i < frames; i++) {
      await draw();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    }
    const ms = (performance.now() - start) / frames;
    document.body.dataset.frameMs = ms.toFixed(2);
    document.title = `bakeshop view: ready, ${ms.toFixed(2)} ms a frame`;
  }
}

main().catch(e => {
  if (!document.title.startsWith("bakeshop view: error")) fail(String(e));
});
