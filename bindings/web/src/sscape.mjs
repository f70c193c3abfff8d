// sscape in the browser: the C library compiled to WebAssembly (bindings/web/CMakeLists.txt), called
// through the same C API as the Node package calls libsscape.so. No server: the model file and the
// module are fetched once, everything else runs on the user's machine.
//
//   import { loadRuntime } from './sscape.mjs';
//   const sscape = await loadRuntime();                        // sscape_runtime.wasm beside this file
//   const model = await sscape.loadModel('sscape-default.sscape');
//   const body = model.createBody();
//   body.setSlider('stature', 1.85);
//   body.setNamedPose('sitting');
//   const vertices = body.vertices;                            // Float32Array, metres, Y up
//   const glb = body.toGLB({ level: 'all' });                  // Uint8Array
//
// Memory: the module's heap holds the C objects; close() releases a model or body at once, and the
// garbage collector does it for those left open. Typed arrays returned are copies the caller owns.
import createSscapeRuntime from './sscape_runtime.mjs';

/** The error of a failed call: `status` (the ssc_status value), `code` (its name), the library's message. */
export class SscapeError extends Error {
  constructor(status, code, message, functionName) {
    super(`${code}: ${message}`);
    this.name = 'SscapeError';
    this.status = status;
    this.code = code;
    this.functionName = functionName;
  }
}

const SSC_OK = 0;
const SSC_LEVEL_ALL = 0xFFFFFFFF;
const UNITS = ['metre', 'square_metre', 'cubic_metre', 'kilogram'];
const FILE_FORMATS = { obj: 1, ply: 2, glb: 3 };
const MORPHS = { none: 0, components: 1, sliders: 2 };
// Struct sizes and field offsets on wasm32 (pointers and size_t 4 bytes); layout_check.c asserts them
// when the module is built.
const SLIDER_INFO = { size: 28, name: 4, unit: 8, description: 12, mean: 16, minimum: 20, maximum: 24 };
const LEVEL_INFO = { size: 20, name: 4, vertexCount: 8, triangleCount: 12, uvCount: 16 };
const EXPORT_DEF = { size: 20, format: 4, level: 8, morphs: 12, morphCount: 16 };
const MADE_TO_MEASURE_DEF = { size: 20, sex: 4, age: 8 };
const FITTER_DEF = { size: 48, shapeCount: 4, maxIterations: 12, seed: 36, jointLimits: 40, fitSegments: 44 };
const FIT_REPORT = { size: 60, iterations: 4, converged: 8, landmarkRms: 24, pointMean: 28, seconds: 36, restarts: 40,
  unexplainedFraction: 44, implausible: 48, problem: 52 };
const BATCH_DESC = { size: 48, bodyCount: 4, shapes: 8, shapeCount: 12, poses: 20, translations: 24, vertices: 28,
  verticesCapacity: 32, normals: 36, normalsCapacity: 40, level: 44 };

function floats(values, count, what) {
  const array = values instanceof Float32Array ? values : Float32Array.from(values);
  if (count !== undefined && array.length !== count) {
    throw new RangeError(`${what}: ${array.length} values where ${count} are needed`);
  }
  return array;
}

/**
 * Loads the WebAssembly runtime.
 * @param options.wasm  the module: a URL (default: sscape_runtime.wasm beside this file) or its bytes
 *                      (ArrayBuffer or Uint8Array: Node, or a page that fetched it itself).
 */
export async function loadRuntime({ wasm } = {}) {
  const settings = {};
  if (wasm instanceof ArrayBuffer || ArrayBuffer.isView(wasm)) {
    settings.wasmBinary = wasm instanceof ArrayBuffer ? new Uint8Array(wasm) : wasm;
  } else {
    const url = wasm ? new URL(String(wasm), globalThis.location?.href ?? import.meta.url) : new URL('sscape_runtime.wasm', import.meta.url);
    settings.locateFile = () => url.href;
  }
  return new Runtime(await createSscapeRuntime(settings));
}

/** One loaded WebAssembly runtime: the C API, its heap, and the models loaded into it. */
export class Runtime {
  constructor(module) {
    this._m = module;
    this._files = 0;
    // Handles left open are released when their owners are collected.
    this._finalizer = new FinalizationRegistry(({ destroy, handle }) => module[`_${destroy}`](handle));
  }

