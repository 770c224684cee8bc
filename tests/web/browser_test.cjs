// browser_test.cjs: the look-dev page (web/) in Debian's Chromium, headless, driven by
// playwright-core (pinned by package-lock.json; it downloads no browser), served by
// `retroprism view`. Checks, each against the C++ reference:
//   1. the page loads without console errors and renders;
//   2. its first frame (linear float pixels) matches `retroprism render --samples 1` of the same
//      document and scene;
//   3. its R_A table (computed by the page's shader) matches `retroprism ra`;
//   4. moving a control (ior) changes the image and the R_A table as the C++ node says: the page
//      exports the tuned document and the C++ renders it;
//   5. a malformed document dropped on the page shows an error naming it, and the canvas keeps
//      the previous image;
//   6. the switch to the MaterialX-style GGX baseline: the view server (web/serve.py) answers
//      POST /fit-baseline with the C++ fit, or the reader's message; the table the server fitted
//      is the node's table the page showed; the baseline's R_A table, computed by its shader on
//      the page, matches the C++ baseline's values the server returned; the image changes and the
//      node's controls are disabled; switching back gives the node's frame bit for bit;
//   7. a table the fit refuses (every entry 0) shows the server's message, and the canvas keeps
//      the node's image.
// Prints the load time, the shader's compile time and the frame time; writes screenshots.
//
//   node browser_test.cjs --retroprism BIN --doc DOC.mtlx --out DIR
// Exit status 0 when every check passes; each failure is printed with its figures.
'use strict';
const fs = require('fs');
const net = require('net');
const path = require('path');
const { spawn, execFileSync } = require('child_process');

const SETUP_HINT = 'run scripts/setup-debian.sh (it installs Debian\'s chromium and runs npm ci in tests/web)';
const CHROMIUM = process.env.RETROPRISM_CHROMIUM || '/usr/bin/chromium';
// WebGL2 in headless Chromium without a GPU: ANGLE on Mesa's llvmpipe through EGL. (Chromium's
// default here, ANGLE on SwiftShader, takes minutes to compile the node's shader; llvmpipe
// seconds.) On a machine with a GPU the page needs none of these flags.
const CHROMIUM_ARGS = ['--ignore-gpu-blocklist', '--enable-gpu', '--use-gl=angle', '--use-angle=gl-egl'];
const WIDTH = 480;
const HEIGHT = 270;

// Frame tolerance, OpenImageIO's idiff style: per-pixel error, fraction allowed over it, hard
// maximum, with err = max over R, G, B of |page - C++| / max(|C++|, 1e-6 * peak) (values below a
// millionth of the frame's peak do not show). Compared: the pixels that both renders cover and
// whose eight neighbours the C++ render covers too (a silhouette pixel is covered or not by the
// sphere's chords). The sign fills the frame's left half, the sphere its right half.
const FRAME = {
  floor: 1e-6,
  regions: [
    {
      name: 'sign',
      inside: (x) => x < WIDTH / 2,
      // The flat sign's normal and tangent are exact and its positions float roundings: the
      // float shader against the double node, backends/check.h's contract (1e-4 per value, 0.1%
      // of the values over it, 1% at most).
      perPixel: 1e-4,
      allowedFraction: 1e-3,
      hardMax: 1e-2,
    },
    {
      name: 'sphere',
      inside: (x) => x >= WIDTH / 2,
      // The sphere is 512 x 1024 quads (web/scene.js): its interpolated normals and positions
      // are off the C++ analytic sphere's by up to ~5e-6 rad, which the steep retro lobe of a
      // 0.05-rough sheet at 0.5 degrees from its peak turns into up to 1.5e-3 (measured 1.45e-3
      // with a mean of 5.6e-5; with 192 x 384 quads 8.5e-3, as (1/N)^2 predicts): 2e-3.
      perPixel: 2e-3,
      // Where such a normal crosses a kink of the node (the prism faces' critical angle, the
      // ERA polygon's changes) the error is larger: with ior 1.586, 2 of 20786 pixels, at most
      // 6.5e-3. The contract's 0.1% and 1% hold those.
      allowedFraction: 1e-3,
      hardMax: 1e-2,
    },
  ],
};
// R_A tolerance: backends/check.h's contract (float shader vs double reference, 1e-4 per value,
// 1% hard), applied to every entry with no failures allowed: the table's directions are exact
// floats of the same angles.
const RA = { perEntry: 1e-4 };
// The baseline's R_A table (the page's float shader of glsl/mrm_ggx.glsl) against the C++
// baseline's values in double the server returned: the same contract, 1e-4 per entry, none over
// it: the patch's frame is exact (normal +z, tangent +x), wi and wo are float roundings of the
// same angles, and the GGX lobe of a fit to the white sheeting (roughness ~0.03) moves by far less
// than 1e-4 under a float ulp of those directions (measured: see the printed figure).
const BASELINE_RA = { perEntry: 1e-4 };

