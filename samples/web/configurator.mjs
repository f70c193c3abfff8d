// The configurator page (index.html): every control changes the one body, the body is drawn again
// and measured. The whole library runs here: nothing is sent anywhere.
import * as THREE from 'three';
import { OrbitControls } from './OrbitControls.js';
import { loadRuntime } from './sscape.mjs';

const started = performance.now();
const status = document.getElementById('status');
// What the browser test and the benchmark page read (tests/web).
const app = { ready: false, redraws: 0, timings: {} };
window.sscapeApp = app;

const sscape = await loadRuntime();
const model = await sscape.loadModel('sscape-default.sscape');
app.timings.modelMs = performance.now() - started;
const body = model.createBody();
Object.assign(app, { sscape, model, body });

const state = { level: 0, pose: 'a_pose', hands: 0 };
const componentCount = Math.min(5, model.shapeCount);

// --- the view -------------------------------------------------------------------------------------
const view = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
view.prepend(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xe9edf2);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8070, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(1.5, 3, 2.5);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(30, 1, 0.05, 50);
camera.position.set(0.9, 1.1, 4.2);
const controls = new OrbitControls(camera, renderer.domElement);
controls.target.set(0, 0.9, 0);
controls.update();
const floor = new THREE.Mesh(new THREE.CircleGeometry(0.8, 48), new THREE.MeshStandardMaterial({ color: 0xc9cfd6, roughness: 1 }));
floor.rotation.x = -Math.PI / 2;
scene.add(floor);
const geometry = new THREE.BufferGeometry();
const mesh = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({ color: 0xd9a88f, roughness: 0.6, metalness: 0 }));
scene.add(mesh);