  /** The library's version: { major, minor, patch, number, text }. */
  version() {
    const number = this._m._ssc_version();
    const major = Math.floor(number / 10000), minor = Math.floor(number / 100) % 100, patch = number % 100;
    return { major, minor, patch, number, text: `${major}.${minor}.${patch}` };
  }

  /** The measurements the library knows, [{ name, unit, definition }], in the order of Body.measureAll(). */
  measurements() {
    if (!this._measurements) {
      this._measurements = [];
      const count = this._m._ssc_measurement_count();
      this._scratch(12, (p) => {
        for (let i = 0; i < count; ++i) {
          this._check(this._m._ssc_measurement_get_info(i, p, p + 4, p + 8), 'ssc_measurement_get_info');
          this._measurements.push({ name: this._string(this._u32(p)), unit: UNITS[this._u32(p + 4)], definition: this._string(this._u32(p + 8)) });
        }
      });
    }
    return this._measurements.map((m) => ({ ...m }));
  }

  /** The named poses, [{ name, description }] (Body.setNamedPose takes the names). */
  namedPoses() {
    const poses = [];
    const count = this._m._ssc_named_pose_count();
    this._scratch(8, (p) => {
      for (let i = 0; i < count; ++i) {
        this._check(this._m._ssc_named_pose_get_info(i, p, p + 4), 'ssc_named_pose_get_info');
        poses.push({ name: this._string(this._u32(p)), description: this._string(this._u32(p + 4)) });
      }
    });
    return poses;
  }

  /**
   * A model from a URL (fetched) or a .sscape file's bytes. The file is verified completely (container,
   * checksum, schema, every index and size) before the model exists: a damaged file throws
   * SscapeError SSC_ERROR_MODEL_CORRUPT.
   */
  async loadModel(source) {
    if (source instanceof ArrayBuffer || ArrayBuffer.isView(source)) return this.modelFromBytes(source);
    const response = await fetch(source);
    if (!response.ok) throw new Error(`sscape: fetching ${source} failed: HTTP ${response.status}`);
    return this.modelFromBytes(new Uint8Array(await response.arrayBuffer()));
  }

  /** A model from a .sscape file's bytes (ArrayBuffer or typed array; copied). */
  modelFromBytes(bytes) {
    const data = bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes.buffer ?? bytes, bytes.byteOffset ?? 0, bytes.byteLength);
    const handle = this._scratch(4, (out) => this._withBytes(data, (p) => {
      this._check(this._m._ssc_model_load_memory(0, p, data.length, out), 'ssc_model_load_memory');
      return this._u32(out);
    }));
    return new Model(this, handle);
  }

  // --- the heap --------------------------------------------------------------------------------------
  _check(status, functionName) {
    if (status === SSC_OK) return;
    const code = this._string(this._m._ssc_status_name(status));
    throw new SscapeError(status, code, this._string(this._m._ssc_last_error()), functionName);
  }
  _string(pointer) { return pointer ? this._m.UTF8ToString(pointer) : ''; }
  _u32(pointer) { return this._m.HEAPU32[pointer >>> 2]; }
  _f32(pointer) { return this._m.HEAPF32[pointer >>> 2]; }
  _setU32(pointer, value) { this._m.HEAPU32[pointer >>> 2] = value; }
  _setF32(pointer, value) { this._m.HEAPF32[pointer >>> 2] = value; }
  // fn(pointer) with `bytes` zeroed bytes of the heap, freed afterwards whatever happens.
  _scratch(bytes, fn) {
    const p = this._m._malloc(Math.max(bytes, 4));
    if (!p) throw new SscapeError(-2, 'SSC_ERROR_OUT_OF_MEMORY', 'the WebAssembly heap cannot grow', 'malloc');
    this._m.HEAPU8.fill(0, p, p + bytes);
    try {
      return fn(p);
    } finally {
      this._m._free(p);
    }
  }
  // fn(pointer) with a copy of a typed array on the heap (null: fn(0)).
  _withBytes(array, fn) {
    if (array === null || array === undefined) return fn(0);
    const bytes = new Uint8Array(array.buffer, array.byteOffset, array.byteLength);
    return this._scratch(bytes.length, (p) => {
      this._m.HEAPU8.set(bytes, p);
      return fn(p);
    });
  }
  _withString(text, fn) {
    const size = this._m.lengthBytesUTF8(text) + 1;
    return this._scratch(size, (p) => {
      this._m.stringToUTF8(text, p, size);
      return fn(p);
    });
  }
  // A Float32Array of `count` floats filled by fn(pointer).
  _floatsOut(count, fn) {
    return this._scratch(count * 4, (p) => {
      fn(p);
      return this._m.HEAPF32.slice(p >>> 2, (p >>> 2) + count);
    });
  }
  _u32sOut(count, fn) {
    return this._scratch(count * 4, (p) => {
      fn(p);
      return this._m.HEAPU32.slice(p >>> 2, (p >>> 2) + count);
    });
  }
  // A file the library writes into the in-memory file system, returned as bytes and removed.
  _writtenFile(extension, fn) {
    const path = `/sscape-out-${++this._files}.${extension}`;
    try {
      this._withString(path, fn);
      return this._m.FS.readFile(path);
    } finally {
      try { this._m.FS.unlink(path); } catch { /* not written */ }
    }
  }
}

