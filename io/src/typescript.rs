//! The TypeScript declarations of the fitted-model file
//! (`wasm/npm/fits.d.ts`), generated from the Rust types that write it
//! ([`crate::fits`], `laminar_brdf_fit`'s models and results) and the model
//! descriptor ([`Model::ALL`], [`Param::ALL`]). The test fails when the
//! file in the repository is stale; `LAMINAR_BLESS=1` rewrites it:
//!
//! ```sh
//! LAMINAR_BLESS=1 cargo test -p laminar-brdf-io typescript
//! ```

use crate::fits::{
    Energy, FitEntry, FitsFile, IntervalEntry, JointEntry, MaterialChannel, MaterialEntry,
    NotIdentified, ParamValue, ParameterEntry, Units,
};
use laminar_brdf_fit::adequacy::Adequacy;
use laminar_brdf_fit::choice::{CrossValidation, Information, Rank};
use laminar_brdf_fit::fitted::{ModelParams, NormalisationConstants};
use laminar_brdf_fit::graphics_metrics::GraphicsMetrics;
use laminar_brdf_fit::report::{Released, Source};
use laminar_brdf_fit::{Edge, FittedModel, Model, Objective, Param};
use ts_rs::{Config, TS};

/// Where the declarations live, from this crate's directory.
const PATH: &str = "../wasm/npm/fits.d.ts";

/// A union of string literals.
fn union(names: impl IntoIterator<Item = &'static str>) -> String {
    names
        .into_iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(" | ")
}

/// `T`'s declaration, exported.
fn declare<T: TS>(cfg: &Config) -> String {
    let docs = T::docs().unwrap_or_default();
    format!("{docs}export {}\n", T::decl(cfg))
}

/// Rust doc comments as a TypeScript reader wants them: without Rust code
/// examples, and with intra-doc links (`` [`X`] ``) as plain code (`` `X` ``).
fn tidy(text: &str) -> String {
    let mut out = String::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.trim_start().trim_start_matches('*').trim() == "```" {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        out += &line.replace("[`", "`").replace("`]", "`");
        out.push('\n');
    }
    // A comment left with a blank last line before its end.
    out.replace(" *\n */", " */")
}

/// One declared type: its TypeScript name, declaration and the names of the
/// types it refers to.
struct Declared {
    name: fn(&Config) -> String,
    decl: fn(&Config) -> String,
    dependencies: fn(&Config) -> Vec<String>,
}

impl Declared {
    const fn of<T: TS + 'static>() -> Self {
        Declared {
            name: |cfg| T::name(cfg),
            decl: declare::<T>,
            dependencies: |cfg| {
                T::dependencies(cfg)
                    .into_iter()
                    .map(|d| d.ts_name)
                    .collect()
            },
        }
    }
}

/// Every type the file declares, each after the types it refers to.
const DECLARED: &[Declared] = &[
    Declared::of::<Model>(),
    Declared::of::<Objective>(),
    Declared::of::<Edge>(),
    Declared::of::<Source>(),
    Declared::of::<Released>(),
    Declared::of::<NotIdentified>(),
    Declared::of::<ParamValue>(),
    Declared::of::<IntervalEntry>(),
    Declared::of::<ParameterEntry>(),
    Declared::of::<ModelParams>(),
    Declared::of::<NormalisationConstants>(),
    Declared::of::<FittedModel>(),
    Declared::of::<Units>(),
    Declared::of::<Energy>(),
    Declared::of::<Adequacy>(),
    Declared::of::<Information>(),
    Declared::of::<Rank>(),
    Declared::of::<CrossValidation>(),
    Declared::of::<GraphicsMetrics>(),
    Declared::of::<FitEntry>(),
    Declared::of::<JointEntry>(),
    Declared::of::<MaterialChannel>(),
    Declared::of::<MaterialEntry>(),
    Declared::of::<FitsFile>(),
];

/// The whole file.
fn declarations() -> String {
    let cfg = Config::new();
    let mut out = String::from(
        "// The fitted-model file's types (`laminar fit --format json`, wasm `fit`).\n\
         // Generated from the Rust types by laminar-brdf-io's test `typescript`\n\
         // (io/src/typescript.rs): do not edit; `LAMINAR_BLESS=1 cargo test -p\n\
         // laminar-brdf-io typescript` rewrites it.\n\n",
    );
    out += "/** A model's parameter, by name (laminar_brdf_fit::Param). */\n";
    out += &format!(
        "export type Param = {};\n\n",
        union(Param::ALL.map(Param::name))
    );
    let decls: Vec<String> = DECLARED.iter().map(|d| (d.decl)(&cfg)).collect();
    out += &decls.join("\n");
    tidy(&out)
}

#[test]
fn every_type_the_declarations_name_is_declared() {
    let cfg = Config::new();
    let mut names: Vec<String> = vec!["Param".into()];
    names.extend(DECLARED.iter().map(|d| (d.name)(&cfg)));
    for d in DECLARED {
        for dep in (d.dependencies)(&cfg) {
            assert!(
                names.contains(&dep),
                "{} refers to {dep}, which {PATH} does not declare: add it to DECLARED",
                (d.name)(&cfg)
            );
        }
    }
}

#[test]
fn typescript_declarations_are_the_rust_types() {
    let cfg = Config::new();
    // The union ts-rs derives from Model's variants is the names Model
    // serialises as (its serde is written by hand, by Model::name).
    assert_eq!(Model::inline(&cfg), union(Model::ALL.map(Model::name)));
    let want = declarations();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(PATH);
    if std::env::var_os("LAMINAR_BLESS").is_some() {
        std::fs::write(&path, &want).expect("write the declarations");
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "{PATH} is stale: regenerate it with LAMINAR_BLESS=1 cargo test -p laminar-brdf-io typescript"
    );
}
