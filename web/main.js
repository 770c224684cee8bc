// main.js: the look-dev page. Loads MaterialX and the node library, reads a document (the one
// `retroprism view DOC.mtlx` serves, else the bundled white_sign.mtlx, or one dropped on the
// page), generates its ESSL, renders the night scene with it and computes the R_A table with
// the same shader; controls from the parameter table; exports the tuned material as .mtlx; a
// switch shows the MaterialX-style GGX baseline fitted to the node's R_A table (baseline.js).
// window.retroprism is what the browser test (tests/web/browser_test.cjs) reads.
import { loadMaterialX, readDocument, generateEssl, exportDocument } from './mx.js';
import { baselineShader, baselineUniforms, fitBaseline, raTableCsv } from './baseline.js';
import { Renderer } from './renderer.js';
import { buildControls, sceneControl, uniformValue, valueString, mtlxType } from './controls.js';

const $ = (id) => document.getElementById(id);

const state = {
  site: null, // site.json: the parameter table, the R_A angles, the luminance weights
  m: null, // MaterialX and its generation context
  found: null, // the document, its material and the retroprism node
  renderer: null,
  values: {}, // input name -> uniform value
  uniformNames: {}, // input name -> uniform name in the shader
  observation: 0.5,
  entrance: 15,
  exposure: -8,
  baselineShown: false, // the baseline's program renders the frame and the table
};

const hook = {
  ready: false,
  error: '',
  documentLabel: '',
  timings: {},
  // The linear RGBA float frame, row 0 at the top, as base64 of its little-endian bytes.
  frame: () => {
    const bytes = new Uint8Array(state.renderer.readFrame().buffer);
    let s = '';
    for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
    return btoa(s);
  },
  ra: () => state.renderer.raTable(state.site.ra.observation, state.site.ra.entrance),
  exportMtlx: () => exportMtlx(),
  scene: null,
  // The baseline shown: { sent: the entries posted [{observation, entrance, ra}], skipped: the
  // entries left out (R_A <= 0), fit: the server's answer }; null while the node is shown.
  baseline: null,
  baselineDone: 0, // switches of the baseline finished (shown, failed or hidden)
};
window.retroprism = hook;

function showError(text) {
  hook.error = text;
  const e = $('error');
  e.textContent = text;
  e.hidden = !text;
  if (text) console.warn(`retroprism: ${text}`);
}

function status(text) {
  $('status').textContent = text;
}

async function fetchText(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: HTTP ${r.status} ${r.statusText}`);
  return r.text();
}

// The shader's uniform of each input of the table: `<node>_<input>`, or `<node>_<input>_cm_in`
// when MaterialX converts the input's colour space in the shader; starting values from the
// generated shader (the document's values, enums as indices).
function inputUniforms(uniforms, nodeName) {
  const byName = new Map(uniforms.map((u) => [u.name, u.value]));
  state.values = {};
  state.uniformNames = {};
  for (const p of state.site.params) {
    for (const name of [`${nodeName}_${p.name}`, `${nodeName}_${p.name}_cm_in`]) {
      if (!byName.has(name)) continue;
      state.uniformNames[p.name] = name;
      state.values[p.name] = uniformValue(p, byName.get(name));
    }
  }
}

function applyInputs() {
  const types = { float: 'float', color3: 'color3', string: 'integer', boolean: 'boolean' };
  const inputs = [];
  for (const p of state.site.params) {
    if (!(p.name in state.values)) continue;
    inputs.push({ name: state.uniformNames[p.name], type: types[p.type], value: state.values[p.name] });
  }
  state.renderer.setUniforms(inputs);
}

function render() {
  const t0 = performance.now();
  if (!state.baselineShown) applyInputs();
  hook.scene = state.renderer.renderFrame(state.observation, state.entrance, state.exposure);
  state.renderer.finish();
  hook.timings.frameMs = performance.now() - t0;
  const t1 = performance.now();
  showRaTable($(state.baselineShown ? 'baseline-ra' : 'ra'), hook.ra());
  hook.timings.raMs = performance.now() - t1;
  $('angles').textContent =
    `at the sign's centre: observation ${hook.scene.observationAtSign.toFixed(3)}°, ` +
    `entrance ${hook.scene.entranceAtSign.toFixed(2)}° · frame ${hook.timings.frameMs.toFixed(0)} ms`;
  hook.renders = (hook.renders || 0) + 1;
}

