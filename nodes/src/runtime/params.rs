//! Node parameters from ROS 2 params-file YAML (`node: ros__parameters: ...`)
//! with `-p name:=value` overrides, deserialized into a node's own typed struct.

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde_json::{Map, Value};
use yaml_rust2::{Yaml, YamlLoader};

/// Errors while reading or applying parameters.
#[derive(Debug, thiserror::Error)]
pub enum ParamsError {
    /// The params file could not be read.
    #[error("cannot read params file {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The YAML text is malformed.
    #[error("{origin}: invalid YAML: {reason}")]
    Yaml {
        /// File name or `-p` argument.
        origin: String,
        /// Parser message.
        reason: String,
    },
    /// The YAML parses but is not a ROS 2 params file.
    #[error("{origin}: {reason}")]
    Shape {
        /// File name or `-p` argument.
        origin: String,
        /// What is wrong, e.g. a missing `ros__parameters` key.
        reason: String,
    },
    /// The merged parameters do not fit the node's parameter struct.
    #[error("parameters of node `{node}`: {reason}")]
    Invalid {
        /// Node name.
        node: String,
        /// Serde's message (unknown name, wrong type, ...).
        reason: String,
    },
}

/// The parameter set of one node, merged from defaults, files and overrides.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParamSet {
    values: Map<String, Value>,
}

impl ParamSet {
    /// Merges the params of `node` from a params-file text: the node's own
    /// section (`node`, `/node`, `/ns/node`) and the wildcard `/**` section.
    pub fn merge_yaml(&mut self, text: &str, node: &str, origin: &str) -> Result<(), ParamsError> {
        let docs = YamlLoader::load_from_str(text).map_err(|e| ParamsError::Yaml {
            origin: origin.to_string(),
            reason: e.to_string(),
        })?;
        let Some(first) = docs.into_iter().next() else {
            return Ok(());
        };
        let Yaml::Hash(top) = first else {
            return Err(ParamsError::Shape {
                origin: origin.to_string(),
                reason: "expected a mapping of node names to `ros__parameters`".into(),
            });
        };
        // Wildcards first so a node's own section wins.
        let mut sections: Vec<(bool, &Yaml)> = Vec::new();
        for (key, body) in &top {
            let key = key.as_str().unwrap_or_default();
            let wildcard = key == "/**" || key == "**";
            let mine = key.trim_start_matches('/').rsplit('/').next() == Some(node);
            if wildcard || mine {
                sections.push((!wildcard, body));
            }
        }
        sections.sort_by_key(|(own, _)| *own);
        for (_, body) in sections {
            let params = &body["ros__parameters"];
            match params {
                Yaml::Hash(_) => flatten_into(&mut self.values, "", params),
                Yaml::BadValue | Yaml::Null => {
                    return Err(ParamsError::Shape {
                        origin: origin.to_string(),
                        reason: format!("section for `{node}` has no `ros__parameters` mapping"),
                    });
                }
                _ => {
                    return Err(ParamsError::Shape {
                        origin: origin.to_string(),
                        reason: "`ros__parameters` must be a mapping".into(),
                    });
                }
            }
        }
        Ok(())
    }

