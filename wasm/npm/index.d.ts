// Types of laminar-wasm. The functions and classes are declared by
// wasm-bindgen (plain/laminar_wasm.d.ts, the same for both builds); the
// fitted-model file that `fit` returns is typed here.
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
export declare function load(options?: { simd?: boolean }): Promise<Laminar>;

/** What releasing a bound of the box gives (a diagnostic, not an estimate). */
export interface Released {
  /** The parameter's value with that bound released to the model's domain. */
  value: number;
  /** Δ_RMS (eq. 15) there. */
  rms: number;
  /** Δ_RMS of the fit inside the box. */
  rms_in_box: number;
}

/** A searched parameter of a fit (docs/conventions.md §11, §11b). */
export interface FitParameter {
  /** The best grid point's value. */
  grid: number;
  /** After refinement (null when not refined); `'not_identified'` when the
   * data do not determine the parameter (its flags hold `not_identified`). */
  refined: number | 'not_identified' | null;
  /** 68.27% and 95% interval ends (null when not computed or open). */
  lo68: number | null;
  hi68: number | null;
  lo95: number | null;
  hi95: number | null;
  /** Where the interval ends come from. */
  interval: 'profile' | 'jacobian' | null;
  /** The Jacobian's standard deviation (null at a domain bound). */
  sd: number | null;
  /** `range_edge`, `domain_bound`, `open_below`, `open_above`, `not_identified`. */
  flags: string[];
  /** The box searched (free objective; null for the paper's). */
  box: [number, number] | null;
  /** For an estimate on a face of the box: the fit with that bound released. */
  released: Released | null;
}

/** A fitted model: what `predict` needs to reproduce the fit's prediction anywhere. */
export interface FittedModel {
  model: string;
  /** Full-precision parameters (β: eq. 8's under the free objective, the paper normalisation's balance under the paper's). */
  params: Record<string, number>;
  /** Free objective: `{amplitude}`; paper: the maxima over the fit's geometries of the raw surface and subsurface terms and the normalised mix (baselines: of the raw radiance). */
  normalisation: Record<string, number>;
  /** Eq. 8's β giving the same lobe (layered models). */
  beta_eq8: number | null;
  /** The fitted lobe is eq8_scale · eq. 8 at beta_eq8. */
  eq8_scale: number | null;
  /** The max the measured radiance was divided by. */
  data_scale: number;
}

/** One fit of the fitted-model file (`laminar fit --format json`). */
export interface FitEntry {
  sample: string;
  channel: string;
  model: 'exp' | 'gauss' | 'rh-exp' | 'rh-gauss' | 'jensen' | 'oren-nayar';
  /** The objective minimised. */
  objective: 'free' | 'paper';
  /** Δ_RMS (eq. 15) of the reported estimate: the refined one (free), the best grid point (paper). */
  rms: number;
  /** χ²/ν (eq. 16). */
  chi2_dof: number | null;
  chi2_used: number | null;
  chi2_left_out: number | null;
  /** The reported estimate's parameters (as `rms`); `'not_identified'` in
   * place of a value the data do not determine. */
  params: Record<string, number | 'not_identified'>;
  rh_rms: number | null;
  rh_params: Record<string, number> | null;
  measurements: number;
  search_rms: number;
  nonpositive: number;
  rh_chi2_dof: number | null;
  /** The model `predict` uses (the refined one when refined). */
  fitted: FittedModel;
  /** The best grid point's model, when `fitted` is the refined one. */
  grid_fitted: FittedModel | null;
  /** The Ragheb–Hancock best (a = 0) of an exp or gauss fit. */
  rh_fitted: FittedModel | null;
  rms_grid: number | null;
  rms_refined: number | null;
  /** Free objective: the fitted amplitude. */
  amplitude: number | null;
  /** Free objective: the weighted χ²/ν. */
  chi2w_dof: number | null;
  correlations: Record<string, number>;
  trade_offs: Record<string, number>;
  parameters: Record<string, FitParameter>;
  /** The directional albedo, present when asked for (`laminar fit --albedo`). */
  energy?: Energy;
}

/** A fitted model's directional albedo ρ(θv) = ∫ f cos θi dωi (docs/conventions.md §12). */
export interface Energy {
  /** The fitted data's units as stated: ρ > 1 is a gain of energy only when `absolute`. */
  units: 'absolute' | 'relative';
  /** View angles, degrees. */
  theta_v: number[];
  /** ρ(θv) in the fitted data's units. */
  albedo: number[];
  /** Each value's quadrature error. */
  error: number[];
  /** ρ > 1 somewhere, in absolute units. */
  energy_gain: boolean;
}

/** The fitted-model file: `JSON.parse(fit(...))`. */
export interface FitsFile {
  format: string;
  version: number;
  quantities: Record<string, string>;
  fits: FitEntry[];
}
