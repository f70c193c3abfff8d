'use strict';
// sscape for Node.js: the C library through koffi. Model, Body and Fitter own their C handles; a
// handle is released by close() or, failing that, when the object is garbage collected. A body or
// fitter keeps its model alive in C, so they may be closed in any order.
const koffi = require('koffi');
const native = require('./native.js');

const { enums } = native;
const SSC_OK = enums.ssc_status.SSC_OK;

/** The error of a failed call: `status` (the ssc_status value), `code` (its name), and the library's message. */
class SscapeError extends Error {
  constructor(status, code, message, functionName) {
    super(`${code}: ${message}`);  // the library's message names the function already
    this.name = 'SscapeError';
    this.status = status;
    this.code = code;
    this.functionName = functionName;
  }
}

let loaded = null;

function libraryCandidates() {
  if (process.env.SSCAPE_LIBRARY) return [process.env.SSCAPE_LIBRARY];
  const soname = `libsscape.so.${native.VERSION_MAJOR}`;
  return process.platform === 'win32' ? ['sscape.dll'] : process.platform === 'darwin'
    ? [`libsscape.${native.VERSION_MAJOR}.dylib`, 'libsscape.dylib'] : [soname, 'libsscape.so'];
}

/**
 * Loads the C library once: SSCAPE_LIBRARY if set, else the system's (libsscape.so.MAJOR through the
 * dynamic loader's search path). Throws when none loads or its ABI major is not this package's.
 */
function library() {
  if (loaded) return loaded;
  const errors = [];
  for (const name of libraryCandidates()) {
    let lib;
    try {
      lib = koffi.load(name);
    } catch (e) {
      errors.push(`${name}: ${e.message}`);
      continue;
    }
    // The version first: a library of another major may lack or change the other functions.
    const number = lib.func('uint32_t ssc_version()')();
    const major = Math.floor(number / 10000);
    if (major !== native.VERSION_MAJOR) {
      throw new Error(`sscape: ${name} has ABI major ${major} (version ${major}.${Math.floor(number / 100) % 100}.${number % 100}); this package is for major ${native.VERSION_MAJOR}`);
    }
    loaded = { lib, api: native.declare(koffi, lib) };
    return loaded;
  }
  throw new Error(`sscape: cannot load the C library (set SSCAPE_LIBRARY to its path): ${errors.join('; ')}`);
}

function api() {
  return library().api;
}

/** Throws SscapeError unless status is SSC_OK. */
function check(status, functionName) {
  if (status === SSC_OK) return;
  const c = api();
  throw new SscapeError(status, c.ssc_status_name(status), c.ssc_last_error(), functionName);
}

/** Calls the C function `name` with args and throws on a failed status. */
function call(name, ...args) {
  check(api()[name](...args), name);
}

/** The loaded library's version: { major, minor, patch, number, text } (text: "0.1.0"). */
function version() {
  const number = api().ssc_version();
  const major = Math.floor(number / 10000), minor = Math.floor(number / 100) % 100, patch = number % 100;
  return { major, minor, patch, number, text: `${major}.${minor}.${patch}` };
}

function floats(values, count, what) {
  const array = values instanceof Float32Array ? values : Float32Array.from(values);
  if (count !== undefined && array.length !== count) {
    throw new RangeError(`${what}: ${array.length} values where ${count} are needed`);
  }
  return array;
}

// Releases a handle when its owner is collected without close().
const finalizer = new FinalizationRegistry(({ destroy, handle }) => api()[destroy](handle));

class Handle {
  constructor(handle, destroy) {
    this._handle = handle;
    this._destroy = destroy;
    finalizer.register(this, { destroy, handle }, this);
  }

  /** The C handle; throws once closed. */
  get handle() {
    if (this._handle === null) throw new Error(`sscape: ${this.constructor.name} used after close()`);
    return this._handle;
  }

  /** Releases the C object now (idempotent). */
  close() {
    if (this._handle === null) return;
    finalizer.unregister(this);
    api()[this._destroy](this._handle);
    this._handle = null;
  }
}

/** A loaded model: immutable, shared by any number of bodies and fitters. */
class Model extends Handle {
  /** The default model built into the library. */
  static loadDefault() {
    const out = [null];
    call('ssc_model_load_default', null, out);
    return new Model(out[0]);
  }