const failures = [];
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
}

function args() {
  const a = { retroprism: '', doc: '', out: '' };
  const v = process.argv.slice(2);
  for (let i = 0; i < v.length; i += 2) a[v[i].replace(/^--/, '')] = v[i + 1];
  for (const k of Object.keys(a)) if (!a[k]) throw new Error(`usage: node browser_test.cjs --retroprism BIN --doc DOC.mtlx --out DIR (missing --${k})`);
  return a;
}

function freePort() {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.once('error', reject);
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

// `retroprism view DOC --port P --no-open`, resolved with the page's URL once it prints it.
function startView(bin, doc, port) {
  const child = spawn(bin, ['view', doc, '--port', String(port), '--no-open'], { stdio: ['ignore', 'pipe', 'pipe'] });
  let out = '';
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`retroprism view printed no address in 30 s: ${out}`)), 30000);
    const onData = (d) => {
      out += d;
      const m = /retroprism view: (http:\S+)/.exec(out);
      if (m) {
        clearTimeout(timer);
        resolve({ child, url: m[1] });
      }
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', onData);
    child.on('exit', (code) => reject(new Error(`retroprism view exited (${code}): ${out}`)));
  });
}

async function waitForServer(url) {
  for (let i = 0; i < 100; ++i) {
    try {
      const r = await fetch(url);
      if (r.ok) return;
    } catch (e) {
      // not listening yet
    }
    await new Promise((r) => setTimeout(r, 100));
  }
  throw new Error(`${url}: the server did not answer in 10 s`);
}

// The C++ reference frame: `retroprism render` with one ray per pixel through its centre (the
// rasteriser's sample), read back through oiiotool as RGBA floats, row 0 at the top.
function referenceFrame(bin, doc, out, name, observation, entrance) {
  const exr = path.join(out, `${name}.exr`);
  execFileSync(bin, ['render', doc, '-o', exr, '--width', String(WIDTH), '--height', String(HEIGHT), '--samples', '1',
    '--observation', String(observation), '--sign-angle', String(entrance)], { stdio: 'pipe' });
  const text = execFileSync('oiiotool', ['--dumpdata:empty=1', exr], { maxBuffer: 1 << 30 }).toString();
  const px = new Float32Array(WIDTH * HEIGHT * 4);
  const re = /Pixel \((\d+), (\d+)\): (\S+) (\S+) (\S+) (\S+)/g;
  let m;
  let n = 0;
  while ((m = re.exec(text))) {
    const i = 4 * (Number(m[2]) * WIDTH + Number(m[1]));
    for (let c = 0; c < 4; ++c) px[i + c] = Number(m[3 + c]);
    ++n;
  }
  if (n !== WIDTH * HEIGHT) throw new Error(`${exr}: read ${n} pixels, expected ${WIDTH * HEIGHT}`);
  return px;
}

function pageFrame(base64) {
  const b = Buffer.from(base64, 'base64');
  return new Float32Array(b.buffer, b.byteOffset, b.length / 4);
}