class Handle {
  constructor(runtime, handle, destroy) {
    this._rt = runtime;
    this._handle = handle;
    this._destroy = destroy;
    runtime._finalizer.register(this, { destroy, handle }, this);
  }

  /** The C handle (a heap address); throws once closed. */
  get handle() {
    if (this._handle === null) throw new Error(`sscape: ${this.constructor.name} used after close()`);
    return this._handle;
  }

  /** Releases the C object now (idempotent). */
  close() {
    if (this._handle === null) return;
    this._rt._finalizer.unregister(this);
    this._rt._m[`_${this._destroy}`](this._handle);
    this._handle = null;
  }
}

/** A loaded model: immutable, shared by any number of bodies. */
export class Model extends Handle {
  constructor(runtime, handle) {
    super(runtime, handle, 'ssc_model_release');
    const m = runtime._m;
    this.vertexCount = m._ssc_model_vertex_count(handle);
    this.triangleCount = m._ssc_model_triangle_count(handle);
    this.jointCount = m._ssc_model_joint_count(handle);
    this.shapeCount = m._ssc_model_shape_count(handle);
  }

  /** The triangles, 3 vertex indices each. */
  get triangles() {
    const rt = this._rt;
    return rt._u32sOut(this.triangleCount * 3, (p) => rt._check(rt._m._ssc_model_get_triangles(this.handle, p, this.triangleCount), 'ssc_model_get_triangles'));
  }

  /** Joint names, in joint order. */
  get jointNames() { return this._names('ssc_model_get_joint_name', this.jointCount); }

  // The names fn(model, index, &name) gives for index < count.
  _names(fn, count) {
    const rt = this._rt;
    const names = [];
    rt._scratch(4, (p) => {
      for (let i = 0; i < count; ++i) {
        rt._check(rt._m[`_${fn}`](this.handle, i, p), fn);
        names.push(rt._string(rt._u32(p)));
      }
    });
    return names;
  }

  /** Landmark names (the CAESAR names for the default model), in the order of Body.landmarks. */
  get landmarkNames() { return this._names('ssc_model_get_landmark_name', this._rt._m._ssc_model_landmark_count(this.handle)); }

  /** Each shape component's standard deviation (the body's shape is in these units). */
  get shapeStddevs() {
    const rt = this._rt;
    return rt._floatsOut(this.shapeCount, (p) => rt._check(rt._m._ssc_model_get_shape_stddevs(this.handle, p, this.shapeCount), 'ssc_model_get_shape_stddevs'));
  }

  /** The levels of detail, [{ index, name, vertexCount, triangleCount, uvCount }]: 0 the full mesh ("full"), then coarser. */
  get levels() {
    if (!this._levels) {
      const rt = this._rt;
      this._levels = [];
      const count = rt._m._ssc_model_level_count(this.handle);
      rt._scratch(LEVEL_INFO.size, (p) => {
        for (let i = 0; i < count; ++i) {
          rt._setU32(p, LEVEL_INFO.size);
          rt._check(rt._m._ssc_model_get_level_info(this.handle, i, p), 'ssc_model_get_level_info');
          this._levels.push({ index: i, name: rt._string(rt._u32(p + LEVEL_INFO.name)), vertexCount: rt._u32(p + LEVEL_INFO.vertexCount),
            triangleCount: rt._u32(p + LEVEL_INFO.triangleCount), uvCount: rt._u32(p + LEVEL_INFO.uvCount) });
        }
      });
    }
    return this._levels.map((l) => ({ ...l }));
  }