// Luminance Y of each entry of an RGB R_A table.
function luminanceTable(rgb) {
  const w = state.site.luminance;
  return rgb.map((row) => row.map((c) => w[0] * c[0] + w[1] * c[1] + w[2] * c[2]));
}

function showRaTable(t, rgb) {
  const { observation, entrance } = state.site.ra;
  const y = luminanceTable(rgb);
  t.replaceChildren();
  const head = t.insertRow();
  head.insertCell().textContent = 'α \\ β';
  for (const b of entrance) head.insertCell().textContent = `${b}°`;
  observation.forEach((a, i) => {
    const r = t.insertRow();
    r.insertCell().textContent = `${a}°`;
    entrance.forEach((b, j) => {
      r.insertCell().textContent = y[i][j].toFixed(2);
    });
  });
}

// The baseline's side of the page: the node's controls disabled while it is shown, its table
// and its fit's parameters and errors.
function showBaselineFit(info) {
  $('inputs').disabled = Boolean(info);
  $('baseline').checked = Boolean(info);
  $('baseline-fit').hidden = !info;
  if (!info) return;
  const { params, log_rms: logRms, max_error: maxError } = info.fit.mrm;
  const g = (x) => Number(x.toPrecision(6));
  $('baseline-summary').textContent =
    `Fitted by retroprism fit --ra … --baseline-only to the node's ${info.sent.length} entries above ` +
    `(log R_A, rotation 0): GGX roughness ${g(params.roughness)}, ior ${g(params.ior)}, ` +
    `specular ${g(params.specular)}, Lambert colour ${params.color.map(g).join(', ')}; ` +
    `RMS of ln(baseline / node) ${logRms.toFixed(4)}, largest error ${(100 * maxError).toFixed(1)}%` +
    (info.skipped ? `; ${info.skipped} entries with R_A ≤ 0 left out (the fit works on ln R_A)` : '') +
    '. The node’s controls are disabled while the baseline is shown.';
}

// Shows the baseline fitted to the node's current R_A table, or the node again. A failed fit
// shows the server's message and leaves the node on the canvas.
async function setBaseline(on) {
  const box = $('baseline');
  box.disabled = true;
  let table = null;
  try {
    if (!on) {
      state.renderer.use('material');
      state.baselineShown = false;
      hook.baseline = null;
      showBaselineFit(null);
      render();
      status(`showing ${hook.documentLabel}: material "${hook.material}"`);
      return;
    }
    // The table fitted is the one shown: the node's controls wait for the answer.
    $('inputs').disabled = true;
    status('fitting the GGX baseline to the node’s R_A table …');
    table = raTableCsv(state.site.ra.observation, state.site.ra.entrance, luminanceTable(hook.ra()));
    const fit = await fitBaseline(table.csv);
    if (!state.renderer.hasShader('baseline')) {
      const library = await fetchText(state.site.baseline);
      hook.timings.baselineCompileMs = state.renderer.setShader(baselineShader(library), 'baseline');
    }
    state.renderer.use('baseline');
    state.renderer.setUniforms(baselineUniforms(fit.mrm.params));
    state.baselineShown = true;
    hook.baseline = { sent: table.entries, skipped: table.skipped, fit };
    showBaselineFit(hook.baseline);
    showError('');
    render();
    status(`showing the MaterialX-style GGX baseline fitted to ${hook.documentLabel}'s R_A table`);
  } catch (e) {
    if (state.renderer.hasShader('material')) state.renderer.use('material');
    state.baselineShown = false;
    hook.baseline = null;
    showBaselineFit(null);
    const left = table && table.skipped ? ` (${table.skipped} entries with R_A ≤ 0 were left out of the table sent)` : '';
    showError(`baseline: ${e && e.message ? e.message : e}${left}`);
    status(`showing ${hook.documentLabel}; the baseline was not fitted`);
  } finally {
    box.disabled = false;
    hook.baselineDone += 1;
  }
}