// The frame comparison above over one region; its figures.
function compareFrames(gpu, cpu, region = { inside: () => true, perPixel: 0 }) {
  let peak = 0;
  for (let i = 0; i < cpu.length; i += 4) for (let c = 0; c < 3; ++c) peak = Math.max(peak, cpu[i + c]);
  const covered = (x, y) => x >= 0 && y >= 0 && x < WIDTH && y < HEIGHT && cpu[4 * (y * WIDTH + x) + 3] > 0.5;
  let compared = 0;
  let over = 0;
  let maxErr = 0;
  let coverageDiff = 0;
  let sumErr = 0;
  for (let y = 0; y < HEIGHT; ++y) {
    for (let x = 0; x < WIDTH; ++x) {
      if (!region.inside(x)) continue;
      const i = 4 * (y * WIDTH + x);
      if ((gpu[i + 3] > 0.5) !== (cpu[i + 3] > 0.5)) ++coverageDiff;
      let interior = gpu[i + 3] > 0.5;
      for (let dy = -1; dy <= 1 && interior; ++dy) for (let dx = -1; dx <= 1; ++dx) interior = interior && covered(x + dx, y + dy);
      if (!interior) continue;
      ++compared;
      let e = 0;
      for (let c = 0; c < 3; ++c) e = Math.max(e, Math.abs(gpu[i + c] - cpu[i + c]) / Math.max(Math.abs(cpu[i + c]), FRAME.floor * peak));
      sumErr += e;
      maxErr = Math.max(maxErr, e);
      if (e > region.perPixel) ++over;
    }
  }
  return { compared, over, fraction: over / compared, maxErr, meanErr: sumErr / compared, coverageDiff, peak };
}

function checkFrame(label, gpu, cpu) {
  for (const region of FRAME.regions) {
    const r = compareFrames(gpu, cpu, region);
    const l = `${label}, ${region.name}`;
    console.log(`${l}: ${r.compared} interior pixels, mean err ${r.meanErr.toExponential(2)}, max ${r.maxErr.toExponential(2)}, ` +
      `${r.over} (${(100 * r.fraction).toFixed(3)}%) over ${region.perPixel}; coverage differs at ${r.coverageDiff} silhouette pixels`);
    check(r.compared > 0.1 * WIDTH * HEIGHT, `${l}: covers the frame (${r.compared} pixels compared)`);
    check(r.fraction <= region.allowedFraction, `${l}: pixels over ${region.perPixel}: ${(100 * r.fraction).toFixed(3)}% <= ${100 * region.allowedFraction}%`);
    check(r.maxErr <= region.hardMax, `${l}: largest pixel error ${r.maxErr.toExponential(2)} <= ${region.hardMax}`);
    check(r.coverageDiff <= 0.005 * WIDTH * HEIGHT, `${l}: coverage differs at ${r.coverageDiff} pixels (silhouettes only)`);
  }
}

// `retroprism ra --document DOC --csv` as rows [observation][entrance] of [R, G, B].
function referenceRa(bin, doc, observation, entrance) {
  const text = execFileSync(bin, ['ra', '--document', doc, '--csv']).toString().trim().split('\n');
  const head = text[0].split(',');
  const col = (n) => head.indexOf(n);
  const rgb = observation.map(() => entrance.map(() => null));
  for (const line of text.slice(1)) {
    const f = line.split(',').map(Number);
    const i = observation.indexOf(f[col('observation_deg')]);
    const j = entrance.indexOf(f[col('entrance_deg')]);
    if (i >= 0 && j >= 0) rgb[i][j] = [f[col('R_A_R')], f[col('R_A_G')], f[col('R_A_B')]];
  }
  return rgb;
}

function checkRa(label, gpu, cpu) {
  let maxErr = 0;
  let missing = 0;
  for (let i = 0; i < cpu.length; ++i) {
    for (let j = 0; j < cpu[i].length; ++j) {
      if (!cpu[i][j]) {
        ++missing;
        continue;
      }
      for (let c = 0; c < 3; ++c) maxErr = Math.max(maxErr, Math.abs(gpu[i][j][c] - cpu[i][j][c]) / Math.abs(cpu[i][j][c]));
    }
  }
  check(missing === 0, `${label}: retroprism ra gives every entry of the page's table`);
  check(maxErr <= RA.perEntry, `${label}: largest relative R_A difference ${maxErr.toExponential(2)} <= ${RA.perEntry}`);
}

