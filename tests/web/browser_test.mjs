// The configurator page in a real browser: Debian's Chromium, headless, driven by npm puppeteer-core,
// against a static server on 127.0.0.1 serving the WebAssembly build's folder as it is.
//
// usage: node browser_test.mjs WEB_DIR NODE_MODULES LIBSSCAPE [SCREENSHOT.png]
//   WEB_DIR       build-wasm/web (the module, the browser package, the page, three.js, the model)
//   NODE_MODULES  with puppeteer-core, koffi and gltf-validator (setup.sh: build/npm/node_modules)
//   LIBSSCAPE     the native library the WebAssembly results are compared with
// Exit 0: passed; 1: failed; 77: skipped (no Chromium, no WebAssembly build, or an npm package missing).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';
import { serve } from './static_server.mjs';

const [webDir, nodeModules, libsscape, screenshot] = process.argv.slice(2);
const chromium = ['/usr/bin/chromium', '/usr/bin/chromium-browser'].find((p) => fs.existsSync(p));
function skip(why) {
  console.log(`SKIPPED: ${why}`);
  process.exit(77);
}
if (!chromium) skip('no Chromium (Debian package chromium; setup.sh test installs it)');
if (!webDir || !fs.existsSync(path.join(webDir, 'sscape_runtime.wasm'))) skip(`no WebAssembly build in ${webDir} (setup.sh test builds build-wasm)`);
const require = createRequire(path.join(path.resolve(nodeModules), 'x.js'));
let puppeteer, validator;
try {
  puppeteer = require('puppeteer-core');
  validator = require('gltf-validator');
  require('koffi');
} catch (e) {
  skip(`an npm package is missing (${e.message.split('\n')[0]}); setup.sh installs them`);
}
process.env.SSCAPE_LIBRARY = path.resolve(libsscape);
const native = require(path.resolve(path.dirname(new URL(import.meta.url).pathname), '../../bindings/javascript/lib/index.js'));

let failures = 0;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures += 1;
}
function maxDifference(a, b) {
  let worst = 0;
  for (let i = 0; i < a.length; ++i) worst = Math.max(worst, Math.abs(a[i] - b[i]));
  return a.length === b.length ? worst : Infinity;
}