  /** One level by index or name; throws RangeError for one the model lacks. */
  level(level) {
    const levels = this.levels;
    const found = typeof level === 'string' ? levels.find((l) => l.name === level) : levels[level];
    if (!found) throw new RangeError(`sscape: no level of detail ${JSON.stringify(level)} (the model has ${levels.map((l) => l.name).join(', ')})`);
    return found;
  }

  /** A level's triangles, 3 vertex indices each. */
  levelTriangles(level) {
    const rt = this._rt;
    const l = this.level(level);
    return rt._u32sOut(l.triangleCount * 3, (p) => rt._check(rt._m._ssc_model_get_level_triangles(this.handle, l.index, p, l.triangleCount), 'ssc_model_get_level_triangles'));
  }

  /** The semantic sliders, [{ index, name, unit, description, mean, minimum, maximum }] (the population's range). */
  get sliders() {
    if (!this._sliders) {
      const rt = this._rt;
      this._sliders = [];
      const count = rt._m._ssc_model_slider_count(this.handle);
      rt._scratch(SLIDER_INFO.size, (p) => {
        for (let i = 0; i < count; ++i) {
          rt._setU32(p, SLIDER_INFO.size);
          rt._check(rt._m._ssc_model_get_slider_info(this.handle, i, p), 'ssc_model_get_slider_info');
          this._sliders.push({ index: i, name: rt._string(rt._u32(p + SLIDER_INFO.name)), unit: rt._string(rt._u32(p + SLIDER_INFO.unit)),
            description: rt._string(rt._u32(p + SLIDER_INFO.description)), mean: rt._f32(p + SLIDER_INFO.mean),
            minimum: rt._f32(p + SLIDER_INFO.minimum), maximum: rt._f32(p + SLIDER_INFO.maximum) });
        }
      });
    }
    return this._sliders.map((s) => ({ ...s }));
  }

  /** A named pose's joint rotations for this model (jointCount quaternions x y z w); NOT_FOUND for an unknown name.
   *  handsClosed: [left, right] in 0 (open) .. 1 (a loose fist). */
  namedPose(name, { handsClosed = null } = {}) {
    const rt = this._rt;
    const count = this.jointCount * 4;
    return rt._withString(String(name), (n) => rt._floatsOut(count, (p) => {
      rt._check(rt._m._ssc_model_get_named_pose(this.handle, n, p, this.jointCount), 'ssc_model_get_named_pose');
      if (handsClosed) rt._check(rt._m._ssc_model_close_hands(this.handle, handsClosed[0], handsClosed[1], p, this.jointCount), 'ssc_model_close_hands');
    }));
  }

  /**
   * Many bodies in one call: count * vertexCount * 3 floats (and normals when asked for), equal to
   * each body's vertices. shapes: count * n coefficients (n <= shapeCount) or null (the mean);
   * poses: count * jointCount quaternions or null; translations: count * 3 or null; level: a level of detail.
   */
  synthesize({ shapes = null, count, poses = null, translations = null, normals = false, level = 0 } = {}) {
    const rt = this._rt;
    const l = this.level(level);
    if (!Number.isInteger(count) || count < 1) throw new RangeError('sscape: synthesize needs count >= 1');
    const shapeArray = shapes === null ? null : floats(shapes);
    if (shapeArray && shapeArray.length % count !== 0) throw new RangeError(`sscape: ${shapeArray.length} shape values are not ${count} bodies' worth`);
    const poseArray = poses === null ? null : floats(poses, count * this.jointCount * 4, 'poses');
    const translationArray = translations === null ? null : floats(translations, count * 3, 'translations');
    const size = count * l.vertexCount * 3;
    const result = {};
    rt._withBytes(shapeArray, (ps) => rt._withBytes(poseArray, (pp) => rt._withBytes(translationArray, (pt) => rt._scratch(size * 4 * (normals ? 2 : 1), (out) => {
      rt._scratch(BATCH_DESC.size, (d) => {
        rt._m._ssc_batch_desc_init(d, BATCH_DESC.size);
        rt._setU32(d + BATCH_DESC.bodyCount, count);
        rt._setU32(d + BATCH_DESC.shapes, ps);
        rt._setU32(d + BATCH_DESC.shapeCount, shapeArray ? shapeArray.length / count : 0);
        rt._setU32(d + BATCH_DESC.poses, pp);
        rt._setU32(d + BATCH_DESC.translations, pt);
        rt._setU32(d + BATCH_DESC.vertices, out);
        rt._setU32(d + BATCH_DESC.verticesCapacity, count * l.vertexCount);
        if (normals) {
          rt._setU32(d + BATCH_DESC.normals, out + size * 4);
          rt._setU32(d + BATCH_DESC.normalsCapacity, count * l.vertexCount);
        }
        rt._setU32(d + BATCH_DESC.level, l.index);
        rt._check(rt._m._ssc_model_synthesize_batch(this.handle, d), 'ssc_model_synthesize_batch');
      });
      result.vertices = rt._m.HEAPF32.slice(out >>> 2, (out >>> 2) + size);
      if (normals) result.normals = rt._m.HEAPF32.slice((out >>> 2) + size, (out >>> 2) + 2 * size);
    }))));
    return result;
  }