async function dropDocument(page, name, text) {
  const dt = await page.evaluateHandle(({ name, text }) => {
    const d = new DataTransfer();
    d.items.add(new File([text], name, { type: 'application/xml' }));
    return d;
  }, { name, text });
  const before = await page.evaluate(() => window.retroprism.documentLabel);
  await page.evaluate(() => { window.retroprism.dropped = undefined; });
  await page.dispatchEvent('body', 'drop', { dataTransfer: dt });
  await page.waitForFunction(() => window.retroprism.dropped !== undefined, null, { polling: 100, timeout: 60000 });
  return before;
}

// The view server's own answers (web/serve.py): a table the reader refuses gives 400 and its
// message naming the line, another request 404; the static files are still served.
async function checkServer(pageUrl) {
  const origin = new URL(pageUrl).origin;
  const post = (p, body) => fetch(origin + p, { method: 'POST', body }).then(async (r) => ({ status: r.status, json: await r.json() }));
  const refused = await post('/fit-baseline', 'observation_deg,entrance_deg,rotation_deg,ra\n0.2,-4,0,100\n0.5,-4,0,-3\n');
  check(refused.status === 400 && /the page's R_A table:3, column 4 \(ra\): -3 is out of range/.test(refused.json.error),
    `POST /fit-baseline of a table with R_A -3 on its line 3: HTTP ${refused.status}, "${refused.json.error}"`);
  const unknown = await post('/fit-node', 'x');
  check(unknown.status === 404 && /no such request/.test(unknown.json.error), `POST /fit-node: HTTP ${unknown.status}, "${unknown.json.error}"`);
  const site = await fetch(origin + '/site.json');
  check(site.ok, `GET /site.json: HTTP ${site.status}`);
}

// Luminance Y of an RGB R_A table, as the page computes it (web/main.js, luminanceTable).
function luminanceTable(rgb, w) {
  return rgb.map((row) => row.map((c) => w[0] * c[0] + w[1] * c[1] + w[2] * c[2]));
}

// Clicks the baseline switch (on or off) and waits for the page to finish; its state then.
async function switchBaseline(page, on) {
  const done = await page.evaluate(() => window.retroprism.baselineDone);
  const t0 = Date.now();
  // A click toggles it; the page may uncheck it again (a refused fit), which check() would
  // take for a failed click.
  const box = page.locator('#baseline');
  if ((await box.isChecked()) === on) throw new Error(`the baseline switch is already ${on ? 'on' : 'off'}`);
  await box.click();
  await page.waitForFunction((n) => window.retroprism.baselineDone > n, done, { polling: 100, timeout: 300000 });
  const seconds = (Date.now() - t0) / 1000;
  return page.evaluate((s) => ({
    seconds: s,
    baseline: window.retroprism.baseline,
    error: window.retroprism.error,
    checked: document.getElementById('baseline').checked,
    controlsDisabled: document.getElementById('input-ior').matches(':disabled'),
    timings: window.retroprism.timings,
  }), seconds);
}

