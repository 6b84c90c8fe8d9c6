// Types of laminar-brdf/eval, the evaluation-only package. The functions are
// declared by wasm-bindgen (plain/laminar_wasm.d.ts, the same for both
// builds); the fitted model `predictFitted` takes is the `fitted` entry of
// the whole package's fitted-model file.
import type * as Build from './plain/laminar_wasm.js';
import type { FittedModel } from '../index.js';

export type { Components } from './plain/laminar_wasm.js';
export type { FittedModel } from '../index.js';

/** Everything one build exports, initialised. */
export type LaminarEval = Omit<typeof Build, 'default' | 'initSync' | 'predictFitted'> & {
  /** True for the `+simd128` build. */
  readonly simd: boolean;
  /**
   * A fitted layered model's prediction at flat (θi, θs, φs) triples
   * (radians): bit for bit the whole package's `predict` of the file the
   * model came from.
   */
  predictFitted(fitted: FittedModel, angles: Float64Array): Float64Array;
};

/** Whether this engine runs WebAssembly SIMD (the `+simd128` build). */
export declare function simdSupported(): boolean;

/** Loads one build (SIMD where supported, unless `simd` says) and initialises it. */
export declare function load(options?: {
  simd?: boolean;
  /** The `.wasm`'s bytes from its URL (the default: fetch it; in node: read it from disk). */
  read?: (url: URL) => Promise<ArrayBuffer | ArrayBufferView> | ArrayBuffer | ArrayBufferView;
}): Promise<LaminarEval>;