    /// Merges a params file from disk.
    pub fn merge_file(&mut self, path: &Path, node: &str) -> Result<(), ParamsError> {
        let text = std::fs::read_to_string(path).map_err(|source| ParamsError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        self.merge_yaml(&text, node, &path.display().to_string())
    }

    /// Applies one `-p name:=value` override; the value is read as YAML.
    pub fn set_override(&mut self, name: &str, value: &str) -> Result<(), ParamsError> {
        let origin = format!("-p {name}:={value}");
        let docs = YamlLoader::load_from_str(value).map_err(|e| ParamsError::Yaml {
            origin: origin.clone(),
            reason: e.to_string(),
        })?;
        let v = docs
            .first()
            .map(yaml_to_json)
            .unwrap_or(Value::String(String::new()));
        self.values.insert(name.to_string(), v);
        Ok(())
    }

    /// Sets one value directly (used by tools that start nodes).
    pub fn set(&mut self, name: &str, value: Value) {
        self.values.insert(name.to_string(), value);
    }

    /// The value of a dotted parameter name, if set.
    pub fn get(&self, name: &str) -> Option<&Value> {
        self.values.get(name)
    }

    /// Deserializes the merged set into a node's parameter struct; dotted names
    /// become nested objects. `use_sim_time` is handled by the runtime and skipped.
    pub fn parse<T: DeserializeOwned>(&self, node: &str) -> Result<T, ParamsError> {
        let mut root = Map::new();
        for (name, v) in &self.values {
            if name == "use_sim_time" {
                continue;
            }
            insert_dotted(&mut root, name, v.clone());
        }
        serde_json::from_value(Value::Object(root)).map_err(|e| ParamsError::Invalid {
            node: node.to_string(),
            reason: e.to_string(),
        })
    }

    /// Whether `use_sim_time` is set true.
    pub fn use_sim_time(&self) -> bool {
        matches!(self.values.get("use_sim_time"), Some(Value::Bool(true)))
    }

    /// All values as (dotted name, value), sorted by name.
    pub fn entries(&self) -> Vec<(String, Value)> {
        let mut v: Vec<_> = self
            .values
            .iter()
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        v.sort_by(|a, b| a.0.cmp(&b.0));
        v
    }
}

/// A node's params section as `T`, from its config/ defaults and an optional file
/// (keys of the node this command does not use are ignored).
pub fn section<T: serde::de::DeserializeOwned>(
    node: &str,
    defaults: &str,
    file: Option<&Path>,
    keys: &[&str],
) -> Result<T, ParamsError> {
    section_over(node, (defaults, None), file, keys)
}

/// As [`section`], with the command's own defaults (`(origin, yaml)`) over
/// the node's and under the file's.
pub fn section_over<T: serde::de::DeserializeOwned>(
    node: &str,
    (defaults, own): (&str, Option<(&str, &str)>),
    file: Option<&Path>,
    keys: &[&str],
) -> Result<T, ParamsError> {
    let mut params = ParamSet::default();
    params.merge_yaml(defaults, node, &format!("config/{node}.yaml"))?;
    if let Some((origin, yaml)) = own {
        params.merge_yaml(yaml, node, origin)?;
    }
    if let Some(f) = file {
        params.merge_file(f, node)?;
    }
    let v: serde_json::Value = params.parse(node)?;
    let picked: serde_json::Map<String, serde_json::Value> = keys
        .iter()
        .filter_map(|k| v.get(*k).map(|x| ((*k).to_string(), x.clone())))
        .collect();
    serde_json::from_value(serde_json::Value::Object(picked)).map_err(|e| ParamsError::Invalid {
        node: node.to_string(),
        reason: e.to_string(),
    })
}

fn flatten_into(out: &mut Map<String, Value>, prefix: &str, y: &Yaml) {
    if let Yaml::Hash(h) = y {
        for (k, v) in h {
            let key = match k {
                Yaml::String(s) => s.clone(),
                Yaml::Integer(i) => i.to_string(),
                other => format!("{other:?}"),
            };
            let name = if prefix.is_empty() {
                key
            } else {
                format!("{prefix}.{key}")
            };
            match v {
                Yaml::Hash(_) => flatten_into(out, &name, v),
                _ => {
                    out.insert(name, yaml_to_json(v));
                }
            }
        }
    }
}

fn yaml_to_json(y: &Yaml) -> Value {
    match y {
        Yaml::Real(s) => s
            .parse::<f64>()
            .ok()
            .and_then(serde_json::Number::from_f64)
            .map_or_else(|| Value::String(s.clone()), Value::Number),
        Yaml::Integer(i) => Value::from(*i),
        Yaml::String(s) => Value::String(s.clone()),
        Yaml::Boolean(b) => Value::Bool(*b),
        Yaml::Array(a) => Value::Array(a.iter().map(yaml_to_json).collect()),
        Yaml::Hash(_) => {
            let mut m = Map::new();
            flatten_into(&mut m, "", y);
            let mut nested = Map::new();
            for (k, v) in m {
                insert_dotted(&mut nested, &k, v);
            }
            Value::Object(nested)
        }
        Yaml::Null | Yaml::BadValue | Yaml::Alias(_) => Value::Null,
    }
}

fn insert_dotted(root: &mut Map<String, Value>, name: &str, v: Value) {
    match name.split_once('.') {
        None => {
            root.insert(name.to_string(), v);
        }
        Some((head, rest)) => {
            let child = root
                .entry(head.to_string())
                .or_insert_with(|| Value::Object(Map::new()));
            if !child.is_object() {
                *child = Value::Object(Map::new());
            }
            if let Value::Object(m) = child {
                insert_dotted(m, rest, v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct P {
        rate: f64,
        topic: String,
        lidar: Lidar,
    }
    #[derive(Debug, Deserialize, PartialEq)]
    #[serde(deny_unknown_fields)]
    struct Lidar {
        beams: u32,
    }

    const FILE: &str = "
/**:
  ros__parameters:
    use_sim_time: true
    rate: 1
pub:
  ros__parameters:
    topic: /aerial_cloud
    lidar:
      beams: 16
other:
  ros__parameters:
    topic: /nope
";

    #[test]
    fn node_section_wildcard_and_overrides_merge() {
        let mut p = ParamSet::default();
        p.merge_yaml(FILE, "pub", "test.yaml").unwrap();
        assert!(p.use_sim_time());
        p.set_override("rate", "2.5").unwrap();
        p.set_override("lidar.beams", "32").unwrap();
        let v: P = p.parse("pub").unwrap();
        assert_eq!(
            v,
            P {
                rate: 2.5,
                topic: "/aerial_cloud".into(),
                lidar: Lidar { beams: 32 }
            }
        );
    }

    #[test]
    fn namespaced_section_matches_node_name() {
        let mut p = ParamSet::default();
        p.merge_yaml("/robot/pub:\n  ros__parameters:\n    rate: 3\n", "pub", "x")
            .unwrap();
        assert_eq!(p.get("rate"), Some(&Value::from(3)));
    }

    #[test]
    fn wrong_type_and_unknown_names_are_errors() {
        let mut p = ParamSet::default();
        p.merge_yaml(FILE, "pub", "test.yaml").unwrap();
        p.set_override("rate", "fast").unwrap();
        let e = p.parse::<P>("pub").unwrap_err().to_string();
        assert!(e.contains("pub") && e.contains("invalid type"), "{e}");
        let mut p = ParamSet::default();
        p.merge_yaml(FILE, "pub", "t").unwrap();
        p.set_override("colour", "1").unwrap();
        let e = p.parse::<P>("pub").unwrap_err().to_string();
        assert!(e.contains("unknown field `colour`"), "{e}");
    }

    #[test]
    fn malformed_files_are_errors() {
        let mut p = ParamSet::default();
        assert!(matches!(
            p.merge_yaml("pub: [1, 2", "pub", "a.yaml"),
            Err(ParamsError::Yaml { .. })
        ));
        assert!(matches!(
            p.merge_yaml("pub:\n  rate: 1\n", "pub", "a.yaml"),
            Err(ParamsError::Shape { .. })
        ));
        assert!(matches!(
            p.merge_file(Path::new("/nonexistent/x.yaml"), "pub"),
            Err(ParamsError::Read { .. })
        ));
    }
}