  /** A .sscape file (checked before use; a corrupt file throws MODEL_CORRUPT). */
  static load(path) {
    const out = [null];
    call('ssc_model_load_file', null, String(path), out);
    return new Model(out[0]);
  }

  /** A .sscape file's bytes (a Buffer or Uint8Array; copied). */
  static fromBuffer(bytes) {
    const out = [null];
    call('ssc_model_load_memory', null, bytes, bytes.length, out);
    return new Model(out[0]);
  }

  constructor(handle) {
    super(handle, 'ssc_model_release');
  }

  get vertexCount() { return api().ssc_model_vertex_count(this.handle); }
  get triangleCount() { return api().ssc_model_triangle_count(this.handle); }
  get jointCount() { return api().ssc_model_joint_count(this.handle); }
  get shapeCount() { return api().ssc_model_shape_count(this.handle); }
  get landmarkCount() { return api().ssc_model_landmark_count(this.handle); }

  /** The triangles, 3 vertex indices each (Uint32Array). */
  get triangles() {
    const out = new Uint32Array(this.triangleCount * 3);
    call('ssc_model_get_triangles', this.handle, out, this.triangleCount);
    return out;
  }

  /** Joint names, in joint order. */
  get jointNames() {
    return this._names('ssc_model_get_joint_name', this.jointCount);
  }

  /** Landmark names (CAESAR names for the default model), in landmark order. */
  get landmarkNames() {
    return this._names('ssc_model_get_landmark_name', this.landmarkCount);
  }

  _names(fn, count) {
    const names = [];
    for (let i = 0; i < count; ++i) {
      const out = [null];
      call(fn, this.handle, i, out);
      names.push(out[0]);
    }
    return names;
  }

  /** A joint's index by name; throws NOT_FOUND for an unknown name. */
  jointIndex(name) {
    const out = new Uint32Array(1);
    call('ssc_model_find_joint', this.handle, String(name), out);
    return out[0];
  }

  /** A landmark's index by name; throws NOT_FOUND for an unknown name. */
  landmarkIndex(name) {
    const out = new Uint32Array(1);
    call('ssc_model_find_landmark', this.handle, String(name), out);
    return out[0];
  }

  /** The segment shape spaces, [{ name, shapeCount, vertexCount }] in index order (none in a model without them). */
  get segments() {
    const segments = [];
    const count = api().ssc_model_segment_count(this.handle);
    for (let i = 0; i < count; ++i) {
      const info = { struct_size: koffi.sizeof('ssc_segment_info') };
      call('ssc_model_get_segment_info', this.handle, i, info);
      segments.push({ name: info.name, shapeCount: info.shape_count, vertexCount: info.vertex_count });
    }
    return segments;
  }

  /** The levels of detail, [{ index, name, vertexCount, triangleCount, uvCount }]: 0 the full mesh ("full"), then the model's, finest first. */
  get levels() {
    const levels = [];
    const count = api().ssc_model_level_count(this.handle);
    for (let i = 0; i < count; ++i) {
      const info = { struct_size: koffi.sizeof('ssc_level_info') };
      call('ssc_model_get_level_info', this.handle, i, info);
      levels.push({ index: i, name: info.name, vertexCount: info.vertex_count, triangleCount: info.triangle_count, uvCount: info.uv_count });
    }
    return levels;
  }

  /** One level of detail by index or name; throws RangeError for one the model lacks. */
  level(level) {
    return pickLevel(this.levels, level);
  }

  /** A level's triangles: 3 vertex indices each (Uint32Array). */
  levelTriangles(level) {
    const l = this.level(level);
    const out = new Uint32Array(l.triangleCount * 3);
    call('ssc_model_get_level_triangles', this.handle, l.index, out, l.triangleCount);
    return out;
  }

  /** A segment's index by name; throws NOT_FOUND for a name the model lacks. */
  segmentIndex(name) {
    const out = new Uint32Array(1);
    call('ssc_model_find_segment', this.handle, String(name), out);
    return out[0];
  }

  /** Standard deviation of each shape coefficient. */
  get shapeStddevs() {
    const out = new Float32Array(this.shapeCount);
    call('ssc_model_get_shape_stddevs', this.handle, out, out.length);
    return out;
  }

