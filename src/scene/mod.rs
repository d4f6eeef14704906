//! The scene file: typed serde structs of its sections, their validation, `--set` overrides
//! and the resolved plan.
//!
//! A scene is a TOML file whose sections say what to model (DESIGN.md, "Scene files"); the
//! doc comments of the section structs are the scene reference (also in `docs/scenes.md`).
//! Loading goes: read → parse TOML (syntax errors with line and column) → apply `--set`
//! overrides to the document → typed deserialisation (unknown keys, wrong types and wrong
//! dimensions refused, quantities converted to internal units once) → physical checks of each
//! section → the [`Plan`] (which stages, which physics) → for a `[sweep]`, the same for every
//! swept value. Every problem names the file, the key path, its line and what is allowed.
//!
//! Entry points: [`load`] (a file), [`load_str`] (a text, for tests), [`Loaded`].

pub mod adhesion;
mod check;
pub mod compression;
pub mod error;
pub mod halfspace;
pub mod homogenize;
pub mod indenter;
pub mod machine;
pub mod material;
pub mod mesh;
pub mod output;
pub mod overrides;
pub mod plan;
pub mod quantity;
pub mod resources;
pub mod rods;
pub mod scene_meta;
pub mod schedule;
pub mod solver;
mod source;
pub mod stage;
pub mod sweep;
pub mod turf;
pub mod viscoelastic;

pub use error::{Problem, SceneError};
pub use plan::{Derived, Plan, ResolvedScene};
pub use stage::Stage;

use check::Checker;
use overrides::Override;
use serde::{Deserialize, Serialize};
use source::SourceMap;
use std::path::{Path, PathBuf};

/// A scene: every section of DESIGN.md, each optional except `[scene]` (which has defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// name, description, seed
    #[serde(default)]
    pub scene: scene_meta::SceneMeta,
    /// the rigid indenter
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub indenter: Option<indenter::Indenter>,
    /// the indented solid
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<material::Material>,
    /// Prony relaxation
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscoelastic: Option<viscoelastic::Viscoelastic>,
    /// indenter–surface adhesion
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adhesion: Option<adhesion::Adhesion>,
    /// control mode and machine springs
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine: Option<machine::Machine>,
    /// the indentation history
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub schedule: Option<schedule::Schedule>,
    /// FE mesh sizes
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<mesh::Mesh>,
    /// FE solver
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<solver::Solver>,
    /// the half-space solver
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub halfspace: Option<halfspace::Halfspace>,
    /// a generated turf
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turf: Option<turf::Turf>,
    /// explicit rods
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rods: Option<rods::Rods>,
    /// the discrete drive
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compression: Option<compression::Compression>,
    /// fit options of the material card
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub homogenize: Option<homogenize::Homogenize>,
    /// a parameter sweep
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<sweep::Sweep>,
    /// output folder and files
    #[serde(default)]
    pub output: output::Output,
}

/// One point of a `[sweep]`.
#[derive(Debug, Clone, Serialize)]
pub struct SweepPoint {
    /// the swept key's value at this point, as written
    pub value: toml::Value,
    /// the scene at this point
    pub scene: ResolvedScene,
}

/// A loaded scene: the scene as written (with overrides), and one resolved scene per swept
/// value when it has a `[sweep]`.
#[derive(Debug, Clone, Serialize)]
pub struct Loaded {
    /// the scene (with the sweep key at its written value)
    pub base: ResolvedScene,
    /// the sweep points, empty without `[sweep]`
    pub sweep: Vec<SweepPoint>,
}

/// Load and validate a scene file with `--set` overrides.
pub fn load(file: &Path, overrides: &[String]) -> Result<Loaded, SceneError> {
    let text = std::fs::read_to_string(file).map_err(|source| SceneError::Io {
        file: file.to_path_buf(),
        source,
    })?;
    load_str(&text, file, overrides)
}

/// Load and validate a scene given as text; `file` names it in messages, gives the default
/// scene name and the folder relative paths are read from.
pub fn load_str(text: &str, file: &Path, overrides: &[String]) -> Result<Loaded, SceneError> {
    let original = SourceMap::new(text);
    let mut doc: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        let (line, column) = e
            .span()
            .map_or((1, 1), |s| source::line_column(text, s.start));
        SceneError::Syntax {
            file: file.to_path_buf(),
            line,
            column,
            message: e.message().trim().to_string(),
        }
    })?;
    let sets = overrides
        .iter()
        .map(|a| Override::parse(a))
        .collect::<Result<Vec<_>, _>>()?;
    for s in &sets {
        s.apply(&mut doc)?;
    }
    let ctx = Context {
        file,
        original: &original,
        set_keys: sets.iter().map(|s| s.key.clone()).collect(),
    };
    // without overrides the typed read sees the file itself, so its spans are the file's
    let base = if sets.is_empty() {
        ctx.resolve_text(text)?
    } else {
        ctx.resolve_doc(&doc)?
    };
    let sweep = match &base.scene.sweep {
        Some(s) => ctx.sweep_points(&doc, s)?,
        None => Vec::new(),
    };
    Ok(Loaded { base, sweep })
}

