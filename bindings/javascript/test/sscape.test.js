'use strict';
// Tests of the Node package against the built library (SSCAPE_LIBRARY). The scenario and layout
// files to compare with come from tests/bindings/run.sh (SSCAPE_SCENARIO_REFERENCE, SSCAPE_LAYOUTS);
// without them those two tests are skipped with a message.
const test = require('node:test');
const assert = require('node:assert');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const koffi = require('koffi');
const sscape = require('..');
const native = require('../lib/native.js');

// The scenario of tests/bindings/scenario.c, step for step, as floats in the same order.
function scenario() {
  const model = sscape.Model.loadDefault();
  const body = model.createBody();
  body.shape = [0.8, -0.5, 1.2, 0.3, -1.0];
  const rotations = new Float32Array(model.jointCount * 4);
  for (let j = 0; j < model.jointCount; ++j) rotations[j * 4 + 3] = 1;
  rotations.set([0, 0, 0.25881904, 0.96592583], model.jointIndex('upperarm_l') * 4);
  rotations.set([0, -0.17364818, 0, 0.98480775], model.jointIndex('lowerarm_r') * 4);
  body.setPose(rotations, [0.1, 0, -0.2]);
  const vertices = body.vertices;
  const measurements = body.measureAll();
  const landmarks = body.landmarks;
  const fitter = model.createFitter();
  fitter.addLandmarks(model.landmarkNames, landmarks);
  fitter.solve();
  const pose = fitter.pose();
  const batch = model.synthesize({ shapes: model.sampleShapes(3, { seed: 7, truncation: 2 }) }).vertices;
  const parts = [vertices, measurements, landmarks, fitter.shape, pose.rotations, pose.translation,
    Float32Array.of(pose.scale), batch];
  fitter.close();
  body.close();
  model.close();
  return Buffer.concat(parts.map((p) => Buffer.from(p.buffer, p.byteOffset, p.byteLength)));
}

test('the scenario gives the C API\'s bytes', (t) => {
  const reference = process.env.SSCAPE_SCENARIO_REFERENCE;
  if (!reference) { t.skip('SSCAPE_SCENARIO_REFERENCE not set (tests/bindings/run.sh sets it)'); return; }
  const mine = scenario();
  const theirs = fs.readFileSync(reference);
  assert.strictEqual(mine.length, theirs.length);
  assert.ok(mine.equals(theirs), 'the floats differ from the C program\'s');
});

test('every struct is laid out as C lays it out', (t) => {
  const layouts = process.env.SSCAPE_LAYOUTS;
  if (!layouts) { t.skip('SSCAPE_LAYOUTS not set (tests/bindings/run.sh sets it)'); return; }
  native.declareTypes(koffi);
  const lines = [];
  for (const line of fs.readFileSync(layouts, 'utf8').trim().split('\n')) {
    const [what] = line.split(' ');
    const [struct, field] = what.split('.');
    lines.push(field ? `${what} offset ${koffi.offsetof(struct, field)}` : `${struct} size ${koffi.sizeof(struct)}`);
  }
  assert.deepStrictEqual(lines, fs.readFileSync(layouts, 'utf8').trim().split('\n'));
});

