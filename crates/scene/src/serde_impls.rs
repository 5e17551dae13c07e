//! Hand-written serde impls for the keys that accept a string or a table/number
//! (`law`, `friction`, `gap`, `subdomains`) and for `mesh` (a generator table or a
//! file table). They exist to give clear messages: errors raised here are plain
//! `de::Error::custom` values, to which the `toml` crate adds the line and column of
//! the offending value.

use crate::output::OutputSteps;
use crate::types::{Friction, Gap, Generator, Law, MeshSpec, Subdomains};
use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;
use std::path::PathBuf;

// ---------------------------------------------------------------- numbers

/// Deserializes one number (integer or float) and names the key when it is not one.
struct Number(&'static str);

impl<'de> DeserializeSeed<'de> for Number {
    type Value = f64;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<f64, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Number {
    type Value = f64;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a number for `{}`", self.0)
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
        Ok(v)
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }
}

/// One number or an array of numbers (`coulomb = 0.3` or `coulomb = [0.3, 0.1]`).
struct Numbers(&'static str);

impl<'de> DeserializeSeed<'de> for Numbers {
    type Value = Vec<f64>;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Vec<f64>, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Numbers {
    type Value = Vec<f64>;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a number or an array of numbers for `{}`", self.0)
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Vec<f64>, E> {
        Ok(vec![v])
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Vec<f64>, E> {
        Ok(vec![v as f64])
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Vec<f64>, E> {
        Ok(vec![v as f64])
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<f64>, A::Error> {
        let mut out = Vec::new();
        while let Some(v) = seq.next_element_seed(Number(self.0))? {
            out.push(v);
        }
        Ok(out)
    }
}

// ---------------------------------------------------------------- law

const LAW_EXPECTED: &str = r#"law: expected "unilateral", "tied" or { penalty = <stiffness> }"#;

impl<'de> Deserialize<'de> for Law {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Law;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(r#""unilateral", "tied" or { penalty = <stiffness> } for `law`"#)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Law, E> {
                match v {
                    "unilateral" => Ok(Law::Unilateral),
                    "tied" => Ok(Law::Tied),
                    "penalty" => Err(E::custom(
                        "law: \"penalty\" needs a stiffness; write law = { penalty = <stiffness> }",
                    )),
                    _ => Err(E::custom(format!("{LAW_EXPECTED}, got \"{v}\""))),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Law, A::Error> {
                let mut penalty = None;
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "penalty" => penalty = Some(map.next_value_seed(Number("law.penalty"))?),
                        other => {
                            return Err(de::Error::custom(format!(
                                "{LAW_EXPECTED}; unknown key `{other}`"
                            )))
                        }
                    }
                }
                match penalty {
                    Some(penalty) => Ok(Law::Penalty { penalty }),
                    None => Err(de::Error::custom(format!(
                        "{LAW_EXPECTED}; the table has no `penalty`"
                    ))),
                }
            }
        }
        d.deserialize_any(V)
    }
}

impl Serialize for Law {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Law::Unilateral => s.serialize_str("unilateral"),
            Law::Tied => s.serialize_str("tied"),
            Law::Penalty { penalty } => {
                let mut m = s.serialize_map(Some(1))?;
                m.serialize_entry("penalty", penalty)?;
                m.end()
            }
        }
    }
}

// ---------------------------------------------------------------- friction

const FRICTION_EXPECTED: &str = r#"friction: expected "none", { tresca = <threshold> }, { coulomb = <mu> }, { coulomb = <mu>, slip_stiffness = <k> }, { coulomb = <mu>, slip_stiffness = <k>, roughness = <Q> }, { coulomb = [<mu1>, <mu2>] } or { norton_hoff = <mu>, rho = <r> }"#;

impl<'de> Deserialize<'de> for Friction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Friction;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(
                    r#""none" or a table { tresca = .. } | { coulomb = .. } | { norton_hoff = .., rho = .. } for `friction`"#,
                )
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Friction, E> {
                match v {
                    "none" => Ok(Friction::None),
                    "tresca" | "coulomb" | "norton_hoff" => Err(E::custom(format!(
                        "friction: \"{v}\" needs a coefficient; write friction = {{ {v} = <value> }}"
                    ))),
                    _ => Err(E::custom(format!("{FRICTION_EXPECTED}, got \"{v}\""))),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Friction, A::Error> {
                let mut tresca = None;
                let mut coulomb = None;
                let mut slip_stiffness = None;
                let mut roughness = None;
                let mut norton_hoff = None;
                let mut rho = None;
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "tresca" => tresca = Some(map.next_value_seed(Number("friction.tresca"))?),
                        "coulomb" => {
                            coulomb = Some(map.next_value_seed(Numbers("friction.coulomb"))?)
                        }
                        "slip_stiffness" => {
                            slip_stiffness =
                                Some(map.next_value_seed(Number("friction.slip_stiffness"))?)
                        }
                        "roughness" => {
                            roughness = Some(map.next_value_seed(Number("friction.roughness"))?)
                        }
                        "norton_hoff" => {
                            norton_hoff = Some(map.next_value_seed(Number("friction.norton_hoff"))?)
                        }
                        "rho" => rho = Some(map.next_value_seed(Number("friction.rho"))?),
                        other => {
                            return Err(de::Error::custom(format!(
                                "{FRICTION_EXPECTED}; unknown key `{other}`"
                            )))
                        }
                    }
                }
                let laws = [tresca.is_some(), coulomb.is_some(), norton_hoff.is_some()]
                    .iter()
                    .filter(|x| **x)
                    .count();
                if laws != 1 {
                    return Err(de::Error::custom(format!(
                        "{FRICTION_EXPECTED}; give exactly one of `tresca`, `coulomb`, `norton_hoff`"
                    )));
                }
                if slip_stiffness.is_some() && coulomb.is_none() {
                    return Err(de::Error::custom(
                        "friction: `slip_stiffness` only goes with `coulomb` ({ coulomb = <mu>, slip_stiffness = <k> })",
                    ));
                }
                if roughness.is_some() && coulomb.is_none() {
                    return Err(de::Error::custom(
                        "friction: `roughness` only goes with `coulomb` and `slip_stiffness` ({ coulomb = <mu>, slip_stiffness = <k>, roughness = <Q> })",
                    ));
                }
                if rho.is_some() && norton_hoff.is_none() {
                    return Err(de::Error::custom(
                        "friction: `rho` only goes with `norton_hoff` ({ norton_hoff = <mu>, rho = <r> })",
                    ));
                }
                if let Some(g) = tresca {
                    return Ok(Friction::Tresca(g));
                }
                if let Some(coefficient) = coulomb {
                    return Ok(Friction::Coulomb {
                        coefficient,
                        slip_stiffness,
                        roughness,
                    });
                }
                match (norton_hoff, rho) {
                    (Some(coefficient), Some(rho)) => Ok(Friction::NortonHoff { coefficient, rho }),
                    _ => Err(de::Error::custom(
                        "friction: `norton_hoff` needs `rho`, the exponent with 0 < rho < 1 ({ norton_hoff = <mu>, rho = <r> })",
                    )),
                }
            }
        }
        d.deserialize_any(V)
    }
}