async function checkBaseline(page, site, out) {
  const { observation, entrance } = site.ra;
  const nodeFrame = await page.evaluate(() => window.retroprism.frame());
  const nodeRa = await page.evaluate(() => window.retroprism.ra());
  const nodeY = luminanceTable(nodeRa, site.luminance);
  const shown = await page.evaluate(() => [...document.querySelectorAll('#ra tr')].slice(1).map((r) => [...r.cells].slice(1).map((c) => c.textContent)));
  const on = await switchBaseline(page, true);
  check(on.error === '' && on.baseline !== null && on.checked, `the baseline switch shows the baseline (${on.error || 'no error'})`);
  if (!on.baseline) return;
  const { sent, skipped, fit } = on.baseline;
  const p = fit.mrm.params;
  console.log(`baseline: fitted and shown in ${on.seconds.toFixed(1)} s (its shader compiled in ${on.timings.baselineCompileMs.toFixed(0)} ms, ` +
    `frame ${on.timings.frameMs.toFixed(0)} ms): GGX roughness ${p.roughness}, ior ${p.ior}, specular ${p.specular}; ` +
    `RMS of ln(baseline / node) ${fit.mrm.log_rms.toFixed(4)}, largest error ${(100 * fit.mrm.max_error).toFixed(1)}%`);
  check(on.controlsDisabled, 'the node\'s controls are disabled while the baseline is shown');
  // The table the server fitted is the node's table the page showed: the page's values (and the
  // shown ones at their two decimals), every entry but those with R_A <= 0, read back exactly.
  let exact = true;
  let shownMatch = true;
  let k = 0;
  let positive = 0;
  observation.forEach((a, i) => entrance.forEach((b, j) => {
    shownMatch = shownMatch && shown[i][j] === nodeY[i][j].toFixed(2);
    if (!(nodeY[i][j] > 0)) return;
    ++positive;
    const s = sent[k];
    const f = fit.mrm.entries[k];
    exact = exact && s && f && s.observation === a && s.entrance === b && s.ra === nodeY[i][j] &&
      f.observation_deg === a && f.entrance_deg === b && f.rotation_deg === 0 && f.ra === s.ra;
    ++k;
  }));
  check(shownMatch, 'the R_A table shown is the node\'s (its luminance to two decimals)');
  check(sent.length === positive && skipped === observation.length * entrance.length - positive && fit.mrm.entries.length === positive,
    `the page sent the node's ${positive} entries with R_A > 0 (${skipped} left out) and the server fitted ${fit.mrm.entries.length}`);
  check(exact, 'the server fitted the node\'s R_A values the page computed, bit for bit, at their angles and rotation 0');
  // The baseline's R_A on the page (its GLSL in the browser) against the C++ baseline's.
  const pageY = luminanceTable(await page.evaluate(() => window.retroprism.ra()), site.luminance);
  let maxErr = 0;
  k = 0;
  observation.forEach((a, i) => entrance.forEach((b, j) => {
    if (!(nodeY[i][j] > 0)) return;
    const ref = fit.mrm.entries[k++].mrm;
    maxErr = Math.max(maxErr, Math.abs(pageY[i][j] - ref) / Math.abs(ref));
  }));
  console.log(`baseline R_A: page (float GLSL) vs C++ (double) over ${positive} entries: largest relative difference ${maxErr.toExponential(2)}`);
  check(maxErr <= BASELINE_RA.perEntry, `baseline R_A table vs the C++ baseline's: largest relative difference ${maxErr.toExponential(2)} <= ${BASELINE_RA.perEntry}`);
  const gpuNode = pageFrame(nodeFrame);
  const gpuBaseline = pageFrame(await page.evaluate(() => window.retroprism.frame()));
  const changed = compareFrames(gpuBaseline, gpuNode);
  // As for a moved control: far above the sphere's tolerance, 2e-3.
  check(changed.meanErr > 2e-2, `the baseline changes the image (mean relative change ${changed.meanErr.toExponential(2)})`);
  await page.screenshot({ path: path.join(out, 'view_baseline.png') });
  const off = await switchBaseline(page, false);
  check(off.error === '' && off.baseline === null && !off.checked && !off.controlsDisabled,
    'switching back shows the node, its controls enabled');
  const back = await page.evaluate(() => window.retroprism.frame());
  check(back === nodeFrame, 'switching back gives the node\'s frame bit for bit');
  const backRa = await page.evaluate(() => window.retroprism.ra());
  check(JSON.stringify(backRa) === JSON.stringify(nodeRa), 'switching back gives the node\'s R_A table bit for bit');
}