test('every function of the header is declared', () => {
  const header = fs.readFileSync(path.join(__dirname, '..', '..', '..', 'include', 'sscape', 'sscape.h'), 'utf8');
  const inHeader = [...header.matchAll(/^SSC_(?:API|EXPERIMENTAL)\s[^;(]*?\b(ssc_\w+)\s*\(/gm)].map((m) => m[1]).sort();
  assert.deepStrictEqual(Object.keys(sscape.native).sort(), inHeader);
});

test('the library\'s ABI major is the package\'s', () => {
  assert.strictEqual(sscape.version().major, sscape.ABI_MAJOR);
  assert.strictEqual(sscape.version().number, sscape.native.ssc_version());
  assert.match(sscape.version().text, /^\d+\.\d+\.\d+$/);
});

test('a library of another ABI major is refused with a message', (t) => {
  const fake = process.env.SSCAPE_FAKE_ABI_LIBRARY;
  if (!fake) { t.skip('SSCAPE_FAKE_ABI_LIBRARY not set (tests/CMakeLists.txt sets it)'); return; }
  // In a child process: the package loads its library once per process.
  const child = require('node:child_process').spawnSync(process.execPath,
    ['-e', "require('..').Model.loadDefault()"], { cwd: __dirname, env: { ...process.env, SSCAPE_LIBRARY: fake }, encoding: 'utf8' });
  assert.notStrictEqual(child.status, 0);
  assert.match(child.stderr, new RegExp(`has ABI major ${sscape.ABI_MAJOR + 1} .*this package is for major ${sscape.ABI_MAJOR}`));
});

test('errors become SscapeError with the status and the library\'s message', () => {
  const model = sscape.Model.loadDefault();
  assert.throws(() => model.jointIndex('no_such_joint'), (e) => e instanceof sscape.SscapeError
    && e.code === 'SSC_ERROR_NOT_FOUND' && e.status === native.enums.ssc_status.SSC_ERROR_NOT_FOUND
    && /no_such_joint/.test(e.message));
  const body = model.createBody();
  assert.throws(() => { body.shape = [NaN]; }, (e) => e.code === 'SSC_ERROR_INVALID_ARGUMENT');
  assert.throws(() => body.setPose(new Float32Array(4)), RangeError);  // wrong count: caught before C
  const fitter = model.createFitter();
  assert.throws(() => fitter.addLandmarks(['Sellion', 'Nonsense'], new Float32Array(6)),
    (e) => e.code === 'SSC_ERROR_NOT_FOUND' && /Nonsense/.test(e.message));
  assert.throws(() => model.createFitter({ shape_count: 1000000 }), (e) => e.code === 'SSC_ERROR_INVALID_ARGUMENT');
  assert.throws(() => model.createFitter({ no_such_option: 1 }), RangeError);
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'sscape-js-'));
  const corrupt = path.join(dir, 'corrupt.sscape');
  fs.writeFileSync(corrupt, Buffer.from('SSCAPE not really a model'));
  assert.throws(() => sscape.Model.load(corrupt), (e) => e instanceof sscape.SscapeError);
  assert.throws(() => sscape.Model.load(path.join(dir, 'missing.sscape')), (e) => e.code === 'SSC_ERROR_IO');
  fs.rmSync(dir, { recursive: true });
  body.close();
  body.close();  // idempotent
  assert.throws(() => body.vertices, /after close/);
  fitter.close();
  model.close();
});

test('levels of detail: listed, posed, written one or all', () => {
  const model = sscape.Model.loadDefault();
  const levels = model.levels;
  assert.deepStrictEqual(levels.map((l) => l.name), ['full', 'simplified', 'female1605', 'proxy741']);
  assert.strictEqual(model.level('proxy741').vertexCount, 741);
  const tris = model.levelTriangles('proxy741');
  assert.ok(tris.length === 3 * levels[3].triangleCount && Math.max(...tris) < 741);
  const body = model.createBody();
  const far = body.levelVertices(3);
  assert.ok(far.length === 741 * 3 && far.every(Number.isFinite));
  assert.deepStrictEqual(body.levelVertices('full'), body.vertices);
  const n = body.levelNormals('simplified');
  assert.ok(Math.abs(Math.hypot(n[0], n[1], n[2]) - 1) < 1e-4);
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'sscape-levels-'));
  body.write(path.join(dir, 'far.obj'), undefined, { level: 'proxy741' });
  assert.strictEqual((fs.readFileSync(path.join(dir, 'far.obj'), 'utf8').match(/^v /gm) || []).length, 741);
  body.write(path.join(dir, 'all.glb'), undefined, { level: 'all' });
  assert.ok(fs.statSync(path.join(dir, 'all.glb')).size > 1e6);
  assert.throws(() => body.write(path.join(dir, 'all.obj'), undefined, { level: 'all' }), (e) => e.code === 'SSC_ERROR_INVALID_ARGUMENT');
  assert.throws(() => model.level('proxy9'), RangeError);
  // Morph targets for engines, and many bodies of a level at once.
  body.write(path.join(dir, 'morphs.glb'), undefined, { level: 'all', morphs: 3 });
  const glb = fs.readFileSync(path.join(dir, 'morphs.glb'));
  const doc = JSON.parse(glb.subarray(20, 20 + glb.readUInt32LE(12)).toString());
  assert.deepStrictEqual(doc.meshes[0].extras.targetNames, ['component_1', 'component_2', 'component_3']);
  body.write(path.join(dir, 'sliders.glb'), undefined, { morphs: 'sliders' });
  assert.throws(() => body.write(path.join(dir, 'x.obj'), undefined, { morphs: 2 }), (e) => e.code === 'SSC_ERROR_INVALID_ARGUMENT');
  const batch = model.synthesize({ count: 2, level: 'proxy741' });
  assert.strictEqual(batch.vertices.length, 2 * 741 * 3);
  fs.rmSync(dir, { recursive: true });
  body.close();
  model.close();
});

