//! Property tests of the scene loader: arbitrary text and randomly mutated valid scenes never
//! make it panic — it returns a plan or an error — and an accepted scene never carries a
//! non-finite number into what a run would write.

use proptest::prelude::*;
use std::path::Path;
use toml::{Table, Value};
use turf::scene::load_str;
use turf::scene::overrides::{set, Step};

pub(crate) const SCENES: [&str; 5] = [
    include_str!("../../scenes/jkr_sphere.toml"),
    include_str!("../../scenes/hertz.toml"),
    include_str!("../../scenes/hyperfoam_indent.toml"),
    include_str!("../../scenes/turf_compression.toml"),
    include_str!("../../scenes/turf_indent.toml"),
];

/// Every key path (tables, arrays and leaves) of a document.
fn paths(v: &Value, here: Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match v {
        Value::Table(t) => {
            for (k, x) in t {
                let mut p = here.clone();
                p.push(Step::Key(k.clone()));
                out.push(p.clone());
                paths(x, p, out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                let mut p = here.clone();
                p.push(Step::Index(i));
                out.push(p.clone());
                paths(x, p, out);
            }
        }
        _ => {}
    }
}

/// Remove the value at `path`.
fn delete(doc: &mut Table, path: &[Step]) {
    let Some((last, parent)) = path.split_last() else {
        return;
    };
    let mut root = Value::Table(std::mem::take(doc));
    let mut here = Some(&mut root);
    for s in parent {
        here = here.and_then(|v| match (s, v) {
            (Step::Key(k), Value::Table(t)) => t.get_mut(k),
            (Step::Index(i), Value::Array(a)) => a.get_mut(*i),
            _ => None,
        });
    }
    match (last, here) {
        (Step::Key(k), Some(Value::Table(t))) => {
            t.remove(k);
        }
        (Step::Index(i), Some(Value::Array(a))) if *i < a.len() => {
            a.remove(*i);
        }
        _ => {}
    }
    if let Value::Table(t) = root {
        *doc = t;
    }
}

fn garbage() -> impl Strategy<Value = Value> {
    prop_oneof![
        any::<i64>().prop_map(Value::Integer),
        any::<f64>().prop_map(Value::Float),
        Just(Value::Float(0.0)),
        Just(Value::Float(-1.0)),
        Just(Value::Float(0.5)),
        Just(Value::Float(1e300)),
        any::<bool>().prop_map(Value::Boolean),
        "[a-z0-9 /^.-]{0,12}".prop_map(Value::String),
        prop::sample::select(vec![
            "3 nm",
            "1 GPa",
            "-2 um",
            "0.1 J/m^2",
            "5 s",
            "lj93",
            "sphere",
            "1e400 nm",
            "10 uN/s"
        ])
        .prop_map(|s| Value::String(s.to_string())),
        Just(Value::Array(vec![])),
        Just(Value::Array(vec![Value::Float(0.4), Value::Float(0.7)])),
        Just(Value::Table(Table::new())),
    ]
}

#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize),
    Replace(usize, Value),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        any::<usize>().prop_map(Mutation::Delete),
        (any::<usize>(), garbage()).prop_map(|(i, v)| Mutation::Replace(i, v)),
    ]
}

/// Whatever the loader accepts must serialise without NaN (serde_json writes them as null).
fn assert_finite(v: &serde_json::Value) {
    match v {
        serde_json::Value::Null => panic!("a null (non-finite number) in an accepted scene"),
        serde_json::Value::Array(a) => a.iter().for_each(assert_finite),
        serde_json::Value::Object(o) => o.values().for_each(assert_finite),
        _ => {}
    }
}

/// Load `text`; an accepted scene must have a plan and no non-finite number.
pub(crate) fn check(text: &str) {
    if let Ok(loaded) = load_str(text, Path::new("prop.toml"), &[]) {
        assert!(!loaded.base.plan.stages.is_empty());
        assert_finite(&serde_json::to_value(&loaded).unwrap());
    }
}

/// Text shaped like TOML: section headers and `key = value` lines of assorted kinds.
pub(crate) const TOML_LIKE: &str =
    "(\\[[a-z.]{1,12}\\]\n|[a-z_]{1,8} = (\"[-0-9a-z /^.]{0,10}\"|[-0-9.e]{1,6}|true|\\[\\])\n){0,12}";

/// An example scene with one to three keys deleted or replaced by garbage, as TOML text.
pub(crate) fn mutated_scene() -> impl Strategy<Value = String> {
    (0..SCENES.len(), prop::collection::vec(mutation(), 1..4))
        .prop_map(|(which, muts)| mutate(SCENES[which], muts))
}

/// Apply `muts` in turn to the scene `text`; each picks its key path modulo the paths present.
fn mutate(text: &str, muts: Vec<Mutation>) -> String {
    let mut doc: Table = text.parse().unwrap();
    for m in muts {
        let mut all = Vec::new();
        paths(&Value::Table(doc.clone()), Vec::new(), &mut all);
        if all.is_empty() {
            break;
        }
        match m {
            Mutation::Delete(i) => delete(&mut doc, &all[i % all.len()]),
            Mutation::Replace(i, v) => {
                let _ = set(&mut doc, &all[i % all.len()], v);
            }
        }
    }
    toml::to_string(&doc).unwrap()
}

/// An example scene's index and a random `--set KEY=VALUE` argument.
pub(crate) fn set_argument() -> impl Strategy<Value = (usize, String)> {
    (
        0..SCENES.len(),
        "[a-z_]{1,10}(\\.[a-z_0-9]{1,10}){0,2}(\\[[0-9]\\])?",
        "[-0-9a-zA-Z \\[\\]\",./^=]{0,16}",
    )
        .prop_map(|(which, key, value)| (which, format!("{key}={value}")))
}

/// Load example scene `which` with the override `arg`; accepted, it must be finite.
pub(crate) fn check_set(which: usize, arg: &str) {
    if let Ok(loaded) = load_str(SCENES[which], Path::new("prop.toml"), &[arg.to_string()]) {
        assert_finite(&serde_json::to_value(&loaded).unwrap());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        check(&text);
    }

    #[test]
    fn arbitrary_toml_like_text_never_panics(text in TOML_LIKE) {
        check(&text);
    }

    #[test]
    fn mutated_scenes_never_panic(text in mutated_scene()) {
        check(&text);
    }

    #[test]
    fn random_set_arguments_never_panic((which, arg) in set_argument()) {
        check_set(which, &arg);
    }
}