  /**
   * A fitter: shape and pose from landmarks and scan points (options: shapeCount, maxIterations, seed,
   * jointLimits, fitSegments as ssc_fitter_def; the rest of the defaults as the library's).
   */
  createFitter({ shapeCount, maxIterations, seed, jointLimits, fitSegments } = {}) {
    const rt = this._rt;
    const handle = rt._scratch(FITTER_DEF.size + 4, (d) => {
      rt._m._ssc_fitter_def_init(d, FITTER_DEF.size);
      if (shapeCount !== undefined) rt._setU32(d + FITTER_DEF.shapeCount, shapeCount);
      if (maxIterations !== undefined) rt._setU32(d + FITTER_DEF.maxIterations, maxIterations);
      if (seed !== undefined) rt._setU32(d + FITTER_DEF.seed, seed);
      if (jointLimits !== undefined) rt._setU32(d + FITTER_DEF.jointLimits, jointLimits ? 1 : 0);
      if (fitSegments !== undefined) rt._setU32(d + FITTER_DEF.fitSegments, fitSegments ? 1 : 0);
      const out = d + FITTER_DEF.size;
      rt._check(rt._m._ssc_fitter_create(this.handle, d, out), 'ssc_fitter_create');
      return rt._u32(out);
    });
    return new Fitter(this, handle);
  }

  /** A body of this model: the mean shape in the rest pose. */
  createBody() {
    const rt = this._rt;
    const handle = rt._scratch(4, (out) => {
      rt._check(rt._m._ssc_body_create(this.handle, 0, out), 'ssc_body_create');
      return rt._u32(out);
    });
    return new Body(this, handle);
  }
}

/** One body: shape and pose in, vertices, measurements and files out. */
export class Body extends Handle {
  constructor(model, handle) {
    super(model._rt, handle, 'ssc_body_destroy');
    this.model = model;  // keeps the model object alive (the C body holds its own reference)
  }

  /** The shape coefficients (standard deviations). Setting n of them sets the rest to 0. */
  get shape() {
    const rt = this._rt, n = this.model.shapeCount;
    return rt._floatsOut(n, (p) => rt._check(rt._m._ssc_body_get_shape(this.handle, p, n), 'ssc_body_get_shape'));
  }
  set shape(values) {
    const rt = this._rt, array = floats(values);
    rt._withBytes(array, (p) => rt._check(rt._m._ssc_body_set_shape(this.handle, p, array.length), 'ssc_body_set_shape'));
  }

  /** jointCount quaternions (x y z w; null: the rest pose) and a translation (metres; null: none). */
  setPose(rotations = null, translation = null) {
    const rt = this._rt, joints = this.model.jointCount;
    const r = rotations === null ? null : floats(rotations, joints * 4, 'rotations');
    const t = translation === null ? null : floats(translation, 3, 'translation');
    rt._withBytes(r, (pr) => rt._withBytes(t, (pt) => rt._check(rt._m._ssc_body_set_pose(this.handle, pr, r ? joints : 0, pt), 'ssc_body_set_pose')));
  }

  /** A named pose (Runtime.namedPoses()), hands optionally closed ([left, right] in 0..1). */
  setNamedPose(name, { handsClosed = null, translation = null } = {}) {
    this.setPose(this.model.namedPose(name, { handsClosed }), translation);
  }

  /** The slider values read from the body's shape, by name. */
  get sliders() {
    const rt = this._rt, list = this.model.sliders;
    const values = rt._floatsOut(list.length, (p) => rt._check(rt._m._ssc_body_get_sliders(this.handle, p, list.length), 'ssc_body_get_sliders'));
    return Object.fromEntries(list.map((s, i) => [s.name, values[i]]));
  }