test('segment shape spaces: listed, set on a body, moving their part only', () => {
  const model = sscape.Model.loadDefault();
  const segments = model.segments;
  assert.deepStrictEqual(segments.map((s) => s.name), ['head', 'arm_l', 'arm_r', 'torso', 'leg_l', 'leg_r']);
  const arm = model.segmentIndex('arm_l');
  assert.ok(segments[arm].shapeCount === 10 && segments[arm].vertexCount > 1000);
  const body = model.createBody();
  const before = body.vertices;
  body.setSegmentShape(arm, [2.0]);
  const shape = body.segmentShape(arm, segments[arm].shapeCount);
  assert.ok(shape[0] === 2 && shape.slice(1).every((c) => c === 0));
  const after = body.vertices;
  let left = 0, right = 0;
  for (let v = 0; v < after.length; v += 3) {
    const d = Math.hypot(after[v] - before[v], after[v + 1] - before[v + 1], after[v + 2] - before[v + 2]);
    if (before[v] > 0.3) left = Math.max(left, d);  // +X: the body's left
    if (before[v] < -0.3) right = Math.max(right, d);
  }
  assert.ok(left > 0.005 && right === 0, `the left arm moves ${left} m, the right ${right} m`);
  assert.throws(() => model.segmentIndex('tail'), (e) => e.code === 'SSC_ERROR_NOT_FOUND');
  assert.throws(() => body.setSegmentShape(arm, new Float32Array(11)), (e) => e.code === 'SSC_ERROR_INVALID_ARGUMENT');
  assert.throws(() => body.setSegmentShape(6, [1]), (e) => e.code === 'SSC_ERROR_INVALID_ARGUMENT');
  assert.throws(() => body.setSegmentShape(-1, [1]), RangeError);
  body.close();
  model.close();
});

test('a body outlives its closed model; a fit recovers a shape from its landmarks', () => {
  const model = sscape.Model.loadDefault();
  const body = model.createBody();
  model.close();  // the body holds its own reference in C
  body.shape = [1.5, -1];
  const measured = body.measure();
  assert.ok(measured.stature > 1.4 && measured.stature < 2.1, `stature ${measured.stature}`);
  assert.strictEqual(Object.keys(measured).length, sscape.measurements().length);
  const again = sscape.Model.loadDefault();
  const fitter = again.createFitter();
  fitter.addLandmarks(again.landmarkNames, body.landmarks);
  const report = fitter.solve({ onProgress: () => false });
  assert.ok(report.iterations > 0 && report.landmark_rms < 0.01, JSON.stringify(report));
  let calls = 0;
  assert.throws(() => fitter.solve({ onProgress: () => ++calls >= 2 }), (e) => e.code === 'SSC_ERROR_CANCELLED');
  assert.strictEqual(calls, 2);
  body.close();
  fitter.close();
  again.close();
});

test('the batch equals bodies made one by one', () => {
  const model = sscape.Model.loadDefault();
  const shapes = model.sampleShapes(2, { seed: 3 });
  const { vertices, normals } = model.synthesize({ shapes, normals: true });
  const body = model.createBody();
  const V = model.vertexCount;
  for (let b = 0; b < 2; ++b) {
    body.shape = shapes.subarray(b * model.shapeCount, (b + 1) * model.shapeCount);
    assert.deepStrictEqual(body.vertices, vertices.subarray(b * V * 3, (b + 1) * V * 3));
    assert.strictEqual(normals.length, vertices.length);
  }
  body.close();
  model.close();
});
