//! The suite as data: the case list `cases.toml` and the scene templates
//! `scenes/*.toml`, compiled in (`include_str!`) so that the binary stays
//! self-contained. See the head of `cases.toml` for its format.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Value;

use crate::stiff::{
    roundoff, scene, Case, Expectation, Measure, Reference, FRICTION_TOLERANCE, HERTZ_TOLERANCE,
    NTS_DEVIATION, PENALTY_DEVIATION,
};

/// The case list.
pub const CASES: &str = include_str!("../../cases.toml");

macro_rules! templates {
    ($($name:literal),* $(,)?) => {
        /// The scene templates, by name (crates/suite/scenes/<name>.toml).
        pub const TEMPLATES: &[(&str, &str)] = &[
            $(($name, include_str!(concat!("../../scenes/", $name, ".toml")))),*
        ];
    };
}

templates!(
    "header2d",
    "header3d",
    "pin",
    "top",
    "top3d",
    "drag",
    "push",
    "sides",
    "contact2d",
    "contact3d",
    "coulomb",
    "penalty_law",
    "solver_method",
    "solver_penalty",
    "solver_uzawa",
    "solver_friction",
    "steps",
    "single_node2d",
    "single_node3d",
    "wall2d",
    "corner2d",
    "walls3d",
    "corner3d",
    "stacked",
    "hertz",
);

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Suite {
    defaults: BTreeMap<String, String>,
    family: Vec<Family>,
}

/// A group of cases of one family sharing a scene and parameters (a family
/// may have several groups).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Family {
    name: String,
    scene: Vec<String>,
    #[serde(default)]
    params: BTreeMap<String, String>,
    cases: Vec<CaseData>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseData {
    name: String,
    parameter: String,
    value: f64,
    scene: Option<Vec<String>>,
    #[serde(default)]
    params: BTreeMap<String, String>,
    expect: Kind,
    code: Option<u8>,
    message: Option<String>,
    #[serde(default)]
    references: Vec<ReferenceData>,
    #[serde(default)]
    on_stop: Vec<ReferenceData>,
}

#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum Kind {
    Solves,
    Stops,
    Either,
}

#[derive(Deserialize)]
struct ReferenceData {
    name: String,
    scale: Option<f64>,
    tolerance: Option<Tolerance>,
    per: Option<f64>,
    roundoff: Option<f64>,
    #[serde(flatten)]
    measure: Measure,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Tolerance {
    Value(f64),
    Named(String),
}

impl ReferenceData {
    /// `tolerance` (a number or a named constant) / `per`, plus
    /// [`roundoff`]`(kappa)` when `roundoff = kappa` is given.
    fn tolerance(&self) -> Result<f64, String> {
        let base = match &self.tolerance {
            None => None,
            Some(Tolerance::Value(v)) => Some(*v),
            Some(Tolerance::Named(n)) => Some(named_tolerance(n)?),
        };
        let base = match (base, self.per) {
            (Some(b), Some(p)) => Some(b / p),
            (b, None) => b,
            (None, Some(_)) => return Err(format!("{}: `per` without `tolerance`", self.name)),
        };
        match (base, self.roundoff) {
            (Some(b), Some(k)) => Ok(b + roundoff(k)),
            (Some(b), None) => Ok(b),
            (None, Some(k)) => Ok(roundoff(k)),
            (None, None) => Err(format!("{}: no tolerance", self.name)),
        }
    }

    fn reference(self) -> Result<Reference, String> {
        Ok(Reference {
            tolerance: self.tolerance()?,
            name: self.name,
            scale: self.scale,
            measure: self.measure,
        })
    }
}

/// The tolerances `cases.toml` names (documented in src/lib.rs).
fn named_tolerance(name: &str) -> Result<f64, String> {
    match name {
        "hertz" => Ok(HERTZ_TOLERANCE),
        "nts_deviation" => Ok(NTS_DEVIATION),
        "friction" => Ok(FRICTION_TOLERANCE),
        "penalty_deviation" => Ok(PENALTY_DEVIATION),
        _ => Err(format!("unknown tolerance \"{name}\"")),
    }
}

/// Replaces every table `{ quick = a, full = b }` by `a` (quick) or `b`.
fn pick_mode(v: Value, quick: bool) -> Value {
    match v {
        Value::Table(t) if t.len() == 2 && t.contains_key("quick") && t.contains_key("full") => {
            let key = if quick { "quick" } else { "full" };
            pick_mode(t[key].clone(), quick)
        }
        Value::Table(t) => Value::Table(
            t.into_iter()
                .map(|(k, v)| (k, pick_mode(v, quick)))
                .collect(),
        ),
        Value::Array(a) => Value::Array(a.into_iter().map(|v| pick_mode(v, quick)).collect()),
        other => other,
    }
}

/// The text of template `name`.
pub fn template(name: &str) -> Result<&'static str, String> {
    TEMPLATES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t)
        .ok_or_else(|| format!("no scene template \"{name}\""))
}