  /** Moves one slider (name or index) to a value in its unit, keeping the rest of the shape. */
  setSlider(slider, value) {
    const rt = this._rt, list = this.model.sliders;
    const s = typeof slider === 'string' ? list.find((x) => x.name === slider) : list[slider];
    if (!s) throw new RangeError(`sscape: no slider ${JSON.stringify(slider)} (the model has ${list.map((x) => x.name).join(', ')})`);
    rt._check(rt._m._ssc_body_set_slider(this.handle, s.index, value), 'ssc_body_set_slider');
  }

  /**
   * Sets the shape to reproduce measurements: { stature: 1.80, waist_girth: 0.86, ... } (Runtime.measurements()
   * names, SI units), with sex (0 female, 1 male) and age when known. Returns { converged, achieved }:
   * achieved holds every measurement of the result by name.
   */
  makeToMeasure(targets, { sex = NaN, age = NaN } = {}) {
    const rt = this._rt;
    const names = Object.keys(targets);
    const all = rt.measurements();
    const ids = Uint32Array.from(names.map((name) => {
      const i = all.findIndex((m) => m.name === name);
      if (i < 0) throw new RangeError(`sscape: no measurement ${JSON.stringify(name)}`);
      return i;
    }));
    const values = Float32Array.from(names.map((name) => targets[name]));
    let converged = 0;
    const achieved = rt._withBytes(ids, (pi) => rt._withBytes(values, (pv) => rt._scratch(MADE_TO_MEASURE_DEF.size + 4, (d) => rt._floatsOut(all.length, (pa) => {
      rt._m._ssc_made_to_measure_def_init(d, MADE_TO_MEASURE_DEF.size);
      rt._setF32(d + MADE_TO_MEASURE_DEF.sex, sex);
      rt._setF32(d + MADE_TO_MEASURE_DEF.age, age);
      const pc = d + MADE_TO_MEASURE_DEF.size;
      rt._check(rt._m._ssc_body_make_to_measure(this.handle, pi, pv, ids.length, d, pa, all.length, pc), 'ssc_body_make_to_measure');
      converged = rt._u32(pc);
    }))));
    return { converged: converged !== 0, achieved: Object.fromEntries(all.map((m, i) => [m.name, achieved[i]])) };
  }

  // fn(body, level, out, capacity, stride) of a level (level 0 is the full mesh in the C API).
  _vertexArray(fn, level) {
    const rt = this._rt, l = this.model.level(level);
    return rt._floatsOut(l.vertexCount * 3, (p) => rt._check(rt._m[`_${fn}`](this.handle, l.index, p, l.vertexCount, 12), fn));
  }
  /** The posed vertices (vertexCount * 3 floats, metres). */
  get vertices() { return this._vertexArray('ssc_body_get_level_vertices', 0); }
  /** Unit vertex normals. */
  get normals() { return this._vertexArray('ssc_body_get_level_normals', 0); }
  /** A level of detail's posed vertices (index or name). */
  levelVertices(level) { return this._vertexArray('ssc_body_get_level_vertices', level); }
  levelNormals(level) { return this._vertexArray('ssc_body_get_level_normals', level); }

  /** The posed landmarks (Model.landmarkNames order), 3 floats each. */
  get landmarks() {
    const rt = this._rt, n = rt._m._ssc_model_landmark_count(this.model.handle);
    return rt._floatsOut(n * 3, (p) => rt._check(rt._m._ssc_body_get_landmarks(this.handle, p, n, 12), 'ssc_body_get_landmarks'));
  }

  /** Every measurement, in the order of Runtime.measurements(). */
  measureAll() {
    const rt = this._rt, n = rt._m._ssc_measurement_count();
    return rt._floatsOut(n, (p) => rt._check(rt._m._ssc_body_measure(this.handle, p, n), 'ssc_body_measure'));
  }
  /** Every measurement by name. */
  measure() {
    const values = this.measureAll();
    return Object.fromEntries(this._rt.measurements().map((m, i) => [m.name, values[i]]));
  }

  /** The body as a GLB file's bytes: level (index, name or 'all'), morphs (the first K shape components, or
   *  'sliders') as morph targets, exactly as the library writes files (docs/engines.md). */
  toGLB({ level = 0, morphs = null } = {}) {
    return this._export('glb', level, morphs);
  }
  /** The body as OBJ text (a level of detail: index or name). */
  toOBJ({ level = 0 } = {}) {
    return new TextDecoder().decode(this._export('obj', level, null));
  }