  /** count random shapes of the population (count * shapeCount coefficients), reproducible by seed. */
  sampleShapes(count, { seed = 1, truncation = 2.5 } = {}) {
    const out = new Float32Array(count * this.shapeCount);
    call('ssc_model_sample_shapes', this.handle, seed >>> 0, count, truncation, out, out.length);
    return out;
  }

  /**
   * Many bodies in one call (the library's batch path). shapes: count * shapeCount coefficients (or
   * null for mean bodies, with count); poses: count * jointCount quaternions (x y z w) or null for the
   * rest pose; translations: count * 3 or null. Returns { vertices, normals } (count * vertexCount * 3
   * each; normals only when asked for).
   */
  synthesize({ shapes = null, count, poses = null, translations = null, normals = false, level = 0 } = {}) {
    const K = this.shapeCount;
    if (count === undefined) {
      if (!shapes) throw new RangeError('synthesize: give shapes or count');
      count = Math.floor(shapes.length / K);
    }
    const lv = pickLevel(this.levels, level);
    const V = lv.vertexCount;
    const desc = {};
    api().ssc_batch_desc_init(desc, koffi.sizeof('ssc_batch_desc'));
    desc.level = lv.index;
    const vertices = new Float32Array(count * V * 3);
    const normalsOut = normals ? new Float32Array(count * V * 3) : null;
    Object.assign(desc, {
      body_count: count,
      shapes: shapes ? floats(shapes, count * K, 'shapes') : null,
      shape_count: shapes ? K : 0,
      poses: poses ? floats(poses, count * this.jointCount * 4, 'poses') : null,
      translations: translations ? floats(translations, count * 3, 'translations') : null,
      vertices, vertices_capacity: count * V, normals: normalsOut, normals_capacity: normals ? count * V : 0,
    });
    call('ssc_model_synthesize_batch', this.handle, desc);
    return normals ? { vertices, normals: normalsOut } : { vertices };
  }

  /** A new body of this model (mean shape, rest pose). */
  createBody() {
    const out = [null];
    call('ssc_body_create', this.handle, null, out);
    return new Body(this, out[0]);
  }

  /** A new fitter; options are ssc_fitter_def's fields (shape_count, max_iterations, ...). */
  createFitter(options = {}) {
    const def = {};
    api().ssc_fitter_def_init(def, koffi.sizeof('ssc_fitter_def'));
    for (const [key, value] of Object.entries(options)) {
      if (!(key in def) || key === 'struct_size') throw new RangeError(`createFitter: unknown option ${key}`);
      def[key] = value;
    }
    const out = [null];
    call('ssc_fitter_create', this.handle, def, out);
    return new Fitter(this, out[0]);
  }
}

// What a body or fitter needs of its model, read once: the model object may be closed first (the
// C object lives on while a body or fitter holds it).
// A non-negative integer index, or a RangeError naming what it is.
function index(value, what) {
  if (!Number.isInteger(value) || value < 0 || value > 0xffffffff) throw new RangeError(`${what} must be an index, not ${value}`);
  return value;
}

function counts(model) {
  return Object.freeze({ vertexCount: model.vertexCount, jointCount: model.jointCount, shapeCount: model.shapeCount,
    landmarkCount: model.landmarkCount, levels: Object.freeze(model.levels) });
}

// A level of detail of a list (Model.levels) by index or name; RangeError for one it lacks.
function pickLevel(levels, level) {
  const found = typeof level === 'string' ? levels.find((l) => l.name === level) : levels[level];
  if (!found) throw new RangeError(`no level ${level}; the model's: ${levels.map((l) => l.name).join(', ')}`);
  return found;
}

/** The measurements the library knows: [{ name, unit, definition }], in measurement order. */
let measurementList = null;  // the library's static table, read once
function measurements() {
  if (measurementList) return measurementList.map((m) => ({ ...m }));
  const c = api();
  const list = [];
  for (let i = 0; i < c.ssc_measurement_count(); ++i) {
    const name = [null], unit = new Int32Array(1), definition = [null];
    call('ssc_measurement_get_info', i, name, unit, definition);
    const unitName = Object.keys(enums.ssc_unit).find((k) => enums.ssc_unit[k] === unit[0]);
    list.push({ name: name[0], unit: unitName.replace(/^SSC_UNIT_/, '').toLowerCase(), definition: definition[0] });
  }
  measurementList = list;
  return measurements();
}

