// TypeScript declarations of the sscape Node package (lib/index.js). Units: metres, kilograms;
// right-handed, Y up, the body facing +Z; quaternions x y z w.

type Floats = Float32Array | ArrayLike<number>;

/** A failed call of the C library: the ssc_status value, its name and the library's message. */
export class SscapeError extends Error {
  /** The ssc_status value (negative). */
  readonly status: number;
  /** Its name, e.g. 'SSC_ERROR_NOT_FOUND'. */
  readonly code: string;
  /** The C function that failed. */
  readonly functionName: string;
}

/** The loaded library's version (ssc_version). */
export function version(): { major: number; minor: number; patch: number; number: number; text: string };

/** The C API major version this package is written for; the loaded library must have the same. */
export const ABI_MAJOR: number;

/** Every enum of sscape.h, by C name: enums.ssc_status.SSC_OK, ... */
export const enums: Record<string, Record<string, number>>;

/** The raw C API: every function of sscape.h through koffi (pointer outputs take typed arrays or [null]). */
export const native: Record<string, (...args: any[]) => any>;

export interface Measurement {
  name: string;
  /** 'metre', 'square_metre', 'cubic_metre' or 'kilogram'. */
  unit: string;
  definition: string;
}

/** The measurements the library knows, in the order of Body.measureAll(). */
export function measurements(): Measurement[];

declare class Handle {
  /** Releases the C object now; later use throws. Idempotent. Unclosed objects are released when collected. */
  close(): void;
}

export interface FitterOptions {
  shape_count?: number;
  fit_scale?: number;
  max_iterations?: number;
  landmark_sigma?: number;
  point_sigma?: number;
  shape_prior?: number;
  pose_prior?: number;
  max_points?: number;
  seed?: number;
  joint_limits?: number;
}

/** ssc_fit_report's fields. */
export interface FitReport {
  iterations: number;
  converged: number;
  initial_cost: number;
  final_cost: number;
  landmark_rms: number;
  point_mean: number;
  inlier_fraction: number;
  seconds: number;
  restarts: number;
  unexplained_fraction: number;
  implausible: number;
}

/** A loaded model: immutable, shared by any number of bodies and fitters. */
/** A segment shape space: its name, components and the vertices they move. */
export interface Segment {
  name: string;
  shapeCount: number;
  vertexCount: number;
}

/** A level of detail: 0 the full mesh ("full"), then the model's coarser meshes, finest first. */
export interface Level {
  index: number;
  name: string;
  vertexCount: number;
  triangleCount: number;
  uvCount: number;
}

export class Model extends Handle {
  /** The default model built into the library. */
  static loadDefault(): Model;
  /** A .sscape file. */
  static load(path: string): Model;
  /** A .sscape file's bytes (copied). */
  static fromBuffer(bytes: Uint8Array): Model;
  readonly vertexCount: number;
  readonly triangleCount: number;
  readonly jointCount: number;
  readonly shapeCount: number;
  readonly landmarkCount: number;
  /** 3 vertex indices per triangle. */
  readonly triangles: Uint32Array;
  readonly jointNames: string[];
  readonly landmarkNames: string[];
  readonly shapeStddevs: Float32Array;
  /** Throws SscapeError (SSC_ERROR_NOT_FOUND) for an unknown name. */
  jointIndex(name: string): number;
  landmarkIndex(name: string): number;
  /** The segment shape spaces (head, arm_l, ...), in index order; none in a model without them. */
  readonly segments: Segment[];
  segmentIndex(name: string): number;
  /** The levels of detail, in index order (at least the full mesh). */
  readonly levels: Level[];
  /** One level by index or name; throws RangeError for one the model lacks. */
  level(level: number | string): Level;
  /** A level's triangles, 3 vertex indices each. */
  levelTriangles(level: number | string): Uint32Array;
  /** count * shapeCount coefficients of random bodies of the population, reproducible by seed. */
  sampleShapes(count: number, options?: { seed?: number; truncation?: number }): Float32Array;
  /** Many bodies in one call: count * vertexCount * 3 floats (and normals when asked for); with a
   *  level of detail (index or name), its vertices. */
  synthesize(options: { shapes?: Floats | null; count?: number; poses?: Floats | null; translations?: Floats | null;
                        normals?: boolean; level?: number | string }): { vertices: Float32Array; normals?: Float32Array };
  createBody(): Body;
  createFitter(options?: FitterOptions): Fitter;
}

/** One body: shape and pose in, vertices and measurements out. One thread at a time. */
export class Body extends Handle {
  /** The shape coefficients; setting n of them sets the rest to 0. */
  shape: Float32Array;
  /** One segment's coefficients (Model.segmentIndex), on top of the whole-body shape; the segment's rest 0. */
  setSegmentShape(segment: number, coefficients: Floats): void;
  /** One segment's coefficients: shapeCount of them. */
  segmentShape(segment: number, shapeCount: number): Float32Array;
  /** jointCount quaternions (or null: the rest pose) and a translation. */
  setPose(rotations?: Floats | null, translation?: Floats | null): void;
  /** jointCount axis-angle vectors (radians). */
  setPoseAxisAngle(rotations: Floats, translation?: Floats | null): void;
  readonly vertices: Float32Array;
  readonly normals: Float32Array;
  readonly landmarks: Float32Array;
  /** A level of detail's posed vertices and unit normals (its vertexCount * 3). */
  levelVertices(level: number | string): Float32Array;
  levelNormals(level: number | string): Float32Array;
  /** Every measurement, in the order of measurements(). */
  measureAll(): Float32Array;
  /** Every measurement by name. */
  measure(): Record<string, number>;
  /** 'obj', 'ply' or 'glb'; from the file name when omitted. level: a level of detail or 'all' (GLB);
   *  morphs (GLB): the first K shape components, or 'sliders', as morph targets (docs/engines.md). */
  write(path: string, format?: 'obj' | 'ply' | 'glb', options?: { level?: number | string | 'all'; morphs?: number | 'sliders' }): void;
}

/** Fits shape and pose to landmarks and points. One thread at a time. */
export class Fitter extends Handle {
  /** Landmark names (or indices) and their positions (count * 3). */
  addLandmarks(names: string[] | number[], positions: Floats, options?: { weights?: Floats | null; frame?: number }): void;
  addPoints(points: Floats, options?: { normals?: Floats | null; frame?: number }): void;
  /** onProgress returning true cancels (throws SSC_ERROR_CANCELLED). */
  solve(options?: { onProgress?: ((iteration: number, cost: number) => boolean) | null }): FitReport;
  readonly shape: Float32Array;
  pose(frame?: number): { rotations: Float32Array; translation: Float32Array; scale: number };
  vertices(frame?: number): Float32Array;
}