  _export(format, level, morphs) {
    const rt = this._rt;
    const levelIndex = level === 'all' ? SSC_LEVEL_ALL : this.model.level(level).index;
    return rt._writtenFile(format, (path) => rt._scratch(EXPORT_DEF.size, (d) => {
      rt._m._ssc_export_def_init(d, EXPORT_DEF.size);
      rt._setU32(d + EXPORT_DEF.format, FILE_FORMATS[format]);
      rt._setU32(d + EXPORT_DEF.level, levelIndex);
      if (morphs === 'sliders') rt._setU32(d + EXPORT_DEF.morphs, MORPHS.sliders);
      else if (morphs !== null && morphs !== undefined) {
        rt._setU32(d + EXPORT_DEF.morphs, MORPHS.components);
        rt._setU32(d + EXPORT_DEF.morphCount, morphs);
      }
      rt._check(rt._m._ssc_body_export(this.handle, path, d), 'ssc_body_export');
    }));
  }
}

/** Fits shape and pose to landmarks and scan points (one frame). */
export class Fitter extends Handle {
  constructor(model, handle) {
    super(model._rt, handle, 'ssc_fitter_destroy');
    this.model = model;
  }

  /** Landmarks by name (Model.landmarkNames) at positions (3 per name, metres, any frame of reference). */
  addLandmarks(names, positions) {
    const rt = this._rt, m = rt._m;
    const xyz = floats(positions, names.length * 3, 'positions');
    const strings = names.map((n) => {
      const size = m.lengthBytesUTF8(String(n)) + 1, p = m._malloc(size);
      m.stringToUTF8(String(n), p, size);
      return p;
    });
    try {
      rt._withBytes(Uint32Array.from(strings), (pn) => rt._withBytes(xyz, (pp) =>
        rt._check(m._ssc_fitter_add_landmarks_by_name(this.handle, 0, pn, pp, 0, names.length), 'ssc_fitter_add_landmarks_by_name')));
    } finally {
      strings.forEach((p) => m._free(p));
    }
  }

  /** Scan points (3 floats each, metres). */
  addPoints(points) {
    const rt = this._rt, xyz = floats(points);
    if (xyz.length % 3 !== 0) throw new RangeError('sscape: points hold 3 floats each');
    rt._withBytes(xyz, (p) => rt._check(rt._m._ssc_fitter_add_points(this.handle, 0, p, 0, 0, xyz.length / 3, 12), 'ssc_fitter_add_points'));
  }

  /** Solves; returns { iterations, converged, landmarkRms, pointMean, seconds, restarts, unexplainedFraction, implausible, problem }. */
  solve() {
    const rt = this._rt;
    return rt._scratch(FIT_REPORT.size, (r) => {
      rt._setU32(r, FIT_REPORT.size);
      rt._check(rt._m._ssc_fitter_solve(this.handle, 0, 0, r), 'ssc_fitter_solve');
      return { iterations: rt._u32(r + FIT_REPORT.iterations), converged: rt._u32(r + FIT_REPORT.converged) !== 0,
        landmarkRms: rt._f32(r + FIT_REPORT.landmarkRms), pointMean: rt._f32(r + FIT_REPORT.pointMean), seconds: rt._f32(r + FIT_REPORT.seconds),
        restarts: rt._u32(r + FIT_REPORT.restarts), unexplainedFraction: rt._f32(r + FIT_REPORT.unexplainedFraction),
        implausible: rt._u32(r + FIT_REPORT.implausible) !== 0, problem: rt._u32(r + FIT_REPORT.problem) };
    });
  }

  /** The fitted shape (shapeCount coefficients). */
  get shape() {
    const rt = this._rt, n = this.model.shapeCount;
    return rt._floatsOut(n, (p) => rt._check(rt._m._ssc_fitter_get_shape(this.handle, p, n), 'ssc_fitter_get_shape'));
  }

  /** The fitted surface's vertices (full mesh, as placed on the data). */
  get vertices() {
    const rt = this._rt, n = this.model.vertexCount;
    return rt._floatsOut(n * 3, (p) => rt._check(rt._m._ssc_fitter_get_vertices(this.handle, 0, p, n, 12), 'ssc_fitter_get_vertices'));
  }
}