/** One body: shape and pose in, vertices and measurements out. One thread at a time. */
class Body extends Handle {
  constructor(model, handle) {
    super(handle, 'ssc_body_destroy');
    this.model = counts(model);
  }

  /** The shape coefficients (Float32Array of the model's shapeCount). */
  get shape() {
    const out = new Float32Array(this.model.shapeCount);
    call('ssc_body_get_shape', this.handle, out, out.length);
    return out;
  }

  /** Sets the first coefficients.length shape coefficients (the rest 0). */
  set shape(coefficients) {
    const c = floats(coefficients, undefined, 'shape');
    call('ssc_body_set_shape', this.handle, c, c.length);
  }

  /** One segment's coefficients (model.segmentIndex), on top of the whole-body shape; the segment's rest 0. */
  setSegmentShape(segment, coefficients) {
    const c = floats(coefficients, undefined, 'coefficients');
    call('ssc_body_set_segment_shape', this.handle, index(segment, 'segment'), c, c.length);
  }

  /** One segment's coefficients: shapeCount of them (its segments[] entry's). */
  segmentShape(segment, shapeCount) {
    const out = new Float32Array(shapeCount);
    call('ssc_body_get_segment_shape', this.handle, index(segment, 'segment'), out, out.length);
    return out;
  }

  /** The pose: jointCount quaternions (x y z w, parent-relative) or null (rest), and a translation in metres. */
  setPose(rotations = null, translation = null) {
    const J = this.model.jointCount;
    call('ssc_body_set_pose', this.handle, rotations ? floats(rotations, J * 4, 'rotations') : null, rotations ? J : 0,
      translation ? floats(translation, 3, 'translation') : null);
  }

  /** As setPose, each rotation an axis times its angle in radians (3 floats per joint). */
  setPoseAxisAngle(rotations, translation = null) {
    const J = this.model.jointCount;
    call('ssc_body_set_pose_axis_angle', this.handle, floats(rotations, J * 3, 'rotations'), J,
      translation ? floats(translation, 3, 'translation') : null);
  }

  _vertexArray(fn, count) {
    const out = new Float32Array(count * 3);
    call(fn, this.handle, out, count, 0);
    return out;
  }

  /** Posed vertices, metres (vertexCount * 3). */
  get vertices() { return this._vertexArray('ssc_body_get_vertices', this.model.vertexCount); }
  /** Unit normals of the posed body (vertexCount * 3). */
  get normals() { return this._vertexArray('ssc_body_get_normals', this.model.vertexCount); }
  /** The landmarks on the posed body (landmarkCount * 3). */
  get landmarks() { return this._vertexArray('ssc_body_get_landmarks', this.model.landmarkCount); }

  /** A level of detail's posed vertices (Model.level: by index or name; its vertexCount * 3). */
  levelVertices(level) {
    const l = pickLevel(this.model.levels, level);
    const out = new Float32Array(l.vertexCount * 3);
    call('ssc_body_get_level_vertices', this.handle, l.index, out, l.vertexCount, 0);
    return out;
  }

  /** A level of detail's unit normals (its vertexCount * 3). */
  levelNormals(level) {
    const l = pickLevel(this.model.levels, level);
    const out = new Float32Array(l.vertexCount * 3);
    call('ssc_body_get_level_normals', this.handle, l.index, out, l.vertexCount, 0);
    return out;
  }

  /** Every measurement, in the order of measurements() (Float32Array; metres, square metres, kg, ...). */
  measureAll() {
    const out = new Float32Array(api().ssc_measurement_count());
    call('ssc_body_measure', this.handle, out, out.length);
    return out;
  }

  /** Every measurement by name: { stature: 1.73, ... }. */
  measure() {
    const values = this.measureAll();
    return Object.fromEntries(measurements().map((m, i) => [m.name, values[i]]));
  }

