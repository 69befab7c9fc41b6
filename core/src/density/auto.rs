//! A parameter that is either derived by a rule (`auto`) or given.

use std::fmt;

use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize, Serializer};

/// A length (or other number) a params file writes as `auto` (derive it
/// from the measured density) or as a number (use that).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Auto<T> {
    /// Derived by the parameter's documented rule.
    #[default]
    Auto,
    /// Given by the user; overrides the rule.
    Value(T),
}

impl<T: Copy> Auto<T> {
    /// The given value, or `rule()` for `auto`.
    pub fn or_rule(self, rule: impl FnOnce() -> T) -> T {
        match self {
            Auto::Auto => rule(),
            Auto::Value(v) => v,
        }
    }

    /// The given value, `None` for `auto`.
    pub fn value(self) -> Option<T> {
        match self {
            Auto::Auto => None,
            Auto::Value(v) => Some(v),
        }
    }

    /// `Value(rule())` for `auto`, itself otherwise: the parameter resolved.
    pub fn resolved(self, rule: impl FnOnce() -> T) -> Self {
        Auto::Value(self.or_rule(rule))
    }
}

impl<T: Serialize> Serialize for Auto<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Auto::Auto => s.serialize_str("auto"),
            Auto::Value(v) => v.serialize(s),
        }
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Auto<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw<T> {
            Value(T),
            Word(String),
        }
        struct Expected;
        impl Visitor<'_> for Expected {
            type Value = ();
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or \"auto\"")
            }
        }
        match Raw::<T>::deserialize(d) {
            Ok(Raw::Value(v)) => Ok(Auto::Value(v)),
            Ok(Raw::Word(w)) if w.eq_ignore_ascii_case("auto") => Ok(Auto::Auto),
            Ok(Raw::Word(w)) => Err(de::Error::invalid_value(de::Unexpected::Str(&w), &Expected)),
            Err(_) => Err(de::Error::custom("expected a number or \"auto\"")),
        }
    }
}

impl<T: fmt::Display> fmt::Display for Auto<T> {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            Auto::Auto => f.write_str("auto"),
            Auto::Value(v) => v.fmt(f),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_and_numbers_round_trip_and_other_words_fail() {
        let a: Auto<f32> = serde_json::from_str("\"auto\"").unwrap();
        assert_eq!(a, Auto::Auto);
        let v: Auto<f32> = serde_json::from_str("2.5").unwrap();
        assert_eq!(v, Auto::Value(2.5));
        assert_eq!(serde_json::to_string(&a).unwrap(), "\"auto\"");
        assert_eq!(serde_json::to_string(&v).unwrap(), "2.5");
        let e = serde_json::from_str::<Auto<f32>>("\"fast\"").unwrap_err();
        assert!(e.to_string().contains("auto"), "{e}");
        assert!(serde_json::from_str::<Auto<f32>>("true").is_err());
        assert_eq!(a.or_rule(|| 4.0), 4.0);
        assert_eq!(v.or_rule(|| 4.0), 2.5);
        assert_eq!(a.resolved(|| 3.0), Auto::Value(3.0));
        assert_eq!(v.value(), Some(2.5));
    }
}