/// What the loader needs to turn problems into messages.
struct Context<'a> {
    file: &'a Path,
    original: &'a SourceMap,
    set_keys: Vec<String>,
}

impl Context<'_> {
    fn invalid(&self, problems: Vec<(String, String)>) -> SceneError {
        let problems = problems
            .into_iter()
            .map(|(key, message)| {
                let is_from_command_line = self.is_from_command_line(&key);
                Problem {
                    line: (!is_from_command_line)
                        .then(|| self.original.line_of(&key))
                        .flatten(),
                    key,
                    is_from_command_line,
                    message,
                }
            })
            .collect();
        SceneError::Invalid {
            file: self.file.to_path_buf(),
            problems,
        }
    }

    /// Whether `key` was set (or created) by `--set`.
    fn is_from_command_line(&self, key: &str) -> bool {
        let under = |a: &str, b: &str| {
            a == b || a.starts_with(&format!("{b}.")) || a.starts_with(&format!("{b}["))
        };
        self.set_keys
            .iter()
            .any(|k| under(key, k) || (under(k, key) && !self.original.has(key)))
    }

    fn resolve_doc(&self, doc: &toml::Table) -> Result<ResolvedScene, SceneError> {
        let text = toml::to_string(doc).map_err(|e| SceneError::Override {
            arg: self.set_keys.join(", "),
            message: e.to_string(),
        })?;
        self.resolve_text(&text)
    }

    fn resolve_text(&self, text: &str) -> Result<ResolvedScene, SceneError> {
        let scene: Scene = toml::from_str(text).map_err(|e| {
            let map = SourceMap::new(text);
            let key = e
                .span()
                .and_then(|s| map.key_at(&s).map(str::to_string))
                .unwrap_or_else(|| "(top level)".into());
            self.invalid(vec![(key, e.message().trim().to_string())])
        })?;
        resolve(scene, self.file).map_err(|p| self.invalid(p))
    }

    fn sweep_points(
        &self,
        doc: &toml::Table,
        s: &sweep::Sweep,
    ) -> Result<Vec<SweepPoint>, SceneError> {
        let bad = |m: String| self.invalid(vec![("sweep.key".into(), m)]);
        let steps = overrides::parse_path(&s.key)
            .ok_or_else(|| bad(format!("\"{}\" is not a dotted key path", s.key)))?;
        let key = overrides::path_string(&steps);
        if key.starts_with("sweep") || key.starts_with("scene") || key.starts_with("output") {
            return Err(bad(format!(
                "\"{key}\" cannot be swept: choose a numeric key of a physical section"
            )));
        }
        let numeric = match overrides::get(doc, &steps) {
            Some(toml::Value::Integer(_) | toml::Value::Float(_)) => true,
            Some(toml::Value::String(t)) => t
                .trim_start()
                .starts_with(|c: char| c.is_ascii_digit() || "+-.".contains(c)),
            _ => false,
        };
        if !numeric {
            return Err(bad(format!(
                "\"{key}\" must name an existing numeric key of the scene (a number or a quantity such as \"0.1 J/m^2\")"
            )));
        }
        if s.values.is_empty() {
            return Err(self.invalid(vec![(
                "sweep.values".into(),
                "is empty: give at least one value".into(),
            )]));
        }
        // Each point is resolved from the scene without its `[sweep]` table: the values list
        // would otherwise be copied, written and re-read once per point (quadratic in the
        // number of values), and a point's scene is one value, not the sweep.
        let mut without_sweep = doc.clone();
        without_sweep.remove("sweep");
        let mut points = Vec::with_capacity(s.values.len());
        for (i, value) in s.values.iter().enumerate() {
            let mut d = without_sweep.clone();
            overrides::set(&mut d, &steps, value.clone()).map_err(|e| bad(e.to_string()))?;
            let scene = self.resolve_doc(&d).map_err(|e| {
                let detail = match &e {
                    SceneError::Invalid { problems, .. } => problems
                        .iter()
                        .map(|p| format!("{}: {}", p.key, p.message))
                        .collect::<Vec<_>>()
                        .join("; "),
                    other => other.to_string(),
                };
                self.invalid(vec![(
                    format!("sweep.values[{i}]"),
                    format!("{value} for {key}: {detail}"),
                )])
            })?;
            points.push(SweepPoint {
                value: value.clone(),
                scene,
            });
        }
        Ok(points)
    }
}