/// The placeholders of a text: every `{name}`, name a lower-case
/// identifier (TOML's inline tables, `{ x = 0.0 }`, are left alone), as
/// (start, end, name).
pub fn placeholders(text: &str) -> Vec<(usize, usize, &str)> {
    let mut found = Vec::new();
    let mut rest = 0;
    while let Some(open) = text[rest..].find('{').map(|i| rest + i) {
        rest = open + 1;
        let Some(close) = text[rest..].find('}').map(|i| rest + i) else {
            break;
        };
        let name = &text[open + 1..close];
        let ident = name.starts_with(|c: char| c.is_ascii_lowercase())
            && name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
        if ident {
            found.push((open, close + 1, name));
            rest = close + 1;
        }
    }
    found
}

/// `text` with every placeholder replaced by its parameter.
pub fn fill(text: &str, params: &BTreeMap<String, String>) -> Result<String, String> {
    let mut out = String::with_capacity(text.len());
    let mut at = 0;
    for (start, end, name) in placeholders(text) {
        let value = params
            .get(name)
            .ok_or_else(|| format!("placeholder {{{name}}} not filled"))?;
        out.push_str(&text[at..start]);
        out.push_str(value);
        at = end;
    }
    out.push_str(&text[at..]);
    Ok(out)
}

/// A case's scene: its templates, concatenated and filled.
fn scene_text(parts: &[String], params: &BTreeMap<String, String>) -> Result<String, String> {
    let mut text = String::new();
    for p in parts {
        text.push_str(&fill(template(p)?, params)?);
    }
    Ok(text)
}

fn expectation(c: &mut CaseData) -> Result<Expectation, String> {
    let references = std::mem::take(&mut c.references)
        .into_iter()
        .map(ReferenceData::reference)
        .collect::<Result<Vec<_>, _>>()?;
    let on_stop = std::mem::take(&mut c.on_stop)
        .into_iter()
        .map(ReferenceData::reference)
        .collect::<Result<Vec<_>, _>>()?;
    let stop = |what: &str| match (c.code, c.message.clone()) {
        (Some(code), Some(message)) => Ok((code, message)),
        _ => Err(format!("{}: \"{what}\" needs `code` and `message`", c.name)),
    };
    Ok(match c.expect {
        Kind::Solves => Expectation::Solves(references),
        Kind::Stops => {
            let (code, message) = stop("stops")?;
            Expectation::Stops {
                code,
                message,
                references,
            }
        }
        Kind::Either => {
            let (code, message) = stop("either")?;
            Expectation::Either {
                code,
                message,
                references,
                on_stop,
            }
        }
    })
}

/// Every case of the data, for the quick suite or the full one.
pub fn load(quick: bool) -> Result<Vec<Case>, String> {
    let value: Value = toml::from_str(CASES).map_err(|e| format!("cases.toml: {e}"))?;
    let suite: Suite = pick_mode(value, quick)
        .try_into()
        .map_err(|e| format!("cases.toml: {e}"))?;
    let mut cases = Vec::new();
    for family in suite.family {
        for mut c in family.cases {
            let mut params = suite.defaults.clone();
            params.extend(family.params.clone());
            params.extend(std::mem::take(&mut c.params));
            let parts = c.scene.as_ref().unwrap_or(&family.scene);
            let text = scene_text(parts, &params).map_err(|e| format!("{}: {e}", c.name))?;
            let expect = expectation(&mut c)?;
            let scene = scene::parse_toml(&text).map_err(|e| e.to_string());
            cases.push(Case {
                name: c.name,
                family: family.name.clone(),
                parameter: c.parameter,
                value: c.value,
                text,
                scene,
                expect,
            });
        }
    }
    Ok(cases)
}

/// Every case of the suite (the data is compiled in: an error in it is a bug).
pub fn cases(quick: bool) -> Vec<Case> {
    load(quick).unwrap_or_else(|e| panic!("the stiff suite's data: {e}"))
}