// Reads a document, generates and compiles its shader, rebuilds the controls and renders.
// On failure the error is shown and the previous material stays on the canvas.
async function openDocument(xml, label) {
  status(`reading ${label} …`);
  try {
    const t0 = performance.now();
    const found = await readDocument(state.m, xml, label);
    const essl = generateEssl(state.m, found);
    const t1 = performance.now();
    const compileMs = state.renderer.setShader(essl, 'material');
    state.renderer.setUniforms(essl.uniforms);
    state.found = found;
    // A new document is shown as the node: the baseline was fitted to the previous one.
    state.baselineShown = false;
    hook.baseline = null;
    showBaselineFit(null);
    inputUniforms(essl.uniforms, found.bsdf.getName());
    buildControls($('inputs'), state.site.params, state.values, render);
    showError('');
    render();
    hook.documentLabel = label;
    hook.material = found.material.getName();
    hook.timings.generateMs = t1 - t0;
    hook.timings.compileMs = compileMs;
    status(
      `${label}: material "${found.material.getName()}" · ESSL generated in ${(t1 - t0).toFixed(0)} ms, ` +
        `compiled in ${compileMs.toFixed(0)} ms`,
    );
    return true;
  } catch (e) {
    showError(String(e && e.message ? e.message : e));
    status(state.found ? `still showing the previous material; ${label} was not loaded` : 'no material loaded');
    return false;
  }
}

async function exportMtlx() {
  const values = {};
  const types = {};
  for (const p of state.site.params) {
    if (!(p.name in state.values)) continue;
    values[p.name] = valueString(p, state.values[p.name]);
    types[p.name] = mtlxType(p);
  }
  return exportDocument(state.m, state.found, values, types);
}

async function download() {
  const text = await exportMtlx();
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([text], { type: 'application/xml' }));
  a.download = `${state.found.material.getName()}.mtlx`;
  a.click();
  URL.revokeObjectURL(a.href);
}

function sceneControls() {
  const c = $('scene');
  sceneControl(c, 'observation °', 'observation angle at the sign’s centre (headlight below the eye)',
    0, 5, state.observation, 'scene-observation', (v) => { state.observation = v; render(); });
  sceneControl(c, 'entrance °', 'entrance angle of the headlight at the sign’s centre',
    0, 80, state.entrance, 'scene-entrance', (v) => { state.entrance = v; render(); });
  sceneControl(c, 'exposure EV', 'display exposure in stops (the frame itself is linear)',
    -14, 2, state.exposure, 'scene-exposure', (v) => {
      state.exposure = v;
      state.renderer.show(v);
    });
}

function dropping() {
  const zone = document.body;
  zone.addEventListener('dragover', (e) => {
    e.preventDefault();
    zone.classList.add('dragging');
  });
  zone.addEventListener('dragleave', () => zone.classList.remove('dragging'));
  zone.addEventListener('drop', async (e) => {
    e.preventDefault();
    zone.classList.remove('dragging');
    const file = e.dataTransfer && e.dataTransfer.files[0];
    if (!file) return showError('the drop held no file: drop a MaterialX document (.mtlx)');
    hook.dropped = await openDocument(await file.text(), file.name);
  });
  $('open').addEventListener('change', async (e) => {
    const file = e.target.files[0];
    if (file) hook.dropped = await openDocument(await file.text(), file.name);
  });
  $('export').addEventListener('click', download);
}

async function main() {
  const t0 = performance.now();
  try {
    state.site = JSON.parse(await fetchText('../site.json'));
    status('loading MaterialX …');
    // ?size=WxH sets the frame's size (the test's, smaller than the default 640x360).
    const size = /^(\d+)x(\d+)$/.exec(new URLSearchParams(location.search).get('size') || '');
    if (size) [$('view').width, $('view').height] = [Number(size[1]), Number(size[2])];
    state.renderer = new Renderer($('view'));
    state.m = await loadMaterialX();
    hook.timings.materialxMs = performance.now() - t0;
    sceneControls();
    dropping();
    $('baseline').addEventListener('change', (e) => setBaseline(e.target.checked));
    const docUrl = new URLSearchParams(location.search).get('doc') || state.site.document;
    await openDocument(await fetchText(docUrl), docUrl.split('/').pop());
  } catch (e) {
    showError(String(e && e.message ? e.message : e));
  }
  hook.timings.loadMs = performance.now() - t0;
  hook.ready = true;
}

main();