/// Check every section, fill defaults, and plan; problems as (key, message).
fn resolve(mut scene: Scene, file: &Path) -> Result<ResolvedScene, Vec<(String, String)>> {
    let mut c = Checker::default();
    let dir = file.parent().unwrap_or(Path::new("")).to_path_buf();
    if scene.scene.name.is_none() {
        let stem = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| "scene".into());
        scene.scene.name = Some(stem);
    }
    scene.scene.check(&mut c);
    scene.output.check(&mut c);
    if let Some(s) = &mut scene.indenter {
        s.check(&mut c);
    }
    if let Some(s) = &mut scene.material {
        s.check(&mut c, &dir);
    }
    if let Some(s) = &scene.viscoelastic {
        s.check(&mut c);
    }
    if let Some(s) = &scene.adhesion {
        s.check(&mut c);
    }
    if let Some(s) = &scene.machine {
        s.check(&mut c);
    }
    let control = scene
        .machine
        .as_ref()
        .map_or(machine::Control::Displacement, |m| m.control);
    let totals = scene.schedule.as_mut().map(|s| s.check(&mut c, control));
    if let Some(s) = &scene.mesh {
        s.check(&mut c);
    }
    if let Some(s) = &scene.solver {
        s.check(&mut c);
    }
    if let Some(s) = &mut scene.halfspace {
        s.check(&mut c);
    }
    if let Some(s) = &mut scene.turf {
        s.check(&mut c);
    }
    let compressed = scene.compression.is_some();
    if let Some(s) = &mut scene.rods {
        s.check(&mut c, compressed);
    }
    if let Some(s) = &scene.compression {
        s.check(&mut c, scene.adhesion.as_ref());
    }
    let to = scene.compression.as_ref().map(|k| k.to.0);
    let sphere = scene
        .compression
        .as_ref()
        .is_some_and(|k| k.indenter == compression::Indenter::Sphere);
    if sphere && scene.homogenize.is_some() {
        c.bad(
            "compression.indenter",
            "\"sphere\" is not allowed with [homogenize]: the sphere gives a load–depth \
             curve, not the stress–strain curve homogenisation fits (allowed: \"platen\")",
        );
    }
    if let Some(s) = &mut scene.homogenize {
        s.check(&mut c, to);
    }
    check_stick(&scene, &mut c);
    if !c.problems.is_empty() {
        return Err(c.problems);
    }
    let (plan, derived) = plan::plan(&mut scene, totals, &mut c);
    if !c.problems.is_empty() {
        return Err(c.problems);
    }
    Ok(ResolvedScene {
        file: file.to_path_buf(),
        scene,
        derived,
        plan,
    })
}

/// A sticking indenter renews its anchors increment by increment on a fixed mesh: refuse the
/// arc-length method and the adaptive mesh with it.
fn check_stick(scene: &Scene, c: &mut Checker) {
    let stick = scene
        .indenter
        .as_ref()
        .is_some_and(|i| i.tangential == compression::Tangential::Stick);
    if !stick {
        return;
    }
    if scene
        .solver
        .as_ref()
        .is_some_and(|s| s.method == solver::Method::Riks)
    {
        c.bad(
            "indenter.tangential",
            "\"stick\" needs solver.method = \"newton\": the anchors that hold the surface are \
             renewed after each increment, which the arc-length path does not have (allowed \
             with \"riks\": \"frictionless\")",
        );
    }
    if scene.mesh.as_ref().and_then(|m| m.adaptive) == Some(true) {
        c.bad(
            "indenter.tangential",
            "\"stick\" needs mesh.adaptive = false: the anchors are not carried across \
             meshes (allowed with an adaptive mesh: \"frictionless\")",
        );
    }
}

/// The output folder of a run: `--out`, else `[output] dir`, else `runs/<scene name>`.
pub fn output_dir(scene: &ResolvedScene, out: Option<&Path>) -> PathBuf {
    match (out, &scene.scene.output.dir) {
        (Some(o), _) => o.to_path_buf(),
        (None, Some(d)) => d.clone(),
        (None, None) => Path::new("runs").join(scene.name()),
    }
}