impl Serialize for Friction {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Friction::None => s.serialize_str("none"),
            Friction::Tresca(g) => {
                let mut m = s.serialize_map(Some(1))?;
                m.serialize_entry("tresca", g)?;
                m.end()
            }
            Friction::Coulomb {
                coefficient,
                slip_stiffness,
                roughness,
            } => {
                let mut m = s.serialize_map(None)?;
                if coefficient.len() == 1 {
                    m.serialize_entry("coulomb", &coefficient[0])?;
                } else {
                    m.serialize_entry("coulomb", coefficient)?;
                }
                if let Some(k) = slip_stiffness {
                    m.serialize_entry("slip_stiffness", k)?;
                }
                if let Some(q) = roughness {
                    m.serialize_entry("roughness", q)?;
                }
                m.end()
            }
            Friction::NortonHoff { coefficient, rho } => {
                let mut m = s.serialize_map(Some(2))?;
                m.serialize_entry("norton_hoff", coefficient)?;
                m.serialize_entry("rho", rho)?;
                m.end()
            }
        }
    }
}

// ---------------------------------------------------------------- gap

impl<'de> Deserialize<'de> for Gap {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Gap;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(r#""geometric" or a number (a uniform initial gap) for `gap`"#)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Gap, E> {
                match v {
                    "geometric" => Ok(Gap::Geometric),
                    _ => Err(E::custom(format!(
                        "gap: expected \"geometric\" or a number (a uniform initial gap), got \"{v}\""
                    ))),
                }
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Gap, E> {
                Ok(Gap::Uniform(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Gap, E> {
                Ok(Gap::Uniform(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Gap, E> {
                Ok(Gap::Uniform(v as f64))
            }
        }
        d.deserialize_any(V)
    }
}

impl Serialize for Gap {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Gap::Geometric => s.serialize_str("geometric"),
            Gap::Uniform(g) => s.serialize_f64(*g),
        }
    }
}

// ---------------------------------------------------------------- output.steps

const STEPS_EXPECTED: &str = r#"output.steps: expected "all", "last", { every = N } or a list of step numbers such as [1, 5, 10]"#;

/// A whole number (possibly negative: validation names the entry and the
/// valid range) for `output.steps`.
fn step_number<E: de::Error>(v: f64) -> Result<i64, E> {
    if v.is_finite() && v.fract() == 0.0 && v.abs() < i64::MAX as f64 {
        Ok(v as i64)
    } else {
        Err(E::custom(format!(
            "{STEPS_EXPECTED}; got the number {}",
            show_f64(v)
        )))
    }
}

/// One entry of a `steps` list or the N of `every`.
struct StepNumber;

impl<'de> DeserializeSeed<'de> for StepNumber {
    type Value = i64;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<i64, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for StepNumber {
    type Value = i64;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a whole step number for `output.steps`")
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<i64, E> {
        Ok(v)
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<i64, E> {
        i64::try_from(v).map_err(|_| E::custom(format!("output.steps: {v} is too large")))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<i64, E> {
        step_number(v)
    }
}

impl<'de> Deserialize<'de> for OutputSteps {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = OutputSteps;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(STEPS_EXPECTED)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<OutputSteps, E> {
                match v {
                    "all" => Ok(OutputSteps::All),
                    "last" => Ok(OutputSteps::Last),
                    _ => Err(E::custom(format!("{STEPS_EXPECTED}; got \"{v}\""))),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<OutputSteps, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element_seed(StepNumber)? {
                    out.push(v);
                }
                Ok(OutputSteps::List(out))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<OutputSteps, A::Error> {
                let mut every = None;
                while let Some(key) = map.next_key::<String>()? {
                    if key != "every" {
                        return Err(de::Error::custom(format!(
                            "{STEPS_EXPECTED}; unknown key `{key}`"
                        )));
                    }
                    every = Some(map.next_value_seed(StepNumber)?);
                }
                every.map(OutputSteps::Every).ok_or_else(|| {
                    de::Error::custom(format!("{STEPS_EXPECTED}; the table lacks `every`"))
                })
            }
        }
        d.deserialize_any(V)
    }
}

impl Serialize for OutputSteps {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            OutputSteps::All => s.serialize_str("all"),
            OutputSteps::Last => s.serialize_str("last"),
            OutputSteps::Every(n) => {
                let mut m = s.serialize_map(Some(1))?;
                m.serialize_entry("every", n)?;
                m.end()
            }
            OutputSteps::List(l) => l.serialize(s),
        }
    }
}

// ---------------------------------------------------------------- subdomains

impl<'de> Deserialize<'de> for Subdomains {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Subdomains;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(r#"an integer >= 1 or "auto" for `subdomains`"#)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Subdomains, E> {
                match v {
                    "auto" => Ok(Subdomains::Auto),
                    _ => Err(E::custom(format!(
                        "subdomains: expected an integer >= 1 or \"auto\", got \"{v}\""
                    ))),
                }
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Subdomains, E> {
                usize::try_from(v)
                    .map(Subdomains::Count)
                    .map_err(|_| E::custom(format!("subdomains: {v} is too large")))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Subdomains, E> {
                if v >= 0 {
                    self.visit_u64(v as u64)
                } else {
                    Err(E::custom(format!(
                        "subdomains: expected an integer >= 1 or \"auto\", got {v}"
                    )))
                }
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Subdomains, E> {
                match whole(v) {
                    Ok(n) => self.visit_u64(n),
                    Err(got) => Err(E::custom(format!(
                        "subdomains: expected an integer >= 1 or \"auto\", got {got}"
                    ))),
                }
            }
        }
        d.deserialize_any(V)
    }
}

impl Serialize for Subdomains {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Subdomains::Count(n) => s.serialize_u64(*n as u64),
            Subdomains::Auto => s.serialize_str("auto"),
        }
    }
}

// ---------------------------------------------------------------- whole numbers

/// `v` as it would be written in a scene file (`-8`, `8.5`, `1e30`, `1e-300`,
/// `NaN`): a few characters, never the hundreds of digits `{}` gives 1e300.
pub(crate) fn show_f64(v: f64) -> String {
    Shown(v).to_string()
}

/// Displays a number of the scene in a message as [`show_f64`] does: in
/// exponent form when very large or very small, as written otherwise.
pub struct Shown(pub f64);

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v.is_finite() && (v.abs() >= 1e15 || (v != 0.0 && v.abs() < 1e-5)) {
            write!(f, "{v:e}")
        } else {
            write!(f, "{v}")
        }
    }
}

/// A whole number ≥ 0 (a float with no fractional part is one too: `8.0`,
/// `1e9`); `Err` holds the value as written, for the message.
fn whole(v: f64) -> Result<u64, String> {
    if v.is_finite() && v >= 0.0 && v.fract() == 0.0 && v < u64::MAX as f64 {
        Ok(v as u64)
    } else {
        Err(show_f64(v))
    }
}

/// Deserializes a whole number ≥ 0 for the key `key`; anything else is an
/// error naming the key, the value and `expected`.
struct Whole {
    key: &'static str,
    expected: &'static str,
}

impl<'de> Visitor<'de> for Whole {
    type Value = u64;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} for `{}`", self.expected, self.key)
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<u64, E> {
        Ok(v)
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<u64, E> {
        u64::try_from(v).map_err(|_| self.bad(v))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<u64, E> {
        whole(v).map_err(|s| self.bad(s))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<u64, E> {
        Err(self.bad(format!("\"{v}\"")))
    }
    fn visit_bool<E: de::Error>(self, v: bool) -> Result<u64, E> {
        Err(self.bad(v))
    }
}

impl Whole {
    fn bad<E: de::Error>(&self, got: impl fmt::Display) -> E {
        E::custom(format!(
            "{}: expected {}, got {got}",
            self.key, self.expected
        ))
    }
}

/// `dimension`: 2 or 3 (other whole numbers are refused by validation, with
/// the same words).
pub(crate) fn dimension<'de, D: Deserializer<'de>>(d: D) -> Result<u8, D::Error> {
    let v = d.deserialize_any(Whole {
        key: "dimension",
        expected: "2 or 3",
    })?;
    u8::try_from(v).map_err(|_| de::Error::custom(format!("dimension: expected 2 or 3, got {v}")))
}

/// `solver.max_iterations`: a whole number (0 is refused by validation).
pub(crate) fn max_iterations<'de, D: Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
    let v = d.deserialize_any(Whole {
        key: "solver.max_iterations",
        expected: "a whole number >= 1",
    })?;
    usize::try_from(v).map_err(|_| {
        de::Error::custom(format!(
            "solver.max_iterations: expected a whole number >= 1, got {v} (too large)"
        ))
    })
}

// ---------------------------------------------------------------- buffered values

/// A value buffered as written. `serde_json::Value` would do, but it turns
/// NaN and ±inf (valid TOML floats) into null, so that `size = [nan, 1.0]`
/// used to fail with "invalid type: null, expected f64" instead of reaching
/// the validation that names `bodies[0].mesh.size`.
#[derive(Debug, Clone)]
enum Raw {
    Null,
    Bool(bool),
    Int(i64),
    UInt(u64),
    Float(f64),
    Str(String),
    Seq(Vec<Raw>),
    Map(Vec<(String, Raw)>),
}

impl Raw {
    fn number(&self) -> Option<f64> {
        match *self {
            Raw::Int(v) => Some(v as f64),
            Raw::UInt(v) => Some(v as f64),
            Raw::Float(v) => Some(v),
            _ => None,
        }
    }

    /// The value as a user would recognise it in a message.
    fn show(&self) -> String {
        match self {
            Raw::Null => "null".into(),
            Raw::Bool(b) => b.to_string(),
            Raw::Int(v) => v.to_string(),
            Raw::UInt(v) => v.to_string(),
            Raw::Float(v) => show_f64(*v),
            Raw::Str(s) => format!("\"{s}\""),
            Raw::Seq(_) => "an array".into(),
            Raw::Map(_) => "a table".into(),
        }
    }

    fn get(&self, key: &str) -> Option<&Raw> {
        match self {
            Raw::Map(m) => m.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    fn get_mut(&mut self, key: &str) -> Option<&mut Raw> {
        match self {
            Raw::Map(m) => m.iter_mut().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }
}

impl<'de> Deserialize<'de> for Raw {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Raw;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a value")
            }
            fn visit_unit<E: de::Error>(self) -> Result<Raw, E> {
                Ok(Raw::Null)
            }
            fn visit_none<E: de::Error>(self) -> Result<Raw, E> {
                Ok(Raw::Null)
            }
            fn visit_some<D2: Deserializer<'de>>(self, d: D2) -> Result<Raw, D2::Error> {
                Raw::deserialize(d)
            }
            fn visit_bool<E: de::Error>(self, v: bool) -> Result<Raw, E> {
                Ok(Raw::Bool(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Raw, E> {
                Ok(Raw::Int(v))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Raw, E> {
                Ok(Raw::UInt(v))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Raw, E> {
                Ok(Raw::Float(v))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Raw, E> {
                Ok(Raw::Str(v.to_string()))
            }
            fn visit_string<E: de::Error>(self, v: String) -> Result<Raw, E> {
                Ok(Raw::Str(v))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Raw, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element()? {
                    out.push(v);
                }
                Ok(Raw::Seq(out))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Raw, A::Error> {
                let mut out = Vec::new();
                while let Some((k, v)) = map.next_entry::<String, Raw>()? {
                    out.push((k, v));
                }
                Ok(Raw::Map(out))
            }
        }
        d.deserialize_any(V)
    }
}

impl<'de> Deserializer<'de> for Raw {
    type Error = de::value::Error;
    fn deserialize_any<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Self::Error> {
        use serde::de::value::{MapDeserializer, SeqDeserializer};
        match self {
            Raw::Null => v.visit_unit(),
            Raw::Bool(b) => v.visit_bool(b),
            Raw::Int(i) => v.visit_i64(i),
            Raw::UInt(u) => v.visit_u64(u),
            Raw::Float(f) => v.visit_f64(f),
            Raw::Str(s) => v.visit_string(s),
            Raw::Seq(items) => v.visit_seq(SeqDeserializer::new(items.into_iter())),
            Raw::Map(entries) => v.visit_map(MapDeserializer::new(entries.into_iter())),
        }
    }
    fn deserialize_option<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Self::Error> {
        match self {
            Raw::Null => v.visit_none(),
            other => v.visit_some(other),
        }
    }
    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf unit unit_struct newtype_struct seq tuple tuple_struct
        map struct enum identifier ignored_any
    }
}

impl<'de> de::IntoDeserializer<'de, de::value::Error> for Raw {
    type Deserializer = Raw;
    fn into_deserializer(self) -> Raw {
        self
    }
}

// ---------------------------------------------------------------- mesh

const MESH_EXPECTED: &str = r#"mesh: expected { generator = "<rectangle|half_disk|box|hemisphere|quarter_disk>", ... } or { file = "<part.msh>" }"#;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshFile {
    file: PathBuf,
    #[serde(default)]
    volume: Option<String>,
}

/// Checks the numeric keys of a generator table by name before serde sees
/// them (serde alone would say "invalid value: integer `-8`, expected usize"
/// without the key), and makes whole-valued floats in `divisions` integers
/// (`divisions = 1e3` is 1000 elements).
fn check_generator(map: &mut Raw) -> Result<(), String> {
    let generator = match map.get("generator") {
        Some(Raw::Str(g)) => g.clone(),
        _ => String::new(),
    };
    let dim = match generator.as_str() {
        "box" | "hemisphere" => 3,
        "rectangle" | "half_disk" | "quarter_disk" => 2,
        // serde names the unknown generator and lists the known ones
        _ => return Ok(()),
    };
    let per_side = matches!(generator.as_str(), "rectangle" | "box");
    check_lengths(map, dim, per_side)?;
    check_numbers(map, dim)?;
    check_grading(map, per_side)?;
    whole_divisions(map, dim, per_side, &generator)
}

/// Fixed-size arrays of the wrong length (serde alone: "invalid length 3");
/// `divisions` is an array only for the generators `per_side`.
fn check_lengths(map: &Raw, dim: usize, per_side: bool) -> Result<(), String> {
    // Fixed-size arrays of the wrong length (serde alone: "invalid length 3").
    for key in ["origin", "size", "divisions", "center", "pole"] {
        if let Some(Raw::Seq(a)) = map.get(key) {
            if (per_side || key != "divisions") && a.len() != dim {
                return Err(format!(
                    "mesh.{key}: this generator needs {dim} components, got {}",
                    a.len()
                ));
            }
        }
    }
    Ok(())
}

/// Vectors and scalars of numbers: `origin`, `size`, `center`, `pole`,
/// `radius`.
fn check_numbers(map: &Raw, dim: usize) -> Result<(), String> {
    for key in ["origin", "size", "center", "pole"] {
        match map.get(key) {
            None => {}
            Some(Raw::Seq(a)) => {
                if let Some(x) = a.iter().find(|x| x.number().is_none()) {
                    return Err(format!(
                        "mesh.{key}: expected {dim} numbers, got {}",
                        x.show()
                    ));
                }
            }
            Some(other) => {
                return Err(format!(
                    "mesh.{key}: expected an array of {dim} numbers, got {}",
                    other.show()
                ))
            }
        }
    }
    if let Some(r) = map.get("radius") {
        if r.number().is_none() {
            return Err(format!(
                "mesh.radius: expected a number > 0, got {}",
                r.show()
            ));
        }
    }
    Ok(())
}

/// `grading`: a table { towards, ratio } for the generators `per_side`, a
/// number for the others.
fn check_grading(map: &Raw, per_side: bool) -> Result<(), String> {
    match map.get("grading") {
        None => {}
        Some(Raw::Map(_)) if per_side => {
            let g = map.get("grading").and_then(|g| g.get("ratio"));
            if let Some(r) = g.filter(|r| r.number().is_none()) {
                return Err(format!(
                    "mesh.grading.ratio: expected a number >= 1, got {}",
                    r.show()
                ));
            }
        }
        Some(g) if per_side => {
            return Err(format!(
                "mesh.grading: expected {{ towards = \"<side>\", ratio = <number >= 1> }}, got {}",
                g.show()
            ))
        }
        Some(g) if g.number().is_none() => {
            return Err(format!(
                "mesh.grading: expected a number >= 1 (largest over smallest element size), got {}",
                g.show()
            ))
        }
        Some(_) => {}
    }
    Ok(())
}

/// Divisions: whole numbers, named with the value when not, made integers
/// (`divisions = 1e3` is 1000 elements).
fn whole_divisions(
    map: &mut Raw,
    dim: usize,
    per_side: bool,
    generator: &str,
) -> Result<(), String> {
    let what = if per_side {
        "positive whole numbers (elements along each side)"
    } else if generator == "hemisphere" {
        "a positive whole number (elements along a quarter meridian)"
    } else {
        "a positive whole number (elements along the arc)"
    };
    let to_whole = |x: &mut Raw| -> Result<(), String> {
        let n = match &*x {
            Raw::UInt(_) => return Ok(()),
            Raw::Int(v) if *v >= 0 => return Ok(()),
            Raw::Int(v) => Err(v.to_string()),
            Raw::Float(v) => whole(*v),
            other => Err(other.show()),
        };
        match n {
            Ok(n) => {
                *x = Raw::UInt(n);
                Ok(())
            }
            Err(got) => Err(format!("mesh.divisions: expected {what}, got {got}")),
        }
    };
    match map.get_mut("divisions") {
        None => {}
        Some(Raw::Seq(a)) if per_side => a.iter_mut().try_for_each(to_whole)?,
        Some(x @ (Raw::Int(_) | Raw::UInt(_) | Raw::Float(_))) if !per_side => to_whole(x)?,
        Some(other) => {
            return Err(format!(
                "mesh.divisions: expected {}{what}, got {}",
                if per_side {
                    format!("an array of {dim} ")
                } else {
                    String::new()
                },
                other.show()
            ))
        }
    }
    Ok(())
}

impl<'de> Deserialize<'de> for MeshSpec {
    /// Buffers the table (format-independently, keeping every number as
    /// written), then picks the struct by the presence of `generator` or
    /// `file`, so that an unknown key inside the table is reported by name
    /// (e.g. "unknown field `radus`"), and a wrong number by its key.
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let mut value = Raw::deserialize(d)?;
        let Raw::Map(map) = &value else {
            return Err(de::Error::custom(format!(
                "{MESH_EXPECTED}, got {}",
                value.show()
            )));
        };
        let has = |k: &str| map.iter().any(|(key, _)| key == k);
        match (has("generator"), has("file")) {
            (true, false) => {
                check_generator(&mut value).map_err(de::Error::custom)?;
                Generator::deserialize(value)
                    .map(MeshSpec::Generator)
                    .map_err(|e| de::Error::custom(format!("mesh: {e}")))
            }
            (false, true) => MeshFile::deserialize(value)
                .map(|m| MeshSpec::File {
                    file: m.file,
                    volume: m.volume,
                })
                .map_err(|e| {
                    de::Error::custom(format!(
                        "mesh: {e} (a file mesh is {{ file = \"<part.msh>\" }} or {{ file = \"<assembly.msh>\", volume = \"<physical group>\" }})"
                    ))
                }),
            (true, true) => Err(de::Error::custom(format!(
                "{MESH_EXPECTED}; give `generator` or `file`, not both"
            ))),
            (false, false) => Err(de::Error::custom(format!(
                "{MESH_EXPECTED}; the table has neither `generator` nor `file`"
            ))),
        }
    }
}