const server = await serve(webDir);
const downloads = fs.mkdtempSync(path.join(os.tmpdir(), 'sscape-web-'));
const browser = await puppeteer.launch({ executablePath: chromium, headless: true,
  args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'] });
try {
  const page = await browser.newPage();
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error' && !m.text().includes('GPU stall')) pageErrors.push(m.text()); });
  await page.setViewport({ width: 1280, height: 800 });
  const started = Date.now();
  await page.goto(server.url);
  await page.waitForFunction(() => window.sscapeApp?.ready || document.getElementById('status').textContent.startsWith('failed'), { timeout: 60000 });
  const loadMs = Date.now() - started;

  // The page loads, the model verifies, the first body is drawn and measured.
  const first = await page.evaluate(() => {
    const a = window.sscapeApp;
    return { status: document.getElementById('status').textContent, vertices: a.model.vertexCount, levels: a.model.levels.length,
      redraws: a.redraws, stature: a.measurements.stature, cells: document.querySelectorAll('#measurements tr').length, timings: a.timings };
  });
  console.log(`page ready in ${loadMs} ms from navigation (in the page: model ${first.timings.modelMs.toFixed(0)} ms, first body ${first.timings.readyMs.toFixed(0)} ms)`);
  check(first.status.includes('model verified') && first.vertices === 13380 && first.levels === 4, `the model verified: ${first.status}`);
  check(first.redraws >= 1 && first.cells === 16 && first.stature > 1.5 && first.stature < 1.9, `the first body drawn and measured (stature ${first.stature.toFixed(4)} m, 16 measurements)`);

  // A slider changes the body and its measurements.
  const moved = await page.evaluate(() => {
    const a = window.sscapeApp;
    const before = { vertices: Array.from(a.body.vertices.subarray(0, 3000)), redraws: a.redraws };
    const input = document.getElementById('slider-stature');
    input.value = '1.8';
    input.dispatchEvent(new Event('input'));
    const cell = document.querySelector('#measurements tr[data-name="stature"] td:last-child').textContent;
    const after = Array.from(a.body.vertices.subarray(0, 3000));
    let changed = 0;
    for (let i = 0; i < after.length; ++i) changed = Math.max(changed, Math.abs(after[i] - before.vertices[i]));
    return { stature: a.measurements.stature, slider: a.body.sliders.stature, cell, changed, redraws: a.redraws - before.redraws };
  });
  check(Math.abs(moved.slider - 1.8) < 0.003 &&  // the range input snaps to its step
    Math.abs(moved.stature - 1.8) < 0.01 && moved.redraws === 1 && moved.changed > 0.01,
    `the stature slider to 1.8 m: slider ${moved.slider.toFixed(4)}, measured ${moved.stature.toFixed(4)} m, table "${moved.cell}", vertices moved ${(moved.changed * 1000).toFixed(1)} mm`);
  check(moved.cell === `${(moved.stature * 100).toFixed(1)} cm`, 'the measurement table shows the new stature');

  // Made to measure: the waist girth's control, solved on release.
  const tailored = await page.evaluate(() => {
    const a = window.sscapeApp;
    const input = document.getElementById('measure-waist_girth');
    input.value = '0.95';
    input.dispatchEvent(new Event('change'));
    return { waist: a.measurements.waist_girth, stature: a.measurements.stature, note: document.getElementById('measure-result').textContent };
  });
  check(Math.abs(tailored.waist - 0.95) < 0.003 && Math.abs(tailored.stature - 1.8) < 0.01,
    `made to measure: waist girth ${tailored.waist.toFixed(4)} m asked 0.95, stature kept at ${tailored.stature.toFixed(4)} (${tailored.note})`);

  // A named pose and a level of detail.
  const posed = await page.evaluate(() => {
    const a = window.sscapeApp;
    const pose = document.getElementById('pose');
    pose.value = 'sitting';
    pose.dispatchEvent(new Event('change'));
    const hands = document.getElementById('hands');
    hands.value = '0.6';
    hands.dispatchEvent(new Event('input'));
    const level = document.getElementById('level');
    level.value = '3';
    level.dispatchEvent(new Event('change'));
    return { redraws: a.redraws, options: pose.options.length };
  });
  check(posed.options === 11, `the pose list holds the 11 named poses (${posed.options})`);
  if (screenshot) {
    await page.evaluate(() => { const l = document.getElementById('level'); l.value = '0'; l.dispatchEvent(new Event('change')); });
    await page.screenshot({ path: screenshot });
    console.log(`wrote ${screenshot}`);
    await page.evaluate(() => { const l = document.getElementById('level'); l.value = '3'; l.dispatchEvent(new Event('change')); });
  }

  // The downloaded GLB (the coarsest level, as shown) validates.
  const cdp = await page.createCDPSession();
  await cdp.send('Browser.setDownloadBehavior', { behavior: 'allow', downloadPath: downloads });
  await page.click('#download');
  const file = path.join(downloads, 'sscape-body.glb');
  for (let i = 0; i < 100 && !(fs.existsSync(file) && fs.statSync(file).size > 0); ++i) await new Promise((r) => setTimeout(r, 100));
  const glb = fs.existsSync(file) ? new Uint8Array(fs.readFileSync(file)) : new Uint8Array(0);
  const expectedBytes = await page.evaluate(() => window.sscapeApp.lastDownloadBytes);
  check(glb.length > 0 && glb.length === expectedBytes, `the Download GLB button saved ${glb.length} bytes (the page made ${expectedBytes})`);
  if (glb.length > 0) {
    const report = await validator.validateBytes(glb);
    check(report.issues.numErrors === 0, `the Khronos validator on the download: ${report.issues.numErrors} errors, ${report.issues.numWarnings} warnings`);
  }

  // Hostile model bytes in the page: a clear error, no crash.
  const refused = await page.evaluate(async () => {
    const a = window.sscapeApp;
    const bytes = new Uint8Array(await (await fetch('sscape-default.sscape')).arrayBuffer());
    const results = [];
    for (const damage of [(b) => { b[5000] ^= 0x40; return b; }, (b) => b.subarray(0, 1000), () => new Uint8Array(0)]) {
      try {
        a.sscape.modelFromBytes(damage(bytes.slice()));
        results.push('loaded');
      } catch (e) {
        results.push(e.code);
      }
    }
    return results;
  });
  check(refused.every((c) => c === 'SSC_ERROR_MODEL_CORRUPT' || c === 'SSC_ERROR_INVALID_ARGUMENT'),
    `damaged model bytes refused: ${refused.join(', ')}`);
  // The module has no built-in model: the C API says so (the page fetches the file).
  const builtin = await page.evaluate(() => {
    const { sscape } = window.sscapeApp;
    return sscape._scratch(4, (out) => ({ status: sscape._m._ssc_model_load_default(0, out), message: sscape._string(sscape._m._ssc_last_error()) }));
  });
  check(builtin.status === -7 && builtin.message.includes('no built-in model'), `ssc_model_load_default in the browser: ${builtin.status}, "${builtin.message}"`);

  // A batch equals the bodies made one by one; OBJ text comes out of the in-memory file system.
  const batch = await page.evaluate(() => {
    const { model, body } = window.sscapeApp;
    const shapes = new Float32Array(2 * 10).map((_, i) => Math.cos(i) * 1.2);
    const poses = new Float32Array([...model.namedPose('lunge'), ...model.namedPose('crouching')]);
    const { vertices, normals } = model.synthesize({ count: 2, shapes, poses, normals: true, level: 'simplified' });
    let worst = 0;
    for (let g = 0; g < 2; ++g) {
      const b = model.createBody();
      b.shape = shapes.subarray(10 * g, 10 * g + 10);
      b.setPose(poses.subarray(4 * model.jointCount * g, 4 * model.jointCount * (g + 1)));
      const v = b.levelVertices('simplified'), n = b.levelNormals('simplified');
      for (let i = 0; i < v.length; ++i) worst = Math.max(worst, Math.abs(v[i] - vertices[g * v.length + i]), Math.abs(n[i] - normals[g * v.length + i]));
      b.close();
    }
    const obj = body.toOBJ({ level: 'proxy741' });
    return { worst, length: vertices.length, objVertices: obj.split('\n').filter((l) => l.startsWith('v ')).length };
  });
  check(batch.worst === 0 && batch.length === 2 * 4002 * 3, `a batch of 2 bodies at the simplified level equals the bodies one by one (worst ${batch.worst})`);
  check(batch.objVertices === 741, `OBJ of the proxy741 level: ${batch.objVertices} vertices`);

  // Fitting to landmarks in the page: the 73 landmarks of a body in a named pose give back its surface.
  const fit = await page.evaluate(() => {
    const { model } = window.sscapeApp;
    const truth = model.createBody();
    truth.shape = Float32Array.from({ length: 10 }, (_, i) => Math.sin(3 * i + 1));
    truth.setNamedPose('arms_raised');
    const fitter = model.createFitter({ shapeCount: 10 });
    fitter.addLandmarks(model.landmarkNames, truth.landmarks);
    const report = fitter.solve();
    const v = fitter.vertices, t = truth.vertices;
    let sum = 0;
    for (let i = 0; i < v.length; i += 3) sum += Math.hypot(v[i] - t[i], v[i + 1] - t[i + 1], v[i + 2] - t[i + 2]);
    let refused = '';
    try { fitter.addLandmarks(['no_such_landmark'], [0, 0, 0]); } catch (e) { refused = e.code; }
    fitter.close();
    truth.close();
    return { converged: report.converged, rms: report.landmarkRms, seconds: report.seconds, error: sum / (v.length / 3), refused };
  });
  check(fit.converged && fit.error < 0.005 && fit.refused === 'SSC_ERROR_NOT_FOUND',
    `fitting to 73 landmarks in the page: converged in ${(fit.seconds * 1000).toFixed(0)} ms, landmark RMS ${(fit.rms * 1000).toFixed(2)} mm, ` +
    `mean vertex error ${(fit.error * 1000).toFixed(2)} mm; an unknown landmark name: ${fit.refused}`);

  // The WebAssembly results against the native library's, for the same parameters: the page's body
  // as the controls left it, and random ones.
  const cases = await page.evaluate(() => {
    const { model, body } = window.sscapeApp;
    const out = [];
    const shapes = [body.shape, ...[1, 2].map((k) => Float32Array.from({ length: model.shapeCount }, (_, i) => Math.sin(7 * i + k) * 1.5))];
    const poses = [['sitting', 0.6], ['kneeling', 1], ['arms_raised', 0]];
    shapes.forEach((shape, i) => {
      const b = model.createBody();
      b.shape = shape;
      const rotations = model.namedPose(poses[i][0], { handsClosed: [poses[i][1], poses[i][1]] });
      b.setPose(rotations, [0.1, -0.2, 0.3]);
      const levels = model.levels.map((l) => ({ vertices: Array.from(b.levelVertices(l.index)), normals: Array.from(b.levelNormals(l.index)) }));
      out.push({ shape: Array.from(shape), rotations: Array.from(rotations), levels, measurements: Array.from(b.measureAll()) });
      b.close();
    });
    return out;
  });
  const nativeModel = native.Model.loadDefault();
  const worst = { vertices: 0, normals: 0, measurements: 0 };
  let identicalVertices = 0, vertexValues = 0;
  for (const c of cases) {
    const b = nativeModel.createBody();
    b.shape = Float32Array.from(c.shape);
    b.setPose(Float32Array.from(c.rotations), Float32Array.from([0.1, -0.2, 0.3]));
    c.levels.forEach((l, level) => {
      const v = b.levelVertices(level);
      worst.vertices = Math.max(worst.vertices, maxDifference(v, l.vertices));
      worst.normals = Math.max(worst.normals, maxDifference(b.levelNormals(level), l.normals));
      for (let i = 0; i < v.length; ++i) identicalVertices += v[i] === Math.fround(l.vertices[i]);
      vertexValues += v.length;
    });
    worst.measurements = Math.max(worst.measurements, maxDifference(b.measureAll(), c.measurements));
    b.close();
  }
  console.log(`WebAssembly against the native library (${cases.length} bodies, every level): vertices differ by at most ${worst.vertices.toExponential(2)} m ` +
    `(${(100 * identicalVertices / vertexValues).toFixed(1)} % of the coordinates bit-identical), normals by ${worst.normals.toExponential(2)}, measurements by ${worst.measurements.toExponential(2)}`);
  // WebAssembly has no fused multiply-add: the shape and skinning stages round twice where the native
  // library rounds once, and Eigen sums the skeleton's 3x3 products in another order without SSE2
  // (docs/web.md, "Same bits?"): an ulp or a few on the vertices (measured: under 1e-6 m).
  check(worst.vertices <= 5e-6, 'WebAssembly vertices within 5e-6 m of the native library\'s');
  check(worst.normals <= 5e-3, 'WebAssembly normals within 5e-3 of the native library\'s (small triangles magnify the vertices\' ulps)');
  check(worst.measurements <= 1e-5, 'WebAssembly measurements within 1e-5 of the native library\'s');
  check(pageErrors.length === 0, `no errors in the page${pageErrors.length ? `: ${pageErrors.join(' | ')}` : ''}`);
} finally {
  await browser.close();
  await server.close();
  fs.rmSync(downloads, { recursive: true, force: true });
}
console.log(failures ? `${failures} check(s) failed` : 'browser test passed');
process.exit(failures ? 1 : 0);