// Every entry 0 (weight 0): the page sends no entry, the server's reader refuses the table, the
// page shows its message and keeps the node's image. Chromium logs the 400 answer as a console
// error: that one is expected.
async function checkBaselineRefused(page, consoleErrors) {
  const renders = await page.evaluate(() => window.retroprism.renders);
  await page.locator('#input-weight').fill('0');
  await page.waitForFunction((n) => window.retroprism.renders > n, renders, { polling: 100, timeout: 60000 });
  const before = await page.evaluate(() => window.retroprism.frame());
  const errorsBefore = consoleErrors.length;
  const r = await switchBaseline(page, true);
  const shown = await page.evaluate(() => !document.getElementById('error').hidden && document.getElementById('error').textContent);
  check(r.baseline === null && !r.checked && !r.controlsDisabled, 'a refused fit leaves the node shown, its controls enabled');
  check(shown && /^baseline: the server could not fit the baseline: .*the page's R_A table:1: no rows/.test(shown) && /25 entries with R_A ≤ 0/.test(shown),
    `a refused fit shows the server's message: "${shown}"`);
  const kept = await page.evaluate(() => window.retroprism.frame());
  check(kept === before, 'after a refused fit the canvas keeps the node\'s image');
  const added = consoleErrors.splice(errorsBefore);
  check(added.length <= 1 && added.every((e) => /status of 400/.test(e) && /fit-baseline/.test(e)),
    `the refused fit adds no console error but Chromium's note of the 400 answer (${added.join(' | ') || 'none'})`);
  check(consoleErrors.length === 0, `no other console errors (${consoleErrors.join(' | ') || 'none'})`);
}

