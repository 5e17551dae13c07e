//! Hand-written serde impls for the keys that accept a string or a table/number
//! (`law`, `friction`, `gap`, `subdomains`) and for `mesh` (a generator table or a
//! file table). They exist to give clear messages: errors raised here are plain
//! `de::Error::custom` values, to which the `toml` crate adds the line and column of
//! the offending value.

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

const LAW_EXPECTED: &str = r#"law: expected "unilateral" or { penalty = <stiffness> }"#;

impl<'de> Deserialize<'de> for Law {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Law;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(r#""unilateral" or { penalty = <stiffness> } for `law`"#)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Law, E> {
                match v {
                    "unilateral" => Ok(Law::Unilateral),
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
            Law::Penalty { penalty } => {
                let mut m = s.serialize_map(Some(1))?;
                m.serialize_entry("penalty", penalty)?;
                m.end()
            }
        }
    }
}

// ---------------------------------------------------------------- friction

const FRICTION_EXPECTED: &str = r#"friction: expected "none", { tresca = <threshold> }, { coulomb = <mu> }, { coulomb = <mu>, slip_stiffness = <k> }, { coulomb = [<mu1>, <mu2>] } or { norton_hoff = <mu>, rho = <r> }"#;

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

// ---------------------------------------------------------------- mesh

const MESH_EXPECTED: &str = r#"mesh: expected { generator = "<rectangle|half_disk|box|hemisphere|quarter_disk>", ... } or { file = "<part.msh>" }"#;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshFile {
    file: PathBuf,
}

impl<'de> Deserialize<'de> for MeshSpec {
    /// Buffers the table (format-independently, through `serde_json::Value`), then
    /// picks the struct by the presence of `generator` or `file`, so that an unknown
    /// key inside the table is reported by name (e.g. "unknown field `radus`").
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let value = serde_json::Value::deserialize(d)?;
        let serde_json::Value::Object(map) = &value else {
            return Err(de::Error::custom(format!("{MESH_EXPECTED}, got {value}")));
        };
        match (map.contains_key("generator"), map.contains_key("file")) {
            (true, false) => {
                // Name the key of a fixed-size array of the wrong length (serde
                // alone would only say "invalid length 3").
                let dim = match map.get("generator").and_then(|g| g.as_str()) {
                    Some("box" | "hemisphere") => 3,
                    _ => 2,
                };
                for key in ["origin", "size", "divisions", "center", "pole"] {
                    if let Some(serde_json::Value::Array(a)) = map.get(key) {
                        if a.len() != dim {
                            return Err(de::Error::custom(format!(
                                "mesh.{key}: this generator needs {dim} components, got {}",
                                a.len()
                            )));
                        }
                    }
                }
                Generator::deserialize(value)
                    .map(MeshSpec::Generator)
                    .map_err(|e| de::Error::custom(format!("mesh: {e}")))
            }
            (false, true) => MeshFile::deserialize(value)
                .map(|m| MeshSpec::File { file: m.file })
                .map_err(|e| {
                    de::Error::custom(format!(
                        "mesh: {e} (a file mesh is {{ file = \"<part.msh>\" }} and nothing else)"
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
