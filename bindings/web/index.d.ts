// TypeScript declarations of the sscape browser package (src/sscape.mjs): the library as WebAssembly.
// Units: metres, kilograms; right-handed, Y up, the body facing +Z; quaternions x y z w. The shapes
// the Node package (bindings/javascript) shares with it are its own declarations, imported.
import type { Measurement, Level } from '../javascript/index';

export type { Measurement, Level };
type Floats = Float32Array | ArrayLike<number>;

/** A failed call of the library: the ssc_status value, its name and the library's message. */
export class SscapeError extends Error {
  readonly status: number;
  /** e.g. 'SSC_ERROR_MODEL_CORRUPT'. */
  readonly code: string;
  /** The C function that failed. */
  readonly functionName: string;
}

/** Loads the WebAssembly runtime: sscape_runtime.wasm beside sscape.mjs, another URL, or the module's bytes. */
export function loadRuntime(options?: { wasm?: string | URL | ArrayBuffer | Uint8Array }): Promise<Runtime>;

export interface NamedPose {
  name: string;
  description: string;
}

/** A semantic slider and its population range (the 0.5th to the 99.5th percentile). */
export interface Slider {
  index: number;
  name: string;
  /** 'm', 'kg', 'years' or '' (a fraction). */
  unit: string;
  description: string;
  mean: number;
  minimum: number;
  maximum: number;
}

/** One loaded runtime: its heap holds the models and bodies made from it. */
export class Runtime {
  version(): { major: number; minor: number; patch: number; number: number; text: string };
  /** The measurements the library knows, in the order of Body.measureAll(). */
  measurements(): Measurement[];
  namedPoses(): NamedPose[];
  /** Fetches (a URL) or takes (bytes) a .sscape file and verifies it completely before use. */
  loadModel(source: string | URL | ArrayBuffer | Uint8Array): Promise<Model>;
  modelFromBytes(bytes: ArrayBuffer | Uint8Array): Model;
}

declare class Handle {
  /** Releases the object now; later use throws. Idempotent. Objects left open are released when collected. */
  close(): void;
}

export class Model extends Handle {
  readonly vertexCount: number;
  readonly triangleCount: number;
  readonly jointCount: number;
  readonly shapeCount: number;
  readonly triangles: Uint32Array;
  readonly jointNames: string[];
  readonly shapeStddevs: Float32Array;
  /** The levels of detail: 0 the full mesh ("full"), then coarser ones. */
  readonly levels: Level[];
  /** One level by index or name; throws RangeError for one the model lacks. */
  level(level: number | string): Level;
  levelTriangles(level: number | string): Uint32Array;
  readonly sliders: Slider[];
  /** A named pose's joint rotations (jointCount quaternions), hands closed 0..1 when asked. */
  namedPose(name: string, options?: { handsClosed?: [number, number] | null }): Float32Array;
  /** Many bodies in one call: count * vertexCount * 3 floats (of the level), as each body's vertices. */
  synthesize(options: { shapes?: Floats | null; count: number; poses?: Floats | null; translations?: Floats | null;
                        normals?: boolean; level?: number | string }): { vertices: Float32Array; normals?: Float32Array };
  createBody(): Body;
  /** Landmark names (CAESAR names for the default model), in the order of Body.landmarks. */
  readonly landmarkNames: string[];
  /** A fitter of shape and pose to landmarks and scan points (one frame). */
  createFitter(options?: { shapeCount?: number; maxIterations?: number; seed?: number; jointLimits?: boolean }): Fitter;
}

/** What a solve did (ssc_fit_report's fields). */
export interface FitReport {
  iterations: number;
  converged: boolean;
  landmarkRms: number;
  pointMean: number;
  seconds: number;
  restarts: number;
  unexplainedFraction: number;
  implausible: boolean;
  problem: number;
}

export class Fitter extends Handle {
  readonly model: Model;
  /** Landmarks by name at positions (3 floats each, metres, any frame of reference). */
  addLandmarks(names: string[], positions: Floats): void;
  /** Scan points, 3 floats each. */
  addPoints(points: Floats): void;
  solve(): FitReport;
  readonly shape: Float32Array;
  readonly vertices: Float32Array;
}

export class Body extends Handle {
  readonly model: Model;
  /** The shape coefficients (standard deviations); setting n of them sets the rest to 0. */
  shape: Float32Array;
  setPose(rotations?: Floats | null, translation?: Floats | null): void;
  setNamedPose(name: string, options?: { handsClosed?: [number, number] | null; translation?: Floats | null }): void;
  /** The slider values read from the shape, by name. */
  readonly sliders: Record<string, number>;
  setSlider(slider: string | number, value: number): void;
  /** The shape that reproduces measurements (names of Runtime.measurements(), SI units). */
  makeToMeasure(targets: Record<string, number>, options?: { sex?: number; age?: number }): { converged: boolean; achieved: Record<string, number> };
  readonly vertices: Float32Array;
  readonly normals: Float32Array;
  levelVertices(level: number | string): Float32Array;
  levelNormals(level: number | string): Float32Array;
  /** The posed landmarks, 3 floats each (Model.landmarkNames order). */
  readonly landmarks: Float32Array;
  measureAll(): Float32Array;
  measure(): Record<string, number>;
  /** The body as a GLB file's bytes; morphs: the first K shape components, or 'sliders' (docs/engines.md). */
  toGLB(options?: { level?: number | string | 'all'; morphs?: number | 'sliders' | null }): Uint8Array;
  toOBJ(options?: { level?: number | string }): string;
}