async function main() {
  const a = args();
  if (!fs.existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} not found: ${SETUP_HINT}`);
  let chromium;
  try {
    ({ chromium } = require('playwright-core'));
  } catch (e) {
    throw new Error(`playwright-core is not installed in tests/web: ${SETUP_HINT}`);
  }
  fs.mkdirSync(a.out, { recursive: true });
  const t0 = Date.now();
  const port = await freePort();
  const view = await startView(a.retroprism, a.doc, port);
  let browser;
  try {
    const url = view.url.replace(/\?.*$/, '') + `?size=${WIDTH}x${HEIGHT}`;
    await waitForServer(url);
    browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
    const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
    const consoleErrors = [];
    page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(`${m.text()} (${m.location().url})`); });
    page.on('pageerror', (e) => consoleErrors.push(e.message));
    const tLoad = Date.now();
    await page.goto(url);
    await page.waitForFunction(() => window.retroprism && window.retroprism.ready, null, { polling: 200, timeout: 300000 });
    const loadS = (Date.now() - tLoad) / 1000;
    const first = await page.evaluate(() => ({ error: window.retroprism.error, timings: window.retroprism.timings, scene: window.retroprism.scene }));
    const t = first.timings;
    console.log(`page loaded in ${loadS.toFixed(1)} s (MaterialX ${(t.materialxMs / 1000).toFixed(1)} s, ESSL generation ` +
      `${(t.generateMs / 1000).toFixed(1)} s, compile and link ${(t.compileMs / 1000).toFixed(1)} s, first frame ` +
      `${(t.frameMs / 1000).toFixed(1)} s, R_A table ${(t.raMs / 1000).toFixed(1)} s)`);
    check(first.error === '', `the page shows no error (${first.error || 'none'})`);
    check(consoleErrors.length === 0, `no console errors (${consoleErrors.join(' | ') || 'none'})`);
    await page.screenshot({ path: path.join(a.out, 'view.png') });

    // 2, 3: the first frame and the R_A table against the C++ node.
    const obs = first.scene.observationAtSign;
    const ent = 15;
    const gpu0 = pageFrame(await page.evaluate(() => window.retroprism.frame()));
    const cpu0 = referenceFrame(a.retroprism, a.doc, a.out, 'reference', 0.5, ent);
    checkFrame('first frame vs retroprism render', gpu0, cpu0);
    check(Math.abs(obs - 0.5) < 1e-3, `observation angle at the sign's centre ${obs.toFixed(4)} deg (0.5 asked)`);
    const site = await page.evaluate(() => fetch('../site.json').then((r) => r.json()));
    const ra0 = await page.evaluate(() => window.retroprism.ra());
    checkRa('R_A table vs retroprism ra', ra0, referenceRa(a.retroprism, a.doc, site.ra.observation, site.ra.entrance));

    // 4: a control moved; the page's exported document is the C++ reference's input.
    const renders = await page.evaluate(() => window.retroprism.renders);
    await page.locator('#input-ior').fill('1.586');
    await page.waitForFunction((n) => window.retroprism.renders > n, renders, { polling: 100, timeout: 60000 });
    const frameMs = await page.evaluate(() => window.retroprism.timings.frameMs);
    console.log(`frame after a control moved: ${frameMs.toFixed(0)} ms (${WIDTH}x${HEIGHT})`);
    const tuned = path.join(a.out, 'tuned.mtlx');
    fs.writeFileSync(tuned, await page.evaluate(() => window.retroprism.exportMtlx()));
    check(/name="ior"[^>]*value="1.586"/.test(fs.readFileSync(tuned, 'utf8')), 'the exported document has ior 1.586');
    const gpu1 = pageFrame(await page.evaluate(() => window.retroprism.frame()));
    const cpu1 = referenceFrame(a.retroprism, tuned, a.out, 'reference_tuned', 0.5, ent);
    const moved = compareFrames(gpu1, gpu0);
    // The change must stand far above the sphere's tolerance, 2e-3.
    check(moved.meanErr > 2e-2, `moving ior changes the image (mean relative change ${moved.meanErr.toExponential(2)})`);
    checkFrame('frame after ior 1.586 vs retroprism render of the exported document', gpu1, cpu1);
    const ra1 = await page.evaluate(() => window.retroprism.ra());
    checkRa('R_A table after ior 1.586 vs retroprism ra of the exported document', ra1,
      referenceRa(a.retroprism, tuned, site.ra.observation, site.ra.entrance));
    check(Math.abs(ra1[0][0][0] / ra0[0][0][0] - 1) > 1e-3, `moving ior changes R_A (0.2 deg, -4 deg: ${ra0[0][0][0].toFixed(2)} -> ${ra1[0][0][0].toFixed(2)})`);

    // 5: malformed documents dropped on the page.
    for (const [name, text, expected] of [
      ['broken.mtlx', '<?xml version="1.0"?>\n<materialx version="1.39">\n  <surfacematerial name="m"', 'not a MaterialX document'],
      ['no_node.mtlx', '<?xml version="1.0"?><materialx version="1.39"><standard_surface name="s" type="surfaceshader"/>' +
        '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s"/></surfacematerial></materialx>',
        'is not a <rp_prismatic_retroreflector_bsdf> node'],
    ]) {
      const before = await dropDocument(page, name, text);
      const r = await page.evaluate(() => ({
        error: window.retroprism.error,
        shown: !document.getElementById('error').hidden && document.getElementById('error').textContent,
        label: window.retroprism.documentLabel,
      }));
      check(r.shown && r.shown.includes(name) && r.shown.includes(expected), `dropping ${name} shows "${r.shown}"`);
      check(r.label === before, `after ${name} the page still shows ${before}`);
      const kept = pageFrame(await page.evaluate(() => window.retroprism.frame()));
      check(compareFrames(kept, gpu1).maxErr === 0, `after ${name} the canvas keeps the previous image`);
    }
    await page.screenshot({ path: path.join(a.out, 'view_error.png') });
    check(consoleErrors.length === 0, `still no console errors (${consoleErrors.join(' | ') || 'none'})`);

    // 6, 7: the GGX baseline.
    await checkServer(view.url);
    await checkBaseline(page, site, a.out);
    await checkBaselineRefused(page, consoleErrors);
  } finally {
    if (browser) await browser.close();
    view.child.kill('SIGTERM');
  }
  console.log(`browser test: ${((Date.now() - t0) / 1000).toFixed(1)} s, ${failures.length} failure(s)`);
  return failures.length === 0 ? 0 : 1;
}

main().then(
  (code) => process.exit(code),
  (e) => {
    console.error(`FAIL ${e.message}`);
    process.exit(1);
  },
);
