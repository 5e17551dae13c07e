//! A serde serializer that writes nothing and notes whether any float it
//! sees is not finite (or any embedded `serde_json::Value::Null`, which is
//! what `to_value` makes of one).

use serde::ser::{self, Serialize};

#[derive(Default)]
pub struct Finder {
    pub found: bool,
}

#[derive(Debug)]
pub struct Error(String);

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

impl ser::Error for Error {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        Error(msg.to_string())
    }
}

type R = Result<(), Error>;

/// Methods that see a value with nothing in it to check.
macro_rules! ignore {
    ($($method:ident($($arg:ty),*);)*) => {
        $(fn $method(self, $(_: $arg),*) -> R {
            Ok(())
        })*
    };
}

/// Methods that open a compound value, whose parts this serializer sees.
macro_rules! open {
    ($($method:ident($($arg:ty),*);)*) => {
        $(fn $method(self, $(_: $arg),*) -> Result<Self, Error> {
            Ok(self)
        })*
    };
}

/// The compound serializers: every part goes through the finder.
macro_rules! compound {
    ($($trait:ident { $($method:ident($($key:ty)?);)* })*) => {
        $(impl ser::$trait for &mut Finder {
            type Ok = ();
            type Error = Error;
            $(fn $method<T: ?Sized + Serialize>(&mut self, $(_: $key,)? v: &T) -> R {
                v.serialize(&mut **self)
            })*
            fn end(self) -> R {
                Ok(())
            }
        })*
    };
}

impl ser::Serializer for &mut Finder {
    type Ok = ();
    type Error = Error;
    type SerializeSeq = Self;
    type SerializeTuple = Self;
    type SerializeTupleStruct = Self;
    type SerializeTupleVariant = Self;
    type SerializeMap = Self;
    type SerializeStruct = Self;
    type SerializeStructVariant = Self;

    ignore! {
        serialize_bool(bool);
        serialize_i8(i8);
        serialize_i16(i16);
        serialize_i32(i32);
        serialize_i64(i64);
        serialize_u8(u8);
        serialize_u16(u16);
        serialize_u32(u32);
        serialize_u64(u64);
        serialize_char(char);
        serialize_str(&str);
        serialize_bytes(&[u8]);
        serialize_none();
        serialize_unit_struct(&'static str);
        serialize_unit_variant(&'static str, u32, &'static str);
    }
    fn serialize_f32(self, v: f32) -> R {
        self.found |= !v.is_finite();
        Ok(())
    }
    fn serialize_f64(self, v: f64) -> R {
        self.found |= !v.is_finite();
        Ok(())
    }
    fn serialize_some<T: ?Sized + Serialize>(self, v: &T) -> R {
        v.serialize(self)
    }
    /// `serde_json::Value::Null` serialises as a unit (an absent
    /// `Option` as none).
    fn serialize_unit(self) -> R {
        self.found = true;
        Ok(())
    }
    fn serialize_newtype_struct<T: ?Sized + Serialize>(self, _: &'static str, v: &T) -> R {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        v: &T,
    ) -> R {
        v.serialize(self)
    }
    open! {
        serialize_seq(Option<usize>);
        serialize_tuple(usize);
        serialize_tuple_struct(&'static str, usize);
        serialize_tuple_variant(&'static str, u32, &'static str, usize);
        serialize_map(Option<usize>);
        serialize_struct(&'static str, usize);
        serialize_struct_variant(&'static str, u32, &'static str, usize);
    }
}

compound! {
    SerializeSeq { serialize_element(); }
    SerializeTuple { serialize_element(); }
    SerializeTupleStruct { serialize_field(); }
    SerializeTupleVariant { serialize_field(); }
    SerializeMap { serialize_key(); serialize_value(); }
    SerializeStruct { serialize_field(&'static str); }
    SerializeStructVariant { serialize_field(&'static str); }
}

#[cfg(test)]
mod tests {
    use super::Finder;
    use serde::Serialize;

    #[derive(Serialize)]
    struct S {
        a: f64,
        b: Option<f64>,
        c: Vec<f64>,
        v: serde_json::Value,
    }

    fn found(s: &S) -> bool {
        let mut f = Finder::default();
        s.serialize(&mut f).unwrap();
        f.found
    }

    #[test]
    fn finds_non_finite_numbers_and_embedded_json_nulls_not_absent_options() {
        let ok = S {
            a: 1.0,
            b: None,
            c: vec![2.0],
            v: serde_json::json!({"x": [1.0, 2]}),
        };
        assert!(!found(&ok));
        assert!(found(&S {
            a: f64::NAN,
            ..ok_clone(&ok)
        }));
        assert!(found(&S {
            c: vec![1.0, f64::INFINITY],
            ..ok_clone(&ok)
        }));
        assert!(found(&S {
            b: Some(f64::NEG_INFINITY),
            ..ok_clone(&ok)
        }));
        assert!(found(&S {
            v: serde_json::to_value(vec![f64::NAN]).unwrap(),
            ..ok_clone(&ok)
        }));
    }

    fn ok_clone(s: &S) -> S {
        S {
            a: s.a,
            b: s.b,
            c: s.c.clone(),
            v: s.v.clone(),
        }
    }
}