  /** Writes the posed body: format 'obj', 'ply' or 'glb' (from the file name when omitted); level: a level of
   *  detail by index or name (0 the full mesh), or 'all' for every level in one .glb (a node each). */
  write(path, format, { level = 0, morphs = null } = {}) {
    const kind = (format || String(path).split('.').pop()).toUpperCase();
    const value = enums.ssc_file_format[`SSC_FILE_${kind}`];
    if (value === undefined) throw new RangeError(`write: unknown format ${kind}`);
    const def = {};
    api().ssc_export_def_init(def, koffi.sizeof('ssc_export_def'));
    def.format = value;
    def.level = level === 'all' ? 0xFFFFFFFF : pickLevel(this.model.levels, level).index;
    // Shape morph targets (GLB): the first K components, or 'sliders' (docs/engines.md).
    if (morphs === 'sliders') {
      def.morphs = enums.ssc_morphs.SSC_MORPHS_SLIDERS;
    } else if (morphs !== null) {
      def.morphs = enums.ssc_morphs.SSC_MORPHS_COMPONENTS;
      def.morph_count = index(morphs, 'morphs');
    }
    call('ssc_body_export', this.handle, String(path), def);
  }
}

/** Fits shape and pose to observations (landmarks, points). One thread at a time. */
class Fitter extends Handle {
  constructor(model, handle) {
    super(handle, 'ssc_fitter_destroy');
    this.model = counts(model);
  }

  /** Landmarks of frame 0 (or `frame`): names (or indices) and positions (count * 3, metres). */
  addLandmarks(names, positions, { weights = null, frame = 0 } = {}) {
    const p = floats(positions, names.length * 3, 'positions');
    const w = weights ? floats(weights, names.length, 'weights') : null;
    if (names.every((n) => typeof n === 'number')) {
      call('ssc_fitter_add_landmarks', this.handle, frame, Uint32Array.from(names), p, w, names.length);
    } else {
      call('ssc_fitter_add_landmarks_by_name', this.handle, frame, names.map(String), p, w, names.length);
    }
  }

  /** Scan points (count * 3, metres), with normals (count * 3) when known. */
  addPoints(points, { normals = null, frame = 0 } = {}) {
    const p = floats(points, undefined, 'points');
    const count = p.length / 3;
    call('ssc_fitter_add_points', this.handle, frame, p, normals ? floats(normals, p.length, 'normals') : null, null, count, 0);
  }

  /**
   * Solves; onProgress(iteration, cost) may return true to cancel (throws CANCELLED). Returns the
   * report (ssc_fit_report's fields: iterations, converged, final_cost, landmark_rms, ...).
   */
  solve({ onProgress = null } = {}) {
    const report = { struct_size: koffi.sizeof('ssc_fit_report') };
    let callback = null;
    if (onProgress) {
      callback = koffi.register((user, iteration, cost) => (onProgress(iteration, cost) ? 1 : 0),
        koffi.pointer(native.declareTypes(koffi).ssc_progress_fn));
    }
    try {
      call('ssc_fitter_solve', this.handle, callback, null, report);
    } finally {
      if (callback) koffi.unregister(callback);
    }
    return report;
  }

  /** The fitted shape coefficients. */
  get shape() {
    const out = new Float32Array(this.model.shapeCount);
    call('ssc_fitter_get_shape', this.handle, out, out.length);
    return out;
  }

  /** The fitted pose of a frame: { rotations (jointCount * 4), translation (3), scale }. */
  pose(frame = 0) {
    const rotations = new Float32Array(this.model.jointCount * 4);
    const translation = new Float32Array(3);
    const scale = new Float32Array(1);
    call('ssc_fitter_get_pose', this.handle, frame, rotations, this.model.jointCount, translation, scale);
    return { rotations, translation, scale: scale[0] };
  }

  /** The fitted body's vertices in a frame (vertexCount * 3). */
  vertices(frame = 0) {
    const out = new Float32Array(this.model.vertexCount * 3);
    call('ssc_fitter_get_vertices', this.handle, frame, out, this.model.vertexCount, 0);
    return out;
  }
}

module.exports = {
  Model, Body, Fitter, SscapeError, measurements, version, ABI_MAJOR: native.VERSION_MAJOR, enums,
  /** The raw C API: every function of sscape.h, declared through koffi (see lib/native.js). */
  get native() { return api(); },
};