function resize() {
  const { clientWidth: w, clientHeight: h } = view;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
new ResizeObserver(() => { resize(); renderer.render(scene, camera); }).observe(view);
controls.addEventListener('change', () => renderer.render(scene, camera));

let drawnLevel = -1;
function redraw() {
  if (drawnLevel !== state.level) {
    geometry.setIndex(new THREE.BufferAttribute(model.levelTriangles(state.level), 1));
    drawnLevel = state.level;
  }
  geometry.setAttribute('position', new THREE.BufferAttribute(body.levelVertices(state.level), 3));
  geometry.setAttribute('normal', new THREE.BufferAttribute(body.levelNormals(state.level), 3));
  geometry.computeBoundingSphere();
  // Feet on the floor whatever the pose.
  geometry.computeBoundingBox();
  mesh.position.y = -geometry.boundingBox.min.y;
  renderer.render(scene, camera);
  app.redraws += 1;
}

// --- the controls ---------------------------------------------------------------------------------
function rangeControl(parent, { id, label, min, max, step, value, format, onInput, onChange }) {
  const row = document.createElement('label');
  row.textContent = label;
  const input = Object.assign(document.createElement('input'), { type: 'range', id, min, max, step, value });
  const output = document.createElement('output');
  output.textContent = format(Number(value));
  row.append(input, output);
  parent.append(row);
  if (onInput) input.addEventListener('input', () => { output.textContent = format(Number(input.value)); onInput(Number(input.value)); });
  if (onChange) input.addEventListener('change', () => { output.textContent = format(Number(input.value)); onChange(Number(input.value)); });
  return { input, set(v) { input.value = v; output.textContent = format(v); } };
}

const units = { m: (v) => `${(v * 100).toFixed(1)} cm`, kg: (v) => `${v.toFixed(1)} kg`, years: (v) => `${v.toFixed(0)} y`, '': (v) => v.toFixed(2) };
const sliderControls = {};
for (const s of model.sliders) {
  sliderControls[s.name] = rangeControl(document.getElementById('sliders'), {
    id: `slider-${s.name}`, label: s.name, min: s.minimum, max: s.maximum, step: (s.maximum - s.minimum) / 200, value: s.mean,
    format: units[s.unit] ?? units[''],
    onInput: (v) => { body.setSlider(s.name, v); changed({ keep: s.name }); },
  });
}

// Made to measure: stature and the girths, in centimetres; the shape is solved on release.
const measured = ['stature', 'chest_girth', 'waist_girth', 'hip_girth'];
const mean = body.measure();
const measureControls = {};
for (const name of measured) {
  const centre = mean[name];
  measureControls[name] = rangeControl(document.getElementById('measure-inputs'), {
    id: `measure-${name}`, label: name.replace('_girth', ' girth'), min: centre * 0.75, max: centre * 1.3, step: 0.0025, value: centre,
    format: units.m,
    onChange: () => {
      const targets = Object.fromEntries(measured.map((n) => [n, Number(measureControls[n].input.value)]));
      try {
        const result = body.makeToMeasure(targets);
        document.getElementById('measure-result').textContent = result.converged ? 'reached' : 'as close as the model allows';
      } catch (e) {
        document.getElementById('measure-result').textContent = e.message;
      }
      changed({ keep: 'measure' });
    },
  });
}

const componentControls = [];
for (let i = 0; i < componentCount; ++i) {
  componentControls.push(rangeControl(document.getElementById('components'), {
    id: `component-${i + 1}`, label: `component ${i + 1}`, min: -3, max: 3, step: 0.05, value: 0, format: (v) => `${v.toFixed(2)} SD`,
    onInput: (v) => {
      const shape = body.shape;
      shape[i] = v;
      body.shape = shape;
      changed({ keep: `component-${i}` });
    },
  }));
}

const poseSelect = document.getElementById('pose');
for (const p of sscape.namedPoses()) {
  poseSelect.append(Object.assign(document.createElement('option'), { value: p.name, textContent: p.name.replaceAll('_', ' '), title: p.description }));
}
poseSelect.value = state.pose;
function applyPose() {
  body.setNamedPose(state.pose, { handsClosed: [state.hands, state.hands] });
}
poseSelect.addEventListener('change', () => { state.pose = poseSelect.value; applyPose(); redraw(); });
const handsOutput = document.getElementById('hands-value');
document.getElementById('hands').addEventListener('input', (e) => {
  state.hands = Number(e.target.value);
  handsOutput.textContent = state.hands.toFixed(2);
  applyPose();
  redraw();
});

const levelSelect = document.getElementById('level');
for (const l of model.levels) {
  levelSelect.append(Object.assign(document.createElement('option'), { value: l.index, textContent: `${l.name} (${l.vertexCount.toLocaleString('en')} vertices)` }));
}
levelSelect.addEventListener('change', () => { state.level = Number(levelSelect.value); redraw(); });

document.getElementById('download').addEventListener('click', () => {
  const glb = body.toGLB({ level: state.level });
  app.lastDownloadBytes = glb.length;
  const url = URL.createObjectURL(new Blob([glb], { type: 'model/gltf-binary' }));
  const link = Object.assign(document.createElement('a'), { href: url, download: 'sscape-body.glb' });
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
});

// --- the measurements -----------------------------------------------------------------------------
const table = document.getElementById('measurements');
const formatByUnit = { metre: (v) => `${(v * 100).toFixed(1)} cm`, square_metre: (v) => `${v.toFixed(2)} m²`, cubic_metre: (v) => `${(v * 1000).toFixed(1)} L`,
  kilogram: (v) => `${v.toFixed(1)} kg` };
const cells = {};
for (const m of sscape.measurements()) {
  const row = table.insertRow();
  row.dataset.name = m.name;
  const name = row.insertCell();
  name.textContent = m.name.replaceAll('_', ' ');
  name.title = m.definition;
  cells[m.name] = { cell: row.insertCell(), format: formatByUnit[m.unit] };
}
function remeasure() {
  app.measurements = body.measure();
  for (const [name, value] of Object.entries(app.measurements)) cells[name].cell.textContent = cells[name].format(value);
}

// After a shape change: the other controls show the body's values, the body is drawn and measured.
function changed({ keep }) {
  const sliders = body.sliders;
  for (const [name, control] of Object.entries(sliderControls)) if (name !== keep) control.set(sliders[name]);
  const shape = body.shape;
  componentControls.forEach((control, i) => { if (keep !== `component-${i}`) control.set(shape[i]); });
  redraw();
  remeasure();
  if (keep !== 'measure') for (const name of measured) measureControls[name].set(app.measurements[name]);
}

resize();
applyPose();
redraw();
remeasure();
app.timings.readyMs = performance.now() - started;
app.timings.sinceNavigationMs = performance.now();  // the page's time origin: navigation start
app.ready = true;
status.textContent = `${model.vertexCount.toLocaleString('en')} vertices, ${model.jointCount} joints, model verified; ready in ${app.timings.readyMs.toFixed(0)} ms (sscape ${sscape.version().text}, WebAssembly)`;
