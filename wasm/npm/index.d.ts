// Types of laminar-brdf. The functions and classes are declared by
// wasm-bindgen (plain/laminar_wasm.d.ts, the same for both builds); the
// fitted-model file that `fit` returns is typed in fits.d.ts, generated.
import type * as Build from './plain/laminar_wasm.js';

export type { Components, FitOptions, Measurements, SceneData } from './plain/laminar_wasm.js';

/** Everything one build exports, initialised. */
export type Laminar = Omit<typeof Build, 'default' | 'initSync'> & {
  /** True for the `+simd128` build. */
  readonly simd: boolean;
};

/** Whether this engine runs WebAssembly SIMD (the `+simd128` build). */
export declare function simdSupported(): boolean;

/** Loads one build (SIMD where supported, unless `simd` says) and initialises it. */
export declare function load(options?: {
  simd?: boolean;
  /** The `.wasm`'s bytes from its URL (the default: fetch it; in node: read it from disk). */
  read?: (url: URL) => Promise<ArrayBuffer | ArrayBufferView> | ArrayBuffer | ArrayBufferView;
}): Promise<Laminar>;

// The fitted-model file's types (FitsFile, FitEntry, FitParameter,
// FittedModel, Model, Param, …), generated from the Rust types that write it.
export type * from './fits.js';
